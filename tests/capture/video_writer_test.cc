// The video writer, read back by the reader and by ffprobe: size (odd sizes padded), frame count
// and rate, the index at the front of the file, the picture within H.264's loss, and nothing left
// behind by a writer that did not finish.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "acro/capture/video.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("acro_writer_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A smooth gradient with a square moving one pixel right per frame.
std::vector<std::uint8_t> Picture(int w, int h, int k) {
  std::vector<std::uint8_t> rgb(3 * static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * w + x)];
      const bool square = x >= 40 + k && x < 80 + k && y >= 60 && y < 100;
      p[0] = square ? 230 : static_cast<std::uint8_t>(255 * x / w);
      p[1] = square ? 30 : static_cast<std::uint8_t>(255 * y / h);
      p[2] = square ? 40 : 128;
    }
  }
  return rgb;
}

TEST(VideoWriter, WritesH264Mp4ThatReadsBack) {
  const fs::path dir = TempDir("roundtrip");
  const fs::path path = dir / "out.mp4";
  const int w = 321, h = 241, n = 45;  // odd: padded to 322 x 242
  {
    VideoWriter writer(path, w, h, {.fps = 30.0});
    for (int k = 0; k < n; ++k) writer.Write(Picture(w, h, k));
    EXPECT_FALSE(fs::exists(path)) << "visible before Finish()";
    writer.Finish();
  }
  ASSERT_TRUE(fs::exists(path));
  // Only the file: the temporary one was renamed.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);

  VideoReader reader(path);
  EXPECT_EQ(reader.info().codec, "h264");
  EXPECT_EQ(reader.info().width, 322);
  EXPECT_EQ(reader.info().height, 242);
  EXPECT_EQ(reader.num_frames(), n);
  EXPECT_NEAR(reader.info().average_fps, 30.0, 1e-6);
  EXPECT_FALSE(reader.info().variable_frame_rate);

  // The picture within H.264's loss at crf 18: PSNR over the original area above 35 dB, for the
  // first, a middle and the last frame (the square where it was drawn).
  for (int k : {0, 22, n - 1}) {
    const VideoFrame f = reader.Frame(k);
    const std::vector<std::uint8_t> original = Picture(w, h, k);
    double se = 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const double d = f.pixels[3 * (static_cast<size_t>(y) * f.width + x) + c] -
                           original[3 * (static_cast<size_t>(y) * w + x) + c];
          se += d * d;
        }
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / (se / (3.0 * w * h)));
    EXPECT_GT(psnr, 35.0) << "frame " << k;
  }

  // "+faststart": the index (moov) comes before the data (mdat).
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const size_t moov = bytes.find("moov"), mdat = bytes.find("mdat");
  ASSERT_NE(moov, std::string::npos);
  ASSERT_NE(mdat, std::string::npos);
  EXPECT_LT(moov, mdat);
  fs::remove_all(dir);
}

TEST(VideoWriter, AnUnfinishedOrFailedWriterLeavesNothing) {
  const fs::path dir = TempDir("unfinished");
  {
    VideoWriter writer(dir / "half.mp4", 64, 48);
    writer.Write(Picture(64, 48, 0));
  }  // destroyed before Finish()
  EXPECT_TRUE(fs::is_empty(dir));
  // A frame of the wrong size, a folder that does not exist, a size no video has: one line each.
  VideoWriter writer(dir / "x.mp4", 64, 48);
  try {
    writer.Write(std::vector<std::uint8_t>(10));
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.mp4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("frame 0 has 10 bytes"), std::string::npos) << e.what();
  }
  EXPECT_THROW(VideoWriter(dir / "no" / "such" / "dir.mp4", 64, 48), InputError);
  EXPECT_THROW(VideoWriter(dir / "zero.mp4", 0, 48), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro::capture
