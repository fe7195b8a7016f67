#include "acro/analysis/yaml.h"

#include <charconv>
#include <cmath>
#include <limits>

#include "acro/base/input_error.h"
#include "acro/capture/file_io.h"

namespace acro::analysis {

// ---------------------------------------------------------------------------------------------
// Node accessors.

const YamlNode* YamlNode::Find(std::string_view key) const {
  for (const auto& [k, v] : entries_)
    if (k == key) return &v;
  return nullptr;
}

const YamlNode& YamlNode::At(std::string_view key) const {
  if (kind_ != Kind::kMap) Fail("expected a map with the key '" + std::string(key) + "'");
  const YamlNode* node = Find(key);
  if (node == nullptr) Fail("the required key '" + std::string(key) + "' is missing");
  return *node;
}

void YamlNode::Fail(const std::string& problem) const {
  throw InputError(file_, Where(), key_.empty() ? problem : key_ + ": " + problem);
}

namespace {

const char* KindName(YamlNode::Kind kind) {
  switch (kind) {
    case YamlNode::Kind::kNull:
      return "nothing";
    case YamlNode::Kind::kScalar:
      return "a scalar";
    case YamlNode::Kind::kSequence:
      return "a sequence";
    case YamlNode::Kind::kMap:
      return "a map";
  }
  return "?";
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>((c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c);
  return out;
}

}  // namespace

std::string YamlNode::AsString() const {
  if (kind_ != Kind::kScalar) Fail(std::string("expected a text value, found ") + KindName(kind_));
  return text_;
}

double YamlNode::AsDouble() const {
  if (kind_ == Kind::kNull) Fail("has no value (expected a number)");
  if (kind_ != Kind::kScalar) Fail(std::string("expected a number, found ") + KindName(kind_));
  double value = 0.0;
  if (quoted_ || !ParseYamlNumber(text_, &value)) Fail("'" + text_ + "' is not a number");
  return value;
}

int YamlNode::AsInt() const {
  const double value = AsDouble();
  if (!(std::abs(value) <= std::numeric_limits<int>::max()) || std::floor(value) != value)
    Fail("'" + text_ + "' is not an integer");
  return static_cast<int>(value);
}

bool YamlNode::AsBool() const {
  if (kind_ != Kind::kScalar || quoted_) Fail("expected true or false");
  const std::string lower = Lower(text_);
  if (lower == "true") return true;
  if (lower == "false") return false;
  Fail("'" + text_ + "' is not true or false");
}

std::vector<double> YamlNode::AsDoubleList() const {
  if (kind_ != Kind::kSequence)
    Fail(std::string("expected a list of numbers, found ") + KindName(kind_));
  std::vector<double> out;
  out.reserve(items_.size());
  for (const YamlNode& item : items_) out.push_back(item.AsDouble());
  return out;
}

std::vector<std::string> YamlNode::AsStringList() const {
  if (kind_ != Kind::kSequence) Fail(std::string("expected a list, found ") + KindName(kind_));
  std::vector<std::string> out;
  out.reserve(items_.size());
  for (const YamlNode& item : items_) out.push_back(item.AsString());
  return out;
}

void YamlNode::RequireKnownKeys(const std::vector<std::string_view>& allowed) const {
  for (const auto& [k, v] : entries_) {
    bool known = false;
    for (std::string_view a : allowed) known = known || (a == k);
    if (!known) {
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      throw InputError(file_, v.Where(), "unknown key '" + k + "' (expected one of: " + list + ")");
    }
  }
}

bool ParseYamlNumber(std::string_view text, double* value) {
  text = Trim(text);
  if (text.empty()) return false;
  const std::string lower = Lower(text);
  if (lower == ".inf" || lower == "+.inf") {
    *value = std::numeric_limits<double>::infinity();
    return true;
  }
  if (lower == "-.inf") {
    *value = -std::numeric_limits<double>::infinity();
    return true;
  }
  if (lower == ".nan") {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (text.front() == '+') {
    text.remove_prefix(1);
    if (text.empty() || text.front() == '-' || text.front() == '+') return false;
  }
  const bool negative = text.front() == '-';
  if (negative && text.size() < 2) return false;
  // from_chars accepts "inf"/"nan" spellings that YAML does not: require a digit or a dot first.
  const char first = negative ? text[1] : text.front();
  if (!((first >= '0' && first <= '9') || first == '.')) return false;
  double parsed = 0.0;
  const auto result =
      std::from_chars(text.data(), text.data() + text.size(), parsed, std::chars_format::general);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return false;
  *value = parsed;
  return true;
}

// ---------------------------------------------------------------------------------------------
// The parser: lines are split, comments stripped and indentation measured first; then a
// recursive descent over lines builds the tree (a block's extent is given by its indentation).

class YamlParser {
 public:
  YamlParser(std::string_view text, std::string file) : file_(std::move(file)) { Split(text); }

  YamlNode ParseDocument() {
    if (lines_.empty()) {
      YamlNode null_node;
      null_node.file_ = file_;
      null_node.line_ = 1;
      return null_node;
    }
    YamlNode root = ParseBlock(lines_[0].indent);
    if (next_ < lines_.size()) {
      Fail(lines_[next_].number,
           lines_[next_].indent == lines_[0].indent ? "unexpected content after a top-level value"
                                                    : "unexpected indentation");
    }
    return root;
  }

 private:
  struct Line {
    int number = 0;
    int indent = 0;
    std::string content;
  };

  [[noreturn]] void Fail(int line, const std::string& problem) const {
    throw InputError(file_, "line " + std::to_string(line), problem);
  }

  // Splits into significant lines: comments and trailing blanks removed, blank lines skipped,
  // document markers handled, tabs in indentation refused.
  void Split(std::string_view text) {
    int number = 0;
    bool seen_content = false;
    size_t start = 0;
    while (start <= text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      std::string_view raw = text.substr(start, end - start);
      ++number;
      start = end + 1;
      if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
      // Indentation (spaces only).
      size_t indent = 0;
      while (indent < raw.size() && (raw[indent] == ' ' || raw[indent] == '\t')) {
        if (raw[indent] == '\t') {
          const std::string_view rest = Trim(raw);
          if (!rest.empty() && rest.front() != '#') Fail(number, "tab character in indentation");
          break;
        }
        ++indent;
      }
      const std::string content(Trim(StripComment(raw.substr(indent))));
      if (content.empty()) {
        if (end == text.size()) break;
        continue;
      }
      if (indent == 0 && (content == "---" || content.rfind("--- ", 0) == 0)) {
        if (seen_content) Fail(number, "a second document ('---') is not supported");
        if (content != "---") Fail(number, "content after '---' is not supported");
        continue;
      }
      if (indent == 0 && content == "...") break;
      seen_content = true;
      lines_.push_back({number, static_cast<int>(indent), content});
      if (end == text.size()) break;
    }
  }

  // Removes a comment: '#' at the start or after a blank, outside quotes.
  static std::string_view StripComment(std::string_view s) {
    char quote = 0;
    for (size_t i = 0; i < s.size(); ++i) {
      const char c = s[i];
      if (quote == '"') {
        if (c == '\\') {
          ++i;
        } else if (c == '"') {
          quote = 0;
        }
      } else if (quote == '\'') {
        if (c == '\'') {
          if (i + 1 < s.size() && s[i + 1] == '\'') {
            ++i;
          } else {
            quote = 0;
          }
        }
      } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
        return s.substr(0, i);
      } else if ((c == '"' || c == '\'') && StartsScalar(s, i)) {
        quote = c;
      }
    }
    return s;
  }

  // A quote opens a quoted scalar only where a scalar may start (after "- ", ": ", '[', ',').
  static bool StartsScalar(std::string_view s, size_t i) {
    size_t j = i;
    while (j > 0 && (s[j - 1] == ' ' || s[j - 1] == '\t')) --j;
    if (j == 0) return true;
    const char before = s[j - 1];
    return before == '-' || before == ':' || before == '[' || before == ',';
  }

  static bool IsSequenceItem(std::string_view content) {
    return content == "-" || content.rfind("- ", 0) == 0;
  }

  // Position of the ':' that ends a map key on this line, or npos.
  static size_t FindMapColon(std::string_view content) {
    if (content.empty() || content.front() == '[' || content.front() == '{')
      return std::string_view::npos;
    size_t i = 0;
    if (content.front() == '"' || content.front() == '\'') {
      const char q = content.front();
      for (i = 1; i < content.size(); ++i) {
        if (q == '"' && content[i] == '\\') {
          ++i;
          continue;
        }
        if (content[i] == q) {
          if (q == '\'' && i + 1 < content.size() && content[i + 1] == '\'') {
            ++i;
            continue;
          }
          break;
        }
      }
      if (i >= content.size()) return std::string_view::npos;
      ++i;
      while (i < content.size() && content[i] == ' ') ++i;
      if (i < content.size() && content[i] == ':' &&
          (i + 1 == content.size() || content[i + 1] == ' '))
        return i;
      return std::string_view::npos;
    }
    for (i = 0; i < content.size(); ++i) {
      if (content[i] == ':' && (i + 1 == content.size() || content[i + 1] == ' ')) return i;
    }
    return std::string_view::npos;
  }

  YamlNode MakeNode(YamlNode::Kind kind, int line) const {
    YamlNode node;
    node.kind_ = kind;
    node.file_ = file_;
    node.line_ = line;
    return node;
  }

  YamlNode ParseBlock(int indent) {
    const Line& line = lines_[next_];
    if (IsSequenceItem(line.content)) return ParseSequence(indent);
    if (FindMapColon(line.content) != std::string_view::npos) return ParseMap(indent);
    const int number = line.number;
    YamlNode node = ParseInline(line.content, number);
    ++next_;
    if (next_ < lines_.size() && lines_[next_].indent > indent)
      Fail(lines_[next_].number, "unexpected indentation (multi-line scalars are not supported)");
    return node;
  }

  YamlNode ParseMap(int indent) {
    YamlNode map = MakeNode(YamlNode::Kind::kMap, lines_[next_].number);
    while (next_ < lines_.size() && lines_[next_].indent == indent) {
      const Line line = lines_[next_];
      if (IsSequenceItem(line.content))
        Fail(line.number, "a list item where a 'key: value' was expected");
      const size_t colon = FindMapColon(line.content);
      if (colon == std::string_view::npos)
        Fail(line.number, "expected 'key: value', found '" + line.content + "'");
      const std::string key =
          ParseKey(std::string_view(line.content).substr(0, colon), line.number);
      if (map.Find(key) != nullptr) Fail(line.number, "duplicate key '" + key + "'");
      const std::string_view rest = Trim(std::string_view(line.content).substr(colon + 1));
      ++next_;
      YamlNode value;
      if (rest.empty()) {
        if (next_ < lines_.size() && lines_[next_].indent > indent) {
          value = ParseBlock(lines_[next_].indent);
        } else if (next_ < lines_.size() && lines_[next_].indent == indent &&
                   IsSequenceItem(lines_[next_].content)) {
          value = ParseSequence(indent);  // "key:\n- a\n- b" at the key's own indentation
        } else {
          value = MakeNode(YamlNode::Kind::kNull, line.number);
        }
      } else {
        value = ParseInline(rest, line.number);
      }
      if (next_ < lines_.size() && lines_[next_].indent > indent)
        Fail(lines_[next_].number, "unexpected indentation");
      value.line_ = value.kind_ == YamlNode::Kind::kMap || value.kind_ == YamlNode::Kind::kSequence
                        ? value.line_
                        : line.number;
      value.key_ = key;
      map.entries_.emplace_back(key, std::move(value));
    }
    return map;
  }

  YamlNode ParseSequence(int indent) {
    YamlNode seq = MakeNode(YamlNode::Kind::kSequence, lines_[next_].number);
    while (next_ < lines_.size() && lines_[next_].indent == indent &&
           IsSequenceItem(lines_[next_].content)) {
      Line& line = lines_[next_];
      const std::string_view after = std::string_view(line.content).substr(1);
      const std::string_view rest = Trim(after);
      YamlNode item;
      if (rest.empty()) {
        const int number = line.number;
        ++next_;
        if (next_ < lines_.size() && lines_[next_].indent > indent) {
          item = ParseBlock(lines_[next_].indent);
        } else {
          item = MakeNode(YamlNode::Kind::kNull, number);
        }
      } else if (IsSequenceItem(rest) || FindMapColon(rest) != std::string_view::npos) {
        // A nested block starts on the item's own line: re-read the line from the content.
        const int offset = static_cast<int>(line.content.size() - rest.size());
        line.indent += offset;
        line.content = std::string(rest);
        item = ParseBlock(line.indent);
      } else {
        item = ParseInline(rest, line.number);
        ++next_;
        if (next_ < lines_.size() && lines_[next_].indent > indent)
          Fail(lines_[next_].number, "unexpected indentation");
      }
      seq.items_.push_back(std::move(item));
    }
    if (next_ < lines_.size() && lines_[next_].indent == indent &&
        FindMapColon(lines_[next_].content) != std::string_view::npos)
      Fail(lines_[next_].number, "a 'key: value' where a list item was expected");
    return seq;
  }

  std::string ParseKey(std::string_view raw, int number) const {
    raw = Trim(raw);
    if (raw.empty()) Fail(number, "empty key");
    if (raw.front() == '"' || raw.front() == '\'') {
      size_t pos = 0;
      std::string key = ParseQuoted(raw, &pos, number);
      if (!Trim(raw.substr(pos)).empty()) Fail(number, "text after a quoted key");
      return key;
    }
    if (raw.front() == '?' || raw.front() == '&' || raw.front() == '*' || raw.front() == '!')
      Fail(number, "complex keys, anchors, aliases and tags are not supported");
    return std::string(raw);
  }

  // A value written on the key's or the dash's line.
  YamlNode ParseInline(std::string_view text, int number) const {
    text = Trim(text);
    const char c = text.front();
    if (c == '[') {
      size_t pos = 0;
      YamlNode node = ParseFlowSequence(text, &pos, number);
      if (!Trim(text.substr(pos)).empty()) Fail(number, "text after the closing ']'");
      return node;
    }
    if (c == '{')
      Fail(number, "flow maps ('{...}') are not supported; write one 'key: value' per line");
    if (c == '&' || c == '*' || c == '!')
      Fail(number, "anchors, aliases and tags are not supported");
    if (c == '|' || c == '>') Fail(number, "block scalars ('|', '>') are not supported");
    if (c == '"' || c == '\'') {
      size_t pos = 0;
      YamlNode node = MakeNode(YamlNode::Kind::kScalar, number);
      node.text_ = ParseQuoted(text, &pos, number);
      node.quoted_ = true;
      if (!Trim(text.substr(pos)).empty()) Fail(number, "text after a quoted value");
      return node;
    }
    return PlainScalar(text, number);
  }

  YamlNode PlainScalar(std::string_view text, int number) const {
    text = Trim(text);
    if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL")
      return MakeNode(YamlNode::Kind::kNull, number);
    YamlNode node = MakeNode(YamlNode::Kind::kScalar, number);
    node.text_ = std::string(text);
    return node;
  }

  // "[a, 'b', [1, 2]]" starting at text[*pos] == '['; leaves *pos after the ']'.
  YamlNode ParseFlowSequence(std::string_view text, size_t* pos, int number) const {
    YamlNode seq = MakeNode(YamlNode::Kind::kSequence, number);
    size_t i = *pos + 1;
    auto skip = [&] {
      while (i < text.size() && text[i] == ' ') ++i;
    };
    skip();
    if (i < text.size() && text[i] == ']') {
      *pos = i + 1;
      return seq;
    }
    while (true) {
      skip();
      if (i >= text.size()) break;
      if (text[i] == '[') {
        seq.items_.push_back(ParseFlowSequence(text, &i, number));
      } else if (text[i] == '"' || text[i] == '\'') {
        YamlNode item = MakeNode(YamlNode::Kind::kScalar, number);
        std::string_view rest = text.substr(i);
        size_t used = 0;
        item.text_ = ParseQuoted(rest, &used, number);
        item.quoted_ = true;
        i += used;
        seq.items_.push_back(std::move(item));
      } else if (text[i] == '{') {
        Fail(number, "flow maps ('{...}') are not supported");
      } else {
        size_t end = i;
        while (end < text.size() && text[end] != ',' && text[end] != ']' && text[end] != '[') ++end;
        if (end < text.size() && text[end] == '[')
          Fail(number, "unexpected '[' in a flow sequence");
        const std::string_view item = Trim(text.substr(i, end - i));
        if (item.empty()) Fail(number, "empty item in a flow sequence");
        seq.items_.push_back(PlainScalar(item, number));
        i = end;
      }
      skip();
      if (i >= text.size()) break;
      if (text[i] == ']') {
        *pos = i + 1;
        return seq;
      }
      if (text[i] != ',') Fail(number, "expected ',' or ']' in a flow sequence");
      ++i;
    }
    Fail(number, "unterminated flow sequence (a '[...]' must close on its own line)");
  }

  // A quoted scalar starting at text[0]; *pos receives the index after the closing quote.
  std::string ParseQuoted(std::string_view text, size_t* pos, int number) const {
    const char q = text.front();
    std::string out;
    for (size_t i = 1; i < text.size(); ++i) {
      const char c = text[i];
      if (q == '\'' && c == '\'') {
        if (i + 1 < text.size() && text[i + 1] == '\'') {
          out += '\'';
          ++i;
          continue;
        }
        *pos = i + 1;
        return out;
      }
      if (q == '"' && c == '"') {
        *pos = i + 1;
        return out;
      }
      if (q == '"' && c == '\\') {
        if (i + 1 >= text.size()) break;
        const char e = text[++i];
        switch (e) {
          case 'n':
            out += '\n';
            break;
          case 't':
            out += '\t';
            break;
          case 'r':
            out += '\r';
            break;
          case '0':
            out += '\0';
            break;
          case '"':
          case '\\':
          case '/':
          case ' ':
            out += e;
            break;
          default:
            Fail(number, std::string("unsupported escape '\\") + e + "' in a quoted string");
        }
        continue;
      }
      out += c;
    }
    Fail(number, "unterminated quoted string");
  }

  std::string file_;
  std::vector<Line> lines_;
  size_t next_ = 0;
};

YamlNode ParseYaml(std::string_view text, const std::string& file_name) {
  // A UTF-8 byte-order mark (some Windows editors write one) is not content.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return YamlParser(text, file_name).ParseDocument();
}

YamlNode ReadYamlFile(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = capture::ReadFileBytes(path, std::int64_t(64) << 20);
  const std::string text(bytes.begin(), bytes.end());
  return ParseYaml(text, path.string());
}

}  // namespace acro::analysis
