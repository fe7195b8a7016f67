#pragma once

#include <cstddef>
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
int RunAnalyze(const std::vector<std::string>& args);

/// Thrown for a bad command line: main() prints it with the usage hint and exits with status 2.
struct UsageError {
  std::string message;
};

/// The value that follows option args[*i] (advancing *i), or UsageError "<option> needs a value".
const std::string& OptionValue(const std::vector<std::string>& args, std::size_t* i);

/// `text` as a number, or UsageError "<option> needs a number, got '<text>'".
double OptionNumber(const std::string& option, const std::string& text);

}  // namespace acro::app
