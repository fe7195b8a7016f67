// Replays the video fuzz entry point (tests/fuzz/fuzz_video.h) over small videos of each codec
// family a hall brings (H.264 in MP4 with the index in front and behind, HEVC in Matroska, VP9 in
// WebM, AV1, MPEG-4 Part 2 and MJPEG in AVI), made here with the ffmpeg command line, and their
// damaged copies: truncations and overwritten bytes, half of them in the first KiB (headers and
// the index of a "faststart" file). Opening, the sequential pass and the random accesses either
// succeed or throw acro::InputError; anything else fails (a crash fails the whole test binary).
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../fuzz/fuzz_video.h"
#include "mutants.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

TEST(VideoCorpus, EveryCodecAndMutationIsDecodedOrRejectedCleanly) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  const fs::path dir = acro::testing::ScratchDir("video_corpus");
  struct Kind {
    const char* file;
    const char* codec;
  };
  const std::vector<Kind> kinds = {
      {"h264_faststart.mp4", "-c:v libx264 -bf 2 -g 6 -pix_fmt yuv420p -movflags +faststart"},
      {"h264.mp4", "-c:v libx264 -g 6 -pix_fmt yuv420p"},
      {"hevc.mkv", "-c:v libx265 -x265-params log-level=none -g 6 -pix_fmt yuv420p"},
      {"vp9.webm", "-c:v libvpx-vp9 -g 6 -deadline realtime"},
      {"av1.mkv", "-c:v libaom-av1 -cpu-used 8 -g 6"},
      {"mpeg4.avi", "-c:v mpeg4 -g 6"},
      {"mjpeg.avi", "-c:v mjpeg -q:v 5"}};
  std::mt19937 rng(17);
  int inputs = 0;
  for (const Kind& k : kinds) {
    SCOPED_TRACE(k.file);
    const fs::path path = dir / k.file;
    // 16 frames of 64 × 48 at 25 fps: small enough to decode hundreds of copies.
    const std::string make =
        std::string("ffmpeg -v error -y -f lavfi -i testsrc=size=64x48:rate=25 -frames:v 16 ") +
        k.codec + " '" + path.string() + "'";
    ASSERT_EQ(std::system(make.c_str()), 0) << make;
    const std::vector<std::uint8_t> original = acro::testing::Slurp(path);
    // The original: 16 frames in a sequential pass, then 3 random accesses.
    EXPECT_EQ(fuzz::FeedVideoReader(original.data(), original.size(), k.file), 16 + 3);
    ++inputs;
    inputs += acro::testing::ReplayMutants(
        acro::testing::ByteMutants(original, rng, 48, 1024),
        [&](const auto& bytes) { fuzz::FeedVideoReader(bytes.data(), bytes.size(), k.file); });
  }
  RecordProperty("inputs", inputs);
  std::printf("%d video inputs replayed\n", inputs);
}

}  // namespace
}  // namespace acro::capture
