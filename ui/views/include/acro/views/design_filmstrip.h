#pragma once

// A designed skill's timings side by side as filmstrips (`acrolab optimize`'s picture and the
// studio's skill designer; the source paper's Figure 8): each timing a row, the athlete the skill
// was designed for at the same instants evenly spaced over the flight, seen from its left at one
// scale. Needs an X display (display.h).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "acro/design/routine_simulation.h"
#include "acro/design/skill_design.h"
#include "acro/scene/athlete_scene.h"
#include "acro/views/filmstrip.h"

namespace acro::ui {

class DesignFilmstrip {
 public:
  /// One row per (label, trajectory) of `design`, in order (the first grey, the second warm, then
  /// blue), at `instants` instants from take-off to landing.
  DesignFilmstrip(const analysis::SkillDesign& design,
                  const std::vector<std::pair<std::string, analysis::SkillTrajectory>>& timings,
                  int instants = 8);
  ~DesignFilmstrip();

  /// The instants shown (s from take-off).
  const std::vector<double>& times_s() const { return times_s_; }
  /// The picture: width × (rows × height) RGB.
  std::vector<std::uint8_t> Render(const FilmstripOptions& options) const;
  /// The same as a video (WriteFilmstripVideo).
  int WriteVideo(const std::filesystem::path& path,
                 const FilmstripOptions& options,
                 const FilmstripVideoOptions& video) const;
  int num_rows() const { return static_cast<int>(rows_.size()); }

 private:
  std::vector<std::unique_ptr<analysis::AthleteScene>> scenes_;
  std::vector<FilmstripRow> rows_;
  std::vector<double> times_s_;
  Eigen::Vector3d heading_W_ = Eigen::Vector3d::UnitX();
};

/// One picture per flight of a simulated routine (`acrolab routine`'s report): the athlete at
/// `instants` instants evenly spaced from take-off to landing, seen from its left as it faces at
/// take-off; each options.width × options.height RGB.
std::vector<std::vector<std::uint8_t>> RenderRoutineFilmstrips(
    const analysis::SimulatedRoutine& routine,
    const analysis::AthleteProfile& athlete,
    const FilmstripOptions& options,
    int instants = 8);

struct RoutineVideoOptions {
  int width = 1280;
  int height = 720;
  double fps = 30.0;
  /// Called after each frame with (frames done, frames in all); false cancels (acro::InputError,
  /// nothing written).
  std::function<bool(int, int)> progress;
};

/// The routine as an MP4 (H.264) in real time: the athlete over the trampoline (the routine's bed,
/// FIG frame), seen from the side across the bed by a fixed camera that frames the highest apex,
/// each flight's code and name written at the top left while it flies. The file appears only when
/// complete. Returns the number of frames written. Needs an X display.
int WriteRoutineVideo(const analysis::SimulatedRoutine& routine,
                      const analysis::AthleteProfile& athlete,
                      const std::vector<std::string>& flight_labels,
                      const std::filesystem::path& path,
                      const RoutineVideoOptions& options = {});

/// The options `acrolab optimize` draws its filmstrip with: poses 1.5 m apart (the tucked poses at
/// the apex do not overlap).
FilmstripOptions DesignFilmstripOptions();

}  // namespace acro::ui
