#include "acro/views/design_filmstrip.h"

#include <algorithm>
#include <cmath>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/body_mesh.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/capture/video.h"
#include "acro/dynamics/configuration.h"
#include "acro/scene/place_scene.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/camera_composite.h"

namespace acro::ui {

DesignFilmstrip::DesignFilmstrip(
    const analysis::SkillDesign& design,
    const std::vector<std::pair<std::string, analysis::SkillTrajectory>>& timings,
    int instants) {
  static const analysis::Rgba kColours[] = {
      {0.78f, 0.8f, 0.86f, 1.0f}, {1.0f, 0.66f, 0.5f, 1.0f}, {0.45f, 0.65f, 1.0f, 1.0f}};
  const analysis::AthleteBody body = analysis::MakeAthleteBody(design.skill().athlete);
  const analysis::BodyMesh mesh =
      analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions());
  for (size_t k = 0; k < timings.size(); ++k) {
    const analysis::Motion motion = analysis::SampleSkillMotion(design, timings[k].second);
    scenes_.push_back(std::make_unique<analysis::AthleteScene>(body, mesh, motion));
    FilmstripRow row;
    row.scene = scenes_.back().get();
    row.frames = EvenlySpacedFrames(0, motion.num_frames() - 1, instants);
    row.rate_hz = motion.rate_hz;
    row.label = timings[k].first;
    row.colour = kColours[std::min<size_t>(k, 2)];
    if (k == 0) {
      for (const int f : row.frames) times_s_.push_back(motion.time_s(f));
      // Facing the way the take-off faces.
      heading_W_ = dynamics::GetRootQuaternion(motion.q.col(0)) * Eigen::Vector3d::UnitX();
    }
    rows_.push_back(row);
  }
}

DesignFilmstrip::~DesignFilmstrip() = default;

std::vector<std::uint8_t> DesignFilmstrip::Render(const FilmstripOptions& options) const {
  return RenderFilmstrips(rows_, heading_W_, options);
}

int DesignFilmstrip::WriteVideo(const std::filesystem::path& path,
                                const FilmstripOptions& options,
                                const FilmstripVideoOptions& video) const {
  return WriteFilmstripVideo(rows_, heading_W_, path, options, video);
}

