#include "acro/studio/session.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/body_mesh.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/pipeline/monocular_input.h"
#include "acro/pipeline/steps.h"

namespace acro::studio {

namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

}  // namespace

bool OneVideoAlone(const SessionFiles& files) {
  return files.trial.empty() && files.videos.size() == 1;
}

pipeline::TrialInput Session::OpenTrialAndVideos(const acro::Progress& steps) {
  steps.ReportOrThrow("reading " + files_.trial, 0, 1);
  // The trial as every door opens it (the pipeline): read once, upright, its athlete or the one
  // default body.
  pipeline::TrialRequest request;
  request.trial = files_.trial;
  request.athlete.profile = files_.athlete;
  pipeline::TrialInput input = pipeline::OpenTrial(request);
  warnings_ = input.warnings;
  if (!input.athlete.warning.empty()) warnings_.push_back(input.athlete.warning);
  // The videos and their cameras before the work: a wrong calibration costs nothing.
  for (const VideoFiles& v : files_.videos) {
    pipeline::VideoRequest video;
    video.video = v.video;
    video.calibration = v.calibration;
    video.camera = v.camera;
    if (v.offset_s)
      video.sync.offset_s = *v.offset_s;
    else
      video.sync.kind = pipeline::SyncRequest::Kind::kAuto;
    Video opened;
    opened.input = std::make_unique<pipeline::VideoInput>(video);
    for (const std::string& w : opened.input->warnings()) warnings_.push_back(w);
    videos_.push_back(std::move(opened));
  }
  return input;
}

pipeline::TrialInput Session::OpenOneVideo(const acro::Progress& steps,
                                           analysis::TrialAnalysisOptions* options) {
  // As `acrolab analyze --video V [--calib C | --detect-bed]` runs it (docs/one-camera.md): the
  // athlete detected (the cache beside the video reused), the camera from its calibration or
  // from the bed in the first frame, the depth from the flights' physics; the video then shown
  // on its own time line.
  const VideoFiles& v = files_.videos[0];
  pipeline::MonocularRequest request;
  request.video = v.video;
  request.calibration = v.calibration;
  request.camera = v.camera;
  request.detect_bed = v.calibration.empty();
  request.athlete.profile = files_.athlete;
  pipeline::MonocularInput mono = pipeline::OpenMonocular(request, steps);
  pipeline::UseOneCamera(mono, request, options);
  warnings_ = mono.input.warnings;
  if (!mono.input.athlete.warning.empty()) warnings_.push_back(mono.input.athlete.warning);
  if (v.offset_s && *v.offset_s != 0)
    warnings_.push_back(
        fmt::format("{}: offset_s {:g} s not used: a video analysed alone is its "
                    "own time line",
                    v.video,
                    *v.offset_s));
  Video opened;
  opened.input = std::make_unique<pipeline::VideoInput>(*pipeline::OneCameraVideo(mono, request));
  for (const std::string& w : opened.input->warnings()) warnings_.push_back(w);
  videos_.push_back(std::move(opened));
  return std::move(mono.input);
}

std::unique_ptr<Session> Session::Open(const SessionFiles& files, const Progress& progress) {
  std::unique_ptr<Session> s(new Session());
  s->files_ = files;
  const bool alone = OneVideoAlone(files);
  if (files.trial.empty() && !alone)
    throw InputError("", "trial", "no trial to open (or one video to analyse alone)");
  if (files.videos.size() > size_t(kMaxVideos))
    throw InputError(files.videos.back().video,
                     "video",
                     "at most " + std::to_string(kMaxVideos) + " videos in a session, got " +
                         std::to_string(files.videos.size()));
  for (const VideoFiles& v : files.videos)
    if (v.video.empty() || (v.calibration.empty() && !alone))
      throw InputError(v.video.empty() ? v.calibration : v.video,
                       "video",
                       "a video and its camera calibration go together");
  acro::Progress steps;
  steps.report = progress;
  analysis::TrialAnalysisOptions options;
  pipeline::TrialInput input =
      alone ? s->OpenOneVideo(steps, &options) : s->OpenTrialAndVideos(steps);
  const std::string what = alone ? files.videos[0].video : files.trial;
  steps.ReportOrThrow("analysing " + what, 0, 1);
  // The inverse kinematics' progress, frame by frame; Cancel stops it within ten frames.
  std::atomic<bool> stop{false};
  if (progress) {
    options.reconstruction.progress = [&](int done, int total) {
      if (!progress("analysing " + what + ": inverse kinematics", done, total)) stop = true;
    };
    options.cancelled = [&] { return stop.load(); };
  }
  s->analysis_ = std::make_unique<analysis::TrialAnalysis>(pipeline::Analyze(input, options));
  for (const std::string& w : s->analysis_->warnings) s->warnings_.push_back(w);
  s->trial_ = std::make_unique<capture::Trial>(std::move(input.trial));
  s->body_ = input.athlete.body;
  s->scene_ = std::make_unique<analysis::TrialScene>(
      *s->trial_,
      *s->analysis_,
      s->body_,
      analysis::MakeEllipsoidBodyMesh(s->body_, analysis::OverlayBodyMeshOptions()));
  // Each video synced and its silhouettes checked as analyze does (the pipeline's AttachVideo);
  // the jumps' median IoU is the first video's.
  for (size_t k = 0; k < s->videos_.size(); ++k) {
    Video& video = s->videos_[k];
    const std::string which =
        s->videos_.size() > 1 ? fmt::format(" (video {} of {})", k + 1, s->videos_.size()) : "";
    acro::Progress step;
    if (progress)
      step.report = [&](const std::string& name, int done, int total) {
        return progress(name + which, done, total);
      };
    const pipeline::VideoCheck check =
        pipeline::CheckVideo(*video.input, *s->trial_, s->body_, *s->analysis_, step);
    if (k == 0) analysis::AttachSilhouetteCheck(check.silhouettes, s->analysis_.get());
    video.sync = check.sync.sync;
    video.silhouettes = check.silhouettes;
    s->files_.videos[k].offset_s = video.sync.offset_s;
  }
  return s;
}

