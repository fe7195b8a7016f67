#pragma once

// Outputs being written under a temporary name (WriteFileAtomically, the video writer, an overlay's
// staging directory) are registered here while they exist, so that an interrupted program can
// remove them: nothing half-written is left behind by Ctrl-C or a SIGTERM (docs/design.md,
// "Errors"). Helper processes (an Xvfb server) are registered the same way, to be stopped. The
// registries are thread-safe; the command line's interrupt handler empties them.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include <sys/types.h>

namespace acro {

/// Registers `path` (a file or a directory) for the lifetime of this object.
class ScopedTemporary {
 public:
  explicit ScopedTemporary(std::filesystem::path path);
  ~ScopedTemporary();
  ScopedTemporary(const ScopedTemporary&) = delete;
  ScopedTemporary& operator=(const ScopedTemporary&) = delete;

  /// Creates a file from `pattern` (mkstemp's: it ends in XXXXXX and becomes the file's name) and
  /// registers it in one step the interrupt handler cannot come between, so that no file it made
  /// is ever left unregistered. Returns the open descriptor and sets `*registered`; -1 with errno
  /// set when the file cannot be made — ECANCELED once the handler has removed the temporaries
  /// (the program is stopping: nothing new is made).
  static int CreateFile(std::string& pattern, std::unique_ptr<ScopedTemporary>* registered);

 private:
  struct Locked {};
  ScopedTemporary(std::filesystem::path path, Locked);
  std::filesystem::path path_;
};

/// Removes every registered temporary (directories with their contents) and returns how many it
/// removed. For the interrupt handler; safe to call from any thread. Waits while RunUninterrupted
/// runs.
int RemoveRegisteredTemporaries() noexcept;

/// Runs `work` while the interrupt handler cannot remove temporaries (it waits until `work`
/// returns): finished outputs are moved into place as one step, never half. `work` must not
/// register or unregister temporaries.
void RunUninterrupted(const std::function<void()>& work);

/// How many outputs RunUninterrupted has moved into place, whole, so far: what an interrupt that
/// comes after them keeps (and says it kept).
int CommittedOutputs() noexcept;

/// What a child process is to the interrupt handler.
enum class ChildRole {
  kJob,     ///< work of its own (a batch's `library add`): stopped and waited for, first
  kHelper,  ///< serves this program (the Xvfb server): stopped last, not waited for
};

/// A child process this program started and must not leave behind (a batch's jobs, an Xvfb
/// server for the 3D views): registered for the lifetime of this object, so that the interrupt
/// handler stops it too.
class ScopedChildProcess {
 public:
  /// Starts a child with `spawn` (which returns its pid, or a value <= 0 when it started nothing)
  /// and registers it in one step the interrupt handler cannot come between: once the handler has
  /// begun stopping children, `spawn` is not called and nullptr is returned, as it is when `spawn`
  /// fails.
  static std::unique_ptr<ScopedChildProcess> Start(const std::function<pid_t()>& spawn,
                                                   ChildRole role);
  ~ScopedChildProcess();
  ScopedChildProcess(const ScopedChildProcess&) = delete;
  ScopedChildProcess& operator=(const ScopedChildProcess&) = delete;

  pid_t pid() const { return pid_; }

 private:
  explicit ScopedChildProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_;
};

/// Sends SIGTERM to every registered child of `role` and returns how many it signalled. Jobs are
/// waited for until they have ended (their own clean-up done: a batch's job finishes the commit it
/// cannot interrupt and removes its temporaries) or `timeout_ms` has passed, then those still
/// running get SIGKILL. Helpers are not waited for: this program may still need them until it
/// exits (Xlib ends a program whose X server has gone with exit status 1). From the first call on,
/// no child is started (ScopedChildProcess::Start returns nullptr). For the interrupt handler,
/// which stops the jobs, removes its temporaries, then stops the helpers and exits; safe to call
/// from any thread.
int StopRegisteredChildren(ChildRole role, int timeout_ms = 10000) noexcept;

/// True once StopRegisteredChildren has been called: the interrupt handler is stopping this
/// program, and a helper that goes away now (the Xvfb server) went because it was told to. Takes no
/// lock.
bool ChildrenBeingStopped() noexcept;

}  // namespace acro
