#pragma once

// Deterministic damaged copies of a file for the corpus replays of the fuzz entry points
// (tests/fuzz): what a fuzzer tries first, repeatable in the suite. Byte-level mutants for every
// format (truncations; bytes overwritten where the structure is), text-level ones for the text
// formats (each number made hostile, lines deleted or doubled, nesting without end).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace acro::testing {

struct Mutant {
  std::string what;  ///< how it was made, for the failure message
  std::vector<std::uint8_t> bytes;
};

inline std::vector<std::uint8_t> Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

/// Truncations at the header, inside and near the end; then `mutations` copies with four bytes
/// overwritten, every other one within the first `structure_bytes` (headers, parameters, indexes).
inline std::vector<Mutant> ByteMutants(const std::vector<std::uint8_t>& original,
                                       std::mt19937& rng,
                                       int mutations = 12,
                                       std::size_t structure_bytes = 4096) {
  std::vector<Mutant> out;
  for (double fraction : {0.0, 0.001, 0.01, 0.05, 0.2, 0.5, 0.9, 0.999}) {
    const auto n = static_cast<std::size_t>(fraction * static_cast<double>(original.size()));
    out.push_back({"truncated to " + std::to_string(n) + " bytes",
                   std::vector<std::uint8_t>(original.begin(), original.begin() + n)});
  }
  for (int trial = 0; trial < mutations && !original.empty(); ++trial) {
    std::vector<std::uint8_t> bytes = original;
    const std::size_t span = std::min(bytes.size(), trial % 2 ? structure_bytes : bytes.size());
    std::string what = "bytes changed at";
    for (int k = 0; k < 4; ++k) {
      const std::size_t at = rng() % span;
      // Mostly random bytes, sometimes the extremes that sizes and counts are made of.
      const std::uint32_t r = rng();
      bytes[at] = r % 4 == 0 ? 0xff : r % 4 == 1 ? 0x00 : static_cast<std::uint8_t>(r >> 8);
      what += " " + std::to_string(at);
    }
    out.push_back({what, std::move(bytes)});
  }
  return out;
}

/// Text mutants: up to `numbers` of the text's numbers (spread over it) each replaced by two
/// hostile values in turn (infinite, not a number, huge, zero, negative, beyond double); up to
/// `lines` lines deleted and doubled; the text behind 100 000 open brackets.
inline std::vector<Mutant> TextMutants(const std::string& text, int numbers = 40, int lines = 30) {
  static const char* const kHostile[] = {
      ".inf", ".nan", "-1e308", "1e308", "0", "-1", "nan", "1e999", "-.inf", "4294967296"};
  auto bytes = [](const std::string& s) { return std::vector<std::uint8_t>(s.begin(), s.end()); };
  std::vector<Mutant> out;
  const std::regex number(R"([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)");
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
       it != std::sregex_iterator();
       ++it)
    spans.emplace_back(static_cast<std::size_t>(it->position()),
                       static_cast<std::size_t>(it->length()));
  const std::size_t step_n = std::max<std::size_t>(1, spans.size() / std::max(1, numbers));
  int h = 0;
  for (std::size_t k = 0; k < spans.size(); k += step_n) {
    for (int twice = 0; twice < 2; ++twice, ++h) {
      const char* value = kHostile[h % std::size(kHostile)];
      std::string s = text;
      s.replace(spans[k].first, spans[k].second, value);
      out.push_back({"number " + std::to_string(k) + " made " + value, bytes(s)});
    }
  }
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n' && i + 1 < text.size()) starts.push_back(i + 1);
  const std::size_t step_l = std::max<std::size_t>(1, starts.size() / std::max(1, lines));
  for (std::size_t k = 0; k < starts.size(); k += step_l) {
    const std::size_t end = k + 1 < starts.size() ? starts[k + 1] : text.size();
    const std::string line = text.substr(starts[k], end - starts[k]);
    std::string deleted = text, doubled = text;
    deleted.erase(starts[k], end - starts[k]);
    doubled.insert(starts[k], line);
    out.push_back({"line " + std::to_string(k + 1) + " deleted", bytes(deleted)});
    out.push_back({"line " + std::to_string(k + 1) + " doubled", bytes(doubled)});
  }
  out.push_back({"behind 100000 brackets", bytes(std::string(100000, '[') + text)});
  return out;
}

/// Feeds every mutant to `feed(bytes)`: each may be accepted or rejected with acro::InputError
/// (which the fuzz entry points catch); any exception that escapes fails the test, naming the
/// mutant. Returns the number of inputs fed.
template <class Feed>
int ReplayMutants(const std::vector<Mutant>& mutants, Feed feed) {
  for (const Mutant& m : mutants) {
    try {
      feed(m.bytes);
    } catch (const std::exception& e) {
      ADD_FAILURE() << m.what << ": " << e.what();
    }
  }
  return static_cast<int>(mutants.size());
}

/// Messages one per indented line, for a failure's explanation.
inline std::string JoinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += "\n  " + l;
  return out;
}

/// The fenced code blocks of a Markdown file in language `lang` ("yaml"): the documentation's
/// examples, as seeds.
inline std::vector<std::string> FencedBlocks(const std::filesystem::path& markdown,
                                             const std::string& lang) {
  std::ifstream in(markdown);
  std::vector<std::string> blocks;
  std::string line, block;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line == "```" + lang) {
      inside = true;
      block.clear();
    } else if (inside && line.rfind("```", 0) == 0) {
      inside = false;
      blocks.push_back(block);
    } else if (inside) {
      block += line + "\n";
    }
  }
  return blocks;
}

}  // namespace acro::testing
