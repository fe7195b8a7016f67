#include "acro/pipeline/views_input.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/capture/video.h"
#include "acro/pipeline/detect.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/camera.h"

namespace acro::pipeline {

namespace {

// The detections with `names`' order: keypoints the file lacks are absent (confidence 0).
capture::KeypointDetections AlignedTo(const capture::KeypointDetections& d,
                                      const std::vector<std::string>& names,
                                      std::vector<std::string>* warnings,
                                      const std::string& camera) {
  if (d.names == names) return d;
  std::vector<int> from(names.size(), -1);
  int shared = 0;
  for (size_t i = 0; i < names.size(); ++i) {
    const auto it = std::find(d.names.begin(), d.names.end(), names[i]);
    if (it != d.names.end()) {
      from[i] = static_cast<int>(it - d.names.begin());
      ++shared;
    }
  }
  if (shared < static_cast<int>(names.size()) || d.names.size() != names.size())
    warnings->push_back(
        fmt::format("camera {}: {} of its {} keypoints are among the first camera's {}",
                    camera,
                    shared,
                    d.names.size(),
                    names.size()));
  capture::KeypointDetections out;
  out.source = d.source;
  out.names = names;
  out.warnings = d.warnings;
  out.frames.resize(d.frames.size());
  for (size_t k = 0; k < d.frames.size(); ++k)
    for (const capture::DetectedPerson& p : d.frames[k]) {
      capture::DetectedPerson q =
          capture::DetectedPerson::Zero(3, static_cast<Eigen::Index>(names.size()));
      for (size_t i = 0; i < names.size(); ++i)
        if (from[i] >= 0) q.col(static_cast<Eigen::Index>(i)) = p.col(from[i]);
      out.frames[k].push_back(q);
    }
  return out;
}

}  // namespace

std::string HashOfSource(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) return Sha256OfFile(path);
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(path, ec))
    if (entry.is_regular_file(ec) && entry.path().extension() == ".json")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::string text;
  for (const auto& f : files) text += f.filename().string() + " " + Sha256OfFile(f) + "\n";
  return Sha256Hex(text);
}

CameraSource VideoSource(const std::string& text,
                         const std::vector<vision::Camera>& cameras,
                         const std::string& calibration) {
  CameraSource s;
  const size_t eq = text.find('=');
  if (eq != std::string::npos && eq > 0) {
    const std::string name = text.substr(0, eq);
    for (const vision::Camera& c : cameras)
      if (c.name == name) {
        s.camera = name;
        s.video = text.substr(eq + 1);
        return s;
      }
  }
  s.video = text;
  const std::string stem = std::filesystem::path(text).stem().string();
  for (const vision::Camera& c : cameras) {
    const std::string& n = c.name;
    const bool match =
        stem == n || (stem.size() > n.size() && stem.compare(0, n.size(), n) == 0 &&
                      (stem[n.size()] == '_' || stem[n.size()] == '-' || stem[n.size()] == '.'));
    if (match && n.size() > s.camera.size()) s.camera = n;
  }
  if (s.camera.empty()) {
    std::string names;
    for (const vision::Camera& c : cameras) names += (names.empty() ? "" : ", ") + c.name;
    throw InputError(text,
                     "--video",
                     "no camera of " + calibration + " is named by this file (cameras: " + names +
                         "): name the file after its camera or give CAMERA=" + text);
  }
  return s;
}

CameraSource ParseCameraSource(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError(
        "",
        "--detections",
        "expected CAMERA=PATH (a camera of the calibration and its detections), got '" + text +
            "'");
  CameraSource s;
  s.camera = text.substr(0, eq);
  s.detections = text.substr(eq + 1);
  return s;
}

