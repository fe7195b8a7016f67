#pragma once

// The flight simulation of a designed skill: does the design fly as drawn?

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/design/skill_design.h"
#include "acro/dynamics/flight_simulation.h"

namespace acro::analysis {

/// Flight simulation of a designed motion: the joints follow the trajectory, the root is
/// integrated under gravity from the take-off COM velocity and an angular momentum H0 about the
/// COM. H0 is the momentum the design needs: the one whose simulated orientation follows the
/// designed orientation best over the flight (least squares on the orientation error every 10 ms,
/// from the mean of the design's own H_Scm), or that mean itself when `fit_momentum` is false.
struct SkillSimulationResult {
  dynamics::FlightSimulationResult<double> flight;
  Eigen::Vector3d H_Scm_W = Eigen::Vector3d::Zero();   ///< the take-off momentum simulated
  Eigen::Vector3d H_mean_W = Eigen::Vector3d::Zero();  ///< the design's mean H_Scm
  Eigen::Quaterniond final_orientation = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond intended_final_orientation = Eigen::Quaterniond::Identity();
  /// Geodesic angle between the simulated and the intended final root orientation (rad).
  double final_orientation_error_rad = 0.0;
  /// RMS over the flight of the angle between the simulated and the designed orientation (rad).
  double rms_orientation_error_rad = 0.0;
  /// Somersault turns (rotation of the trunk's long axis about W's y axis, unwrapped) and
  /// the same for the designed motion.
  double somersault_turns = 0.0;
  double intended_somersault_turns = 0.0;
  /// Twist turns (the twist angle of R_WB = R_y(somersault) R_x(tilt) R_z(twist), unwrapped) of
  /// the simulated and the designed motion.
  double twist_turns = 0.0;
  double intended_twist_turns = 0.0;
  /// Where the simulated flight departs from the design, in plain words (empty when it follows
  /// it): see SkillSimulationWarnings.
  std::vector<std::string> warnings;
};

/// The warnings SimulateSkill attaches: the simulated landing or the flight's RMS orientation more
/// than 15° from the design's, the somersaults short or long by more than 15°, a twist the other
/// way or short or long by more than a quarter turn — each with its numbers and, for the rotations,
/// what in the keyframes usually causes it.
std::vector<std::string> SkillSimulationWarnings(const SkillSimulationResult& sim);

/// The simulation in one sentence: "the simulated flight (take-off momentum 61.2 kg·m²/s, the
/// design's mean 60.8) turns 0.917 somersaults (designed 0.917) and 0.00 twists (designed 0.00),
/// follows the design within 1.2° RMS and lands 2.3° from the last keyframe's orientation" — what
/// `acrolab optimize` prints, its report and the studio's designer show.
std::string FormatSkillSimulation(const SkillSimulationResult& sim);

/// The simulated flight as a motion of the design's standard human, sampled at about `rate_hz`
/// (nearest simulation steps), time from take-off: to draw it beside the design.
Motion SimulatedSkillMotion(const SkillDesign& design,
                            const SkillSimulationResult& sim,
                            double rate_hz = 100.0);

SkillSimulationResult SimulateSkill(const SkillDesign& design,
                                    const SkillTrajectory& trajectory,
                                    double step_s = 1e-3,
                                    bool fit_momentum = true);

}  // namespace acro::analysis
