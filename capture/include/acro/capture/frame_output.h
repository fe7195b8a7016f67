#pragma once

// Where rendered or annotated frames go: an MP4 (the VideoWriter: H.264, +faststart) or a directory
// of PNG files frame_NNNNNN.png (FFmpeg's PNG encoder, lossless: for measuring and for stills).
// Either appears only when complete: the MP4 under a temporary name, the frames in a staging
// directory beside the target, both registered for removal on interrupt (base/temporaries.h) and
// removed when the output is destroyed before Finish().

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "acro/capture/video.h"

namespace acro::capture {

/// True when `name` is a frame file of a FrameOutput directory: frame_NNNNNN.png.
bool IsFrameFileName(const std::string& name);

/// Encodes one RGB image (3 bytes per pixel, rows top to bottom) as PNG bytes.
std::vector<std::uint8_t> EncodeRgbPng(int width, int height, const std::vector<std::uint8_t>& rgb);

class FrameOutput {
 public:
  /// `path` ending in .mp4: a video at `video.fps`; anything else: a directory of PNGs. An
  /// existing directory is replaced only if it holds nothing but frame files. Throws
  /// acro::InputError naming the path when it cannot be written.
  FrameOutput(const std::filesystem::path& path,
              int width,
              int height,
              const VideoWriterOptions& video = {});
  ~FrameOutput();
  FrameOutput(const FrameOutput&) = delete;
  FrameOutput& operator=(const FrameOutput&) = delete;

  bool is_video() const;
  /// Appends frame `index` (its number in the file name of a PNG directory).
  void Write(int index, const std::vector<std::uint8_t>& rgb);
  /// Puts the output in place.
  void Finish();
  int frames_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::capture
