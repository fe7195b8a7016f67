#include "acro/base/yaml.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_set>

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>
#include <yaml-cpp/yaml.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/text.h"

namespace acro {

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
// The parser is yaml-cpp; this converts its tree into YamlNode, keeping each node's line
// (YAML::Mark is 0-based) and whether a scalar was quoted, and refuses what a settings file never
// needs: a second document, duplicate keys, non-scalar keys, nesting deeper than kMaxDepth, and
// more than kMaxNodes nodes (aliases can expand a small file into a huge tree).

namespace {

constexpr int kMaxDepth = 64;
constexpr std::size_t kMaxNodes = 2'000'000;

int LineOf(const YAML::Mark& mark) {
  return mark.is_null() ? 0 : mark.line + 1;
}

}  // namespace

class YamlParser {
 public:
  explicit YamlParser(std::string file) : file_(std::move(file)) {}

  YamlNode Convert(const YAML::Node& node, int line, const std::string& key, int depth) {
    if (depth > kMaxDepth)
      Fail(line, "nested deeper than " + std::to_string(kMaxDepth) + " levels");
    if (++count_ > kMaxNodes) {
      Fail(line, "more than " + std::to_string(kMaxNodes) + " values (aliases expanding?)");
    }
    YamlNode out;
    out.file_ = file_;
    out.key_ = key;
    out.line_ = line;
    switch (node.Type()) {
      case YAML::NodeType::Undefined:
      case YAML::NodeType::Null:
        out.kind_ = YamlNode::Kind::kNull;
        break;
      case YAML::NodeType::Scalar:
        out.kind_ = YamlNode::Kind::kScalar;
        out.text_ = node.Scalar();
        // yaml-cpp tags a quoted scalar "!" and a plain one "?".
        out.quoted_ = node.Tag() == "!";
        break;
      case YAML::NodeType::Sequence:
        out.kind_ = YamlNode::Kind::kSequence;
        out.items_.reserve(node.size());
        for (const YAML::Node& item : node) {
          const int item_line = item.Mark().is_null() ? line : LineOf(item.Mark());
          out.items_.push_back(Convert(item, item_line, "", depth + 1));
        }
        break;
      case YAML::NodeType::Map: {
        out.kind_ = YamlNode::Kind::kMap;
        std::unordered_set<std::string> seen;
        for (const auto& entry : node) {
          const int key_line = entry.first.Mark().is_null() ? line : LineOf(entry.first.Mark());
          if (!entry.first.IsScalar()) Fail(key_line, "a key must be a plain name");
          const std::string name = entry.first.Scalar();
          if (!seen.insert(name).second) Fail(key_line, "duplicate key '" + name + "'");
          out.entries_.emplace_back(name, Convert(entry.second, key_line, name, depth + 1));
        }
        break;
      }
    }
    return out;
  }

  [[noreturn]] void Fail(int line, const std::string& problem) const {
    throw InputError(file_, "line " + std::to_string(line), problem);
  }

 private:
  std::string file_;
  std::size_t count_ = 0;
};

// Where each document starts, nothing built. yaml-cpp 0.7 (Debian 12) makes no progress on a
// stray ',' at the start of a document and hands out empty documents for ever: its LoadAll loops
// until memory runs out (jbeder/yaml-cpp#1040, fixed upstream by #1319). Found by the YAML fuzzer.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> marks;
  void OnDocumentStart(const YAML::Mark& mark) override { marks.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&,
                const std::string&,
                YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&,
                       const std::string&,
                       YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&,
                  const std::string&,
                  YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

YamlNode ParseYaml(std::string_view text, const std::string& file_name) {
  // A UTF-8 byte-order mark (some Windows editors write one) is not content.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<YAML::Node> documents;
  try {
    // At most two documents are looked at: one is read, a second is refused.
    std::istringstream in{std::string(text)};
    YAML::Parser scan(in);
    DocumentStarts starts;
    while (starts.marks.size() < 2 && scan.HandleNextDocument(starts)) {
    }
    if (starts.marks.size() == 2) {
      const bool stuck = starts.marks[1].pos == starts.marks[0].pos;
      throw InputError(file_name,
                       "line " + std::to_string(LineOf(starts.marks[1])),
                       stuck ? "not YAML here (a stray ',' before any key?)"
                             : "a second document: one document per file");
    }
    if (!starts.marks.empty()) documents.push_back(YAML::Load(std::string(text)));
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp stops its recursive parser at its depth guard with the message "bad file".
    throw InputError(file_name,
                     "line " + std::to_string(LineOf(e.mark)),
                     "nested deeper than " + std::to_string(e.depth()) +
                         " levels (Acrolab's files need " + std::to_string(kMaxDepth) +
                         " at most)");
  } catch (const YAML::Exception& e) {
    // e.msg is yaml-cpp's problem without its own position prefix.
    throw InputError(file_name, "line " + std::to_string(LineOf(e.mark)), e.msg);
  }
  YamlParser parser(file_name);
  if (documents.empty()) return parser.Convert(YAML::Node(), 1, "", 0);
  const YAML::Node& root = documents[0];
  return parser.Convert(root, root.Mark().is_null() ? 1 : LineOf(root.Mark()), "", 0);
}

YamlNode ReadYamlFile(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(64) << 20);
  const std::string text(bytes.begin(), bytes.end());
  return ParseYaml(text, path.string());
}

}  // namespace acro
