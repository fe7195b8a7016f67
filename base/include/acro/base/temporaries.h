#pragma once

// Outputs being written under a temporary name (WriteFileAtomically, the video writer, an overlay's
// staging directory) are registered here while they exist, so that an interrupted program can
// remove them: nothing half-written is left behind by Ctrl-C or a SIGTERM (docs/design.md,
// "Errors"). Helper processes (an Xvfb server) are registered the same way, to be stopped. The
// registries are thread-safe; the command line's interrupt handler empties them.

#include <filesystem>
#include <functional>

#include <sys/types.h>

namespace acro {

/// Registers `path` (a file or a directory) for the lifetime of this object.
class ScopedTemporary {
 public:
  explicit ScopedTemporary(std::filesystem::path path);
  ~ScopedTemporary();
  ScopedTemporary(const ScopedTemporary&) = delete;
  ScopedTemporary& operator=(const ScopedTemporary&) = delete;

 private:
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

/// A helper process this program started and must not leave behind (the Xvfb server the 3D views
/// start when there is no display): registered for the lifetime of this object, so that the
/// interrupt handler stops it too.
class ScopedChildProcess {
 public:
  explicit ScopedChildProcess(pid_t pid);
  ~ScopedChildProcess();
  ScopedChildProcess(const ScopedChildProcess&) = delete;
  ScopedChildProcess& operator=(const ScopedChildProcess&) = delete;

 private:
  pid_t pid_;
};

/// Sends SIGTERM to every registered child process and returns how many it signalled. For the
/// interrupt handler; safe to call from any thread.
int StopRegisteredChildren() noexcept;

}  // namespace acro
