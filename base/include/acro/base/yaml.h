#pragma once

// YAML for Acrolab's own files (athlete profiles, skills, marker sets), read by yaml-cpp and held
// in a small tree of our own so that no yaml-cpp type reaches a public header. Every node remembers
// its file and line, so that a type error found later also names them; the typed reads and the
// unknown-key check give one-line errors "<file>: line N: <key>: <problem>". Everything yaml-cpp
// reads (flow and block collections, quoted strings, block scalars, anchors and aliases) reads the
// same here; a second document, a duplicate key, nesting deeper than 64 levels and trees of more
// than two million values are refused.

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace acro {

class YamlNode {
 public:
  enum class Kind { kNull, kScalar, kSequence, kMap };

  Kind kind() const { return kind_; }
  bool IsNull() const { return kind_ == Kind::kNull; }
  bool IsScalar() const { return kind_ == Kind::kScalar; }
  bool IsSequence() const { return kind_ == Kind::kSequence; }
  bool IsMap() const { return kind_ == Kind::kMap; }
  /// 1-based line of the node's first character (of its key for a map value).
  int line() const { return line_; }
  const std::string& file() const { return file_; }
  /// The key under which the node sits in its parent map ("" for the root or a sequence item).
  const std::string& key() const { return key_; }
  /// "line 12" for error messages.
  std::string Where() const { return "line " + std::to_string(line_); }

  /// Scalar text (quotes removed, escapes resolved). Empty for other kinds.
  const std::string& text() const { return text_; }
  /// True when the scalar was written in quotes (then "null", "123" stay strings).
  bool quoted() const { return quoted_; }
  /// Sequence items (empty for other kinds).
  const std::vector<YamlNode>& items() const { return items_; }
  /// Map entries in file order (empty for other kinds).
  const std::vector<std::pair<std::string, YamlNode>>& entries() const { return entries_; }

  /// The value under `key` in a map, or nullptr when absent (or when this is not a map).
  const YamlNode* Find(std::string_view key) const;
  /// The value under `key`; throws acro::InputError naming file, line and key when absent or
  /// when this node is not a map.
  const YamlNode& At(std::string_view key) const;

  /// Typed reads; each throws acro::InputError "<file>: line N: <key>: <problem>" on a mismatch.
  std::string AsString() const;
  double AsDouble() const;
  int AsInt() const;
  bool AsBool() const;
  std::vector<double> AsDoubleList() const;
  std::vector<std::string> AsStringList() const;

  /// Throws acro::InputError naming the first key of this map not in `allowed` (typo guard).
  void RequireKnownKeys(const std::vector<std::string_view>& allowed) const;

  /// Throws acro::InputError "<file>: line N: <key>: <problem>" for this node.
  [[noreturn]] void Fail(const std::string& problem) const;

 private:
  friend class YamlParser;
  Kind kind_ = Kind::kNull;
  int line_ = 0;
  bool quoted_ = false;
  std::string file_;
  std::string key_;
  std::string text_;
  std::vector<YamlNode> items_;
  std::vector<std::pair<std::string, YamlNode>> entries_;
};

/// Parses YAML text; `file_name` only labels error messages. Throws acro::InputError naming the
/// file and line of the first syntax error. An empty document gives a null node.
YamlNode ParseYaml(std::string_view text, const std::string& file_name);

/// Reads and parses a YAML file (throws acro::InputError when unreadable or malformed).
YamlNode ReadYamlFile(const std::filesystem::path& path);

/// Parses a YAML-style number ("1.5", "-2e3", ".01", "+4"; also ".inf", ".nan"); false when the
/// text is not entirely a number.
bool ParseYamlNumber(std::string_view text, double* value);

}  // namespace acro