int Session::VideoFrameOf(int sample, int k) const {
  if (k < 0 || size_t(k) >= videos_.size() || trial_->point_rate_hz <= 0) return -1;
  const Video& video = videos_[size_t(k)];
  const std::vector<double>& times = video.input->reader().frame_times_s();
  if (times.empty()) return -1;
  const double t = video.sync.VideoTime(sample / trial_->point_rate_hz);
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  size_t i = size_t(it - times.begin());
  if (i == times.size() || (i > 0 && t - times[i - 1] < times[i] - t)) i = i == 0 ? 0 : i - 1;
  const double frame_s = times.size() > 1 ? (times.back() - times.front()) / (times.size() - 1) : 0;
  if (std::abs(times[i] - t) > 0.5 * frame_s + 1e-9) return -1;
  return int(i);
}

int Session::SampleOf(int video_frame, int k) const {
  if (k < 0 || size_t(k) >= videos_.size()) return -1;
  const Video& video = videos_[size_t(k)];
  if (video_frame < 0 || size_t(video_frame) >= video.input->reader().frame_times_s().size())
    return -1;
  return video.sync.NearestSample(*trial_,
                                  video.input->reader().frame_times_s()[size_t(video_frame)]);
}

ShownParts ParseShownParts(const std::string& list) {
  std::string scene;
  ShownParts parts;
  std::stringstream words(list);
  for (std::string word; std::getline(words, word, ',');) {
    if (word == "cameras") {
      parts.cameras = true;
    } else {
      scene += (scene.empty() ? "" : ",") + word;
    }
  }
  parts.scene = analysis::ParseSceneShow(scene);
  return parts;
}

void WriteSessionFile(const fs::path& path, const SessionFiles& files, const SessionView& view) {
  const fs::path base = fs::absolute(path).parent_path();
  // A path below the session's folder is kept relative to it, so the folder can move.
  const auto relative = [&](const std::string& p) -> std::string {
    if (p.empty()) return p;
    const fs::path absolute = fs::weakly_canonical(fs::absolute(p));
    const fs::path rel = absolute.lexically_relative(fs::weakly_canonical(base));
    return !rel.empty() && *rel.begin() != ".." ? rel.string() : absolute.string();
  };
  Json j;
  j["format"] = "acrolab-session";
  j["version"] = 2;
  j["trial"] = relative(files.trial);
  j["athlete"] = relative(files.athlete);
  j["videos"] = Json::array();
  for (const VideoFiles& v : files.videos)
    j["videos"].push_back({{"video", relative(v.video)},
                           {"calibration", relative(v.calibration)},
                           {"camera", v.camera},
                           {"offset_s", v.offset_s ? Json(*v.offset_s) : Json()}});
  j["cursor_sample"] = view.cursor_sample;
  j["speed"] = view.speed;
  j["view"] = view.preset;
  j["follow"] = view.follow;
  j["show"] = view.show;
  j["orbit_azimuth_deg"] = view.orbit_azimuth_deg;
  j["orbit_elevation_deg"] = view.orbit_elevation_deg;
  j["orbit_distance_scale"] = view.orbit_distance_scale;
  WriteFileAtomically(path, j.dump(2) + "\n");
}

