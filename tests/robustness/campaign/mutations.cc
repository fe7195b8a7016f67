#include "mutations.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <functional>
#include <map>

#include <fmt/format.h>

namespace acro::campaign {

const char* DefectName(Defect d) {
  static constexpr std::array<const char*, kDefectCount> names = {"truncation",
                                                                  "bit flips",
                                                                  "counts",
                                                                  "non-finite",
                                                                  "absurd numbers",
                                                                  "units",
                                                                  "names",
                                                                  "encoding",
                                                                  "special files",
                                                                  "nesting",
                                                                  "huge lines",
                                                                  "options",
                                                                  "outputs",
                                                                  "signals",
                                                                  "full disk"};
  return names[static_cast<size_t>(d)];
}

namespace {

using Rng = std::mt19937_64;

struct Span {
  size_t pos = 0, len = 0;
};

bool WordChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Numbers as a reader sees them: a token of digits, '.', exponent and sign that is not the tail of
// a word ("X1", "K_a", "r11" are names, not numbers).
std::vector<Span> Numbers(const std::string& s) {
  std::vector<Span> out;
  size_t i = 0;
  while (i < s.size()) {
    const bool starts = std::isdigit(static_cast<unsigned char>(s[i])) ||
                        ((s[i] == '-' || s[i] == '+' || s[i] == '.') && i + 1 < s.size() &&
                         std::isdigit(static_cast<unsigned char>(s[i + 1])));
    if (!starts || (i > 0 && (WordChar(s[i - 1]) || s[i - 1] == '.'))) {
      ++i;
      continue;
    }
    // A number in a comment ('#' to the line's end, as YAML, TOML and job lists write them) is
    // text: a reader never sees it as a number.
    const size_t line_start = s.rfind('\n', i) == std::string::npos ? 0 : s.rfind('\n', i) + 1;
    if (s.find('#', line_start) < i) {
      const size_t end = s.find('\n', i);
      i = end == std::string::npos ? s.size() : end;
      continue;
    }
    size_t j = i + 1;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' ||
                            ((s[j] == 'e' || s[j] == 'E') && j + 1 < s.size()) ||
                            ((s[j] == '-' || s[j] == '+') && (s[j - 1] == 'e' || s[j - 1] == 'E'))))
      ++j;
    if (j < s.size() && WordChar(s[j])) {  // "1_partie", "2026x": part of a name
      while (j < s.size() && WordChar(s[j])) ++j;
    } else {
      out.push_back({i, j - i});
    }
    i = j;
  }
  return out;
}

