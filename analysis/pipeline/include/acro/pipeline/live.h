#pragma once

/// \file
/// In the hall (docs/live.md): live cameras watched as they send, every jump's line a moment after
/// it lands, every routine cut into its own folder. One thread per source reads it
/// (capture::LiveSource: recorded as it comes, frame-exact), finds the bed in its first frame and
/// the camera from it (the focal length too), watches the frames for jumps
/// (vision::MotionFlightWatcher) and cuts routines: a run of jumps whose contacts with the bed are
/// short, ended when the athlete stays on the bed. `acrolab live` calls it, the studio's live mode
/// too (docs/live.md).

#include <atomic>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "acro/capture/live_source.h"
#include "acro/vision/motion_flights.h"

namespace acro::pipeline {

/// One jump as `jumps.jsonl` has it.
struct LiveJump {
  std::string source;
  vision::MotionJump jump;
  /// Where it landed along the bed (m from the centre, the camera's image of the bed's middle
  /// line), its zone and deduction counting the travel along the bed only (one side camera sees
  /// nothing across); NaN / empty without a camera from the bed.
  double landing_along_bed_m = 0.0;
  std::string zone;
  double deduction = 0.0;
  /// The line was written this long after the landing frame arrived (s).
  double latency_s = 0.0;
};

struct LiveRoutine {
  std::string source;
  int number = 0;
  std::vector<LiveJump> jumps;
  double first_takeoff_s = 0.0, last_landing_s = 0.0;
  /// The source stopped while the athlete was in the air: that jump is lost, the routine is
  /// scored to its last landing. (A routine never spans two connections to a source.)
  bool interrupted = false;
  std::filesystem::path folder;  ///< routines/<source>-NNN/ (clip.ts, routine.json)
  /// The clip's first frame on the session's time line (s): a time t of the clip (its analysis's
  /// times) is clip_start_s + t there. NaN without a clip.
  double clip_start_s = std::numeric_limits<double>::quiet_NaN();
  /// The picture the session found its source's bed in (bed/<source>.png: its first frame), for
  /// the routine's analysis (the clip's own first frame has the athlete standing on the bed);
  /// empty when none was found.
  std::filesystem::path bed_picture;
  std::string clip_error;  ///< why the clip could not be written, if it could not
};

/// One frame as its source's thread saw it, for a window that shows the sources (the studio's
/// live mode keeps them in its delay buffer). Everything pointed to lives for the call only.
struct LiveFrameSeen {
  int source_index = 0;  ///< in LiveRequest::sources
  const std::string* source = nullptr;
  /// RGB at the analysis width; time_s on the session's time line (the source's first
  /// connection's stream time), index counted from each connection's first frame.
  const capture::VideoFrame* picture = nullptr;
  double arrival_s = 0.0;  ///< when its packet arrived (capture::LiveClockNow)
  /// The picture's pixels per pixel of the full picture (the bed and the athlete are given in
  /// the full picture's pixels).
  double picture_per_full_px = 1.0;
  const vision::BedLine* rest_line = nullptr;  ///< null without a bed
  /// The athlete in the frames the watcher looked at with this one: none while it still makes
  /// its background, then the frames that waited for it (earlier ones) and this one; null
  /// without a bed.
  const std::vector<vision::MotionSighting>* athlete = nullptr;
  bool in_air = false;
};

struct LiveRequest {
  std::vector<std::string> sources;  ///< URLs, devices or files (LiveSource)
  /// A new or empty folder: recording/, jumps.jsonl, routines/, live.json. A session never
  /// replaces an earlier one's files.
  std::filesystem::path out_dir;
  capture::LiveSourceOptions source;  ///< timeouts, pace, segment length (name/prefix per source)
  vision::MotionFlightOptions flights;
  /// The cameras' intrinsics (a calibration file in any format `acrolab` reads, e.g. from
  /// `calibrate intrinsics` with a checkerboard; `camera` names one of several): the focal length,
  /// principal point and distortion used, the pose still found on the bed each source sees (the
  /// hall's world is the bed's). Empty: the focal length too from the bed's perspective. Every
  /// source uses it (a session of several cameras of one model, or one camera).
  std::filesystem::path intrinsics;
  std::string camera;
  /// A routine ends when the athlete has stayed on the bed this long after a landing (s); the
  /// contacts between a routine's jumps are shorter (about 0.3–0.6 s on a competition bed).
  double rest_s = 1.5;
  /// A routine's clip starts this long before its first take-off and ends after its last landing.
  double pre_roll_s = 1.0, post_roll_s = 1.0;
  /// A stream or camera that stopped sending is waited for this long to come back (opened again:
  /// recorded in new segments, watched anew, its times on the first connection's time line); 0:
  /// its stop is its end. Files end at their end.
  double reconnect_s = 30.0;
  /// Stop after this long (s of the shared clock), all sources; unset: until they end or Stop.
  std::optional<double> duration_s;
  /// Each line a person watching would read (a jump, a routine, a source's end), as it happens;
  /// called from the sources' threads, one call at a time.
  std::function<void(const std::string&)> on_line;
  /// Each routine as it is cut (its folder written), from the source's thread: a door queues its
  /// analysis here.
  std::function<void(const LiveRoutine&)> on_routine;
  /// Every frame after it was watched, from its source's thread (a window's buffer: keep the
  /// call short, the next frame waits for it).
  std::function<void(const LiveFrameSeen&)> on_frame;
  bool IsValid(std::string* why) const;
};

struct LiveSourceSummary {
  std::string name, url;
  int frames = 0;
  long long packets_recorded = 0;
  std::vector<std::filesystem::path> segments;
  std::string end_reason;
  bool ended_normally = false;
  std::string bed;                    ///< how the bed and camera were found, or why not
  std::filesystem::path bed_picture;  ///< bed/<name>.png, the frame it was found in
  std::string failure;                ///< the source could not be opened (one line)
  double first_arrival_s = 0.0;       ///< its first frame on the shared clock
  /// Arrival − stream time (s), the median over its frames 30–149 (before them FFmpeg reads ahead
  /// to learn the stream, and those frames come out together); NaN with fewer frames.
  double stream_to_clock_s = 0.0;
  /// How much later this source's stream time 0 arrived than the first source's (s): the offset
  /// that puts two cameras started apart side by side; 0 for the first source.
  double offset_to_first_s = 0.0;
};

struct LiveSummary {
  std::vector<LiveSourceSummary> sources;
  std::vector<LiveJump> jumps;
  std::vector<LiveRoutine> routines;
};

/// Runs the session until every source has ended, `duration_s` has passed or `stop` becomes true.
/// Throws acro::InputError naming the folder when it holds an earlier session; a source that
/// cannot be opened is one line (on_line and its summary) and the others go on.
LiveSummary RunLive(const LiveRequest& request, const std::atomic<bool>* stop = nullptr);

/// The routine cut by itself: jumps in, routines out (per source).
class RoutineCutter {
 public:
  explicit RoutineCutter(double rest_s) : rest_s_(rest_s) {}
  /// A jump that landed; returns the routine it ended, if the contact before it was a rest.
  std::optional<std::vector<LiveJump>> AddJump(const LiveJump& jump);
  /// The stream's time now (the last frame seen) while the athlete is on the bed: returns the
  /// routine that ended when the rest has lasted `rest_s`.
  std::optional<std::vector<LiveJump>> OnBed(double now_s);
  /// The source ended: what is open, if anything (interrupted).
  std::optional<std::vector<LiveJump>> Finish();

 private:
  double rest_s_;
  std::vector<LiveJump> open_;
};

}  // namespace acro::pipeline
