#include "acro/base/nesting.h"

#include "acro/base/input_error.h"

namespace acro {

Nesting MeasureNesting(std::string_view text) {
  Nesting deepest;
  int depth = 0, line = 1;
  const std::size_t n = text.size();
  const auto opened = [&] {
    if (++depth > deepest.depth) deepest = {depth, line};
  };
  const auto closed = [&] { depth = depth > 0 ? depth - 1 : 0; };
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '[' || c == '{') {
      opened();
    } else if (c == ']' || c == '}') {
      closed();
    } else if (c == '<' && i + 1 < n) {
      const char next = text[i + 1];
      if (next == '/') {
        closed();
      } else if (next == '!' || next == '?') {
        // A comment, declaration or processing instruction: to its end, counting lines.
        const std::string_view end = text.substr(i, 4) == "<!--" ? "-->" : ">";
        const std::size_t stop = text.find(end, i + 2);
        const std::size_t last = stop == std::string_view::npos ? n : stop + end.size();
        for (std::size_t k = i; k < last; ++k) line += text[k] == '\n';
        i = last - 1;
      } else if ((next >= 'A' && next <= 'Z') || (next >= 'a' && next <= 'z') || next == '_' ||
                 next == ':') {
        opened();
      }
    } else if (c == '/' && i + 1 < n && text[i + 1] == '>') {
      closed();  // <empty/>
    }
  }
  return deepest;
}

void DemandNestingAtMost(std::string_view text, int max_depth, const std::string& file) {
  const Nesting nesting = MeasureNesting(text);
  if (nesting.depth <= max_depth) return;
  throw InputError(file,
                   "line " + std::to_string(nesting.line),
                   "nested deeper than " + std::to_string(max_depth) +
                       " levels (a calibration or settings file needs a few)");
}

}  // namespace acro
