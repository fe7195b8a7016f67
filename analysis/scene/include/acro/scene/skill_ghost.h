#pragma once

// A designed skill read back from `acrolab optimize`'s folder (result.json and motion.mot,
// docs/cli.md) as the motion of an athlete's standard human, so that it can be drawn as a ghost
// over a real jump (`acrolab overlay --ghost DIR`) or beside it. The design's time runs from its
// take-off (0) to its landing (the flight time).

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/motion.h"
#include "acro/design/skill_optimization.h"
#include "acro/dynamics/model.h"

namespace acro::analysis {

struct SkillGhost {
  std::string name;      ///< the skill's name ("back tuck")
  std::string fig_code;  ///< may be empty
  std::string athlete;   ///< the athlete it was designed for
  double flight_time_s = 0.0;
  std::vector<std::string> keyframe_names;
  std::vector<double> keyframe_times_s;          ///< optimised
  std::vector<double> keyframe_times_initial_s;  ///< before the optimisation
  /// q(t) of the standard human, time from take-off; the root translation is the design's (its
  /// centre of mass on the take-off parabola).
  Motion motion;
};

/// Reads DIR/result.json and DIR/motion.mot (`path` is the folder, or its result.json or
/// motion.mot) for `model`, a standard human (MakeStandardHumanModel): the .mot's root columns
/// (pelvis_tx … tz in m, somersault, tilt, twist in degrees: R = R_y(s) R_x(t) R_z(w)) become the
/// root position and quaternion, its joint columns are matched to the model's coordinates by name.
/// Throws acro::InputError naming the file and the field or column at fault (a file missing, a
/// joint the model lacks or the model's joint the file lacks, times that do not start at the
/// take-off or do not increase).
SkillGhost ReadSkillGhost(const std::filesystem::path& path,
                                const dynamics::Model<double>& model);

/// The same straight from the optimisation (the studio's designer, before anything is saved): the
/// optimised motion sampled evenly over the flight at about `rate_hz` (SampleSkillMotion), the
/// keyframe times before and after: what ReadSkillGhost reads back from this design's folder,
/// sampled on an even grid (motion.mot's samples are 1/rate apart, the last at the flight time).
SkillGhost MakeSkillGhost(const SkillDesign& design,
                                const SkillOptimizationResult& result,
                                double rate_hz = 100.0);

/// The frame of `motion` nearest to time `t_s` (clamped to the motion's first and last frames).
int FrameNearestTime(const Motion& motion, double t_s);

}  // namespace acro::analysis
