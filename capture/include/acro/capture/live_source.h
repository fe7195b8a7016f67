#pragma once

// Live video sources (docs/live.md): a camera, a network stream or a file played at its own pace,
// read as it comes in. Every packet of the video stream is recorded as it arrives, copied (never
// re-encoded: the recording decodes to the very frames the source sent) into MPEG-TS segments that
// open when cut off at any byte (a pulled cable, a crash); the frames are decoded for the analyses
// that watch them. Each frame carries two times: the stream's own (from its first frame) and its
// arrival on one clock shared by every source of the process (LiveClockNow), which is what puts two
// cameras side by side. FFmpeg stays in capture/src. The frames are handed out scaled down (RGB or
// grey) for the analyses that watch them.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "acro/capture/video.h"

namespace acro::capture {

/// How a live source ended.
enum class LiveEnd {
  kRunning,      ///< it has not
  kFileEnded,    ///< a file's end: the normal end
  kStreamEnded,  ///< the sender closed the stream (it may come back)
  kStalled,      ///< it stopped sending for the stall timeout (it may come back)
  kStopped,      ///< Stop(), or the options' stop flag
  kReadError,    ///< FFmpeg could not read it
  kRecordError,  ///< the recording could not be written (a full disk): it stopped there
};

/// `url` with a user name and password given before an '@' replaced by "***" (for messages,
/// names and files: a camera's password never reaches them).
std::string RedactedUrl(const std::string& url);

/// Seconds on the one steady clock of every live source of this process (from its first call).
double LiveClockNow();

/// A name for a source's messages and files from its URL: a file's stem, a device's last
/// component, a network source's host and port ("127.0.0.1_5000", never a user or password),
/// letters, digits, - and _ only.
std::string LiveSourceName(const std::string& url);

struct LiveSourceOptions {
  /// Names the source in messages and file names; empty: from the URL (its file stem, device or
  /// host and port).
  std::string name;
  /// A source that sends no frame within this many seconds of opening is refused, naming it.
  double open_timeout_s = 10.0;
  /// A source that stops sending for this long has ended ("stopped sending after …").
  double stall_timeout_s = 5.0;
  /// Play a file at its own pace (frame times kept against the clock) rather than as fast as it
  /// decodes. Only for files: a camera or a stream sets its own pace.
  bool pace_files = true;
  /// Where the recording goes: segments <prefix>-000.ts, -001.ts, …; empty: not recorded. An
  /// existing file there is never replaced (the source is refused naming it).
  std::filesystem::path record_prefix;
  /// A new segment starts at the first keyframe after this many seconds.
  double segment_s = 60.0;
  /// The frames handed out are scaled to this width (height in proportion); 0: full size.
  int analysis_width = 640;
  /// ... in colour (RGB: an athlete's skin against a grey wall is told by its colour) or grey.
  VideoPixels analysis_pixels = VideoPixels::kRgb;
  /// How much of the stream is kept in memory for clips (SaveClip), s.
  double clip_memory_s = 120.0;
  int decoder_threads = 1;
  /// When set and true, opening and reading stop as soon as they can (as Stop() does): a session
  /// stops a source that is still opening.
  const std::atomic<bool>* stop = nullptr;
};

/// One frame as it came in.
struct LiveFrame {
  /// RGB or grey as the options say, scaled to the analysis width; index: frames since the first;
  /// time_s: stream time from the first frame.
  VideoFrame picture;
  /// When its packet's first byte arrived (a stream: the read that took it; a played file: when
  /// its time came), on LiveClockNow's clock.
  double arrival_s = 0.0;
};

/// One live source. Not thread-safe except Stop(): one thread reads it.
class LiveSource {
 public:
  /// Opens `url`: a file path, a device (/dev/video*, through FFmpeg's V4L2 input), or a network
  /// URL FFmpeg reads (udp://, rtp://, rtsp://, rtmp://, srt://, http://). Throws acro::InputError
  /// naming the source when it does not exist, cannot be opened, holds no video stream, or sends
  /// no frame within the open timeout; and naming the recording's file when it cannot be written.
  LiveSource(const std::string& url, const LiveSourceOptions& options = {});
  ~LiveSource();
  LiveSource(const LiveSource&) = delete;
  LiveSource& operator=(const LiveSource&) = delete;

  /// The next frame; false once the source has ended (end_reason() says how). What was recorded
  /// up to then is flushed to disk and stays playable.
  bool Next(LiveFrame* frame);
  /// The last frame handed out, grey at full size (for finding the bed, a picture).
  VideoFrame FullSizeGrey();
  /// Makes Next() return false as soon as it can, from any thread (a blocking read is cut short).
  void Stop();

  const std::string& name() const;
  const std::string& url() const;
  int width() const;  ///< full size, as coded
  int height() const;
  double nominal_fps() const;
  /// Empty while the source runs; then "the file ended", "stopped sending after N s", "stopped"
  /// (Stop()), or a read error.
  const std::string& end_reason() const;
  /// True when the source ended by its own end (a file's), not by a failure or a stall.
  bool ended_normally() const;
  LiveEnd end_cause() const;
  /// True when what ended it may pass (a stream or a camera that stalled, closed or failed to
  /// read): opened again, it may send. A file's end, a stop and a recording that cannot be written
  /// are ends.
  bool may_come_back() const;
  const std::vector<std::filesystem::path>& segments() const;
  int frames_decoded() const;
  long long packets_recorded() const;

  /// Writes the packets from the keyframe at or before `from_s` up to `to_s` (stream times) as one
  /// MPEG-TS file, whole or not at all. Returns the stream time of the clip's first frame; throws
  /// acro::InputError naming `path` when that part is no longer in memory or cannot be written.
  /// `*end_s` (when given): the stream time of the clip's last packet — earlier than `to_s` when
  /// the stream has not sent that far yet.
  double SaveClip(double from_s,
                  double to_s,
                  const std::filesystem::path& path,
                  double* end_s = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::capture
