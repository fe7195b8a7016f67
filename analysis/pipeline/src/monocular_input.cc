#include "acro/pipeline/monocular_input.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/capture/video.h"
#include "acro/fig/trampoline.h"
#include "acro/pipeline/detect.h"
#include "acro/pipeline/views_input.h"
#include "acro/reconstruct/up_axis.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/camera_motion.h"

namespace acro::pipeline {

namespace {

constexpr double kG = 9.81;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::string MonocularInput::Report() const {
  std::string per;
  for (const double z : depth_per_flight_m)
    per += fmt::format("{}{:.2f}", per.empty() ? "" : ", ", z);
  const std::string gravity =
      fmt::format("gravity in {} flight(s) ({} m)", depth_per_flight_m.size(), per);
  const std::string how =
      bed_depth_m > 0
          ? fmt::format("the bed's middle line; {} says {:.2f} m", gravity, gravity_depth_m)
          : "from " + gravity;
  return fmt::format(
      "one camera ({}), from {}\n"
      "one camera: the athlete {:.2f} m away along its axis ({}); the keypoints put on the "
      "vertical plane there; the bed at rest {:.3f} m high\n",
      camera.name,
      camera_source,
      depth_m,
      how,
      bed_height_m);
}

namespace {

// The camera's pose (and, with no intrinsics given, its focal length) from the FIG bed found in
// the video's first frame: the world is the bed's.
vision::Camera CameraFromBed(const MonocularRequest& request,
                             const vision::BedDetection& bed,
                             const capture::VideoInfo& info,
                             MonocularInput* out) {
  const std::vector<vision::NamedPoint3> fig = vision::FigTrampolinePoints();
  vision::BedCalibration pose;
  if (!request.intrinsics.empty()) {
    const std::vector<vision::Camera> cameras = vision::ReadCameras(request.intrinsics);
    vision::Camera intrinsics =
        request.camera.empty() && cameras.size() == 1
            ? cameras[0]
            : vision::FindCamera(cameras, request.camera, request.intrinsics.string());
    intrinsics = vision::FitCameraToVideo(
        intrinsics, info.width, info.height, request.video.string(), nullptr);
    pose = vision::CalibrateFromBed(intrinsics, fig, bed);
    out->bed_focal.emplace();
    out->bed_focal->bed = pose;
    out->camera_source =
        fmt::format("the intrinsics of {} (camera {}), the pose from the bed in {} ({:.2f} px RMS)",
                    request.intrinsics.string(),
                    intrinsics.name,
                    bed.source,
                    pose.calibration.rms_px);
  } else {
    out->bed_focal = vision::CalibrateFromBedUnknownFocal(info.width, info.height, fig, bed);
    pose = out->bed_focal->bed;
    const vision::BedFocalCalibration& f = *out->bed_focal;
    const double lo = 0.25 * info.width, hi = 8.0 * info.width;
    out->camera_source = fmt::format(
        "the bed in {}: focal length {:.0f} px (corners good to 1 px tell it within "
        "{}{:.0f}–{}{:.0f} px; from its homography {:.0f} px), the principal point at the "
        "picture's centre, no distortion; the pose {:.2f} px RMS",
        bed.source,
        f.focal_px,
        f.focal_low_px <= lo * 1.0001 ? "≤ " : "",
        f.focal_low_px,
        f.focal_high_px >= hi * 0.9999 ? "≥ " : "",
        f.focal_high_px,
        f.closed_form_px,
        pose.calibration.rms_px);
    // ±15 % in the focal length is ±15 % in every length and speed gravity does not fix.
    if (f.focal_high_px > 1.3 * f.focal_low_px)
      out->camera_warnings.push_back(fmt::format(
          "{}: the bed's picture tells the camera's focal length poorly ({:.0f}–{:.0f} px for "
          "corners good to 1 px: too little perspective, seen from its own height or from far); "
          "distances across the picture are as uncertain — give --intrinsics (a checkerboard's "
          "calibration) or --calib",
          request.video.string(),
          f.focal_low_px,
          f.focal_high_px));
  }
  vision::Camera camera = pose.calibration.camera;
  camera.name = request.video.stem().string();
  return camera;
}

}  // namespace

namespace {

// The camera: posed on the bed found in the first frame (or the bed's picture), or read from the
// calibration and fitted to the video's size; `info` the video's (or, for detections, their rate
// and the camera's width). Its picture-down axis must point down (gravity is the world's −Z).
vision::Camera OpenOneCamera(const MonocularRequest& request,
                             MonocularInput* out,
                             capture::VideoInfo* info,
                             std::optional<vision::BedDetection>* bed) {
  const bool from_video = request.detections.empty();
  const std::filesystem::path& source = from_video ? request.video : request.detections;
  vision::Camera camera;
  if (request.detect_bed) {
    if (!from_video)
      throw InputError(request.detections.string(),
                       "bed",
                       "detections have no picture to find the bed in: give their camera's "
                       "calibration");
    *info = capture::VideoReader(request.video).info();
    *bed = vision::DetectBed(request.bed_picture.empty() ? request.video : request.bed_picture, 0);
    if (!request.bed_picture.empty() &&
        ((*bed)->width_px != info->width || (*bed)->height_px != info->height))
      throw InputError(request.bed_picture.string(),
                       "bed",
                       fmt::format("{} x {} px, the video {} x {}: the bed's picture must be the "
                                   "same camera's, the same size",
                                   (*bed)->width_px,
                                   (*bed)->height_px,
                                   info->width,
                                   info->height));
    camera = CameraFromBed(request, **bed, *info, out);
  } else {
    const std::vector<vision::Camera> cameras = vision::ReadCameras(request.calibration);
    if (!request.camera.empty())
      camera = vision::FindCamera(cameras, request.camera, request.calibration.string());
    else if (cameras.size() == 1)
      camera = cameras[0];
    else
      camera = vision::FindCamera(
          cameras,
          VideoSource(source.string(), cameras, request.calibration.string()).camera,
          request.calibration.string());
    out->camera_source =
        fmt::format("the calibration {}, camera {}", request.calibration.string(), camera.name);
    if (from_video) {
      *info = capture::VideoReader(request.video).info();
      camera = vision::FitCameraToVideo(
          camera, info->width, info->height, request.video.string(), nullptr);
    } else {
      if (!(request.rate_hz > 0 && request.rate_hz <= 10000))
        throw InputError(request.detections.string(),
                         "rate",
                         fmt::format("detections need their frame rate (given {:g} Hz): their "
                                     "files carry no time",
                                     request.rate_hz));
      if (!request.bed_line)
        throw InputError(request.detections.string(),
                         "bed",
                         "one camera's detections need the bed's rest line in their picture: "
                         "there is no video to find the bed in");
      info->average_fps = request.rate_hz;
      info->width = camera.width_px;
    }
  }
  // Gravity is the calibration's −Z: the camera's picture-down axis must point down.
  const Eigen::Vector3d down_W = camera.R_KW.transpose() * Eigen::Vector3d::UnitY();
  if (*bed && !(down_W.z() < -0.5))
    throw InputError(request.video.string(),
                     "bed",
                     fmt::format("the dark four-sided region found in the first frame ({}) does "
                                 "not pose a camera beside a trampoline's bed (the picture's down "
                                 "would be ({:.2f}, {:.2f}, {:.2f}) with the bed's up (0, 0, 1)): "
                                 "not a bed seen from its side — give --calib",
                                 (*bed)->source,
                                 down_W.x(),
                                 down_W.y(),
                                 down_W.z()));
  if (!(down_W.z() < -0.5))
    throw InputError(request.calibration.string(),
                     "camera " + camera.name,
                     fmt::format("the picture's down is ({:.2f}, {:.2f}, {:.2f}) in the "
                                 "calibration's world: one camera needs a world whose Z is up "
                                 "and a camera that is not tilted by more than 60°",
                                 down_W.x(),
                                 down_W.y(),
                                 down_W.z()));
  return camera;
}

// The athlete's distance along the camera's axis: gravity's reading per complete flight (their
// median), or with the bed located the bed's long middle line's. `n` the horizontal normal of
// the athlete's vertical plane.
void FindDepth(const MonocularRequest& request,
               const std::filesystem::path& source,
               const vision::Camera& camera,
               const Eigen::Vector3d& n,
               MonocularInput* out) {
  const double f = 0.5 * (camera.K(0, 0) + camera.K(1, 1));
  for (const vision::ImageFlight& flight : out->flights.flights)
    if (!flight.partial() && flight.com_accel_px_s2 > 0)
      out->depth_per_flight_m.push_back(kG * f / flight.com_accel_px_s2);
  if (out->depth_per_flight_m.empty())
    throw InputError(source.string(),
                     "flights",
                     fmt::format("no complete flight in the picture ({} found): one camera tells "
                                 "the athlete's distance from gravity in flight",
                                 out->flights.flights.size()));
  std::vector<double> sorted = out->depth_per_flight_m;
  std::sort(sorted.begin(), sorted.end());
  out->depth_m = sorted.size() % 2
                     ? sorted[sorted.size() / 2]
                     : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
  const Eigen::Vector3d C = camera.CentreInWorld();
  const Eigen::Vector3d axis = camera.R_KW.transpose() * Eigen::Vector3d::UnitZ();
  // From the bed, a second reading of the distance: the bed's long middle line (y = 0 in its
  // world), where a trampolinist flies, along the camera's axis.
  if (request.detect_bed && std::abs(n.y()) > 0.2 && n.dot(axis) > 1e-6)
    out->bed_depth_m = (-C.y() / n.y()) / n.dot(axis);
  // With the bed located, the athlete's plane is its middle line: a trampolinist flies within
  // zone A's ±0.54 m of it, where gravity's reading was 4.8 % (sample, calibrated) to 9 % (from
  // the bed) far — and the landings, measured on the bed, would sit that far across it. Across
  // the bed one side camera then measures nothing: said.
  if (out->bed_depth_m > 0) {
    out->gravity_depth_m = out->depth_m;
    out->depth_m = out->bed_depth_m;
    out->camera_warnings.push_back(
        "one camera beside the bed sees the landings along the bed, not across it (the athlete is "
        "put on the bed's middle line): the landing spots and H count the travel along the bed "
        "only");
  }
}

// Where pixel `px`'s ray meets the vertical plane with horizontal normal n, `distance` from the
// camera's centre along n (NaN behind the camera); `xy` its normalised coordinates.
Eigen::Vector3d OnPlane(const vision::Camera& camera,
                        const Eigen::Vector3d& n,
                        double distance,
                        const Eigen::Vector2d& px,
                        Eigen::Vector2d* xy = nullptr) {
  const Eigen::Vector2d u = camera.Undistort(px);
  const double y = (u.y() - camera.K(1, 2)) / camera.K(1, 1);
  const double x = (u.x() - camera.K(0, 2) - camera.K(0, 1) * y) / camera.K(0, 0);
  if (xy) *xy = Eigen::Vector2d(x, y);
  const Eigen::Vector3d d = camera.R_KW.transpose() * Eigen::Vector3d(x, y, 1.0);
  const double along = n.dot(d);
  if (!(along > 1e-6)) return Eigen::Vector3d::Constant(kNaN);
  return camera.CentreInWorld() + (distance / along) * d;
}

// The most confident person's keypoints of every frame put on the athlete's plane, as a
// one-camera "triangulation" whose only view is the camera's.
analysis::Triangulation KeypointsOnPlane(const capture::KeypointDetections& detections,
                                         const vision::Camera& camera,
                                         const Eigen::Vector3d& n,
                                         double distance,
                                         double c_min) {
  const int F = detections.num_frames();
  const int P = static_cast<int>(detections.names.size());
  analysis::Triangulation points;
  points.names = detections.names;
  points.num_frames = F;
  points.positions.setConstant(3, static_cast<Eigen::Index>(F) * P, kNaN);
  points.reprojection_px.setConstant(P, F, kNaN);
  points.views.setZero(P, F);
  points.uncertainty_m.setConstant(P, F, kNaN);
  analysis::ViewKeypoints seen;
  seen.camera = camera;
  seen.xy.setConstant(2, static_cast<Eigen::Index>(F) * P, kNaN);
  seen.confidence.setZero(P, F);
  seen.agreed.setConstant(P, F, true);
  for (int k = 0; k < F; ++k) {
    const auto& people = detections.frames[size_t(k)];
    if (people.empty()) continue;
    // The athlete: the person the flights were found from (the most confident).
    const int chosen = vision::MostConfidentPerson(people, c_min);
    if (chosen < 0) continue;
    const capture::DetectedPerson& person = people[size_t(chosen)];
    for (int j = 0; j < P && j < person.cols(); ++j) {
      if (!(person(2, j) >= c_min) || !std::isfinite(person(0, j))) continue;
      Eigen::Vector2d xy;
      const Eigen::Vector3d p = OnPlane(camera, n, distance, person.col(j).head<2>(), &xy);
      if (!p.allFinite()) continue;
      const Eigen::Index col = static_cast<Eigen::Index>(k) * P + j;
      points.positions.col(col) = p;
      points.views(j, k) = 1;
      seen.xy.col(col) = xy;
      seen.confidence(j, k) = person(2, j);
    }
  }
  points.observed.push_back(std::move(seen));
  return points;
}

// The bytes the camera came from (none when the video alone gave it), the source's, and the
// bed's picture: the input's hash and its list of inputs.
void RecordProvenance(const MonocularRequest& request,
                      const std::filesystem::path& source,
                      TrialInput* in) {
  in->path = source;
  const std::filesystem::path& camera_file =
      request.detect_bed ? request.intrinsics : request.calibration;
  const std::string camera_hash = camera_file.empty() ? std::string() : Sha256OfFile(camera_file);
  const std::string source_hash = HashOfSource(source);
  in->sha256 = Sha256Hex(camera_hash + source_hash);
  in->inputs.push_back({request.video.empty() ? "detections" : "video", source, source_hash});
  if (!camera_file.empty())
    in->inputs.push_back(
        {request.detect_bed ? "intrinsics" : "calibration", camera_file, camera_hash});
  if (request.detect_bed && !request.bed_picture.empty())
    in->inputs.push_back({"bed picture", request.bed_picture, Sha256OfFile(request.bed_picture)});
}

}  // namespace

MonocularInput OpenMonocular(const MonocularRequest& request, const Progress& progress) {
  MonocularInput out;
  const bool from_video = request.detections.empty();
  const std::filesystem::path& source = from_video ? request.video : request.detections;
  capture::VideoInfo info;
  std::optional<vision::BedDetection> bed;
  const vision::Camera camera = OpenOneCamera(request, &out, &info, &bed);
  // The bed's line before the detection: a video without a bed costs nothing.
  const vision::BedLine line =
      request.bed_line ? *request.bed_line
                       : vision::RestLineOfBed(bed ? *bed : vision::DetectBed(request.video, 0));
  capture::KeypointDetections detections;
  if (from_video) {
    detections = Body25bDetections(DetectPosesInCache(request.video, request.model, progress));
    detections.source = request.video.string();
  } else {
    detections = capture::ReadDetections(request.detections, request.keypoint_set);
  }
  const double rate = info.average_fps;
  out.flights = vision::FindFlightsInImage(detections, rate, line, request.flights);
  // The bed's line and the camera's pose are the first frame's: a camera that moved after it is
  // said, per flight.
  if (from_video)
    for (const std::string& w : vision::CameraMotionWarnings(
             vision::MeasureCameraMotion(request.video, {}, progress), out.flights))
      out.flights.warnings.push_back(w);

  // The vertical plane square to the camera's horizontal axis, at the athlete's depth, takes the
  // keypoints.
  const Eigen::Vector3d axis = camera.R_KW.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d n = Eigen::Vector3d(axis.x(), axis.y(), 0).normalized();
  FindDepth(request, source, camera, n, &out);
  const double distance = out.depth_m * n.dot(axis);
  const analysis::Triangulation points =
      KeypointsOnPlane(detections, camera, n, distance, request.flights.min_confidence);
  // The bed's rest line on the plane, under the median landing (or the picture's middle).
  std::vector<double> xs;
  for (const vision::ImageFlight& flight : out.flights.flights)
    if (flight.first_contact_frame >= 0 && std::isfinite(flight.landing_px.x()))
      xs.push_back(flight.landing_px.x());
  std::sort(xs.begin(), xs.end());
  const double x_bed = xs.empty() ? 0.5 * info.width : xs[xs.size() / 2];
  out.bed_height_m = OnPlane(camera, n, distance, Eigen::Vector2d(x_bed, line.At(x_bed))).z();
  if (!std::isfinite(out.bed_height_m))
    throw InputError(source.string(),
                     "bed",
                     fmt::format("the bed's line ({}: y = {:.1f} px {:+.4f} x) does not meet the "
                                 "athlete's plane in front of the camera at x = {:.0f} px",
                                 line.source,
                                 line.y0_px,
                                 line.slope,
                                 x_bed));
  TrialInput& in = out.input;
  RecordProvenance(request, source, &in);
  in.trial = points.ToTrial(
      rate,
      fmt::format("one camera's keypoints (camera from {}) on the plane {:.2f} m away",
                  out.camera_source,
                  out.depth_m));
  capture::DemandUsableContent(in.trial, in.path.string(), request.min_frames, request.use);
  const std::string turned = analysis::OrientTrialUp(&in.trial, "z", &in.up);
  (void)turned;  // "z": the calibration's world is Z up (checked above)
  out.views = std::make_shared<const analysis::ViewsToFit>(
      analysis::MakeViewsToFit(points, Eigen::Matrix3d::Identity()));
  for (const std::string& w : out.camera_warnings) in.warnings.push_back(w);
  for (const std::string& w : out.flights.warnings) in.warnings.push_back(w);
  in.athlete = MakeAthlete(request.athlete);
  out.camera = camera;
  return out;
}

void UseOneCamera(const MonocularInput& mono,
                  const MonocularRequest& request,
                  analysis::TrialAnalysisOptions* options) {
  options->reconstruction.views = mono.views;
  if (!options->bed && !options->surface_height_m) options->surface_height_m = mono.bed_height_m;
  // The flights as the picture's soles time them (the trial's clock is the video's).
  options->given_flights_s.clear();
  for (const vision::ImageFlight& f : mono.flights.flights)
    options->given_flights_s.emplace_back(f.takeoff_s, f.landing_s);
  options->reconstruction.ballistic_flights_s = options->given_flights_s;
  options->given_flights_source = "picture's soles against the bed's line";
  if (request.detect_bed && !options->bed) {
    // The camera's world is the FIG bed's: centred, its long side along x, at rest at z 0.
    analysis::BedGeometry bed;
    bed.centre_W = Eigen::Vector3d::Zero();
    bed.long_axis_W = Eigen::Vector3d::UnitX();
    bed.length_m = fig::kBedLength_m;
    bed.width_m = fig::kBedWidth_m;
    bed.source =
        request.bed_picture.empty()
            ? "the FIG bed the camera was posed on (its first frame)"
            : "the FIG bed the camera was posed on (in " + request.bed_picture.string() + ")";
    options->bed = bed;
  }
}

std::optional<VideoRequest> OneCameraVideo(const MonocularInput& mono,
                                           const MonocularRequest& request) {
  if (request.video.empty()) return std::nullopt;
  VideoRequest video;
  video.video = request.video;
  video.calibration = request.calibration;
  video.camera = mono.camera.name;
  if (request.detect_bed) video.camera_given = mono.camera;
  video.sync.kind = SyncRequest::Kind::kOffset;
  video.sync.offset_s = 0;
  video.sync.rate = 1.0;
  return video;
}

}  // namespace acro::pipeline
