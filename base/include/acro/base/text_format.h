#pragma once

// Small text helpers for the report pages and tables every layer writes.

#include <string>
#include <string_view>

namespace acro {

/// `v` with `digits` digits after the point, as printf's "%.*f" writes it.
std::string FormatFixed(double v, int digits);

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
