#pragma once

// What the video reader and writer share about FFmpeg. Internal to capture/src.

extern "C" {
#include <libavutil/error.h>
#include <libavutil/log.h>
}

#include <mutex>
#include <string>

namespace acro::capture::internal {

/// FFmpeg's text for an error code.
inline std::string AvError(int code) {
  char buffer[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, buffer, sizeof buffer);
  return buffer;
}

/// FFmpeg and its codecs (libx264's statistics) log to stderr by default; a library layer prints
/// nothing (STYLE.md), and every failure reaches the caller through the return codes.
inline void SilenceFfmpegLog() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_QUIET); });
}

}  // namespace acro::capture::internal
