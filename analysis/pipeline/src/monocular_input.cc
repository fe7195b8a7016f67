#include "acro/pipeline/monocular_input.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/capture/video.h"
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
  return fmt::format(
      "one camera ({}): the athlete {:.2f} m away along its axis, from gravity in {} flight(s) "
      "({} m); the keypoints put on the vertical plane there; the bed at rest {:.3f} m high\n",
      camera.name,
      depth_m,
      depth_per_flight_m.size(),
      per,
      bed_height_m);
}

MonocularInput OpenMonocular(const MonocularRequest& request, const Progress& progress) {
  MonocularInput out;
  const std::vector<vision::Camera> cameras = vision::ReadCameras(request.calibration);
  const bool from_video = request.detections.empty();
  const std::filesystem::path& source = from_video ? request.video : request.detections;
  vision::Camera camera;
  if (!request.camera.empty())
    camera = vision::FindCamera(cameras, request.camera, request.calibration.string());
  else if (cameras.size() == 1)
    camera = cameras[0];
  else
    camera = vision::FindCamera(
        cameras,
        VideoSource(source.string(), cameras, request.calibration.string()).camera,
        request.calibration.string());
  capture::VideoInfo info;
  if (from_video) {
    info = capture::VideoReader(request.video).info();
    camera =
        vision::FitCameraToVideo(camera, info.width, info.height, request.video.string(), nullptr);
  } else {
    if (!(request.rate_hz > 0 && request.rate_hz <= 10000))
      throw InputError(request.detections.string(),
                       "rate",
                       fmt::format("detections need their frame rate (given {:g} Hz): their files "
                                   "carry no time",
                                   request.rate_hz));
    if (!request.bed_line)
      throw InputError(request.detections.string(),
                       "bed",
                       "one camera's detections need the bed's rest line in their picture: there "
                       "is no video to find the bed in");
    info.average_fps = request.rate_hz;
    info.width = camera.width_px;
  }
  // Gravity is the calibration's −Z: the camera's picture-down axis must point down.
  const Eigen::Vector3d down_W = camera.R_KW.transpose() * Eigen::Vector3d::UnitY();
  if (!(down_W.z() < -0.5))
    throw InputError(request.calibration.string(),
                     "camera " + camera.name,
                     fmt::format("the picture's down is ({:.2f}, {:.2f}, {:.2f}) in the "
                                 "calibration's world: one camera needs a world whose Z is up "
                                 "and a camera that is not tilted by more than 60°",
                                 down_W.x(),
                                 down_W.y(),
                                 down_W.z()));
  // The bed's line before the detection: a video without a bed costs nothing.
  const vision::BedLine line = request.bed_line
                                   ? *request.bed_line
                                   : vision::RestLineOfBed(vision::DetectBed(request.video, 0));
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

  // The depth from gravity, per complete flight.
  const double f = 0.5 * (camera.K(0, 0) + camera.K(1, 1));
  for (const vision::ImageFlight& flight : out.flights.flights)
    if (!flight.partial() && flight.com_accel_px_s2 > 0)
      out.depth_per_flight_m.push_back(kG * f / flight.com_accel_px_s2);
  if (out.depth_per_flight_m.empty())
    throw InputError(source.string(),
                     "flights",
                     fmt::format("no complete flight in the picture ({} found): one camera tells "
                                 "the athlete's distance from gravity in flight",
                                 out.flights.flights.size()));
  std::vector<double> sorted = out.depth_per_flight_m;
  std::sort(sorted.begin(), sorted.end());
  out.depth_m = sorted.size() % 2
                    ? sorted[sorted.size() / 2]
                    : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);

  // The keypoints on the vertical plane square to the camera's horizontal axis, at that depth.
  const Eigen::Vector3d C = camera.CentreInWorld();
  const Eigen::Vector3d axis = camera.R_KW.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d n = Eigen::Vector3d(axis.x(), axis.y(), 0).normalized();
  const double distance = out.depth_m * n.dot(axis);
  const int F = detections.num_frames();
  const int P = static_cast<int>(detections.names.size());
  const double c_min = request.flights.min_confidence;
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
      const Eigen::Vector2d u = camera.Undistort(person.col(j).head<2>());
      const double y = (u.y() - camera.K(1, 2)) / camera.K(1, 1);
      const double x = (u.x() - camera.K(0, 2) - camera.K(0, 1) * y) / camera.K(0, 0);
      const Eigen::Vector3d d = camera.R_KW.transpose() * Eigen::Vector3d(x, y, 1.0);
      const double along = n.dot(d);
      if (!(along > 1e-6)) continue;
      const Eigen::Index col = static_cast<Eigen::Index>(k) * P + j;
      points.positions.col(col) = C + (distance / along) * d;
      points.views(j, k) = 1;
      seen.xy.col(col) << x, y;
      seen.confidence(j, k) = person(2, j);
    }
  }
  points.observed.push_back(std::move(seen));
  // The bed's rest line on the plane, under the median landing (or the picture's middle).
  std::vector<double> xs;
  for (const vision::ImageFlight& flight : out.flights.flights)
    if (flight.first_contact_frame >= 0 && std::isfinite(flight.landing_px.x()))
      xs.push_back(flight.landing_px.x());
  std::sort(xs.begin(), xs.end());
  const double x_bed = xs.empty() ? 0.5 * info.width : xs[xs.size() / 2];
  {
    const Eigen::Vector2d u = camera.Undistort(Eigen::Vector2d(x_bed, line.At(x_bed)));
    const double y = (u.y() - camera.K(1, 2)) / camera.K(1, 1);
    const double x = (u.x() - camera.K(0, 2) - camera.K(0, 1) * y) / camera.K(0, 0);
    const Eigen::Vector3d d = camera.R_KW.transpose() * Eigen::Vector3d(x, y, 1.0);
    const double along = n.dot(d);
    out.bed_height_m = along > 1e-6 ? (C + (distance / along) * d).z() : std::nan("");
    if (!std::isfinite(out.bed_height_m))
      throw InputError(source.string(),
                       "bed",
                       fmt::format("the bed's line ({}: y = {:.1f} px {:+.4f} x) does not meet the "
                                   "athlete's plane in front of the camera at x = {:.0f} px",
                                   line.source,
                                   line.y0_px,
                                   line.slope,
                                   x_bed));
  }
  TrialInput& in = out.input;
  in.path = source;
  in.sha256 = Sha256Hex(Sha256OfFile(request.calibration) + HashOfSource(source));
  in.trial = points.ToTrial(
      rate,
      fmt::format("one camera's keypoints ({}, camera {}) on the plane {:.2f} m away",
                  request.calibration.string(),
                  camera.name,
                  out.depth_m));
  capture::DemandUsableContent(in.trial, in.path.string(), request.min_frames, request.use);
  const std::string turned = analysis::OrientTrialUp(&in.trial, "z", &in.up);
  (void)turned;  // "z": the calibration's world is Z up (checked above)
  out.views = std::make_shared<const analysis::ViewsToFit>(
      analysis::MakeViewsToFit(points, Eigen::Matrix3d::Identity()));
  for (const std::string& w : out.flights.warnings) in.warnings.push_back(w);
  in.athlete = MakeAthlete(request.athlete);
  out.camera = camera;
  return out;
}

}  // namespace acro::pipeline
