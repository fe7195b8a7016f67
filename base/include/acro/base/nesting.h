#pragma once

// A depth check in front of every parser of nested text (docs/limits.md, "Nesting"): OpenCV's
// FileStorage parsers recurse once per level and a calibration nested 100,000 brackets deep (200 KB)
// overflowed the stack (SIGSEGV). The check scans the bytes once, without parsing, before the
// parser sees them.

#include <string>
#include <string_view>

namespace acro {

/// Where the text is deepest and how deep: JSON/YAML/TOML flow brackets `[` and `{`, and XML
/// elements (`<name` opens, `</` and `/>` close; comments, declarations and processing
/// instructions skipped). Quoting is not parsed, so a bracket inside a string counts as well: the
/// depth is an upper bound, exact for files that hold no brackets in their strings.
struct Nesting {
  int depth = 0;  ///< the deepest level
  int line = 0;   ///< where it is first reached, 1-based
};
Nesting MeasureNesting(std::string_view text);

/// acro::InputError (file `file`, "line N") when `text` nests deeper than `max_depth` levels.
void DemandNestingAtMost(std::string_view text, int max_depth, const std::string& file);

}  // namespace acro
