#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace acro {

/// Streaming JSON text builder with two-space indentation. Non-finite numbers are written as
/// null (JSON has no NaN). Usage: w.BeginObject(); w.Key("a"); w.Value(1); w.EndObject();
class JsonWriter {
 public:
  void BeginObject() { Open('{'); }
  void EndObject() { Close('}'); }
  void BeginArray() { Open('['); }
  void EndArray() { Close(']'); }

  void Key(std::string_view key) {
    Separate();
    AppendString(key);
    out_ += ": ";
    after_key_ = true;
  }

  void Value(std::string_view s) {
    Separate();
    AppendString(s);
  }
  void Value(const char* s) { Value(std::string_view(s)); }
  void Value(const std::string& s) { Value(std::string_view(s)); }
  void Value(bool b) {
    Separate();
    out_ += b ? "true" : "false";
  }
  void Value(double d) {
    Separate();
    if (!std::isfinite(d)) {
      out_ += "null";
      return;
    }
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), d);
    out_.append(buffer, result.ptr);
  }
  void Value(float f) { Value(static_cast<double>(f)); }
  void Value(int i) { Value(static_cast<std::int64_t>(i)); }
  void Value(std::int64_t i) {
    Separate();
    out_ += std::to_string(i);
  }
  void Value(std::size_t i) { Value(static_cast<std::int64_t>(i)); }
  void Null() {
    Separate();
    out_ += "null";
  }

  /// Key and value in one call.
  template <typename T>
  void Field(std::string_view key, const T& value) {
    Key(key);
    Value(value);
  }
  /// An array of numbers or strings on one line.
  template <typename Range>
  void Array(const Range& values) {
    BeginArray();
    inline_ = true;
    for (const auto& v : values) Value(v);
    inline_ = false;
    Close(']', /*was_inline=*/true);
  }

  const std::string& str() const { return out_; }

 private:
  void Open(char c) {
    Separate();
    out_ += c;
    first_.push_back(true);
  }
  void Close(char c, bool was_inline = false) {
    const bool empty = first_.back();
    first_.pop_back();
    if (!empty && !was_inline) Newline();
    out_ += c;
  }
  void Separate() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    if (first_.empty()) return;
    if (!first_.back()) out_ += inline_ ? ", " : ",";
    first_.back() = false;
    if (!inline_) Newline();
  }
  void Newline() {
    out_ += '\n';
    out_.append(2 * first_.size(), ' ');
  }
  void AppendString(std::string_view s) {
    out_ += '"';
    for (unsigned char c : s) {
      switch (c) {
        case '"':
          out_ += "\\\"";
          break;
        case '\\':
          out_ += "\\\\";
          break;
        case '\n':
          out_ += "\\n";
          break;
        case '\r':
          out_ += "\\r";
          break;
        case '\t':
          out_ += "\\t";
          break;
        default:
          if (c < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
            out_ += buffer;
          } else {
            out_ += static_cast<char>(c);
          }
      }
    }
    out_ += '"';
  }

  std::string out_;
  std::vector<bool> first_;
  bool after_key_ = false;
  bool inline_ = false;
};

}  // namespace acro
