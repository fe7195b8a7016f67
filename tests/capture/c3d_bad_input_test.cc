// Bad input: every file of the suites either loads or throws acro::InputError whose one-line
// message names the file; truncations at every length and bit flips of good files never crash,
// hang or throw anything else, and never make the reader hold more than the file justifies.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> Bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Reads `bytes`; returns "ok", or the InputError message. Any other exception fails the test.
std::string TryRead(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  try {
    const Trial t = ReadC3dFromMemory(bytes, name);
    // What was allocated is backed by the file: samples × 4 words of at least 2 bytes each.
    const std::int64_t held = t.positions.cols() * 8 + t.analog.size() * 2;
    EXPECT_LE(held, static_cast<std::int64_t>(bytes.size())) << name;
    return "ok";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(name), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    return what;
  }
}

TEST(C3dBadInput, EverySuiteFileLoadsOrFailsNamingIt) {
  int files = 0, failed = 0;
  for (const char* suite : {"c3dio-c3d_org_samples", "BTKData"}) {
    const fs::path dir = acro::testing::RefdataDir() / suite;
    ACRO_REQUIRE_REFDATA_FILE(dir);
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      std::string ext = entry.path().extension().string();
      std::transform(
          ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
      if (!entry.is_regular_file() || ext != ".c3d") continue;
      ++files;
      try {
        ReadC3d(entry.path());
      } catch (const InputError& e) {
        ++failed;
        EXPECT_NE(std::string(e.what()).find(entry.path().string()), std::string::npos) << e.what();
        const std::string name = entry.path().filename().string();
        EXPECT_TRUE(name == "Empty.c3d" || name == "bad_parameter_section.c3d") << e.what();
      }
    }
  }
  EXPECT_GE(files, 74);
  EXPECT_EQ(failed, 2);  // Empty.c3d, sample_18
}

TEST(C3dBadInput, MissingFileNamesIt) {
  try {
    ReadC3d("/no/such/dir/trial.c3d");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/dir/trial.c3d"), std::string::npos) << e.what();
  }
}

// Truncation at every length up to the end of the parameter section and the first data blocks,
// then every 61st byte to the end of the file.
TEST(C3dBadInput, TruncationsNeverCrash) {
  for (const char* file : {"c3dio-c3d_org_samples/sample_01/Eb015vi.c3d",
                           "c3dio-c3d_org_samples/sample_01/Eb015sr.c3d",
                           "BTKData/Input/C3DSamples/others/MyCube.c3d"}) {
    const auto path = acro::testing::RefdataFile(file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const std::vector<std::uint8_t> full = Bytes(path);
    int loaded = 0, rejected = 0;
    for (std::size_t n = 0; n < full.size(); n += (n < 8192 ? 1 : 61)) {
      const std::vector<std::uint8_t> cut(full.begin(), full.begin() + n);
      const std::string result = TryRead(cut, "cut.c3d");
      result == "ok" ? ++loaded : ++rejected;
    }
    EXPECT_GT(rejected, 0) << file;
    // A file cut inside the data loads its complete frames, with a warning.
    if (full.size() > 20000) {
      EXPECT_GT(loaded, 0) << file;
      const std::vector<std::uint8_t> cut(full.begin(), full.begin() + full.size() - 1000);
      const Trial t = ReadC3dFromMemory(cut, "cut.c3d");
      EXPECT_LT(t.num_frames, 450);
      EXPECT_GT(t.num_frames, 400);
      bool warned = false;
      for (const std::string& w : t.warnings)
        warned = warned || w.find("truncated") != std::string::npos;
      EXPECT_TRUE(warned);
    }
  }
}

// Every bit of a small file, and random bytes of the header and parameter section of larger ones
// (fixed seed), flipped one at a time.
TEST(C3dBadInput, BitFlipsNeverCrash) {
  const auto cube = acro::testing::RefdataFile("BTKData/Input/C3DSamples/others/MyCube.c3d");
  ACRO_REQUIRE_REFDATA_FILE(cube);
  const std::vector<std::uint8_t> small = Bytes(cube);
  for (std::size_t i = 0; i < small.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<std::uint8_t> bytes = small;
      bytes[i] ^= static_cast<std::uint8_t>(1u << bit);
      TryRead(bytes, "flip.c3d");
    }
  }
  std::mt19937 random(12345);
  for (const char* file : {"c3dio-c3d_org_samples/sample_01/Eb015vr.c3d",
                           "c3dio-c3d_org_samples/sample_01/Eb015si.c3d",
                           "c3dio-c3d_org_samples/sample_09/PlugInC3D.c3d",
                           "BTKData/Input/C3DSamples/others/parameterOverflow.c3d"}) {
    const auto path = acro::testing::RefdataFile(file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const std::vector<std::uint8_t> full = Bytes(path);
    const std::size_t head =
        std::min<std::size_t>(full.size(), std::size_t(full[16] | (full[17] << 8)) * 512 + 512);
    std::uniform_int_distribution<std::size_t> where(0, std::min(head, full.size()) - 1);
    std::uniform_int_distribution<int> value(0, 255);
    for (int k = 0; k < 3000; ++k) {
      std::vector<std::uint8_t> bytes = full;
      bytes[where(random)] = static_cast<std::uint8_t>(value(random));
      if (k % 3 == 0) bytes[where(random)] = static_cast<std::uint8_t>(value(random));
      TryRead(bytes, "flip.c3d");
    }
  }
}

// Hand-made lies: huge counts in the header and parameters must be refused from the file size.
TEST(C3dBadInput, LyingCountsAreBoundedByTheFileSize) {
  const auto path = acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const std::vector<std::uint8_t> full = Bytes(path);
  // Header last frame 65535: the parameters' 450 frames (what the data section holds) are read,
  // the same samples as from the honest file.
  std::vector<std::uint8_t> bytes = full;
  bytes[8] = 0xFF;
  bytes[9] = 0xFF;
  std::string result = TryRead(bytes, "lying.c3d");
  EXPECT_EQ(result, "ok");
  if (result == "ok") {
    const Trial honest = ReadC3dFromMemory(full, "honest.c3d");
    const Trial lying = ReadC3dFromMemory(bytes, "lying.c3d");
    EXPECT_EQ(lying.num_frames, 450);
    EXPECT_EQ(lying.num_frames, honest.num_frames);
    const auto a = lying.positions.array(), b = honest.positions.array();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE((a == b || (a.isNaN() && b.isNaN())).all());  // the same samples, gaps included
  }
  // Header point count 65535 with POINT:USED 26: the parameter is used, a warning says so.
  bytes = full;
  bytes[2] = 0xFF;
  bytes[3] = 0xFF;
  const Trial t = ReadC3dFromMemory(bytes, "lying.c3d");
  EXPECT_EQ(t.num_points(), 26);
  EXPECT_FALSE(t.warnings.empty());
  // A header key byte that is not 0x50: not a C3D file.
  bytes = full;
  bytes[1] = 0x51;
  result = TryRead(bytes, "notc3d.c3d");
  EXPECT_NE(result.find("not a C3D file"), std::string::npos) << result;
  EXPECT_NE(result.find("byte 1"), std::string::npos) << result;
}

}  // namespace
}  // namespace acro::capture
