#pragma once

#include <string>
#include <vector>

namespace acro::app {

/// Each command parses its own arguments, calls library functions and prints. It returns the exit
/// status; bad input surfaces as acro::InputError, which main() prints as one line.
int RunInfo(const std::vector<std::string>& args);
int RunConvert(const std::vector<std::string>& args);
int RunBody(const std::vector<std::string>& args);
int RunReconstruct(const std::vector<std::string>& args);
int RunOptimize(const std::vector<std::string>& args);

/// Thrown for a bad command line: main() prints it with the usage hint and exits with status 2.
struct UsageError {
  std::string message;
};

}  // namespace acro::app
