// The video reader against the ffmpeg command line (an independent decode of the same files): the
// reference videos of ../shared/refdata (Pose2Sim's four cameras, H.264 and VP9 with audio,
// portrait; Sports2D's demo, VP9), files the test makes with ffmpeg (variable frame rate, a
// display rotation), and broken input.

#include "acro/capture/video.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "long_tests.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

std::string Quote(const fs::path& p) {
  return "'" + p.string() + "'";
}

// The standard output of a shell command (binary-safe).
std::string CommandOutput(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  pclose(pipe);
  return out;
}

bool HaveFfmpeg() {
  return std::system("ffmpeg -version > /dev/null 2>&1") == 0;
}

// FNV-1a of a byte range, as HashFrame computes it over a frame's pixels.
std::uint64_t Hash(const std::uint8_t* data, size_t size) {
  VideoFrame f;
  f.pixels.assign(data, data + size);
  return HashFrame(f);
}

// Every frame's hash as the ffmpeg command line decodes the file to RGB24 (autorotated).
std::vector<std::uint64_t> FfmpegFrameHashes(const fs::path& file, int width, int height) {
  const std::string raw =
      CommandOutput("ffmpeg -v error -i " + Quote(file) + " -f rawvideo -pix_fmt rgb24 -");
  const size_t frame_bytes = 3 * static_cast<size_t>(width) * height;
  std::vector<std::uint64_t> hashes;
  for (size_t at = 0; at + frame_bytes <= raw.size(); at += frame_bytes)
    hashes.push_back(Hash(reinterpret_cast<const std::uint8_t*>(raw.data()) + at, frame_bytes));
  return hashes;
}

fs::path TempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("acro_video_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct ReferenceVideo {
  const char* path;
  const char* codec;
  int width, height, frames;
  double fps;
  bool audio;
};

const ReferenceVideo kReferenceVideos[] = {
    {"pose2sim-demo/videos/cam01.mp4", "h264", 1080, 1920, 100, 60.0, false},
    {"pose2sim-demo/videos/cam02.mp4", "vp9", 1080, 1920, 100, 60.0, true},
    {"pose2sim-demo/videos/cam03.mp4", "h264", 1088, 1920, 100, 60.0, false},
    {"pose2sim-demo/videos/cam04.mp4", "h264", 1088, 1920, 100, 60.0, false},
    {"sports2d-demo/demo.mp4", "vp9", 1768, 994, 230, 30.0, true},
};

TEST(VideoReader, ReferenceVideosHaveTheirFramesAndRates) {
  for (const ReferenceVideo& v : kReferenceVideos) {
    const fs::path path = acro::testing::RefdataFile(v.path);
    ACRO_REQUIRE_REFDATA_FILE(path);
    SCOPED_TRACE(v.path);
    const VideoReader reader(path);
    const VideoInfo& info = reader.info();
    EXPECT_EQ(info.codec, v.codec);
    EXPECT_EQ(info.width, v.width);
    EXPECT_EQ(info.height, v.height);
    EXPECT_EQ(info.num_frames, v.frames);
    EXPECT_NEAR(info.average_fps, v.fps, 1e-9);
    EXPECT_FALSE(info.variable_frame_rate);
    EXPECT_EQ(info.audio_codecs.empty(), !v.audio);
    // Frame times are the timestamps: i / fps here, to the container's time base.
    ASSERT_EQ(reader.frame_times_s().size(), static_cast<size_t>(v.frames));
    EXPECT_NEAR(reader.frame_times_s().back(), (v.frames - 1) / v.fps, 1e-6);
  }
}

// Random access (40 frames at random per video, seed 7; 200 with ACRO_LONG_TESTS=1), a sequential
// pass and the command line's decode give the same pixels, bit for bit.
TEST(VideoReader, RandomAccessEqualsSequentialAndTheFfmpegCommandLine) {
  if (!HaveFfmpeg())
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  std::mt19937 rng(7);
  for (const ReferenceVideo& v : kReferenceVideos) {
    const fs::path path = acro::testing::RefdataFile(v.path);
    ACRO_REQUIRE_REFDATA_FILE(path);
    SCOPED_TRACE(v.path);
    VideoReader reader(path, {.num_threads = 2});
    const std::vector<std::uint64_t> reference = FfmpegFrameHashes(path, v.width, v.height);
    ASSERT_EQ(reference.size(), static_cast<size_t>(v.frames));
    std::vector<std::uint64_t> sequential;
    VideoFrame frame;
    while (reader.ReadNext(&frame)) {
      ASSERT_EQ(frame.index, static_cast<int>(sequential.size()));
      sequential.push_back(HashFrame(frame));
    }
    EXPECT_EQ(sequential, reference);
    std::uniform_int_distribution<int> pick(0, v.frames - 1);
    int mismatches = 0;
    for (int k = 0; k < (acro::testing::LongTests() ? 200 : 40); ++k) {
      const int i = pick(rng);
      const VideoFrame f = reader.Frame(i);
      ASSERT_EQ(f.index, i);
      EXPECT_EQ(f.width, v.width);
      EXPECT_EQ(f.height, v.height);
      if (HashFrame(f) != reference[static_cast<size_t>(i)]) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0);
    // Random access skips the frames nothing refers to before the target, never after it: a
    // sequential pass goes on from the target frame by frame.
    for (int start : {v.frames / 2, v.frames / 3, 7}) {
      reader.Frame(start);
      for (int i = start + 1; i < std::min(v.frames, start + 12); ++i) {
        ASSERT_TRUE(reader.ReadNext(&frame));
        ASSERT_EQ(frame.index, i);
        EXPECT_EQ(HashFrame(frame), reference[static_cast<size_t>(i)]) << "frame " << i;
      }
    }
  }
}