namespace {

// At least two cameras, and a rate for detections that carry no time.
void DemandViewsRequest(const ViewsRequest& request) {
  if (request.cameras.size() < 2)
    throw InputError(
        "",
        "--detections",
        fmt::format("{} camera{} given: the 3D athlete needs at least 2 calibrated views",
                    request.cameras.size(),
                    request.cameras.size() == 1 ? "" : "s"));
  if (!(request.rate_hz > 0 && request.rate_hz <= 10000))
    for (const CameraSource& s : request.cameras)
      if (!(s.rate_hz > 0) && s.video.empty())
        throw InputError(
            "",
            "--rate",
            fmt::format("the detections' frame rate is needed (their files carry no time), "
                        "got {:g}: give the videos' rate in Hz",
                        request.rate_hz));
}

// The cameras given by their videos, detected side by side (cached beside each video); each
// camera and its size checked first, so that a mistyped one costs no detection.
std::vector<pose::VideoPoses> DetectVideos(const ViewsRequest& request,
                                           const std::vector<vision::Camera>& calibrated,
                                           const Progress& progress) {
  std::vector<std::filesystem::path> videos;
  for (const CameraSource& s : request.cameras)
    if (!s.video.empty()) videos.push_back(s.video);
  if (videos.empty()) return {};
  for (const CameraSource& s : request.cameras)
    if (!s.video.empty()) {
      const vision::Camera& c =
          vision::FindCamera(calibrated, s.camera, request.calibration.string());
      const capture::VideoInfo info = capture::VideoReader(s.video).info();
      vision::FitCameraToVideo(c, info.width, info.height, s.video.string(), nullptr);
    }
  return DetectPosesInCache(videos, request.model, progress);
}

// Each camera's view (its calibration fitted to its video, its detections in the first camera's
// keypoint order) and frame rate; each input hashed into `provenance` and `out`'s inputs.
void ReadViews(const ViewsRequest& request,
               const std::vector<vision::Camera>& calibrated,
               const Progress& progress,
               ViewsInput* out,
               std::vector<analysis::CameraView>* views,
               std::vector<double>* rates,
               std::string* provenance) {
  std::vector<std::string>& warnings = out->input.warnings;
  const std::vector<pose::VideoPoses> poses = DetectVideos(request, calibrated, progress);
  std::set<std::string> seen;
  size_t next_video = 0;
  for (const CameraSource& s : request.cameras) {
    if (!seen.insert(s.camera).second)
      throw InputError(
          s.detections.string(), "--detections", "camera '" + s.camera + "' is given twice");
    analysis::CameraView view;
    view.camera = vision::FindCamera(calibrated, s.camera, request.calibration.string());
    double rate = s.rate_hz > 0 ? s.rate_hz : request.rate_hz;
    if (!s.video.empty()) {
      const pose::VideoPoses& p = poses[next_video++];
      view.detections = Body25bDetections(p);
      view.camera = vision::FitCameraToVideo(
          view.camera, p.info.width, p.info.height, s.video.string(), nullptr);
      rate = s.rate_hz > 0 ? s.rate_hz : p.info.average_fps;
      if (p.frames_with_pose() == 0)
        warnings.push_back(
            fmt::format("camera {}: the detector found nobody in {}", s.camera, s.video.string()));
      const std::string hash = Sha256OfFile(s.video);
      *provenance += s.camera + " " + hash + "\n";
      out->input.inputs.push_back({"video " + s.camera, s.video, hash});
    } else {
      view.detections = capture::ReadDetections(s.detections, request.keypoint_set);
      const std::string hash = HashOfSource(s.detections);
      *provenance += s.camera + " " + hash + "\n";
      out->input.inputs.push_back({"detections " + s.camera, s.detections, hash});
    }
    for (const std::string& w : view.detections.warnings) warnings.push_back(s.camera + ": " + w);
    if (!views->empty())
      view.detections =
          AlignedTo(view.detections, (*views)[0].detections.names, &warnings, s.camera);
    rates->push_back(rate);
    if (!(rates->back() > 0 && rates->back() <= 10000))
      throw InputError(
          s.detections.string(),
          "rate",
          fmt::format(
              "camera {}: frame rate {:g} Hz is outside (0, 10000]", s.camera, rates->back()));
    views->push_back(std::move(view));
  }
}

// One time line: each camera's offset given, found from the detections, or 0 (said); then every
// view's detections resampled onto the first camera's frames, from the earliest camera's start to
// the last one's end.
void PutOnOneTimeLine(const ViewsRequest& request,
                      const std::vector<double>& rates,
                      const Progress& progress,
                      std::vector<analysis::CameraView>* views_io,
                      ViewsInput* out) {
  std::vector<analysis::CameraView>& views = *views_io;
  std::vector<std::string>& warnings = out->input.warnings;
  out->offsets.resize(views.size());
  out->offset_origin.assign(views.size(), "assumed");
  out->offset_origin[0] = "the time line";
  bool any_unknown = false;
  for (size_t v = 1; v < views.size(); ++v)
    any_unknown |= std::isnan(request.cameras[v].offset_frames);
  std::vector<analysis::ViewOffset> found;
  if (any_unknown && request.sync)
    found = analysis::SyncViews(views, rates, request.sync_options, progress);
  for (size_t v = 0; v < views.size(); ++v) {
    out->offsets[v].camera = views[v].camera.name;
    const double given = request.cameras[v].offset_frames;
    if (v == 0) {
      out->offsets[v].offset_frames = 0;
    } else if (!std::isnan(given)) {
      out->offsets[v].offset_frames = given;
      out->offset_origin[v] = "given";
    } else if (!found.empty() && found[v].distinct) {
      out->offsets[v] = found[v];
      out->offset_origin[v] = "found";
    } else if (!found.empty()) {
      warnings.push_back(fmt::format(
          "camera {}: its detections do not tell its offset (epipolar distance {:.1f} px at "
          "{:.2f} frames, {:.1f} px two frames or more away: too little motion); taken as started "
          "with camera {} — give --offset {}=FRAMES if it was not",
          views[v].camera.name,
          found[v].cost_px,
          found[v].offset_frames,
          found[v].runner_up_cost_px,
          views[0].camera.name,
          views[v].camera.name));
    }
  }
  double start = 0, end = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const double o = out->offsets[v].offset_frames;
    start = std::min(start, o);
    end = std::max(end, o + views[v].detections.num_frames() * rates[0] / rates[v]);
  }
  const int num_frames = static_cast<int>(std::ceil(end - start - 1e-9));
  out->rates_hz = rates;
  for (size_t v = 0; v < views.size(); ++v)
    out->first_frame.push_back((start - out->offsets[v].offset_frames) * rates[v] / rates[0]);
  for (size_t v = 0; v < views.size(); ++v)
    views[v].detections = analysis::ResampleDetections(
        views[v].detections, rates[v], rates[0], out->offsets[v].offset_frames - start, num_frames);
}

