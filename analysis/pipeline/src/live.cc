#include "acro/pipeline/live.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "acro/fig/score_sheet.h"
#include "acro/fig/trampoline.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/calibration.h"

namespace acro::pipeline {

bool LiveRequest::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& s) {
    if (why != nullptr) *why = s;
    return false;
  };
  if (sources.empty()) return fail("no source");
  if (out_dir.empty()) return fail("no output folder");
  if (!(rest_s > 0 && rest_s < 60)) return fail("rest_s must be in (0, 60) s");
  if (!(pre_roll_s >= 0 && pre_roll_s <= 30 && post_roll_s >= 0 && post_roll_s <= 30))
    return fail("the clip's pre- and post-roll must be in [0, 30] s");
  if (duration_s && !(*duration_s > 0)) return fail("the duration must be positive");
  if (!(reconnect_s >= 0 && reconnect_s <= 3600)) return fail("reconnect_s must be in [0, 3600] s");
  return flights.IsValid(why);
}

std::optional<std::vector<LiveJump>> RoutineCutter::AddJump(const LiveJump& jump) {
  std::optional<std::vector<LiveJump>> ended;
  if (!open_.empty() && jump.jump.takeoff_s - open_.back().jump.landing_s >= rest_s_) {
    ended = std::move(open_);
    open_.clear();
  }
  open_.push_back(jump);
  return ended;
}

std::optional<std::vector<LiveJump>> RoutineCutter::OnBed(double now_s) {
  if (open_.empty() || now_s - open_.back().jump.landing_s < rest_s_) return std::nullopt;
  std::optional<std::vector<LiveJump>> ended = std::move(open_);
  open_.clear();
  return ended;
}

std::optional<std::vector<LiveJump>> RoutineCutter::Finish() {
  if (open_.empty()) return std::nullopt;
  std::optional<std::vector<LiveJump>> ended = std::move(open_);
  open_.clear();
  return ended;
}