// A variable-frame-rate file (frames kept irregularly, timestamps kept) and a rotated one (a 90°
// display matrix), made here with the ffmpeg command line.
TEST(VideoReader, VariableFrameRateTimestampsAndDisplayRotation) {
  if (!HaveFfmpeg())
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  const fs::path dir = TempDir("vfr");
  const fs::path vfr = dir / "vfr.mp4";
  ASSERT_EQ(std::system(("ffmpeg -v error -y -f lavfi -i testsrc=size=320x240:rate=30 -t 3 "
                         "-vf \"select='lt(n\\,30)+not(mod(n\\,3))'\" -vsync vfr -c:v libx264 "
                         "-pix_fmt yuv420p " +
                         Quote(vfr))
                            .c_str()),
            0);
  const VideoReader reader(vfr);
  EXPECT_TRUE(reader.info().variable_frame_rate);
  // The first 30 frames 1/30 s apart, then every third frame: 1/10 s apart.
  const std::vector<double>& t = reader.frame_times_s();
  ASSERT_EQ(t.size(), 30u + 20u);
  EXPECT_NEAR(t[1] - t[0], 1.0 / 30, 1e-4);
  EXPECT_NEAR(t[40] - t[39], 1.0 / 10, 1e-4);
  // ffprobe's own list of presentation times.
  std::istringstream probe(
      CommandOutput("ffprobe -v error -select_streams v:0 -show_entries frame=pts_time "
                    "-of csv=p=0 " +
                    Quote(vfr)));
  std::vector<double> probed;
  for (std::string line; std::getline(probe, line);) {
    line = line.substr(0, line.find(','));  // ffprobe may end a row with a comma
    if (!line.empty()) probed.push_back(std::stod(line));
  }
  ASSERT_EQ(probed.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], probed[i] - probed[0], 1e-6) << i;
  EXPECT_EQ(reader.FrameAt(1.05), 30);  // 1.0 s is frame 30, 1.1 s frame 31

  // Rotation: the same picture stored landscape with a 90° display matrix shows portrait, as the
  // command line's autorotation shows it.
  const fs::path rotated = dir / "rotated.mp4";
  ASSERT_EQ(std::system(("ffmpeg -v error -y -i " + Quote(vfr) +
                         " -c copy -metadata:s:v:0 rotate=90 " + Quote(rotated))
                            .c_str()),
            0);
  VideoReader turned(rotated);
  // FFmpeg 5.1 stores the tag as a display matrix that ffprobe reports as rotation=90 (counter-
  // clockwise): shown upright, the picture turns 90° counter-clockwise, i.e. 270° clockwise.
  EXPECT_EQ(turned.info().rotation_deg, 270);
  EXPECT_EQ(turned.info().width, 240);
  EXPECT_EQ(turned.info().height, 320);
  const VideoFrame ours = turned.Frame(5);
  ASSERT_EQ(ours.width, 240);
  ASSERT_EQ(ours.height, 320);
  const std::string cli =
      CommandOutput("ffmpeg -v error -i " + Quote(rotated) +
                    " -vf \"select=eq(n\\,5)\" -vframes 1 -f rawvideo -pix_fmt rgb24 -");
  ASSERT_EQ(cli.size(), ours.pixels.size());
  // The command line turns the YUV planes before converting, we the RGB picture after: the same
  // picture to chroma interpolation; a wrong turn would differ by whole colour bars.
  double sum = 0.0;
  for (size_t k = 0; k < cli.size(); ++k)
    sum += std::abs(static_cast<int>(static_cast<std::uint8_t>(cli[k])) - ours.pixels[k]);
  EXPECT_LT(sum / cli.size(), 3.0);
  fs::remove_all(dir);
}

