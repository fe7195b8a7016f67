#include "acro/base/temporaries.h"

#include <sys/wait.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>

namespace acro {

namespace {

std::mutex& RegistryMutex() {
  static std::mutex m;
  return m;
}

std::multiset<std::filesystem::path>& Registry() {
  static std::multiset<std::filesystem::path> paths;
  return paths;
}

std::multimap<pid_t, ChildRole>& Children() {
  static std::multimap<pid_t, ChildRole> children;
  return children;
}

// Set by StopRegisteredChildren: no child is started after it. Atomic: read without the lock by
// ChildrenBeingStopped (from an X error handler that must not wait for it).
// Set by RemoveRegisteredTemporaries, under the registry's lock: the program is stopping.
bool& TemporariesRemoved() {
  static bool removed = false;
  return removed;
}

std::atomic<bool>& ChildrenStopping() {
  static std::atomic<bool> stopping{false};
  return stopping;
}

}  // namespace

ScopedTemporary::ScopedTemporary(std::filesystem::path path) : path_(std::move(path)) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().insert(path_);
}

// With the registry's lock held by the caller.
ScopedTemporary::ScopedTemporary(std::filesystem::path path, Locked) : path_(std::move(path)) {
  Registry().insert(path_);
}

int ScopedTemporary::CreateFile(std::string& pattern,
                                std::unique_ptr<ScopedTemporary>* registered) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  if (TemporariesRemoved()) {
    errno = ECANCELED;
    return -1;
  }
  const int fd = mkstemp(pattern.data());
  if (fd < 0) return -1;
  registered->reset(new ScopedTemporary(pattern, Locked{}));
  return fd;
}

ScopedTemporary::~ScopedTemporary() {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  const auto it = Registry().find(path_);
  if (it != Registry().end()) Registry().erase(it);
}

int RemoveRegisteredTemporaries() noexcept {
  int removed = 0;
  try {
    const std::lock_guard<std::mutex> lock(RegistryMutex());
    for (const std::filesystem::path& p : Registry()) {
      std::error_code ec;
      if (std::filesystem::remove_all(p, ec) > 0 && !ec) ++removed;
    }
    Registry().clear();
    TemporariesRemoved() = true;  // nothing made after this (CreateFile refuses)
  } catch (...) {
    // Nothing to report to: the program is stopping.
  }
  return removed;
}

namespace {
std::atomic<int>& Committed() {
  static std::atomic<int> committed{0};
  return committed;
}
}  // namespace

void RunUninterrupted(const std::function<void()>& work) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  work();
  ++Committed();  // a finished output moved into place, whole
}

int CommittedOutputs() noexcept {
  return Committed().load();
}

std::unique_ptr<ScopedChildProcess> ScopedChildProcess::Start(const std::function<pid_t()>& spawn,
                                                              ChildRole role) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  if (ChildrenStopping()) return nullptr;
  const pid_t pid = spawn();
  if (pid <= 0) return nullptr;
  Children().emplace(pid, role);
  return std::unique_ptr<ScopedChildProcess>(new ScopedChildProcess(pid));
}

ScopedChildProcess::~ScopedChildProcess() {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  const auto it = Children().find(pid_);
  if (it != Children().end()) Children().erase(it);
}

bool ChildrenBeingStopped() noexcept {
  return ChildrenStopping();
}

int StopRegisteredChildren(ChildRole role, int timeout_ms) noexcept {
  int stopped = 0;
  try {
    std::set<pid_t> waiting;
    {
      const std::lock_guard<std::mutex> lock(RegistryMutex());
      ChildrenStopping() = true;
      for (const auto& [pid, r] : Children()) {
        if (r == role && pid > 0 && kill(pid, SIGTERM) == 0) {
          ++stopped;
          waiting.insert(pid);
        }
      }
    }
    if (role == ChildRole::kHelper) return stopped;
    // A job has ended once it is a zombie, left for the thread that started it to reap (WNOWAIT),
    // or has been reaped by that thread already (ECHILD, or gone from the registry).
    const auto gone = [](pid_t pid) {
      {
        const std::lock_guard<std::mutex> lock(RegistryMutex());
        if (Children().count(pid) == 0) return true;
      }
      siginfo_t info{};
      const int r = waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT);
      return (r == 0 && info.si_pid == pid) || (r < 0 && errno == ECHILD);
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (!waiting.empty()) {
      for (auto it = waiting.begin(); it != waiting.end();)
        it = gone(*it) ? waiting.erase(it) : ++it;
      if (waiting.empty() || std::chrono::steady_clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    for (const pid_t pid : waiting) kill(pid, SIGKILL);
  } catch (...) {
    // Nothing to report to: the program is stopping.
  }
  return stopped;
}

}  // namespace acro
