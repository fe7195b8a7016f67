#pragma once

// Video input, frame-exact (docs/formats/video.md). On open the video stream's packets are indexed
// without decoding, so that frame i is the i-th frame in presentation order with its own
// timestamp — variable frame rate included, never i / fps. Frames come out as 8-bit RGB at display
// orientation (a phone's display-matrix rotation applied). FFmpeg stays inside capture/src.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace acro::capture {

/// What a video file holds, from its header and the packet index (no decoding).
struct VideoInfo {
  std::string path;
  std::string container;  ///< e.g. "mov,mp4,m4a,3gp,3g2,mj2"
  std::string codec;      ///< e.g. "h264", "vp9"
  int coded_width = 0;    ///< as stored
  int coded_height = 0;
  int width = 0;  ///< as displayed (after the rotation)
  int height = 0;
  int rotation_deg = 0;  ///< clockwise rotation applied for display: 0, 90, 180 or 270
  int num_frames = 0;    ///< exact, from the index
  int num_keyframes = 0;
  double average_fps = 0.0;  ///< (frames − 1) / (last − first timestamp)
  double nominal_fps = 0.0;  ///< the stream's declared (real base) frame rate
  /// True when the frame intervals differ by more than a tenth of their median.
  bool variable_frame_rate = false;
  double duration_s = 0.0;    ///< last frame's time − first frame's time + one median interval
  double start_time_s = 0.0;  ///< the first frame's timestamp in the file
  std::vector<std::string> audio_codecs;  ///< one per audio track
};

/// One decoded frame, rows top to bottom, width × height as displayed: RGB, 3 bytes per pixel, or
/// grey (full-range luma), 1 byte per pixel, as the reader was opened.
struct VideoFrame {
  int index = -1;
  double time_s = 0.0;  ///< from the first frame (the first frame is at 0)
  int width = 0;
  int height = 0;
  int channels = 3;  ///< 3: RGB; 1: grey
  std::vector<std::uint8_t> pixels;
};

/// What a reader hands out: RGB for pictures and overlays, grey for the analyses that need only
/// luma (board detection, image motion), which skips the colour conversion.
enum class VideoPixels { kRgb, kGrey };

struct VideoReaderOptions {
  int num_threads = 0;  ///< decoder threads; 0: as many as the machine has
  VideoPixels pixels = VideoPixels::kRgb;
};

/// Reads one video file. Not thread-safe: one reader per thread.
class VideoReader {
 public:
  /// Opens and indexes `path`. Throws acro::InputError naming the file when it cannot be read,
  /// is not a video, has no video stream or no frame.
  explicit VideoReader(const std::filesystem::path& path, const VideoReaderOptions& options = {});
  ~VideoReader();
  VideoReader(VideoReader&&) noexcept;
  VideoReader& operator=(VideoReader&&) noexcept;

  const VideoInfo& info() const;
  int num_frames() const { return info().num_frames; }
  /// Frame times from the first frame (s), presentation order.
  const std::vector<double>& frame_times_s() const;
  /// The index of the frame shown at `time_s` (from the first frame): the last frame whose time is
  /// not after it, 0 before the first.
  int FrameAt(double time_s) const;

  /// Frame i (0 ≤ i < num_frames()): seeks to the keyframe before it and decodes forward.
  /// Throws acro::InputError naming the file and the frame when it cannot be decoded.
  VideoFrame Frame(int index);

  /// The next frame of a sequential pass from the start (after Frame(), the pass restarts from
  /// the frame after the one returned). False after the last frame.
  bool ReadNext(VideoFrame* frame);

  /// What the next frames are handed out as: a grey pass (image motion) and a colour one
  /// (silhouettes, overlays) on one reader, so that a door indexes its video once.
  void SetPixels(VideoPixels pixels);
  VideoPixels pixels() const;

  /// How many readers this process has opened (each indexes its file): for the tests that hold
  /// a door to one opening per video.
  static long long OpenedCount();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct VideoWriterOptions {
  double fps = 30.0;
  int crf = 18;                   ///< x264's constant rate factor: 18 is visually lossless
  std::string preset = "medium";  ///< x264's speed/size trade-off
  int num_threads = 0;            ///< encoder threads; 0: as many as the machine has
};

/// Writes H.264 in MP4 (libx264, yuv420p, the index at the front: "+faststart") to a temporary
/// file beside `path`, renamed to `path` by Finish(): a reader never sees a half-written video, and
/// a writer destroyed before Finish() leaves nothing. Odd sizes are padded to even ones by
/// repeating the last column and row (yuv420p needs even sizes).
class VideoWriter {
 public:
  /// Throws acro::InputError naming the file when the encoder or the file cannot be opened.
  VideoWriter(const std::filesystem::path& path,
              int width,
              int height,
              const VideoWriterOptions& options = {});
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Appends one RGB frame (3 bytes per pixel, rows top to bottom, the size given on opening).
  void Write(const std::vector<std::uint8_t>& rgb);
  /// Flushes the encoder, writes the index and renames the file into place.
  void Finish();
  int frames_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `acrolab video info`'s text: one "Name  value" line per field.
std::string FormatVideoInfoText(const VideoInfo& info);

/// The same as one JSON object: path, container, codec, width, height, coded_width,
/// coded_height, rotation_deg, frames, keyframes, average_fps, nominal_fps, variable_frame_rate,
/// duration_s, start_time_s, audio_tracks (codec names).
std::string FormatVideoInfoJson(const VideoInfo& info);

/// FNV-1a 64-bit hash of a frame's pixels (for comparing decodes).
std::uint64_t HashFrame(const VideoFrame& frame);

}  // namespace acro::capture
