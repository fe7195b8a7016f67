#pragma once

// The 10 s 1080p 30 fps H.264 file the video and overlay benchmarks read (ffmpeg's testsrc2, 4 s
// groups of pictures), written once into the temporary directory by the ffmpeg command line.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace acro::testing {

/// Its path, or an empty path when ffmpeg could not make it.
inline const std::filesystem::path& Generated1080pVideo() {
  static const std::filesystem::path path = [] {
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() / "acrolab_video_bench_1080p30.mp4";
    if (!std::filesystem::exists(p)) {
      const std::string command =
          "ffmpeg -v error -y -f lavfi -i testsrc2=size=1920x1080:rate=30 -t 10 -c:v libx264 "
          "-preset veryfast -g 120 -pix_fmt yuv420p '" +
          p.string() + "'";
      if (std::system(command.c_str()) != 0) return std::filesystem::path();
    }
    return p;
  }();
  return path;
}

}  // namespace acro::testing
