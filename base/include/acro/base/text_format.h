#pragma once

// Small text helpers for the report pages and tables every layer writes.

#include <cstdio>
#include <string>
#include <string_view>

namespace acro {

/// `v` with `digits` digits after the point ("%.*f").
inline std::string FormatFixed(double v, int digits) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

/// `s` with the characters HTML gives a meaning (& < > ") escaped, for text and attribute values.
inline std::string HtmlEscape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace acro
