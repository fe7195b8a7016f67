#pragma once

// Text helpers every reader of a text format needs: line splitting that accepts every line end,
// trimming and field splitting, all without copying.

#include <string>
#include <string_view>
#include <vector>

namespace acro {

/// Splits text into lines without copying; accepts \n, \r\n and lone \r line ends.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool Next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = pos_;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    *line = text_.substr(pos_, end - pos_);
    if (end < text_.size() && text_[end] == '\r') {
      ++end;
      if (end < text_.size() && text_[end] == '\n') ++end;  // \r\n
    } else if (end < text_.size()) {
      ++end;  // \n
    }
    pos_ = end;
    ++line_number_;
    return true;
  }
  int line_number() const { return line_number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_number_ = 0;
};

/// `s` made safe for one line of a terminal or a log (docs/limits.md, "Messages"): newline,
/// carriage return and tab as \n, \r, \t, every other byte below 0x20 and 0x7f as \xNN (a NUL byte
/// in a C3D label no longer cuts the message short, an escape sequence in a file never reaches the
/// terminal raw); bytes from 0x80 up are kept (UTF-8). Longer than `max_bytes`: cut there, with
/// "… (N more bytes)".
inline std::string EscapeForTerminal(std::string_view s, std::size_t max_bytes = 2000) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  const std::size_t n = s.size() > max_bytes ? max_bytes : s.size();
  out.reserve(n + 16);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (s.size() > n) out += "… (" + std::to_string(s.size() - n) + " more bytes)";
  return out;
}

/// Whether `s` is well-formed UTF-8 (no overlong forms, no surrogates, nothing above U+10FFFF).
inline bool IsValidUtf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int n = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the range of the first continuation byte
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 1;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return false;
    }
    if (i + std::size_t(n) >= s.size()) return false;  // cut short
    for (int k = 1; k <= n; ++k) {
      const unsigned char d = static_cast<unsigned char>(s[i + std::size_t(k)]);
      if (d < (k == 1 ? lo : 0x80) || d > (k == 1 ? hi : 0xBF)) return false;
    }
    i += std::size_t(n) + 1;
  }
  return true;
}

/// `s` as UTF-8: unchanged when it is UTF-8 already, else read as Latin-1 (ISO 8859-1, what old
/// C3D files from Windows labs hold: "Genou_gauche_é") and each byte transcoded (docs/limits.md,
/// "Messages").
inline std::string Utf8FromUtf8OrLatin1(std::string_view s) {
  if (IsValidUtf8(s)) return std::string(s);
  std::string out;
  out.reserve(s.size() + s.size() / 4);
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

inline std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

/// Splits on one delimiter, keeping empty fields.
inline void Split(std::string_view line, char delimiter, std::vector<std::string_view>* fields) {
  fields->clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(delimiter, start);
    if (end == std::string_view::npos) {
      fields->push_back(line.substr(start));
      return;
    }
    fields->push_back(line.substr(start, end - start));
    start = end + 1;
  }
}

/// Splits on runs of blanks (for space-separated files).
inline void SplitWhitespace(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) fields->push_back(line.substr(start, i - start));
  }
}

}  // namespace acro
