#pragma once

#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "acro/base/text.h"

namespace acro::capture::internal {

using acro::LineCursor;
using acro::Split;
using acro::SplitWhitespace;
using acro::Trim;

/// Parses a number; an empty cell or NaN/nan/-nan gives NaN. Returns false for anything else
/// that is not entirely a number.
inline bool ParseCell(std::string_view cell, double* value) {
  cell = Trim(cell);
  if (cell.empty()) {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (cell.front() == '+') cell.remove_prefix(1);
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  const auto result = std::from_chars(first, last, *value);
  if (result.ec == std::errc() && result.ptr == last) return true;
  // from_chars accepts "nan" and "inf" but not every spelling writers use.
  std::string lower(cell);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "nan" || lower == "-nan" || lower == "1.#qnan" || lower == "-1.#ind") {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  return false;
}

/// Shortest text that reads back as the same double ("nan" never: callers decide).
inline void AppendNumber(double value, std::string* out) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

/// Fixed-point text with `decimals` digits.
inline void AppendFixed(double value, int decimals, std::string* out) {
  char buffer[64];
  const auto result =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, decimals);
  if (result.ec != std::errc()) {
    AppendNumber(value, out);
    return;
  }
  out->append(buffer, result.ptr);
}

}  // namespace acro::capture::internal