namespace {

double NaN() {
  return std::numeric_limits<double>::quiet_NaN();
}

nlohmann::json Number(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

nlohmann::json JumpJson(const LiveJump& j) {
  return {{"source", j.source},
          {"jump", j.jump.number},
          {"takeoff_s", j.jump.takeoff_s},
          {"landing_s", j.jump.landing_s},
          {"time_of_flight_s", j.jump.time_of_flight_s()},
          {"apex_above_bed_m", Number(j.jump.apex_above_bed_m)},
          {"landing_frame", j.jump.landing_frame},
          {"landing_px", {j.jump.landing_px.x(), j.jump.landing_px.y()}},
          {"landing_along_bed_m", Number(j.landing_along_bed_m)},
          {"zone", j.zone.empty() ? nlohmann::json() : nlohmann::json(j.zone)},
          {"deduction", j.zone.empty() ? nlohmann::json() : nlohmann::json(j.deduction)},
          {"latency_s", j.latency_s}};
}

std::string JumpLine(const LiveJump& j) {
  std::string where = "landing spot unknown (no camera from the bed)";
  if (std::isfinite(j.landing_along_bed_m))
    where = fmt::format("landed {:+.2f} m along the bed: zone {} ({:.1f})",
                        j.landing_along_bed_m,
                        j.zone,
                        j.deduction);
  return fmt::format(
      "{}  jump {}  flight {:.3f} s (take-off {:.3f} s, landing {:.3f} s)  {}  "
      "[{:.2f} s after landing]",
      j.source,
      j.jump.number,
      j.jump.time_of_flight_s(),
      j.jump.takeoff_s,
      j.jump.landing_s,
      where,
      j.latency_s);
}

// What every source's thread shares: the output folder's files, the lines, the results.
struct Session {
  const LiveRequest* request = nullptr;
  std::optional<vision::Camera> intrinsics;  // read from request->intrinsics
  std::mutex mutex;
  int jumps_fd = -1;
  LiveSummary summary;
  std::vector<capture::LiveSource*> running;

  std::mutex lines;  // on_line one call at a time, never under `mutex`

  void Line(const std::string& line) {
    const std::lock_guard<std::mutex> lock(lines);
    if (request->on_line) request->on_line(line);
  }
  void AddJump(LiveJump j) {
    std::string failure;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      j.latency_s = capture::LiveClockNow() - j.jump.landing_arrival_s;
      const std::string text =
          JumpJson(j).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
      // One write per line, appended: a reader (or a crash) never sees half a line.
      size_t done = 0;
      while (done < text.size()) {
        const ssize_t n = ::write(jumps_fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
          failure = fmt::format("{}: a line could not be written: {}",
                                (request->out_dir / "jumps.jsonl").string(),
                                n < 0 ? std::strerror(errno) : "nothing written");
          break;
        }
        done += static_cast<size_t>(n);
      }
      summary.jumps.push_back(j);
    }
    if (!failure.empty()) Line(failure);
    Line(JumpLine(j));
  }
};

// One source's camera from the bed in its first frame: the watcher and the landing spots.
struct SourceView {
  std::optional<vision::MotionFlightWatcher> watcher;
  std::optional<vision::Camera> camera;
  std::filesystem::path picture;  // where the bed was found (written for the routines' analyses)
};

SourceView FindBed(capture::LiveSource& source,
                   const LiveRequest& request,
                   const vision::Camera* intrinsics,
                   int connection,
                   std::string* how) {
  SourceView view;
  const capture::VideoFrame full = source.FullSizeGrey();
  const vision::BedDetection bed =
      vision::DetectBed(full, fmt::format("{}@frame 0", source.name()));
  view.watcher.emplace(bed, request.flights);
  *how = fmt::format("the bed found in {}", bed.source);
  // The frame kept as a picture: each routine's clip begins with the athlete on the bed, and its
  // analysis finds the bed here instead.
  try {
    std::vector<std::uint8_t> rgb;
    rgb.reserve(full.pixels.size() * 3);
    for (const std::uint8_t g : full.pixels) rgb.insert(rgb.end(), {g, g, g});
    // (one per connection: a routine of an earlier one may still wait for its analysis)
    const std::filesystem::path picture =
        request.out_dir / "bed" /
        (connection == 0 ? source.name() + ".png"
                         : fmt::format("{}-again{}.png", source.name(), connection));
    CreateOutputDirectory(picture.parent_path());
    const std::vector<std::uint8_t> png = capture::EncodeRgbPng(full.width, full.height, rgb);
    WriteFileAtomically(picture, std::string(png.begin(), png.end()));
    view.picture = picture;
  } catch (const InputError& e) {
    *how += fmt::format(" (its picture not kept: {})", e.what());
  }
  try {
    if (intrinsics != nullptr) {
      // The calibration's intrinsics (fitted to this source's picture size), the pose from the bed.
      std::string note;
      const vision::Camera fitted =
          vision::FitCameraToVideo(*intrinsics, full.width, full.height, source.name(), &note);
      const vision::BedCalibration pose =
          vision::CalibrateFromBed(fitted, vision::FigTrampolinePoints(), bed);
      view.camera = pose.calibration.camera;
      *how += fmt::format(
          ", the camera posed on it with the intrinsics of {} (camera {}; {:.2f} px "
          "RMS){}",
          request.intrinsics.string(),
          intrinsics->name,
          pose.calibration.rms_px,
          note.empty() ? "" : "; " + note);
    } else {
      const vision::BedFocalCalibration cam = vision::CalibrateFromBedUnknownFocal(
          full.width, full.height, vision::FigTrampolinePoints(), bed);
      view.camera = cam.bed.calibration.camera;
      *how += fmt::format(", the camera from it (focal length {:.0f} px, {:.2f} px RMS)",
                          cam.focal_px,
                          cam.bed.calibration.rms_px);
    }
  } catch (const InputError& e) {
    *how += fmt::format("; no camera from it ({}): landing spots not measured", e.what());
  }
  return view;
}

// Where the soles' point lands on the bed's middle line (y = 0 of the bed's axes), m from the
// centre along the bed.
double AlongBed(const vision::Camera& camera, const Eigen::Vector2d& px) {
  const Eigen::Vector3d c = camera.CentreInWorld();
  const Eigen::Vector3d d = camera.RayInWorld(px);
  if (std::abs(d.y()) < 1e-9) return NaN();
  const double t = -c.y() / d.y();
  return t > 0 ? c.x() + t * d.x() : NaN();
}

void CloseRoutine(Session& session,
                  capture::LiveSource& source,
                  std::vector<LiveJump> jumps,
                  bool interrupted,
                  double offset_s,
                  const std::filesystem::path& bed_picture) {
  const LiveRequest& request = *session.request;
  LiveRoutine r;
  r.source = source.name();
  r.bed_picture = bed_picture;
  r.jumps = std::move(jumps);
  r.first_takeoff_s = r.jumps.front().jump.takeoff_s;
  r.last_landing_s = r.jumps.back().jump.landing_s;
  r.interrupted = interrupted;
  {
    const std::lock_guard<std::mutex> lock(session.mutex);
    r.number = 1 + static_cast<int>(
                       std::count_if(session.summary.routines.begin(),
                                     session.summary.routines.end(),
                                     [&](const LiveRoutine& o) { return o.source == r.source; }));
  }
  r.folder = request.out_dir / "routines" / fmt::format("{}-{:03d}", r.source, r.number);
  double sum = 0;
  nlohmann::json jumps_json = nlohmann::json::array();
  for (const LiveJump& j : r.jumps) {
    sum += j.jump.time_of_flight_s();
    jumps_json.push_back(JumpJson(j));
  }
  double clip_start = NaN(), clip_end = NaN();
  try {
    CreateOutputDirectory(r.folder);
    // (the clip in the connection's own stream times; reported on the session's)
    clip_start = offset_s + source.SaveClip(r.first_takeoff_s - request.pre_roll_s - offset_s,
                                            r.last_landing_s + request.post_roll_s - offset_s,
                                            r.folder / "clip.ts",
                                            &clip_end);
    clip_end += offset_s;
    r.clip_start_s = clip_start;
  } catch (const InputError& e) {
    r.clip_error = e.what();
  }
  const nlohmann::json j = {
      {"source", r.source},
      {"routine", r.number},
      {"first_takeoff_s", r.first_takeoff_s},
      {"last_landing_s", r.last_landing_s},
      {"interrupted", r.interrupted},
      {"jumps", jumps_json},
      {"time_of_flight_sum_s", sum},
      {"T", fig::TruncateTimeOfFlight(sum, 0.005)},
      {"clip", r.clip_error.empty() ? nlohmann::json("clip.ts") : nlohmann::json()},
      {"clip_start_s", Number(clip_start)},
      {"clip_end_s", Number(clip_end)},
      {"clip_error", r.clip_error.empty() ? nlohmann::json() : nlohmann::json(r.clip_error)},
      {"method", "image motion: the athlete's silhouette against the bed's rest line, one camera"}};
  try {
    WriteFileAtomically(r.folder / "routine.json",
                        j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  } catch (const InputError& e) {
    r.clip_error += (r.clip_error.empty() ? "" : "; ") + std::string(e.what());
  }
  session.Line(fmt::format(
      "{}  routine {}{}: {} jump{} from {:.2f} s to {:.2f} s, time of flight {:.3f} s (T {:.3f})"
      "  → {}{}",
      r.source,
      r.number,
      r.interrupted ? " (interrupted: the source stopped in the air)" : "",
      r.jumps.size(),
      r.jumps.size() == 1 ? "" : "s",
      r.first_takeoff_s,
      r.last_landing_s,
      sum,
      fig::TruncateTimeOfFlight(sum, 0.005),
      r.folder.string(),
      r.clip_error.empty() ? "" : "  (" + r.clip_error + ")"));
  if (request.on_routine) request.on_routine(r);
  const std::lock_guard<std::mutex> lock(session.mutex);
  session.summary.routines.push_back(std::move(r));
}

// One connection to a source, its frames watched until it ends; `offset_s` puts its stream times
// on the session's (the source's first connection's) time line. Returns the connection's end.
void WatchConnection(Session& session,
                     int index,
                     capture::LiveSource& source,
                     int connection,
                     int* jumps_so_far,
                     std::vector<double>* offsets) {
  const LiveRequest& request = *session.request;
  LiveSourceSummary& summary = session.summary.sources[static_cast<size_t>(index)];
  SourceView view;
  RoutineCutter cutter(request.rest_s);
  double offset = 0.0;
  capture::LiveFrame frame;
  while (source.Next(&frame)) {
    if (frame.picture.index == 0) {
      // A connection after the first: its stream time zero where its first frame arrived.
      if (connection == 0)
        summary.first_arrival_s = frame.arrival_s;
      else
        offset = frame.arrival_s - summary.first_arrival_s;
      try {
        view = FindBed(source,
                       request,
                       session.intrinsics ? &*session.intrinsics : nullptr,
                       connection,
                       &summary.bed);
        if (connection == 0) summary.bed_picture = view.picture;
      } catch (const InputError& e) {
        summary.bed = e.what();
        session.Line(fmt::format("{}: recording only, no jumps: {}", summary.name, e.what()));
      }
    }
    // Frames 30–149: past the burst FFmpeg reads to learn the stream (its arrival unknown).
    if (connection == 0 && frame.picture.index >= 30 && frame.picture.index < 150)
      offsets->push_back(frame.arrival_s - frame.picture.time_s);
    frame.picture.time_s += offset;
    std::vector<vision::MotionJump> landed;
    if (view.watcher) {
      try {
        landed = view.watcher->Add(frame.picture, frame.arrival_s);
      } catch (const InputError& e) {
        session.Line(fmt::format("{}: jumps no longer watched: {}", summary.name, e.what()));
        view.watcher.reset();
      }
    }
    if (request.on_frame) {
      LiveFrameSeen seen;
      seen.source_index = index;
      seen.source = &summary.name;
      seen.picture = &frame.picture;
      seen.arrival_s = frame.arrival_s;
      seen.picture_per_full_px = double(frame.picture.width) / std::max(1, source.width());
      if (view.watcher) {
        seen.rest_line = &view.watcher->rest_line();
        seen.athlete = &view.watcher->last_sightings();
        seen.in_air = view.watcher->in_air();
      }
      request.on_frame(seen);
    }
    if (!view.watcher) continue;
    for (const vision::MotionJump& m : landed) {
      LiveJump j;
      j.source = summary.name;
      j.jump = m;
      j.jump.number = ++*jumps_so_far;  // numbered on through a reconnection
      j.landing_along_bed_m = view.camera ? AlongBed(*view.camera, m.landing_px) : NaN();
      if (std::isfinite(j.landing_along_bed_m))
        j.deduction = fig::HdZones::Default().DeductionAt({j.landing_along_bed_m, 0.0}, &j.zone);
      // (measured again when its line is written; routine.json keeps this one)
      j.latency_s = capture::LiveClockNow() - m.landing_arrival_s;
      if (auto ended = cutter.AddJump(j))
        CloseRoutine(session, source, std::move(*ended), false, offset, view.picture);
      session.AddJump(j);
    }
    if (!view.watcher->in_air())
      if (auto ended = cutter.OnBed(view.watcher->last_time_s()))
        CloseRoutine(session, source, std::move(*ended), false, offset, view.picture);
  }
  // A jump in the air when the source ended is lost: the routine is interrupted there. One
  // that ended on the bed is whole to its last landing, however soon after it the source stopped.
  const bool in_air = view.watcher && view.watcher->in_air();
  if (auto open = cutter.Finish())
    CloseRoutine(session, source, std::move(*open), in_air, offset, view.picture);
}

// A source listed as running (for the monitor's Stop) for exactly as long as it exists.
class Running {
 public:
  Running(Session& session, capture::LiveSource* source) : session_(session), source_(source) {
    const std::lock_guard<std::mutex> lock(session_.mutex);
    session_.running.push_back(source_);
  }
  ~Running() {
    const std::lock_guard<std::mutex> lock(session_.mutex);
    session_.running.erase(std::find(session_.running.begin(), session_.running.end(), source_));
  }
  Running(const Running&) = delete;
  Running& operator=(const Running&) = delete;

 private:
  Session& session_;
  capture::LiveSource* source_;
};

// Opens the source again until it sends or `reconnect_s` has passed (a camera plugged back in, a
// server restarted: each may refuse at once for a while), or the session stops.
std::unique_ptr<capture::LiveSource> OpenAgain(const LiveRequest& request,
                                               const capture::LiveSourceOptions& options,
                                               const std::string& url,
                                               const std::atomic<bool>& stop_all,
                                               std::string* why) {
  const double deadline = capture::LiveClockNow() + request.reconnect_s;
  for (;;) {
    const double left = deadline - capture::LiveClockNow();
    if (left <= 0 || stop_all.load()) return nullptr;
    capture::LiveSourceOptions o = options;
    o.open_timeout_s = left;
    try {
      return std::make_unique<capture::LiveSource>(url, o);
    } catch (const InputError& e) {
      *why = e.what();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
}

void WatchSourceConnections(Session& session, int index, const std::atomic<bool>& stop_all) {
  LiveSourceSummary& summary = session.summary.sources[static_cast<size_t>(index)];
  const LiveRequest& request = *session.request;
  std::vector<double> offsets;
  int jumps = 0;
  for (int connection = 0;; ++connection) {
    capture::LiveSourceOptions options = request.source;
    options.name = summary.name;
    options.stop = &stop_all;
    options.record_prefix =
        request.out_dir / "recording" /
        (connection == 0 ? summary.name : fmt::format("{}-again{}", summary.name, connection));
    std::unique_ptr<capture::LiveSource> source;
    if (connection == 0) {
      try {
        source = std::make_unique<capture::LiveSource>(summary.url, options);
      } catch (const InputError& e) {
        summary.failure = e.what();
        session.Line(fmt::format("{}: not recorded: {}", summary.name, e.what()));
        return;
      }
    } else {
      std::string why;
      source = OpenAgain(request, options, summary.url, stop_all, &why);
      if (!source) {
        if (!stop_all.load())
          session.Line(fmt::format(
              "{}: did not come back within {:g} s: {}", summary.name, request.reconnect_s, why));
        break;
      }
      session.Line(fmt::format("{}: sending again", summary.name));
    }
    {
      const Running running(session, source.get());
      WatchConnection(session, index, *source, connection, &jumps, &offsets);
    }
    {
      const std::lock_guard<std::mutex> lock(session.mutex);
      summary.frames += source->frames_decoded();
      summary.packets_recorded += source->packets_recorded();
      summary.segments.insert(
          summary.segments.end(), source->segments().begin(), source->segments().end());
      summary.end_reason = source->end_reason();
      summary.ended_normally = source->ended_normally();
    }
    // A stream or a camera that stopped may come back (a Wi-Fi drop, a cable put back): waited
    // for, recorded and watched anew. A file's end, a stop, and a recording that cannot be
    // written (a full disk) are the end.
    if (!source->may_come_back() || stop_all.load() || !(request.reconnect_s > 0)) break;
    session.Line(fmt::format("{}: {}; waiting up to {:g} s for it to come back",
                             summary.name,
                             source->end_reason(),
                             request.reconnect_s));
  }
  std::sort(offsets.begin(), offsets.end());
  summary.stream_to_clock_s = offsets.empty() ? NaN() : offsets[offsets.size() / 2];
  session.Line(fmt::format("{}: {} ({} frames recorded in {} segment{})",
                           summary.name,
                           summary.end_reason,
                           summary.frames,
                           summary.segments.size(),
                           summary.segments.size() == 1 ? "" : "s"));
}

void WatchSource(Session& session, int index, const std::atomic<bool>& stop_all) {
  LiveSourceSummary& summary = session.summary.sources[static_cast<size_t>(index)];
  // Nothing a source meets may end the others: whatever escapes is its one line.
  try {
    WatchSourceConnections(session, index, stop_all);
  } catch (const std::exception& e) {
    {
      const std::lock_guard<std::mutex> lock(session.mutex);
      summary.end_reason = std::string("stopped by an error: ") + e.what();
      summary.ended_normally = false;
    }
    session.Line(fmt::format("{}: {}", summary.name, summary.end_reason));
  }
}

// Unique names for the sources' files: their own, with -2, -3 … where two would clash.
std::vector<std::string> SourceNames(const std::vector<std::string>& urls,
                                     const std::string& given) {
  std::vector<std::string> names;
  for (const std::string& url : urls) {
    const std::string base = given.empty() ? capture::LiveSourceName(url) : given;
    std::string name = base;
    for (int k = 2; std::find(names.begin(), names.end(), name) != names.end(); ++k)
      name = fmt::format("{}-{}", base, k);
    names.push_back(name);
  }
  return names;
}

void WriteSummary(const LiveRequest& request, const LiveSummary& summary) {
  nlohmann::json sources = nlohmann::json::array();
  for (const LiveSourceSummary& s : summary.sources) {
    nlohmann::json segs = nlohmann::json::array();
    for (const auto& p : s.segments) segs.push_back(p.filename().string());
    sources.push_back(
        {{"name", s.name},
         {"url", capture::RedactedUrl(s.url)},
         {"frames", s.frames},
         {"packets_recorded", s.packets_recorded},
         {"segments", segs},
         {"end", s.end_reason},
         {"ended_normally", s.ended_normally},
         {"bed", s.bed},
         {"bed_picture",
          s.bed_picture.empty()
              ? nlohmann::json()
              : nlohmann::json(std::filesystem::relative(s.bed_picture, request.out_dir).string())},
         {"failure", s.failure.empty() ? nlohmann::json() : nlohmann::json(s.failure)},
         {"stream_to_clock_s", Number(s.stream_to_clock_s)},
         {"offset_to_first_s", Number(s.offset_to_first_s)}});
  }
  nlohmann::json routines = nlohmann::json::array();
  for (const LiveRoutine& r : summary.routines)
    routines.push_back({{"source", r.source},
                        {"routine", r.number},
                        {"folder", std::filesystem::relative(r.folder, request.out_dir).string()},
                        {"jumps", r.jumps.size()},
                        {"first_takeoff_s", r.first_takeoff_s},
                        {"last_landing_s", r.last_landing_s},
                        {"interrupted", r.interrupted}});
  WriteFileAtomically(
      request.out_dir / "live.json",
      nlohmann::json{{"sources", sources}, {"jumps", summary.jumps.size()}, {"routines", routines}}
              .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
          "\n");
}

}  // namespace

LiveSummary RunLive(const LiveRequest& request, const std::atomic<bool>* stop) {
  std::string why;
  if (!request.IsValid(&why)) throw std::invalid_argument("LiveRequest: " + why);
  CheckOutputDirectory(request.out_dir);
  std::error_code ec;
  if (std::filesystem::exists(request.out_dir, ec) &&
      !std::filesystem::is_empty(request.out_dir, ec))
    throw InputError(request.out_dir.string(),
                     "",
                     "not empty: a live session never replaces an earlier one's recordings "
                     "(name a new folder)");
  // The intrinsics read before anything is written: a bad file costs nothing.
  std::optional<vision::Camera> intrinsics;
  if (!request.intrinsics.empty()) {
    const std::vector<vision::Camera> cameras = vision::ReadCameras(request.intrinsics);
    intrinsics = request.camera.empty() && cameras.size() == 1
                     ? cameras[0]
                     : vision::FindCamera(cameras, request.camera, request.intrinsics.string());
  }
  CreateOutputDirectory(request.out_dir);
  Session session;
  session.request = &request;
  session.intrinsics = intrinsics;
  const std::filesystem::path jumps = request.out_dir / "jumps.jsonl";
  session.jumps_fd =
      ::open(jumps.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
  if (session.jumps_fd < 0)
    throw InputError(jumps.string(), "", std::string("cannot be created: ") + std::strerror(errno));
  const std::vector<std::string> names = SourceNames(request.sources, request.source.name);
  for (size_t i = 0; i < request.sources.size(); ++i) {
    LiveSourceSummary s;
    s.name = names[i];
    s.url = request.sources[i];
    session.summary.sources.push_back(s);
  }
  std::atomic<bool> stop_all{false};
  std::vector<std::thread> threads;
  for (size_t i = 0; i < request.sources.size(); ++i)
    threads.emplace_back(
        [&session, &stop_all, i] { WatchSource(session, static_cast<int>(i), stop_all); });
  // The clock and the caller's stop: every source told at once.
  std::atomic<bool> done{false};
  std::thread monitor([&] {
    const double start = capture::LiveClockNow();
    while (!done.load()) {
      const bool time_up =
          request.duration_s && capture::LiveClockNow() - start >= *request.duration_s;
      if (time_up || (stop != nullptr && stop->load())) {
        stop_all = true;
        const std::lock_guard<std::mutex> lock(session.mutex);
        for (capture::LiveSource* s : session.running) s->Stop();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  for (std::thread& t : threads) t.join();
  done = true;
  monitor.join();
  ::close(session.jumps_fd);
  // The sources on one time line: each one's stream time that arrived with the first source's
  // stream time zero.
  const LiveSourceSummary* first = nullptr;
  for (const LiveSourceSummary& s : session.summary.sources)
    if (first == nullptr && std::isfinite(s.stream_to_clock_s)) first = &s;
  for (LiveSourceSummary& s : session.summary.sources)
    s.offset_to_first_s = first != nullptr ? s.stream_to_clock_s - first->stream_to_clock_s : NaN();
  WriteSummary(request, session.summary);
  return std::move(session.summary);
}

}  // namespace acro::pipeline
