// Replays the fuzz corpus through every reader: each reference C3D/TRC/MOT/STO file, its
// truncations and deterministic byte mutations. Each input is accepted or rejected with
// acro::InputError; any other outcome fails (a crash fails the whole test binary).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "../fuzz/fuzz_readers.h"
#include "mutants.h"
#include "refdata.h"

namespace acro::capture {
namespace {

std::vector<std::filesystem::path> CorpusFiles() {
  std::vector<std::filesystem::path> files;
  for (const char* folder :
       {"BTKData", "c3dio-c3d_org_samples", "opensim-models/Pipelines/Gait2354_Simbody"}) {
    const auto root = acro::testing::RefdataFile(folder);
    if (!std::filesystem::exists(root)) continue;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
      if (!entry.is_regular_file()) continue;
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
      if (ext == ".c3d" || ext == ".trc" || ext == ".mot" || ext == ".sto")
        files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ReaderCorpus, EveryReferenceFileAndMutationIsAcceptedOrRejectedCleanly) {
  const auto root = acro::testing::RefdataFile("c3dio-c3d_org_samples");
  ACRO_REQUIRE_REFDATA_FILE(root);
  const auto files = CorpusFiles();
  ASSERT_GE(files.size(), 80u) << "the reference corpus looks incomplete (87 files expected)";
  std::mt19937 rng(7);
  int inputs = 0, accepted_originals = 0;
  for (const auto& path : files) {
    SCOPED_TRACE(path.string());
    const std::vector<std::uint8_t> original = testing::Slurp(path);
    try {
      accepted_originals += fuzz::FeedReaders(original.data(), original.size()) > 0;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "original: " << e.what();
    }
    ++inputs;
    inputs += testing::ReplayMutants(testing::ByteMutants(original, rng), [](const auto& bytes) {
      fuzz::FeedReaders(bytes.data(), bytes.size());
    });
  }
  RecordProperty("inputs", inputs);
  // Nearly every reference file is readable by at least one reader (the broken ones are the
  // exception).
  EXPECT_GE(accepted_originals, static_cast<int>(files.size()) - 6);
}

}  // namespace
}  // namespace acro::capture
