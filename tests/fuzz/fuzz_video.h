#pragma once

// The video reader's fuzz entry point: the bytes as a video file, opened (indexed), read
// sequentially and accessed at random. Opening and every decode accept the file or reject it with
// acro::InputError naming it; anything else is a bug. FFmpeg's own code is not instrumented by the
// fuzzer's build (Debian's libraries), ours is: the index, the seeking and the conversion around
// it. Used by the libFuzzer target (video_fuzz.cc) and by the corpus replay in the suite
// (tests/capture/video_corpus_test.cc).

#include <cstddef>
#include <cstdint>
#include <string>

#include "acro/base/input_error.h"
#include "acro/capture/video.h"
#include "fuzz_files.h"

namespace acro::fuzz {

/// Frames decoded (sequentially and at random) before the end or the first rejected frame; −1 when
/// the file is rejected on open.
inline int FeedVideoReader(const std::uint8_t* data,
                           std::size_t size,
                           const std::string& name = "video.mp4") {
  capture::VideoReaderOptions options;
  options.num_threads = 1;
  int decoded = 0;
  try {
    capture::VideoReader reader(WriteFuzzFile(name, data, size), options);
    const int n = reader.num_frames();
    capture::VideoFrame frame;
    // At most 64 frames of a sequential pass, then a random access at each end and the middle.
    for (int k = 0; k < 64 && reader.ReadNext(&frame); ++k) ++decoded;
    for (int i : {n - 1, n / 2, 0}) {
      reader.Frame(i);
      ++decoded;
    }
  } catch (const InputError&) {
    return decoded == 0 ? -1 : decoded;
  }
  return decoded;
}

}  // namespace acro::fuzz