// The bed, from the videos' first frames (two at least, in a Z-up world).
void LocateBed(const ViewsRequest& request,
               const std::vector<analysis::CameraView>& views,
               ViewsInput* out) {
  std::vector<std::string>& warnings = out->input.warnings;
  std::vector<vision::Camera> bed_cameras;
  std::vector<vision::BedDetection> beds;
  for (size_t v = 0; v < views.size(); ++v) {
    if (request.cameras[v].video.empty()) continue;
    try {
      beds.push_back(vision::DetectBed(request.cameras[v].video, 0));
      bed_cameras.push_back(views[v].camera);
    } catch (const InputError& e) {
      warnings.push_back(fmt::format(
          "camera {}: no bed found in its first frame ({})", views[v].camera.name, e.what()));
    }
  }
  if (beds.size() < 2) return;
  const bool upright = out->input.up.axis == 2 && out->input.up.sign > 0;
  try {
    const vision::BedFromViews bed = vision::LocateBedFromViews(bed_cameras, beds);
    if (upright)
      out->bed = bed;
    else
      warnings.push_back("the bed seen in the videos is not used: the cameras' world is not Z up");
  } catch (const InputError& e) {
    warnings.push_back(std::string("the bed is not located from the videos: ") + e.what());
  }
}

}  // namespace

ViewsInput OpenViews(const ViewsRequest& request, const Progress& progress) {
  DemandViewsRequest(request);
  const std::vector<vision::Camera> calibrated = vision::ReadCameras(request.calibration);
  ViewsInput out;
  std::vector<std::string>& warnings = out.input.warnings;
  std::vector<analysis::CameraView> views;
  std::vector<double> rates;
  std::string provenance = Sha256OfFile(request.calibration) + "\n";
  out.input.inputs.push_back(
      {"calibration", request.calibration, provenance.substr(0, provenance.size() - 1)});
  ReadViews(request, calibrated, progress, &out, &views, &rates, &provenance);
  PutOnOneTimeLine(request, rates, progress, &views, &out);

  out.triangulation = analysis::TriangulateKeypoints(views, request.triangulation, progress);
  for (const std::string& w : out.triangulation.warnings) warnings.push_back(w);
  TrialInput& in = out.input;
  in.path =
      request.cameras[0].video.empty() ? request.cameras[0].detections : request.cameras[0].video;
  in.sha256 = Sha256Hex(provenance);
  in.trial = out.triangulation.ToTrial(
      rates[0],
      fmt::format("{} cameras' detections ({})", views.size(), request.calibration.string()));
  capture::DemandUsableContent(in.trial, in.path.string(), request.min_frames, request.use);
  const std::string turned = analysis::OrientTrialUp(&in.trial, request.up, &in.up);
  if (!turned.empty()) warnings.push_back(turned);
  const Eigen::Matrix3d R_trial_world =
      turned.empty() ? Eigen::Matrix3d::Identity() : analysis::RotationToZUp(in.up);
  out.views = std::make_shared<const analysis::ViewsToFit>(
      analysis::MakeViewsToFit(out.triangulation, R_trial_world));
  LocateBed(request, views, &out);
  in.athlete = MakeAthlete(request.athlete);
  return out;
}

std::string UseViews(const ViewsInput& views, analysis::TrialAnalysisOptions* options) {
  options->reconstruction.views = views.views;
  if (!views.bed || options->bed) return "";
  analysis::BedGeometry bed;
  bed.centre_W = views.bed->centre_W;
  bed.long_axis_W = views.bed->long_axis_W;
  bed.length_m = views.bed->length_m;
  bed.width_m = views.bed->width_m;
  bed.source = fmt::format(
      "the bed in {} videos' first frames ({:.2f} × {:.2f} m, centres within {:.1f} cm)",
      views.bed->views,
      bed.length_m,
      bed.width_m,
      100 * views.bed->spread_m);
  options->bed = bed;
  return fmt::format("bed: {} at ({:.3f}, {:.3f}, {:.3f}) m",
                     bed.source,
                     bed.centre_W.x(),
                     bed.centre_W.y(),
                     bed.centre_W.z());
}

VideoRequest FirstViewVideo(const ViewsInput& views, const std::filesystem::path& calibration) {
  VideoRequest request;
  request.video = views.input.path;
  request.calibration = calibration;
  request.camera = views.offsets.at(0).camera;
  request.sync.kind = SyncRequest::Kind::kOffset;
  request.sync.offset_s = views.first_frame.at(0) / views.rates_hz.at(0);
  request.sync.rate = 1.0;
  return request;
}

}  // namespace acro::pipeline
