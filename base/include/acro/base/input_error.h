#pragma once

#include <stdexcept>
#include <string>

#include "acro/base/text.h"

namespace acro {

/// Thrown when a file or argument is malformed. what() is a single line
/// "<file>: <where>: <problem>" naming the file, the byte offset or field, and the value at fault.
/// Library layers throw it; only app/ and ui/ catch it.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& where, const std::string& problem)
      : std::runtime_error(Compose(file, where, problem)) {}

 private:
  static std::string Compose(const std::string& file,
                             const std::string& where,
                             const std::string& problem) {
    std::string line = file;
    if (!where.empty()) line += (line.empty() ? "" : ": ") + where;
    line += (line.empty() ? "" : ": ") + problem;
    // One line, safe for a terminal: control bytes in a value at fault are shown escaped, and a
    // huge value is cut.
    return EscapeForTerminal(line);
  }
};

/// Throws InputError "<what>: <reason>" when `options.IsValid(&reason)` is false, so that an
/// Options struct's reason reaches the user as one line (never a logic_error that drops it).
template <typename Options>
void DemandValidOptions(const Options& options, const std::string& what) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError("", what, why);
}

/// "byte 1234" for error locations.
inline std::string AtByte(long long offset) {
  return "byte " + std::to_string(offset);
}

}  // namespace acro