// Grey frames (luma, for calibration and the image-motion sync) are the ffmpeg command line's
// `-pix_fmt gray` frames bit for bit, for a portrait H.264 and a VP9 file.
// MPEG-TS (what `acrolab live` records) has no index: FFmpeg seeks it by searching timestamps in
// the bytes, which landed on the second group of pictures for the first frame and past the end
// for the last group. Every frame, in order and at random, as the command line decodes it.
TEST(VideoReader, MpegTsFramesInOrderAndAtRandom) {
  if (!HaveFfmpeg())
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  const fs::path dir = TempDir("ts");
  const fs::path ts = dir / "gop.ts";
  ASSERT_EQ(std::system(("ffmpeg -v error -y -f lavfi -i testsrc=size=320x240:rate=30 -t 4 "
                         "-c:v libx264 -g 25 -bf 2 -pix_fmt yuv420p -f mpegts " +
                         Quote(ts))
                            .c_str()),
            0);
  const std::vector<std::uint64_t> truth = FfmpegFrameHashes(ts, 320, 240);
  ASSERT_EQ(truth.size(), 120u);
  VideoReader reader(ts);
  ASSERT_EQ(reader.num_frames(), 120);
  VideoFrame f;
  std::vector<std::uint64_t> in_order;
  while (reader.ReadNext(&f)) in_order.push_back(HashFrame(f));
  EXPECT_EQ(in_order, truth);
  for (int i : {119, 0, 100, 24, 25, 118, 50, 1, 76, 119})
    EXPECT_EQ(HashFrame(reader.Frame(i)), truth[static_cast<size_t>(i)]) << "frame " << i;
}

TEST(VideoReader, GreyFramesEqualTheFfmpegCommandLinesGray) {
  if (!HaveFfmpeg())
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  for (const char* relative : {"pose2sim-demo/videos/cam01.mp4", "sports2d-demo/demo.mp4"}) {
    const fs::path path = acro::testing::RefdataFile(relative);
    ACRO_REQUIRE_REFDATA_FILE(path);
    SCOPED_TRACE(relative);
    VideoReader reader(path, {.num_threads = 2, .pixels = VideoPixels::kGrey});
    const int w = reader.info().width, h = reader.info().height;
    const std::string raw =
        CommandOutput("ffmpeg -v error -i " + Quote(path) + " -f rawvideo -pix_fmt gray -");
    const size_t frame_bytes = static_cast<size_t>(w) * h;
    ASSERT_EQ(raw.size(), frame_bytes * static_cast<size_t>(reader.num_frames()));
    VideoFrame frame;
    int mismatches = 0;
    while (reader.ReadNext(&frame)) {
      ASSERT_EQ(frame.channels, 1);
      ASSERT_EQ(frame.pixels.size(), frame_bytes);
      const auto* expected =
          reinterpret_cast<const std::uint8_t*>(raw.data()) + frame_bytes * size_t(frame.index);
      if (HashFrame(frame) != Hash(expected, frame_bytes)) {
        ++mismatches;
        if (mismatches == 1) {
          int worst = 0;
          long sum = 0;
          for (size_t k = 0; k < frame_bytes; ++k) {
            const int d = std::abs(int(frame.pixels[k]) - int(expected[k]));
            worst = std::max(worst, d);
            sum += d;
          }
          ADD_FAILURE() << "frame " << frame.index << ": max " << worst << ", mean "
                        << double(sum) / frame_bytes;
        }
      }
    }
    EXPECT_EQ(mismatches, 0);
    // Random access gives the same grey frame.
    const VideoFrame f = reader.Frame(reader.num_frames() / 2);
    EXPECT_EQ(HashFrame(f),
              Hash(reinterpret_cast<const std::uint8_t*>(raw.data()) +
                       frame_bytes * size_t(reader.num_frames() / 2),
                   frame_bytes));
  }
}

TEST(VideoReader, BadInputIsOneLineNamingTheFile) {
  const fs::path dir = TempDir("bad");
  auto error_of = [](const fs::path& p) -> std::string {
    try {
      VideoReader reader(p);
      VideoFrame f;
      while (reader.ReadNext(&f)) {
      }
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  // A text file named .mp4.
  const fs::path text = dir / "notes.mp4";
  std::ofstream(text) << "this is not a video\n";
  std::string e = error_of(text);
  EXPECT_NE(e.find("notes.mp4"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // A missing file and a folder.
  EXPECT_NE(error_of(dir / "missing.mp4").find("missing.mp4"), std::string::npos);
  EXPECT_NE(error_of(dir).find("not a regular file"), std::string::npos);
  // A truncated file: it fails in one line naming the file, or the frames before the damage read
  // and the error names where the stream ends.
  const fs::path whole = acro::testing::RefdataFile("pose2sim-demo/videos/cam01.mp4");
  if (fs::exists(whole)) {
    std::ifstream in(whole, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const fs::path cut = dir / "cut.mp4";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
    e = error_of(cut);
    EXPECT_NE(e.find("cut.mp4"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro::capture
