#include "acro/views/display.h"

#include <X11/Xlib.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>

#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"

namespace acro::ui {

namespace {

// The first executable `name` on $PATH, or nothing.
std::optional<std::string> FindOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) continue;
    const std::string candidate = dir + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

// Waits up to `timeout_ms` for `pid` to exit; true when it did.
bool WaitForExit(pid_t pid, int timeout_ms) {
  for (int waited = 0; waited <= timeout_ms; waited += 10) {
    const pid_t r = waitpid(pid, nullptr, WNOHANG);
    if (r == pid || (r < 0 && errno == ECHILD)) return true;
    usleep(10000);
  }
  return false;
}

// The forked child: becomes the Xvfb server, writing its display number to `pipe_write`.
[[noreturn]] void ExecXvfb(const std::string& xvfb, int pipe_write, pid_t parent) {
  // The server: no blocked signals (the command line blocks SIGINT and SIGTERM for its signal
  // thread), stopped when this process dies, quiet, and only the pipe inherited (as fd 3).
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(1);
  // The pipe's end out of the way of fds 0–3 first (it may be one of them when this process
  // was started with stdin or stdout closed).
  const int pipe_end = fcntl(pipe_write, F_DUPFD, 10);
  if (pipe_end < 0) _exit(1);
  const int null = open("/dev/null", O_RDWR);
  if (null >= 0) {
    dup2(null, 0);
    dup2(null, 1);
    dup2(null, 2);
  }
  dup2(pipe_end, 3);  // dup2 clears close-on-exec on the copy
  close_range(4, ~0U, 0);
  const char* argv[] = {"Xvfb",
                        "-displayfd",
                        "3",
                        "-screen",
                        "0",
                        "1920x1080x24",  // a full-HD screen: the studio's window fits
                        "-nolisten",
                        "tcp",
                        "-noreset",
                        nullptr};
  execv(xvfb.c_str(), const_cast<char* const*>(argv));
  _exit(127);
}

// Xlib calls this when the connection to the X server breaks, and ends the program if it returns.
// When the interrupt handler has stopped our Xvfb server, the break is expected: this thread waits
// for the handler, which exits with 128 + the signal once the outputs are removed — Xlib's own
// exit(1) raced it (seen in CI, Cli.TerminatedOverlayStopsItsXvfb). Any other break is one line
// and exit 1, the unfinished outputs removed first.
int OnXConnectionLost(Display* display) {
  if (ChildrenBeingStopped()) {
    for (;;) pause();
  }
  std::fprintf(stderr,
               "acrolab: lost the connection to the X display %s (its server has gone)\n",
               display != nullptr ? DisplayString(display) : "");
  std::fflush(stderr);
  RemoveRegisteredTemporaries();
  _exit(1);
}

}  // namespace

bool XServerAnswers(const std::string& display_name) {
  Display* display = XOpenDisplay(display_name.c_str());
  if (display == nullptr) return false;
  XCloseDisplay(display);
  return true;
}

struct XDisplay::Impl {
  std::string name;
  pid_t pid = -1;
  std::unique_ptr<ScopedChildProcess> registered;
  std::optional<std::string> previous_display;

  ~Impl() {
    if (pid <= 0) return;
    registered.reset();  // before the pid can be reaped and reused
    kill(pid, SIGTERM);
    if (!WaitForExit(pid, 3000)) {
      kill(pid, SIGKILL);
      WaitForExit(pid, 1000);
    }
    if (previous_display) {
      setenv("DISPLAY", previous_display->c_str(), 1);
    } else {
      unsetenv("DISPLAY");
    }
  }

  void Start() {
    const std::optional<std::string> xvfb = FindOnPath("Xvfb");
    if (!xvfb) {
      throw InputError(
          "",
          "3D views",
          "no X display ($DISPLAY is unset or does not answer) and no Xvfb to start "
          "one: install the xvfb package (apt-get install xvfb), or run with a display");
    }
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw InputError("", "3D views", "cannot make a pipe for Xvfb");
    const pid_t parent = getpid();
    registered = ScopedChildProcess::Start(
        [&] {
          const pid_t child = fork();
          if (child == 0) ExecXvfb(*xvfb, fds[1], parent);
          return child;
        },
        ChildRole::kHelper);
    if (!registered) {
      close(fds[0]);
      close(fds[1]);
      throw InputError("", "3D views", "cannot start Xvfb (fork failed, or acrolab is stopping)");
    }
    pid = registered->pid();
    close(fds[1]);
    // The server writes its display number and a newline when it is ready.
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    for (int waited_ms = 0; waited_ms < 10000;) {
      const int r = poll(&p, 1, 100);
      if (r < 0 && errno == EINTR) continue;
      if (r == 0) {
        waited_ms += 100;
        continue;
      }
      char c = 0;
      const ssize_t n = read(fds[0], &c, 1);
      if (n <= 0 || c == '\n') break;
      number += c;
    }
    close(fds[0]);
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos) {
      throw InputError("",
                       "3D views",
                       *xvfb +
                           " did not open a display within 10 s (is Mesa's OpenGL, "
                           "libgl1-mesa-dri, installed?)");
    }
    const char* display = std::getenv("DISPLAY");
    if (display != nullptr) previous_display = display;
    name = ":" + number;
    setenv("DISPLAY", name.c_str(), 1);
    XSetIOErrorHandler(&OnXConnectionLost);
  }
};

XDisplay::XDisplay() : impl_(std::make_unique<Impl>()) {
  const char* display = std::getenv("DISPLAY");
  if (display != nullptr && *display != '\0' && XServerAnswers(display)) {
    impl_->name = display;
    return;
  }
  impl_->Start();
}

XDisplay::~XDisplay() = default;

const std::string& XDisplay::name() const {
  return impl_->name;
}

bool XDisplay::started_here() const {
  return impl_->pid > 0;
}

}  // namespace acro::ui
