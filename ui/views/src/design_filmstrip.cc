#include "acro/views/design_filmstrip.h"

#include <algorithm>
#include <cmath>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/body_mesh.h"
#include "acro/dynamics/configuration.h"
#include "acro/scene/trial_scene.h"

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

std::vector<std::vector<std::uint8_t>> RenderRoutineFilmstrips(
    const analysis::SimulatedRoutine& routine,
    const analysis::AthleteProfile& athlete,
    const FilmstripOptions& options,
    int instants) {
  const analysis::AthleteBody body = analysis::MakeAthleteBody(athlete);
  analysis::Motion motion;
  motion.coordinate_names = analysis::MakeCoordinateNames(routine.model);
  motion.rate_hz = routine.options.point_rate_hz;
  motion.q = routine.q;
  motion.time_s = Eigen::VectorXd::LinSpaced(
      routine.num_frames(), 0.0, (routine.num_frames() - 1) / motion.rate_hz);
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

FilmstripOptions DesignFilmstripOptions() {
  FilmstripOptions options;
  options.spacing_m = 1.5;
  return options;
}

}  // namespace acro::ui
