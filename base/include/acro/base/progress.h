#pragma once

// Long work's one way to say how far it is and to be stopped (docs/design.md, "Progress and
// cancellation"): a Progress is called with the step's name and a count; it answers false to
// cancel, and the work then throws acro::Cancelled — never an InputError, so that a door tells a
// user's stop from bad input without keeping its own flag.

#include <functional>
#include <stdexcept>
#include <string>

namespace acro {

/// The user stopped the work. what() is one line ("cancelled", or what was left undone).
class Cancelled : public std::runtime_error {
 public:
  explicit Cancelled(const std::string& what = "cancelled") : std::runtime_error(what) {}
};

/// Progress of long work: `report(step, done, total)` returns false to cancel. Empty: nobody
/// listens and nothing cancels. Calls may come from worker threads, one at a time.
struct Progress {
  std::function<bool(const std::string& step, int done, int total)> report;

  /// True to go on.
  bool Report(const std::string& step, int done, int total) const {
    return !report || report(step, done, total);
  }
  /// Throws Cancelled when the listener says stop.
  void ReportOrThrow(const std::string& step, int done, int total) const {
    if (!Report(step, done, total)) throw Cancelled();
  }
};

}  // namespace acro