std::pair<SessionFiles, SessionView> ReadSessionFile(const fs::path& path) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, 1 << 20);
  const Json j = Json::parse(bytes.begin(), bytes.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != "acrolab-session")
    throw InputError(file, "format", "not an Acrolab session file (JSON, format acrolab-session)");
  const int version =
      j.contains("version") && j["version"].is_number_integer() ? j["version"].get<int>() : 0;
  if (version != 1 && version != 2)
    throw InputError(file,
                     "version",
                     (j.contains("version") ? j["version"].dump() : "missing") + ": not 1 or 2");
  const fs::path base = fs::absolute(path).parent_path();
  // A video's keys: in `videos` (version 2) or at the top level (version 1).
  const auto text = [&](const Json& o, const std::string& key, const std::string& field) {
    if (!o.contains(key) || o[key].is_null()) return std::string();
    if (!o[key].is_string()) throw InputError(file, field, "not a string");
    return o[key].get<std::string>();
  };
  const auto located = [&](const Json& o, const std::string& key, const std::string& field) {
    const std::string p = text(o, key, field);
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (base / p).lexically_normal().string();
  };
  const auto read_video = [&](const Json& o, const std::string& prefix) {
    VideoFiles v;
    v.video = located(o, "video", prefix + "video");
    v.calibration = located(o, "calibration", prefix + "calibration");
    v.camera = text(o, "camera", prefix + "camera");
    if (o.contains("offset_s") && !o["offset_s"].is_null()) {
      if (!o["offset_s"].is_number()) throw InputError(file, prefix + "offset_s", "not a number");
      v.offset_s = o["offset_s"].get<double>();
    }
    if (v.video.empty() && !v.calibration.empty())
      throw InputError(file, prefix + "video", "a calibration without its video");
    return v;
  };
  SessionFiles files;
  files.trial = located(j, "trial", "trial");
  files.athlete = located(j, "athlete", "athlete");
  if (version == 1) {
    const VideoFiles v = read_video(j, "");
    if (!v.video.empty()) files.videos.push_back(v);
  } else if (j.contains("videos")) {
    const Json& list = j["videos"];
    if (!list.is_array()) throw InputError(file, "videos", "not a list");
    if (list.size() > size_t(kMaxVideos))
      throw InputError(file, "videos", std::to_string(list.size()) + " videos: at most 4");
    for (size_t k = 0; k < list.size(); ++k) {
      const std::string prefix = "videos[" + std::to_string(k) + "].";
      if (!list[k].is_object())
        throw InputError(file, "videos[" + std::to_string(k) + "]", "not an object");
      files.videos.push_back(read_video(list[k], prefix));
      if (files.videos.back().video.empty()) throw InputError(file, prefix + "video", "missing");
    }
  }
  for (size_t k = 0; k < files.videos.size(); ++k)
    if (files.videos[k].calibration.empty() && !OneVideoAlone(files))
      throw InputError(file,
                       version == 1 ? "calibration" : fmt::format("videos[{}].calibration", k),
                       "missing: a video of a trial goes with its calibration (a video without "
                       "one is analysed alone: no trial, one video)");
  SessionView view;
  const auto number = [&](const char* key, double fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number() || !std::isfinite(j[key].get<double>()))
      throw InputError(file, key, j[key].dump() + " is not a number");
    return j[key].get<double>();
  };
  view.cursor_sample = int(std::clamp(number("cursor_sample", 0), 0.0, 1e9));
  view.speed = number("speed", 1.0);
  if (!(view.speed > 0 && view.speed <= 4))
    throw InputError(file, "speed", std::to_string(view.speed) + " is not between 0 and 4");
  view.preset = text(j, "view", "view").empty() ? "side" : text(j, "view", "view");
  if (view.preset != "side" && view.preset != "front" && view.preset != "top")
    throw InputError(file, "view", "'" + view.preset + "' is not side, front or top");
  view.follow = j.contains("follow") && j["follow"].is_boolean() && j["follow"].get<bool>();
  if (j.contains("show")) {
    view.show = text(j, "show", "show");
    try {
      ParseShownParts(view.show);
    } catch (const std::exception&) {
      throw InputError(
          file,
          "show",
          "'" + view.show + "' is not a list of mesh, skeleton, markers, com, cameras");
    }
  }
  view.orbit_azimuth_deg = number("orbit_azimuth_deg", 0.0);
  view.orbit_elevation_deg = std::clamp(number("orbit_elevation_deg", 0.0), -80.0, 80.0);
  view.orbit_distance_scale = number("orbit_distance_scale", 1.0);
  if (!(view.orbit_distance_scale >= 0.2 && view.orbit_distance_scale <= 5))
    throw InputError(file,
                     "orbit_distance_scale",
                     std::to_string(view.orbit_distance_scale) + " is not between 0.2 and 5");
  if (files.trial.empty() && !OneVideoAlone(files))
    throw InputError(file, "trial", "missing (and not one video analysed alone)");
  return {files, view};
}

}  // namespace acro::studio