namespace {

analysis::Motion RoutineMotion(const analysis::SimulatedRoutine& routine) {
  analysis::Motion motion;
  motion.coordinate_names = analysis::MakeCoordinateNames(routine.model);
  motion.rate_hz = routine.options.point_rate_hz;
  motion.q = routine.q;
  motion.time_s = Eigen::VectorXd::LinSpaced(
      routine.num_frames(), 0.0, (routine.num_frames() - 1) / motion.rate_hz);
  return motion;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> RenderRoutineFilmstrips(
    const analysis::SimulatedRoutine& routine,
    const analysis::AthleteProfile& athlete,
    const FilmstripOptions& options,
    int instants) {
  const analysis::AthleteBody body = analysis::MakeAthleteBody(athlete);
  const analysis::Motion motion = RoutineMotion(routine);
  analysis::AthleteScene scene(
      body, analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()), motion);
  std::vector<std::vector<std::uint8_t>> pictures;
  for (const analysis::RoutineFlightTruth& f : routine.flights) {
    // The frames inside the flight.
    const int first = static_cast<int>(std::ceil(f.takeoff_s * motion.rate_hz));
    const int last = std::min(static_cast<int>(std::floor(f.landing_s * motion.rate_hz)),
                              routine.num_frames() - 1);
    const Eigen::Vector3d heading =
        dynamics::GetRootQuaternion(motion.q.col(first)) * Eigen::Vector3d::UnitX();
    pictures.push_back(
        RenderFilmstrip(scene, EvenlySpacedFrames(first, last, instants), heading, options));
  }
  return pictures;
}

int WriteRoutineVideo(const analysis::SimulatedRoutine& routine,
                      const analysis::AthleteProfile& athlete,
                      const std::vector<std::string>& flight_labels,
                      const std::filesystem::path& path,
                      const RoutineVideoOptions& options) {
  const analysis::AthleteBody body = analysis::MakeAthleteBody(athlete);
  analysis::AthleteScene scene(
      body,
      analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()),
      RoutineMotion(routine));
  SceneRenderer renderer(options.width, options.height, 4);
  renderer.SetBackground({0.93f, 0.94f, 0.96f, 1.0f});
  // The trampoline of the routine's bed.
  analysis::BedGeometry bed;
  bed.centre_W = routine.options.bed_centre_m;
  bed.length_m = routine.options.bed_length_m;
  bed.width_m = routine.options.bed_width_m;
  analysis::TrampolineDimensions dimensions;
  dimensions.height_m = bed.centre_W.z();
  const analysis::TrampolineScene trampoline = analysis::MakeTrampolineScene(bed, dimensions);
  renderer.AddMesh(trampoline.bed);
  renderer.AddMesh(trampoline.frame);
  renderer.AddLines(trampoline.springs);
  renderer.AddLines(trampoline.legs);
  renderer.AddLines(trampoline.cross);
  analysis::AthletePose pose;
  scene.Pose(0, &pose);
  const int athlete_mesh = renderer.AddMesh(pose.mesh);
  // From the side, across the bed (along +y), framing the floor to above the highest apex.
  double top = bed.centre_W.z() + 2.0;
  for (const analysis::RoutineFlightTruth& f : routine.flights)
    top = std::max(top, f.apex_com_z_m + 1.2);
  FreeViewpoint view;
  view.target_W = Eigen::Vector3d(bed.centre_W.x(), bed.centre_W.y(), 0.5 * top);
  view.view_angle_deg = 30.0;
  const double distance =
      0.55 * top / std::tan(0.5 * view.view_angle_deg * 3.14159265358979323846 / 180);
  view.eye_W = view.target_W - distance * Eigen::Vector3d::UnitY();
  renderer.LookFrom(view);
  renderer.SetSceneLights(
      {Eigen::Vector3d(0.3, 0.5, -1.0), Eigen::Vector3d(-0.4, 0.2, -1.0)}, 0.5, 0.5);

  capture::VideoWriterOptions w;
  w.fps = options.fps;
  capture::VideoWriter writer(path, options.width, options.height, w);
  const double rate = routine.options.point_rate_hz;
  const int frames =
      static_cast<int>(std::floor((routine.num_frames() - 1) / rate * options.fps)) + 1;
  RenderImage image, text;
  std::vector<std::uint8_t> rgb(size_t(options.width) * size_t(options.height) * 3);
  const int text_px = std::max(14, options.height / 28);
  for (int k = 0; k < frames; ++k) {
    const double t = k / options.fps;
    const int sample = std::min(static_cast<int>(std::lround(t * rate)), routine.num_frames() - 1);
    scene.Pose(sample, &pose);
    renderer.UpdateMesh(athlete_mesh, pose.mesh.vertices_W);
    renderer.Render(&image);
    for (size_t i = 0, n = size_t(options.width) * size_t(options.height); i < n; ++i)
      for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = image.rgba[4 * i + size_t(c)];
    for (size_t i = 0; i < routine.flights.size() && i < flight_labels.size(); ++i) {
      const analysis::RoutineFlightTruth& f = routine.flights[i];
      if (t < f.takeoff_s || t > f.landing_s) continue;
      RenderTextLine(flight_labels[i], text_px, {1, 1, 1, 1}, &text);
      BlendOver(text, text_px / 2, text_px / 2, options.width, options.height, &rgb);
    }
    writer.Write(rgb);
    if (options.progress && !options.progress(k + 1, frames))
      throw Cancelled(path.string() + ": cancelled");
  }
  writer.Finish();
  return frames;
}

FilmstripOptions DesignFilmstripOptions() {
  FilmstripOptions options;
  options.spacing_m = 1.5;
  return options;
}

}  // namespace acro::ui