// Identifiers: words that start with a letter (names, keys, labels).
std::vector<Span> Words(const std::string& s) {
  std::vector<Span> out;
  for (size_t i = 0; i < s.size();) {
    if (std::isalpha(static_cast<unsigned char>(s[i])) && (i == 0 || !WordChar(s[i - 1]))) {
      size_t j = i;
      while (j < s.size() && WordChar(s[j])) ++j;
      out.push_back({i, j - i});
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

std::vector<size_t> LineStarts(const std::string& s) {
  std::vector<size_t> out = {0};
  for (size_t i = 0; i + 1 < s.size(); ++i)
    if (s[i] == '\n') out.push_back(i + 1);
  return out;
}

template <class T>
const T& Pick(const std::vector<T>& v, Rng& rng) {
  return v[rng() % v.size()];
}

std::string Replace(const std::string& s, Span span, const std::string& with) {
  return s.substr(0, span.pos) + with + s.substr(span.pos + span.len);
}

bool IsText(Format f) {
  return f == Format::kText || f == Format::kXml || f == Format::kJson;
}

// ---- C3D structure (c3d.org's "C3D file format": a 512-byte header, parameter blocks, data).
struct C3dParameter {
  std::string group, name;
  size_t record = 0;  // first byte of the record
  size_t dims = 0;    // first dimension byte
  int ndims = 0;
  int type = 0;
  size_t data = 0;
};

std::vector<C3dParameter> C3dParameters(const std::string& b) {
  std::vector<C3dParameter> out;
  if (b.size() < 512 || b[1] != 0x50) return out;
  const size_t start = (static_cast<unsigned char>(b[0]) - 1) * 512;
  std::map<int, std::string> groups;
  size_t at = start + 4;
  for (int guard = 0; guard < 10000 && at + 2 < b.size(); ++guard) {
    const int nlen = std::abs(static_cast<signed char>(b[at]));
    const int gid = static_cast<signed char>(b[at + 1]);
    if (nlen == 0 || at + 2 + nlen + 2 > b.size()) break;
    const std::string name = b.substr(at + 2, nlen);
    const size_t next_field = at + 2 + nlen;
    const int next = static_cast<unsigned char>(b[next_field]) |
                     (static_cast<unsigned char>(b[next_field + 1]) << 8);
    if (gid < 0) {
      groups[-gid] = name;
    } else if (next_field + 4 < b.size()) {
      C3dParameter p;
      p.group = groups.count(gid) ? groups[gid] : "";
      p.name = name;
      p.record = at;
      p.type = static_cast<signed char>(b[next_field + 2]);
      p.ndims = static_cast<unsigned char>(b[next_field + 3]);
      p.dims = next_field + 4;
      p.data = p.dims + static_cast<size_t>(p.ndims);
      out.push_back(p);
    }
    if (next == 0) break;
    at = next_field + static_cast<size_t>(next);
  }
  // Groups named after their parameters (a group record can follow its parameters).
  for (C3dParameter& p : out)
    if (p.group.empty()) {
      const int gid = static_cast<signed char>(b[p.record + 1]);
      if (groups.count(gid)) p.group = groups[gid];
    }
  return out;
}

const C3dParameter* C3dFind(const std::vector<C3dParameter>& ps,
                            const char* group,
                            const char* name) {
  for (const C3dParameter& p : ps)
    if (p.group == group && p.name == name) return &p;
  return nullptr;
}

void Put16(std::string* b, size_t at, unsigned v) {
  if (at + 1 >= b->size()) return;
  (*b)[at] = static_cast<char>(v & 0xFF);
  (*b)[at + 1] = static_cast<char>((v >> 8) & 0xFF);
}

void PutFloat(std::string* b, size_t at, float v) {
  if (at + 3 >= b->size()) return;
  std::memcpy(&(*b)[at], &v, 4);
}

size_t C3dDataStart(const std::string& b) {
  if (b.size() < 20) return 512;
  const unsigned block =
      static_cast<unsigned char>(b[16]) | (static_cast<unsigned char>(b[17]) << 8);
  return std::max<size_t>(1, block) * 512 - 512;
}

// ---- MP4 boxes (ISO/IEC 14496-12): size (32-bit big-endian), type; containers nest.
struct Box {
  std::string type;
  size_t at = 0, size = 0;
};

void WalkBoxes(const std::string& b, size_t from, size_t to, int depth, std::vector<Box>* out) {
  static const char* containers[] = {"moov", "trak", "mdia", "minf", "stbl", "edts", "dinf"};
  size_t at = from;
  while (at + 8 <= to && out->size() < 1000) {
    const size_t size = (static_cast<size_t>(static_cast<unsigned char>(b[at])) << 24) |
                        (static_cast<size_t>(static_cast<unsigned char>(b[at + 1])) << 16) |
                        (static_cast<size_t>(static_cast<unsigned char>(b[at + 2])) << 8) |
                        static_cast<size_t>(static_cast<unsigned char>(b[at + 3]));
    if (size < 8 || at + size > to) break;
    Box box{b.substr(at + 4, 4), at, size};
    out->push_back(box);
    if (depth < 8)
      for (const char* c : containers)
        if (box.type == c) WalkBoxes(b, at + 8, at + size, depth + 1, out);
    at += size;
  }
}

void Put32Be(std::string* b, size_t at, std::uint32_t v) {
  if (at + 3 >= b->size()) return;
  for (int k = 0; k < 4; ++k) (*b)[at + k] = static_cast<char>((v >> (24 - 8 * k)) & 0xFF);
}

// ---- The classes.

std::optional<Mutation> Truncation(const std::string& s, Format f, int index, Rng& rng) {
  std::vector<size_t> cuts;
  std::string kind = "byte";
  if (IsText(f)) {
    if (index % 3 != 2) {
      cuts = LineStarts(s);
      kind = "line start";
    } else {
      for (const Span& n : Numbers(s)) cuts.push_back(n.pos + n.len / 2);
      kind = "inside a number";
    }
  } else if (f == Format::kC3d && index % 2 == 0) {
    for (size_t k = 512; k < s.size(); k += 512) cuts.push_back(k);
    for (const C3dParameter& p : C3dParameters(s)) cuts.push_back(p.data);
    kind = "block or parameter boundary";
  } else if (f == Format::kMp4 && index % 2 == 0) {
    std::vector<Box> boxes;
    WalkBoxes(s, 0, s.size(), 0, &boxes);
    for (const Box& x : boxes) {
      cuts.push_back(x.at);
      cuts.push_back(x.at + 8);
    }
    kind = "box boundary";
  } else if (f == Format::kSqlite && index % 2 == 0) {
    for (size_t k = 100; k < s.size(); k = (k < 4096 ? 4096 : k + 4096)) cuts.push_back(k);
    kind = "page boundary";
  }
  if (cuts.empty() || index % 5 == 4) {
    cuts = {rng() % std::max<size_t>(1, s.size())};
    kind = "byte";
  }
  size_t cut = Pick(cuts, rng);
  if (cut >= s.size()) cut = s.size() / 2;
  return Mutation{fmt::format("truncated at {} {} of {}", kind, cut, s.size()), s.substr(0, cut)};
}

std::optional<Mutation> BitFlips(const std::string& s, int index, Rng& rng) {
  if (s.empty()) return std::nullopt;
  std::string b = s;
  const int flips = 1 + index % 4;
  std::string where;
  for (int k = 0; k < flips; ++k) {
    const size_t at = rng() % b.size();
    const int bit = static_cast<int>(rng() % 8);
    b[at] = static_cast<char>(b[at] ^ (1 << bit));
    where += fmt::format("{}{}:{}", k ? "," : "", at, bit);
  }
  return Mutation{fmt::format("{} bit(s) flipped at {}", flips, where), b};
}

std::optional<Mutation> Counts(const std::string& s, Format f, int index, Rng& rng) {
  static const std::vector<unsigned> big16 = {0xFFFF, 0x7FFF, 0x8000, 0};
  if (f == Format::kC3d) {
    std::string b = s;
    const std::vector<C3dParameter> ps = C3dParameters(s);
    const unsigned v = big16[static_cast<size_t>(index) % big16.size()];
    const int target = static_cast<int>((index / 4) % 9);
    static const std::array<int, 5> words = {2, 3, 4, 5, 10};  // 1-based header words
    if (target < 5) {
      Put16(&b, static_cast<size_t>(words[target] - 1) * 2, v);
      return Mutation{
          fmt::format("header word {} = {}", words[target], v), b, Special::kNone, true};
    }
    static const std::array<std::pair<const char*, const char*>, 4> params = {
        {{"POINT", "USED"}, {"POINT", "FRAMES"}, {"ANALOG", "USED"}, {"POINT", "LABELS"}}};
    const auto [group, name] = params[static_cast<size_t>(target - 5)];
    const C3dParameter* p = C3dFind(ps, group, name);
    if (p == nullptr) return std::nullopt;
    if (p->ndims >= 2) {  // the LABELS table's count
      b[p->dims + 1] = static_cast<char>(0xFF);
    } else {
      Put16(&b, p->data, v);
    }
    return Mutation{
        fmt::format("{}:{} = {}", group, name, p->ndims >= 2 ? 255u : v), b, Special::kNone, true};
  }
  if (f == Format::kMp4) {
    std::vector<Box> boxes;
    WalkBoxes(s, 0, s.size(), 0, &boxes);
    std::vector<Box> tables;
    for (const Box& x : boxes)
      if (x.type == "stsz" || x.type == "stco" || x.type == "stts" || x.type == "stsc" ||
          x.type == "stss" || x.type == "co64" || x.type == "ctts")
        tables.push_back(x);
    if (tables.empty()) return std::nullopt;
    std::string b = s;
    const Box& t = Pick(tables, rng);
    static const std::array<std::uint32_t, 3> values = {0x7FFFFFFF, 0xFFFFFFFF, 0x10000000};
    const std::uint32_t v = values[static_cast<size_t>(index) % values.size()];
    // entry count after version/flags (stsz: after the sample size too)
    const size_t field = t.at + (t.type == "stsz" ? 16 : 12);
    if (index % 4 == 3) {
      Put32Be(&b, t.at, v);  // the box's own size
      return Mutation{fmt::format("{} box size = {}", t.type, v), b};
    }
    Put32Be(&b, field, v);
    return Mutation{fmt::format("{} entry count = {}", t.type, v), b};
  }
  if (f == Format::kSqlite) {
    if (s.size() < 100) return std::nullopt;
    std::string b = s;
    if (index % 2 == 0) {
      Put32Be(&b, 28, 0x7FFFFFFF);
      return Mutation{"header page count = 2147483647", b};
    }
    b[16] = 0;
    b[17] = 1;
    return Mutation{"header page size = 65536", b};
  }
  if (!IsText(f)) return std::nullopt;
  // A TRC header naming 100 000 markers over its rows (the issue's own case).
  if (s.rfind("PathFileType", 0) == 0 && index % 6 == 5) {
    std::vector<size_t> lines = LineStarts(s);
    if (lines.size() < 5) return std::nullopt;
    std::string line3 = s.substr(lines[2], lines[3] - lines[2]);
    std::vector<std::string> cells;
    size_t a = 0;
    for (size_t t; (t = line3.find('\t', a)) != std::string::npos; a = t + 1)
      cells.push_back(line3.substr(a, t - a));
    cells.push_back(line3.substr(a));
    if (cells.size() < 4) return std::nullopt;
    cells[3] = "100000";
    std::string head;
    for (size_t k = 0; k < cells.size(); ++k) head += (k ? "\t" : "") + cells[k];
    if (head.back() != '\n') head += "\n";
    std::string names = s.substr(lines[3], lines[4] - lines[3] - 1);
    for (int k = 0; k < 100000; ++k) names += fmt::format("\tM{}\t\t", k);
    return Mutation{"NumMarkers 100000 with 100000 names over the same rows",
                    s.substr(0, lines[2]) + head + names + "\n" + s.substr(lines[4]),
                    Special::kNone,
                    true};
  }
  std::vector<Span> ints;
  for (const Span& n : Numbers(s))
    if (s.substr(n.pos, n.len).find_first_of(".eE") == std::string::npos) ints.push_back(n);
  if (ints.empty()) return std::nullopt;
  static const std::vector<std::string> values = {
      "4294967295", "2147483647", "100000000000", "-1", "1000000000", "65536"};
  const Span n = Pick(ints, rng);
  const std::string& v = values[static_cast<size_t>(index) % values.size()];
  return Mutation{fmt::format("integer '{}' at byte {} = {}", s.substr(n.pos, n.len), n.pos, v),
                  Replace(s, n, v)};
}

std::optional<Mutation> Numeric(const std::string& s, Format f, Defect d, int index, Rng& rng) {
  static const std::vector<std::string> nonfinite = {
      "nan", "inf", "-inf", "1e999", "NaN", "-1e400", "Infinity"};
  static const std::vector<std::string> absurd = {
      "1e300", "-1e300", "1e30", "0", "-0", "1e-320", std::string(300, '9'), "-5", "4.9e-324"};
  if (f == Format::kC3d) {
    std::string b = s;
    const size_t data = C3dDataStart(s);
    if (index % 4 == 3) {  // the header's scale (words 7–8) or frame rate (words 11–12)
      const size_t at = (index % 8 == 3) ? 12 : 20;
      const float v = d == Defect::kNonFinite
                          ? (index % 2 ? std::numeric_limits<float>::infinity()
                                       : std::numeric_limits<float>::quiet_NaN())
                          : (index % 2 ? 1e30f : -1.0f);
      PutFloat(&b, at, v);
      return Mutation{fmt::format("header float at byte {} = {}", at, v), b};
    }
    // A coordinate (x, y or z of a point in a frame), not the residual word or an analog sample:
    // the header's counts give the float frame's layout.
    const size_t points =
        static_cast<unsigned char>(s[2]) | (static_cast<unsigned char>(s[3]) << 8);
    const size_t analog =
        static_cast<unsigned char>(s[4]) | (static_cast<unsigned char>(s[5]) << 8);
    const size_t frame_bytes = points * 16 + analog * 4;
    if (points == 0 || data + frame_bytes > s.size()) return std::nullopt;
    const size_t frames = (s.size() - data) / frame_bytes;
    const size_t at =
        data + (rng() % frames) * frame_bytes + (rng() % points) * 16 + 4 * (rng() % 3);
    const std::array<float, 3> bad =
        d == Defect::kNonFinite ? std::array<float, 3>{std::numeric_limits<float>::quiet_NaN(),
                                                       std::numeric_limits<float>::infinity(),
                                                       -std::numeric_limits<float>::infinity()}
                                : std::array<float, 3>{1e30f, -3e38f, 1e-40f};
    const float v = bad[static_cast<size_t>(index) % 3];
    PutFloat(&b, at, v);
    return Mutation{fmt::format("coordinate float at byte {} = {}", at, v), b};
  }
  if (!IsText(f)) return std::nullopt;
  const std::vector<Span> numbers = Numbers(s);
  if (numbers.empty()) return std::nullopt;
  const Span n = Pick(numbers, rng);
  const std::vector<std::string>& values = d == Defect::kNonFinite ? nonfinite : absurd;
  const std::string& v = values[static_cast<size_t>(index) % values.size()];
  return Mutation{
      fmt::format(
          "number '{}' at byte {} = {}",
          s.substr(n.pos, n.len),
          n.pos,
          v.size() > 20 ? v.substr(0, 8) + "… (" + std::to_string(v.size()) + " digits)" : v),
      Replace(s, n, v)};
}

std::optional<Mutation> Units(const std::string& s, Format f, int index, Rng& rng) {
  if (f == Format::kC3d) {
    const std::vector<C3dParameter> ps = C3dParameters(s);
    const C3dParameter* units = C3dFind(ps, "POINT", "UNITS");
    const C3dParameter* scale = C3dFind(ps, "POINT", "SCALE");
    std::string b = s;
    if (index % 2 == 0 && units != nullptr && units->data + 1 < b.size()) {
      static const std::array<const char*, 3> names = {"km", "in", "??"};
      const char* v = names[static_cast<size_t>(index / 2) % names.size()];
      b[units->data] = v[0];
      b[units->data + 1] = v[1];
      return Mutation{fmt::format("POINT:UNITS = '{}'", v), b};
    }
    if (scale == nullptr) return std::nullopt;
    float old = 0;
    std::memcpy(&old, &b[scale->data], 4);
    PutFloat(&b, scale->data, old * (index % 4 == 1 ? 1000.0f : 0.001f));
    return Mutation{"POINT:SCALE in another unit", b};
  }
  if (!IsText(f)) return std::nullopt;
  static const std::vector<std::pair<std::string, std::string>> words = {{"\tmm\t", "\tkm\t"},
                                                                         {"\tm\t", "\tin\t"},
                                                                         {"\tmm\t", "\tm\t"},
                                                                         {"\tm\t", "\tmm\t"},
                                                                         {"_m:", "_cm:"}};
  if (index % 3 == 2)
    for (const auto& [from, to] : words)
      if (size_t at = s.find(from); at != std::string::npos)
        return Mutation{fmt::format("unit '{}' written '{}'", from.substr(1, from.size() - 2), to),
                        s.substr(0, at) + to + s.substr(at + from.size())};
  const std::vector<Span> numbers = Numbers(s);
  if (numbers.empty()) return std::nullopt;
  const Span n = Pick(numbers, rng);
  const double v = std::strtod(s.substr(n.pos, n.len).c_str(), nullptr);
  const double scaled = index % 2 ? v * 1000.0 : v / 1000.0;
  return Mutation{
      fmt::format(
          "number '{}' at byte {} in another unit: {:g}", s.substr(n.pos, n.len), n.pos, scaled),
      Replace(s, n, fmt::format("{:g}", scaled))};
}

std::optional<Mutation> Names(const std::string& s, Format f, int index, Rng& rng) {
  if (f == Format::kC3d) {
    const C3dParameter* labels = nullptr;
    const std::vector<C3dParameter> ps = C3dParameters(s);
    labels = C3dFind(ps, "POINT", "LABELS");
    if (labels == nullptr || labels->ndims != 2) return std::nullopt;
    const size_t len = static_cast<unsigned char>(s[labels->dims]);
    const size_t count = static_cast<unsigned char>(s[labels->dims + 1]);
    if (count < 2 || labels->data + 2 * len > s.size()) return std::nullopt;
    std::string b = s;
    const size_t k = 1 + rng() % (count - 1);
    if (index % 2 == 0) {
      b.replace(labels->data + k * len, len, s.substr(labels->data, len));
      return Mutation{fmt::format("POINT:LABELS {} a copy of label 1", k + 1), b};
    }
    b.replace(labels->data + k * len, len, std::string(len, ' '));
    return Mutation{fmt::format("POINT:LABELS {} empty", k + 1), b};
  }
  if (!IsText(f)) return std::nullopt;
  const std::vector<Span> words = Words(s);
  const std::vector<size_t> lines = LineStarts(s);
  switch (index % 4) {
    case 0: {  // a line twice
      const size_t k = rng() % lines.size();
      const size_t end = k + 1 < lines.size() ? lines[k + 1] : s.size();
      const std::string line = s.substr(lines[k], end - lines[k]);
      return Mutation{fmt::format("line {} twice", k + 1),
                      s.substr(0, end) + line + (line.empty() || line.back() != '\n' ? "\n" : "") +
                          s.substr(end)};
    }
    case 1: {  // a name made another's
      if (words.size() < 2) return std::nullopt;
      const size_t k = 1 + rng() % (words.size() - 1);
      const Span w = words[k];
      const std::string other = s.substr(words[k - 1].pos, words[k - 1].len);
      return Mutation{
          fmt::format("name '{}' at byte {} = '{}'", s.substr(w.pos, w.len), w.pos, other),
          Replace(s, w, other)};
    }
    case 2: {  // a name emptied
      if (words.empty()) return std::nullopt;
      const Span w = Pick(words, rng);
      return Mutation{fmt::format("name '{}' at byte {} emptied", s.substr(w.pos, w.len), w.pos),
                      Replace(s, w, "")};
    }
    default: {  // a name of 10 KB
      if (words.empty()) return std::nullopt;
      const Span w = Pick(words, rng);
      return Mutation{fmt::format("name '{}' at byte {} made 10 KB", s.substr(w.pos, w.len), w.pos),
                      Replace(s, w, s.substr(w.pos, w.len) + std::string(10240, 'N'))};
    }
  }
}

std::optional<Mutation> Encoding(const std::string& s, Format f, int index, Rng& rng) {
  static const std::string escape = "\x1b[31m\x1b]0;title\x07";
  if (f == Format::kC3d) {
    const std::vector<C3dParameter> ps = C3dParameters(s);
    const C3dParameter* labels = C3dFind(ps, "POINT", "LABELS");
    if (labels == nullptr || labels->ndims != 2) return std::nullopt;
    std::string b = s;
    static const std::array<std::string, 3> inserts = {
        escape.substr(0, 5), "\xe9\xe9", std::string("A\0B", 3)};
    const std::string& v = inserts[static_cast<size_t>(index) % inserts.size()];
    b.replace(labels->data, v.size(), v);
    return Mutation{fmt::format("label 1 starts with bytes {}",
                                index % 3 == 0   ? "ESC[31m"
                                : index % 3 == 1 ? "E9 E9"
                                                 : "A NUL B"),
                    b};
  }
  if (!IsText(f) || s.empty()) return std::nullopt;
  const std::vector<Span> words = Words(s);
  const size_t in_word = words.empty() ? s.size() / 2 : Pick(words, rng).pos + 1;
  switch (index % 8) {
    case 0: {
      std::string u = "\xff\xfe";
      for (char c : s) {
        u += c;
        u += '\0';
      }
      return Mutation{"UTF-16LE with a byte-order mark", u};
    }
    case 1:
      return Mutation{"a UTF-8 byte-order mark", "\xef\xbb\xbf" + s};
    case 2:
      return Mutation{fmt::format("Latin-1 byte E9 at byte {}", in_word),
                      s.substr(0, in_word) + "\xe9" + s.substr(in_word)};
    case 3: {
      const size_t at = rng() % s.size();
      return Mutation{fmt::format("a NUL byte at byte {}", at),
                      s.substr(0, at) + std::string(1, '\0') + s.substr(at)};
    }
    case 4:
      return Mutation{fmt::format("terminal escapes at byte {}", in_word),
                      s.substr(0, in_word) + escape + s.substr(in_word)};
    case 5:
      return Mutation{fmt::format("invalid UTF-8 (C3 28) at byte {}", in_word),
                      s.substr(0, in_word) + "\xc3\x28" + s.substr(in_word)};
    case 6: {
      std::string cr = s;
      std::replace(cr.begin(), cr.end(), '\n', '\r');
      return Mutation{"CR line ends (classic Mac)", cr};
    }
    default:
      return Mutation{fmt::format("DEL and backspace at byte {}", in_word),
                      s.substr(0, in_word) + "\x7f\x08\x08" + s.substr(in_word)};
  }
}

std::optional<Mutation> Nesting(const std::string& s, Format f, int index, Rng& rng) {
  constexpr int kDepth = 100000;
  if (f == Format::kXml) {
    std::string open;
    for (int k = 0; k < kDepth; ++k) open += "<a>";
    const size_t at =
        s.find('>', s.find("<", s.find("?>") == std::string::npos ? 0 : s.find("?>") + 2));
    const size_t pos = at == std::string::npos ? s.size() : at + 1;
    return Mutation{fmt::format("{} elements deep at byte {}", kDepth, pos),
                    s.substr(0, pos) + open + s.substr(pos)};
  }
  if (!IsText(f)) return std::nullopt;
  const std::vector<Span> numbers = Numbers(s);
  const size_t at = numbers.empty() ? s.size() : Pick(numbers, rng).pos;
  static const std::array<const char*, 3> brackets = {"[", "{", "[{"};
  const std::string b = brackets[static_cast<size_t>(index) % brackets.size()];
  std::string deep;
  deep.reserve(kDepth * b.size());
  for (int k = 0; k < kDepth; ++k) deep += b;
  return Mutation{fmt::format("{} × '{}' at byte {}", kDepth, b, at),
                  s.substr(0, at) + deep + s.substr(at)};
}

std::optional<Mutation> HugeLine(const std::string& s, Format f, int index, Rng& rng, size_t huge) {
  if (!IsText(f)) {
    return Mutation{
        fmt::format("{} MB of {} appended", huge >> 20, index % 2 ? "FF" : "zero bytes"),
        s + std::string(huge, index % 2 ? '\xff' : '\0')};
  }
  const std::vector<size_t> lines = LineStarts(s);
  const size_t line = lines[rng() % lines.size()];
  switch (index % 4) {
    case 0:
      return Mutation{fmt::format("a {} MB comment line at byte {}", huge >> 20, line),
                      s.substr(0, line) + "#" + std::string(huge, 'x') + "\n" + s.substr(line)};
    case 1: {
      const std::vector<Span> numbers = Numbers(s);
      if (numbers.empty()) return std::nullopt;
      const Span n = Pick(numbers, rng);
      return Mutation{fmt::format("a number of {} MB of digits at byte {}", huge >> 20, n.pos),
                      Replace(s, n, std::string(huge, '7'))};
    }
    case 2: {
      const std::vector<Span> words = Words(s);
      if (words.empty()) return std::nullopt;
      const Span w = Pick(words, rng);
      return Mutation{fmt::format("a name of {} MB at byte {}", huge >> 20, w.pos),
                      Replace(s, w, std::string(huge, 'n'))};
    }
    default:
      return Mutation{fmt::format("{} MB with no line end appended", huge >> 20),
                      s + std::string(huge, 'z')};
  }
}

}  // namespace

std::optional<Mutation> Mutate(const std::string& seed,
                               Format format,
                               Defect defect,
                               int index,
                               std::uint64_t salt,
                               size_t huge_bytes) {
  Rng rng(salt * 1000003u + static_cast<std::uint64_t>(defect) * 7919u +
          static_cast<std::uint64_t>(index));
  switch (defect) {
    case Defect::kTruncation:
      return Truncation(seed, format, index, rng);
    case Defect::kBitFlip:
      return BitFlips(seed, index, rng);
    case Defect::kCounts:
      return Counts(seed, format, index, rng);
    case Defect::kNonFinite:
    case Defect::kAbsurd:
      return Numeric(seed, format, defect, index, rng);
    case Defect::kUnits:
      return Units(seed, format, index, rng);
    case Defect::kNames:
      return Names(seed, format, index, rng);
    case Defect::kEncoding:
      return Encoding(seed, format, index, rng);
    case Defect::kSpecial: {
      static const std::array<std::pair<Special, const char*>, 7> kinds = {
          {{Special::kDirectory, "a directory"},
           {Special::kFifo, "a FIFO nobody writes"},
           {Special::kLinkLoop, "a link loop"},
           {Special::kDanglingLink, "a dangling link"},
           {Special::kEmpty, "an empty file"},
           {Special::kZeroDevice, "the zero device"},
           {Special::kOneByte, "one byte"}}};
      if (index >= static_cast<int>(kinds.size())) return std::nullopt;
      const auto& [kind, what] = kinds[static_cast<size_t>(index)];
      return Mutation{what, kind == Special::kOneByte ? seed.substr(0, 1) : std::string(), kind};
    }
    case Defect::kNesting:
      return Nesting(seed, format, index, rng);
    case Defect::kHugeLine:
      return HugeLine(seed, format, index, rng, huge_bytes);
    default:
      return std::nullopt;
  }
}

}  // namespace acro::campaign
