// Replays the YAML fuzz entry point (tests/fuzz/fuzz_yaml.h) over the samples' YAML files and the
// documentation's YAML examples, and their damaged copies: truncations, overwritten bytes, each
// number made hostile (.inf, .nan, ±1e308, 0, −1, 1e999), lines deleted or doubled, nesting without
// end. Every input is accepted or rejected with acro::InputError; anything else fails (a crash
// fails the whole test binary). The originals must be accepted by their own reader.
#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../../fuzz/fuzz_yaml.h"
#include "mutants.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

namespace fs = std::filesystem;

struct Seed {
  std::string name;
  std::vector<std::uint8_t> bytes;
  bool example = false;  ///< from the documentation
};

std::vector<Seed> Seeds() {
  const fs::path source = acro::testing::SourceDir();
  std::vector<Seed> seeds;
  for (const char* folder : {"samples/athletes", "samples/skills"})
    for (const fs::directory_entry& e : fs::directory_iterator(source / folder))
      if (e.path().extension() == ".yaml")
        seeds.push_back({e.path().filename().string(), acro::testing::Slurp(e.path()), false});
  for (const fs::directory_entry& e : fs::directory_iterator(source / "docs/formats")) {
    int k = 0;
    for (const std::string& block : acro::testing::FencedBlocks(e.path(), "yaml"))
      seeds.push_back({e.path().filename().string() + " example " + std::to_string(++k),
                       std::vector<std::uint8_t>(block.begin(), block.end()),
                       true});
  }
  std::sort(
      seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) { return a.name < b.name; });
  return seeds;
}

TEST(YamlCorpus, EverySampleExampleAndMutationIsAcceptedOrRejectedCleanly) {
  // Skills name their athlete relative to their folder: samples/skills.
  const fs::path base_dir = acro::testing::SourceDir() / "samples/skills";
  const std::vector<Seed> seeds = Seeds();
  // 2 athletes, 6 skills, the examples of athlete.md, markerset.md, routine.md and skill.md.
  ASSERT_GE(seeds.size(), 12u);
  std::mt19937 rng(11);
  int inputs = 0;
  for (const Seed& seed : seeds) {
    SCOPED_TRACE(seed.name);
    // The parse and the file's own reader accept every sample; the documentation's examples
    // parse (some name files of their own: a measurements file, a mirror marker left out).
    std::vector<std::string> errors;
    const int accepted =
        fuzz::FeedYamlReaders(seed.bytes.data(), seed.bytes.size(), base_dir, &errors);
    EXPECT_GE(accepted, seed.example ? 1 : 2) << acro::testing::JoinLines(errors);
    ++inputs;
    std::vector<acro::testing::Mutant> mutants = acro::testing::ByteMutants(seed.bytes, rng);
    for (acro::testing::Mutant& m :
         acro::testing::TextMutants(std::string(seed.bytes.begin(), seed.bytes.end())))
      mutants.push_back(std::move(m));
    inputs += acro::testing::ReplayMutants(mutants, [&](const auto& bytes) {
      fuzz::FeedYamlReaders(bytes.data(), bytes.size(), base_dir);
    });
  }
  RecordProperty("inputs", inputs);
  std::printf("%d YAML inputs replayed\n", inputs);
}

// Found by the fuzzer: a measurements file name longer than the system allows made
// std::filesystem throw its own error out of the profile reader.
TEST(YamlCorpus, AFileNameTooLongIsOneLine) {
  const std::string text =
      "name: x\nsex: m\nheight_m: 1.75\nmass_kg: 65\nyeadon:\n  measurements: " +
      std::string(5000, 'a') + "\n";
  std::vector<std::string> errors;
  fuzz::FeedYamlReaders(reinterpret_cast<const std::uint8_t*>(text.data()),
                        text.size(),
                        acro::testing::SourceDir(),
                        &errors);
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find("line 6: measurements: no such file"), std::string::npos) << errors[0];
}

}  // namespace
}  // namespace acro::analysis
