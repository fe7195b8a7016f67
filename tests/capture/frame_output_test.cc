// Frames out as a PNG directory: complete or absent, "frames/" naming the directory "frames"
// (its staging directory beside it, not inside), and the PNGs decoding back to the pixels.

#include "acro/capture/frame_output.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "acro/base/input_error.h"
#include "acro/capture/video.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> Gradient(int w, int h, int shift) {
  std::vector<std::uint8_t> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[(size_t(y) * w + x) * 3 + c] =
            static_cast<std::uint8_t>((x * 7 + y * 3 + c * 50 + shift) % 256);
  return rgb;
}

TEST(FrameOutput, APathEndingInASlashIsTheDirectoryAndTheFramesComeBackExact) {
  const fs::path dir = acro::testing::ScratchDir("frame_output");
  const int w = 33, h = 17;  // odd sizes
  {
    FrameOutput out(dir.string() + "/frames/", w, h);
    EXPECT_FALSE(out.is_video());
    out.Write(4, Gradient(w, h, 0));
    out.Write(5, Gradient(w, h, 9));
    EXPECT_FALSE(fs::exists(dir / "frames"));  // not before Finish
    out.Finish();
  }
  ASSERT_TRUE(fs::is_directory(dir / "frames"));
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "frames") << "left behind: " << e.path();
  }
  EXPECT_EQ(entries, 1);
  const VideoFrame f = VideoReader(dir / "frames/frame_000005.png").Frame(0);
  EXPECT_EQ(f.width, w);
  EXPECT_EQ(f.height, h);
  EXPECT_EQ(f.pixels, Gradient(w, h, 9));  // lossless
}

TEST(FrameOutput, UnfinishedLeavesNothingAndAForeignDirectoryIsNotReplaced) {
  const fs::path dir = acro::testing::ScratchDir("frame_output_unfinished");
  {
    FrameOutput out(dir / "frames", 8, 8);
    out.Write(0, Gradient(8, 8, 0));
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::create_directories(dir / "mine");
  std::ofstream(dir / "mine/notes.txt") << "keep";
  try {
    FrameOutput out(dir / "mine", 8, 8);
    ADD_FAILURE() << "a directory with other files was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds notes.txt"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir / "mine/notes.txt"));
}

}  // namespace
}  // namespace acro::capture
