// The projection overlay: points drawn where the camera puts them, on the frames the sync pairs
// them with, into an MP4 or a directory of PNGs that appears only when complete.

#include "acro/base/progress.h"
#include "acro/report/projection_overlay.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::ui {
namespace {

namespace fs = std::filesystem;

// A 10-sample trial at 10 Hz with one marker moving along x in the plane z = 5 m in front of a
// camera at the origin looking along +z.
capture::Trial MovingMarker() {
  capture::Trial t;
  t.point_rate_hz = 10;
  t.num_frames = 10;
  t.points.push_back({"M", "", capture::PointType::kMarker, "m"});
  t.positions.resize(3, 10);
  for (int f = 0; f < 10; ++f) t.positions.col(f) = Eigen::Vector3d(-1.0 + 0.2 * f, 0.0, 5.0);
  return t;
}

vision::Camera FrontCamera() {
  vision::Camera c;
  c.name = "front";
  c.width_px = 160;
  c.height_px = 120;
  c.K << 100, 0, 80, 0, 100, 60, 0, 0, 1;
  return c;
}

// Reads pixel (x, y) of a PNG as 0xRRGGBB.
std::uint32_t PngPixel(const fs::path& png, int x, int y) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.string().c_str());
  EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS) << png;
  const std::uint8_t* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  const std::uint32_t v = reinterpret_cast<const std::uint32_t*>(data + y * stride)[x] & 0xFFFFFF;
  cairo_surface_destroy(s);
  return v;
}

TEST(Overlay, PointsLandOnTheirSyncedFramesInPngsAndMp4) {
  const fs::path dir = acro::testing::ScratchDir("overlay");
  // A black 20-frame video at 20 fps: video time k/20.
  {
    capture::VideoWriterOptions w;
    w.fps = 20;
    w.preset = "ultrafast";
    capture::VideoWriter writer(dir / "black.mp4", 160, 120, w);
    const std::vector<std::uint8_t> black(160 * 120 * 3, 0);
    for (int k = 0; k < 20; ++k) writer.Write(black);
    writer.Finish();
  }
  capture::VideoReader video(dir / "black.mp4");
  OverlayVideoOptions options;
  options.sync = {0.2, 1.0};  // the trial starts at video frame 4
  options.radius_px = 4;
  int progress_calls = 0;
  options.progress = [&](int, int) {
    ++progress_calls;
    return true;
  };
  const int written =
      WriteProjectionOverlay(video, MovingMarker(), FrontCamera(), dir / "frames", options);
  EXPECT_EQ(written, 20);
  EXPECT_EQ(progress_calls, 20);
  // Frame 4 (0.2 s) shows sample 0 at u = 80 + 100 · (−1/5) = 60; frame 6 (0.3 s) sample 1 at 64.
  // The marker's colour is the palette's first (0.12, 0.47, 0.71) → 0x1F78B5.
  auto is_blue = [](std::uint32_t v) {
    const int r = int(v >> 16), g = int((v >> 8) & 0xFF), b = int(v & 0xFF);
    return std::abs(r - 0x1F) <= 1 && std::abs(g - 0x78) <= 1 && std::abs(b - 0xB5) <= 1;
  };
  EXPECT_TRUE(is_blue(PngPixel(dir / "frames/frame_000004.png", 60, 60)));
  EXPECT_TRUE(is_blue(PngPixel(dir / "frames/frame_000006.png", 64, 60)));
  EXPECT_EQ(PngPixel(dir / "frames/frame_000006.png", 54, 60), 0u);  // moved on
  // Before the trial and after it (sample 9 is frame 22: beyond), frames are as they were.
  EXPECT_EQ(PngPixel(dir / "frames/frame_000002.png", 60, 60), 0u);
  EXPECT_EQ(fs::exists(dir / "frames/frame_000019.png"), true);
  // Nothing else in the directory, and no staging directory left beside it.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames")) files += e.is_regular_file();
  EXPECT_EQ(files, 20);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();

  // The same as an MP4: 20 frames at 20 fps, with the marker on frame 4.
  capture::VideoReader again(dir / "black.mp4");
  WriteProjectionOverlay(again, MovingMarker(), FrontCamera(), dir / "overlay.mp4", options);
  capture::VideoReader result(dir / "overlay.mp4");
  EXPECT_EQ(result.num_frames(), 20);
  EXPECT_NEAR(result.info().average_fps, 20.0, 1e-6);
  const capture::VideoFrame f4 = result.Frame(4);
  const std::uint8_t* px = &f4.pixels[(60 * 160 + 60) * 3];
  EXPECT_NEAR(px[2], 0xB5, 12);  // blue channel, after H.264
  EXPECT_LT(px[0], 60);

  // A directory holding anything but frames is not replaced; a cancelled run leaves nothing.
  std::ofstream(dir / "frames/notes.txt") << "mine";
  capture::VideoReader third(dir / "black.mp4");
  std::string e;
  try {
    WriteProjectionOverlay(third, MovingMarker(), FrontCamera(), dir / "frames", options);
  } catch (const InputError& error) {
    e = error.what();
  }
  EXPECT_NE(e.find("holds notes.txt, not only frame_NNNNNN.png: not replaced"), std::string::npos)
      << e;
  options.progress = [](int done, int) { return done < 5; };
  capture::VideoReader fourth(dir / "black.mp4");
  EXPECT_THROW(
      WriteProjectionOverlay(fourth, MovingMarker(), FrontCamera(), dir / "cancelled", options),
      Cancelled);
  EXPECT_FALSE(fs::exists(dir / "cancelled"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro::ui
