#include "acro/studio/session.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/athlete/de_leva.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/scene/silhouette_check.h"

namespace acro::studio {

namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

std::function<bool(int, int)> Step(const Session::Progress& progress, const std::string& step) {
  if (!progress) return {};
  return [progress, step](int done, int total) { return progress(step, done, total); };
}

}  // namespace

std::unique_ptr<Session> Session::Open(const SessionFiles& files, const Progress& progress) {
  std::unique_ptr<Session> s(new Session());
  s->files_ = files;
  if (files.trial.empty()) throw InputError("", "trial", "no trial to open");
  if (files.video.empty() != files.calibration.empty())
    throw InputError(files.video.empty() ? files.calibration : files.video,
                     "video",
                     "a video and its camera calibration go together");
  if (progress && !progress("reading " + files.trial, 0, 1))
    throw InputError(files.trial, "", "cancelled");
  s->trial_ = std::make_unique<capture::Trial>(capture::ReadTrial(files.trial));
  if (!files.athlete.empty()) {
    s->body_ = analysis::MakeAthleteBody(analysis::ReadAthleteProfile(files.athlete));
  } else {
    s->body_ = analysis::MakeDeLevaBody(1.70, 65.0, analysis::Sex::kMale);
    s->warnings_.push_back("no athlete profile: a de Leva athlete of 1.70 m and 65 kg");
  }
  // The camera before the work: a wrong calibration costs nothing.
  if (!files.video.empty()) {
    s->camera_ =
        vision::FindCamera(vision::ReadCameras(files.calibration), files.camera, files.calibration);
    s->video_ = std::make_unique<capture::VideoReader>(files.video);
  }
  if (progress && !progress("analysing " + files.trial, 0, 1))
    throw InputError(files.trial, "", "cancelled");
  analysis::TrialAnalysisOptions options;
  s->analysis_ = std::make_unique<analysis::TrialAnalysis>(
      analysis::AnalyzeTrial(*s->trial_, nullptr, s->body_, options));
  for (const std::string& w : s->analysis_->warnings) s->warnings_.push_back(w);
  s->scene_ = std::make_unique<analysis::TrialScene>(
      *s->trial_,
      *s->analysis_,
      s->body_,
      analysis::MakeEllipsoidBodyMesh(s->body_, analysis::OverlayBodyMeshOptions()));
  if (s->video_) {
    // The silhouettes with the body's full mesh (what the video shows), as analyze compares them.
    analysis::TrialScene full(
        *s->trial_, *s->analysis_, s->body_, analysis::MakeEllipsoidBodyMesh(s->body_));
    if (files.offset_s) {
      s->sync_.offset_s = *files.offset_s;
    } else {
      vision::AutoSyncOptions motion;
      motion.progress = Step(progress, "sync (image motion)");
      analysis::SilhouetteCheckOptions refine;
      refine.progress = Step(progress, "sync (silhouettes)");
      s->sync_ = analysis::SyncVideoAutomatically(full, s->camera_, files.video, motion, refine)
                     .refined.sync;
      s->files_.offset_s = s->sync_.offset_s;
    }
    analysis::SilhouetteCheckOptions check;
    check.sync = s->sync_;
    check.progress = Step(progress, "silhouettes");
    s->silhouettes_ = analysis::CheckSilhouettes(*s->video_, full, s->camera_, check);
    analysis::AttachSilhouetteCheck(s->silhouettes_, s->analysis_.get());
  }
  return s;
}

int Session::VideoFrameOf(int sample) const {
  if (!video_ || trial_->point_rate_hz <= 0) return -1;
  const std::vector<double>& times = video_->frame_times_s();
  if (times.empty()) return -1;
  const double t = sync_.VideoTime(sample / trial_->point_rate_hz);
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  size_t k = size_t(it - times.begin());
  if (k == times.size() || (k > 0 && t - times[k - 1] < times[k] - t)) k = k == 0 ? 0 : k - 1;
  const double frame_s = times.size() > 1 ? (times.back() - times.front()) / (times.size() - 1) : 0;
  if (std::abs(times[k] - t) > 0.5 * frame_s + 1e-9) return -1;
  return int(k);
}

int Session::SampleOf(int video_frame) const {
  if (!video_ || video_frame < 0 || size_t(video_frame) >= video_->frame_times_s().size())
    return -1;
  return sync_.NearestSample(*trial_, video_->frame_times_s()[size_t(video_frame)]);
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
  j["version"] = 1;
  j["trial"] = relative(files.trial);
  j["athlete"] = relative(files.athlete);
  j["video"] = relative(files.video);
  j["calibration"] = relative(files.calibration);
  j["camera"] = files.camera;
  j["offset_s"] = files.offset_s ? Json(*files.offset_s) : Json();
  j["cursor_sample"] = view.cursor_sample;
  j["speed"] = view.speed;
  j["view"] = view.preset;
  j["follow"] = view.follow;
  WriteFileAtomically(path, j.dump(2) + "\n");
}

std::pair<SessionFiles, SessionView> ReadSessionFile(const fs::path& path) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, 1 << 20);
  const Json j = Json::parse(bytes.begin(), bytes.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != "acrolab-session")
    throw InputError(file, "format", "not an Acrolab session file (JSON, format acrolab-session)");
  if (j.value("version", 0) != 1)
    throw InputError(file, "version", j.value("version", Json()).dump() + " is not 1");
  const fs::path base = fs::absolute(path).parent_path();
  const auto text = [&](const char* key) -> std::string {
    if (!j.contains(key) || j[key].is_null()) return "";
    if (!j[key].is_string()) throw InputError(file, key, "not a string");
    return j[key].get<std::string>();
  };
  const auto located = [&](const char* key) -> std::string {
    const std::string p = text(key);
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (base / p).lexically_normal().string();
  };
  SessionFiles files;
  files.trial = located("trial");
  files.athlete = located("athlete");
  files.video = located("video");
  files.calibration = located("calibration");
  files.camera = text("camera");
  if (j.contains("offset_s") && !j["offset_s"].is_null()) {
    if (!j["offset_s"].is_number()) throw InputError(file, "offset_s", "not a number");
    files.offset_s = j["offset_s"].get<double>();
  }
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
  view.preset = text("view").empty() ? "side" : text("view");
  if (view.preset != "side" && view.preset != "front" && view.preset != "top")
    throw InputError(file, "view", "'" + view.preset + "' is not side, front or top");
  view.follow = j.contains("follow") && j["follow"].is_boolean() && j["follow"].get<bool>();
  if (files.trial.empty()) throw InputError(file, "trial", "missing");
  return {files, view};
}

}  // namespace acro::studio
