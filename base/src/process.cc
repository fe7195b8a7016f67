#include "acro/base/process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include "acro/base/temporaries.h"
#include "acro/base/text.h"

extern char** environ;

namespace acro {

namespace {

struct Running {
  size_t index = 0;
  std::filesystem::path stderr_file;
  std::unique_ptr<ScopedTemporary> stderr_registered;
  std::unique_ptr<ScopedChildProcess> registered;
  std::chrono::steady_clock::time_point started;
};

std::string LastLine(const std::filesystem::path& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return {};
  // The tail is enough: the one-line error is the last line.
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  const long from = size > 8192 ? size - 8192 : 0;
  std::fseek(f, from, SEEK_SET);
  std::string tail(size_t(size - from), '\0');
  tail.resize(std::fread(tail.data(), 1, tail.size(), f));
  std::fclose(f);
  // Progress bars redraw with \r: a line ends at either.
  size_t end = tail.find_last_not_of("\r\n \t");
  if (end == std::string::npos) return {};
  const size_t start = tail.find_last_of("\r\n", end);
  std::string line = tail.substr(start == std::string::npos ? 0 : start + 1,
                                 end + 1 - (start == std::string::npos ? 0 : start + 1));
  return EscapeForTerminal(line);
}

}  // namespace

std::string CurrentExecutable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : self.string();
}

void RunProcesses(const std::vector<std::vector<std::string>>& commands,
                  int parallel,
                  const std::function<void(size_t, const ProcessOutcome&)>& finished,
                  const std::function<bool()>& keep_going) {
  if (parallel < 1) parallel = 1;
  std::map<pid_t, Running> running;
  size_t next = 0;
  bool stopping = false;
  const std::filesystem::path tmp = std::filesystem::temp_directory_path();
  auto start = [&](size_t index) {
    const std::vector<std::string>& argv_text = commands[index];
    ProcessOutcome failed;
    failed.exit_status = 127;
    if (argv_text.empty()) {
      failed.last_error_line = "empty command";
      finished(index, failed);
      return;
    }
    // The job's stderr file, made and registered in one step: an interrupt never finds it made
    // and not yet registered (which left it behind: seen once under load).
    std::string pattern = (tmp / "acrolab-job-XXXXXX").string();
    std::unique_ptr<ScopedTemporary> registered;
    const int fd = ScopedTemporary::CreateFile(pattern, &registered);
    if (fd < 0) {
      if (errno == ECANCELED) {  // the program is being interrupted: no new job
        stopping = true;
        return;
      }
      failed.last_error_line =
          std::string("cannot create a file in ") + tmp.string() + ": " + std::strerror(errno);
      finished(index, failed);
      return;
    }
    Running r;
    r.index = index;
    r.stderr_file = pattern;
    r.stderr_registered = std::move(registered);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, fd, 2);
    posix_spawn_file_actions_addclose(&actions, fd);
    // The child starts with no signal blocked (this program blocks SIGINT and SIGTERM for its
    // interrupt thread) and default handlers.
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, all;
    sigemptyset(&none);
    sigemptyset(&all);
    sigaddset(&all, SIGINT);
    sigaddset(&all, SIGTERM);
    sigaddset(&all, SIGPIPE);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &all);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    std::vector<char*> argv;
    for (const std::string& a : argv_text) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int rc = 0;
    r.registered = ScopedChildProcess::Start(
        [&] {
          pid_t pid = 0;
          rc = posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), environ);
          return rc == 0 ? pid : pid_t(-1);
        },
        ChildRole::kJob);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    close(fd);
    if (!r.registered) {
      std::filesystem::remove(r.stderr_file);
      if (rc == 0) {  // not started: the program is being interrupted
        stopping = true;
        return;
      }
      failed.last_error_line = "cannot start " + argv_text[0] + ": " + std::strerror(rc);
      finished(index, failed);
      return;
    }
    r.started = std::chrono::steady_clock::now();
    running.emplace(r.registered->pid(), std::move(r));
  };
  while (true) {
    while (!stopping && running.size() < size_t(parallel) && next < commands.size() &&
           (!keep_going || keep_going()))
      start(next++);
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;  // no children left that we know of
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not one of ours
    ProcessOutcome outcome;
    if (WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
    outcome.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.started)
            .count();
    outcome.last_error_line = LastLine(it->second.stderr_file);
    std::error_code ec;
    std::filesystem::remove(it->second.stderr_file, ec);
    const size_t index = it->second.index;
    running.erase(it);
    finished(index, outcome);
  }
}

}  // namespace acro
