#include "acro/base/temporaries.h"

#include <csignal>
#include <mutex>
#include <set>
#include <system_error>

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

std::multiset<pid_t>& Children() {
  static std::multiset<pid_t> pids;
  return pids;
}

}  // namespace

ScopedTemporary::ScopedTemporary(std::filesystem::path path) : path_(std::move(path)) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().insert(path_);
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
  } catch (...) {
    // Nothing to report to: the program is stopping.
  }
  return removed;
}

void RunUninterrupted(const std::function<void()>& work) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  work();
}

ScopedChildProcess::ScopedChildProcess(pid_t pid) : pid_(pid) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  Children().insert(pid_);
}

ScopedChildProcess::~ScopedChildProcess() {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  const auto it = Children().find(pid_);
  if (it != Children().end()) Children().erase(it);
}

int StopRegisteredChildren() noexcept {
  int stopped = 0;
  try {
    const std::lock_guard<std::mutex> lock(RegistryMutex());
    for (const pid_t pid : Children()) {
      if (pid > 0 && kill(pid, SIGTERM) == 0) ++stopped;
    }
    Children().clear();
  } catch (...) {
    // Nothing to report to: the program is stopping.
  }
  return stopped;
}

}  // namespace acro
