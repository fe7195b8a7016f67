#include "acro/pipeline/video_input.h"

#include <cmath>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/vision/sync.h"

namespace acro::pipeline {

bool SyncRequest::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(rate > 0) || !std::isfinite(rate))
    return fail(fmt::format("rate {}: a positive number", rate));
  if (!std::isfinite(offset_s) || !std::isfinite(event_trial_s) || !std::isfinite(event_video_s))
    return fail("the sync's times must be finite");
  return true;
}

bool VideoRequest::IsValid(std::string* why) const {
  if (video.empty() || (calibration.empty() && !camera_given)) {
    if (why) *why = "a video needs its calibration (--video and --calib go together)";
    return false;
  }
  return sync.IsValid(why);
}

VideoInput::VideoInput(const VideoRequest& request) : request_(request) {
  DemandValidOptions(request, "video");
  // The camera first: a mistyped name costs nothing.
  if (request.camera_given) {
    camera_ = *request.camera_given;
  } else {
    const std::vector<vision::Camera> cameras = vision::ReadCameras(request.calibration);
    camera_ = vision::FindCamera(cameras, request.camera, request.calibration.string());
  }
  reader_ = std::make_unique<capture::VideoReader>(request.video);
  const capture::VideoInfo& info = reader_->info();
  std::string note;
  camera_ =
      vision::FitCameraToVideo(camera_, info.width, info.height, request.video.string(), &note);
  if (!note.empty()) warnings_.push_back(note);
}

VideoInput::~VideoInput() = default;
VideoInput::VideoInput(VideoInput&&) noexcept = default;
VideoInput& VideoInput::operator=(VideoInput&&) noexcept = default;

const vision::BackgroundModel& VideoInput::Background() {
  if (!background_) {
    const capture::VideoPixels handed = reader_->pixels();
    reader_->SetPixels(capture::VideoPixels::kRgb);
    background_ = std::make_unique<vision::BackgroundModel>(*reader_);
    reader_->SetPixels(handed);
  }
  return *background_;
}

namespace {

// A Progress as the (done, total) callbacks of vision and scene take it.
std::function<bool(int, int)> Step(const Progress& progress, const std::string& step) {
  if (!progress.report) return {};
  return [progress, step](int done, int total) { return progress.Report(step, done, total); };
}

}  // namespace

const SyncOutcome& VideoInput::Sync(analysis::TrialScene& scene, const Progress& progress) {
  if (sync_) return *sync_;
  SyncOutcome out;
  const SyncRequest& r = request_.sync;
  if (r.kind == SyncRequest::Kind::kOffset) {
    out.sync = {r.offset_s, r.rate};
  } else if (r.kind == SyncRequest::Kind::kEvent) {
    out.sync = vision::SyncFromEvent(r.event_trial_s, r.event_video_s, r.rate);
  }
  if (r.kind != SyncRequest::Kind::kAuto) {
    vision::DemandTrialInsideVideo(
        out.sync, scene.trial().duration_s(), reader_->info().duration_s, request_.video.string());
  } else {
    // From the image motion, then refined by the silhouettes to the trial's sample.
    vision::AutoSyncOptions motion;
    motion.rate = r.rate;
    motion.progress = Step(progress, "sync (image motion)");
    analysis::SilhouetteCheckOptions refine;
    refine.background_model = &Background();
    refine.progress = Step(progress, "sync (silhouettes)");
    out.found = analysis::SyncVideoAutomatically(scene, camera_, *reader_, motion, refine);
    out.sync = out.found->refined.sync;
    out.lines.push_back(
        fmt::format("sync: video time = {:.4f} s + trial time (from the image motion: 1 − "
                    "correlation {:.3f}, runner-up {:.3f})",
                    out.found->motion.sync.offset_s,
                    out.found->motion.cost,
                    out.found->motion.runner_up_cost));
    out.lines.push_back(fmt::format(
        "sync: video time = {:.4f} s + trial time (refined by the silhouettes, median IoU {:.3f})",
        out.sync.offset_s,
        out.found->refined.median_iou));
  }
  sync_ = std::move(out);
  return *sync_;
}

analysis::SilhouetteCheck VideoInput::CheckSilhouettes(analysis::TrialScene& scene,
                                                       const Progress& progress) {
  analysis::SilhouetteCheckOptions check;
  check.sync = Sync(scene, progress).sync;
  check.background_model = &Background();
  check.progress = Step(progress, "silhouettes");
  return analysis::CheckSilhouettes(*reader_, scene, camera_, check);
}

}  // namespace acro::pipeline
