#pragma once

// Outputs being written under a temporary name (WriteFileAtomically, the video writer, an overlay's
// staging directory) are registered here while they exist, so that an interrupted program can
// remove them: nothing half-written is left behind by Ctrl-C or a SIGTERM (docs/design.md,
// "Errors"). The registry is thread-safe; the command line's interrupt handler empties it.

#include <filesystem>

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
/// removed. For the interrupt handler; safe to call from any thread.
int RemoveRegisteredTemporaries() noexcept;

}  // namespace acro
