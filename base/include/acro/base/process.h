#pragma once

// Running other programs as jobs: `acrolab batch` runs each trial as its own `acrolab library add`
// process, so that one trial that fails — or crashes — never stops the others, and an interrupt
// stops them all (each child is registered with the interrupt handler, temporaries.h).

#include <functional>
#include <string>
#include <vector>

namespace acro {

struct ProcessOutcome {
  int exit_status = -1;  ///< the status it exited with, or -1 when a signal ended it
  int signal = 0;        ///< the signal that ended it, or 0
  /// The last non-empty line it wrote on stderr (its one-line error), at most 2000 bytes.
  std::string last_error_line;
  double seconds = 0.0;
  bool ok() const { return exit_status == 0; }
};

/// Runs each command (argv[0] a path or a name looked up in PATH; stdin and stdout /dev/null,
/// stderr kept for `last_error_line`), at most `parallel` at once, in order; calls `finished`
/// (from this thread) as each one ends. `keep_going` is asked before each start: false stops
/// starting new ones (those running are waited for). A command that cannot be started is an
/// outcome with exit status 127 and the reason.
void RunProcesses(const std::vector<std::vector<std::string>>& commands,
                  int parallel,
                  const std::function<void(size_t, const ProcessOutcome&)>& finished,
                  const std::function<bool()>& keep_going = {});

/// The running program's own executable (/proc/self/exe), for starting itself.
std::string CurrentExecutable();

}  // namespace acro
