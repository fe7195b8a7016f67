#pragma once

// A skill from its FIG numeric code (docs/skill-design.md, "Skills from their code"): the
// keyframes of the skill for one athlete — take-off posture, entry into the shape, the held
// shape, where each somersault's half twists happen, the arm and hip actions that start them, the
// opening and the landing posture — found by simulating the flight. The joints follow a schedule
// of postures placed by somersault angle; the root turns free with its angular momentum conserved
// (dynamics::SimulateFlightRotation), and shooting finds the take-off angular momentum (its
// somersault component, and for a skill that twists in its first somersault its twist component,
// the "contact twist") and the size of the asymmetric arm and hip action that starts each later
// twist (the "aerial twist"; Yeadon 1993, J. Sports Sci. 11, Parts II and III) so that the
// flight turns the code's somersaults and puts the code's half twists in each somersault. The
// keyframes are samples of that flight, so they start physically consistent; Models 2 and 1 then
// only remove what the splines between them add.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/assess/jump_rotation.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/design/posture_track.h"
#include "acro/design/skill_file.h"
#include "acro/fig/skill.h"

namespace acro::analysis {

struct SkillFromCodeOptions {
  /// Flight time T (s); 0 chooses it from the somersaults (jumps 1.2 s, singles 1.45 s, doubles
  /// 1.65 s, triples 1.85 s, quadruples 2.0 s) plus 0.05 s per half twist. Ignored when
  /// takeoff_vertical_velocity_mps > 0.
  double flight_time_s = 0.0;
  double takeoff_vertical_velocity_mps = 0.0;
  /// Fixed-step RK4 step of the shooting's flight simulations (s; the step actually used divides
  /// T evenly).
  double step_s = 2e-3;
  /// What the athlete can reach (docs/skill-design.md, "Can the athlete do it"): the longest
  /// flight (s) and the largest somersault angular momentum per mass and squared height (1/s).
  double max_flight_time_s = 2.0;
  double max_normalized_somersault_momentum = 0.40;
  /// The largest tilt of the body from the plane normal to the momentum during the twists (deg),
  /// and the least time between the end of the last twist or opening and the landing (s).
  double max_tilt_deg = 25.0;
  double min_time_to_prepare_landing_s = 0.05;
  /// Asked between shooting iterations; true stops with acro::Cancelled ("design: cancelled").
  std::function<bool()> cancelled;
  /// Progress lines (shooting iterations) are handed here when set; the library prints nothing.
  std::function<void(const std::string&)> progress;
};

/// What the designed skill needs from the take-off and whether this athlete can give it.
struct SkillFromCodeResult {
  Skill skill;  ///< the keyframes as a skill file holds them
  fig::FigSkill code;
  fig::FigDifficulty difficulty;
  double flight_time_s = 0.0;
  double takeoff_vertical_velocity_mps = 0.0;
  /// Take-off angular momentum about the COM in W (kg·m²/s): the somersault component (about the
  /// lateral axis, W's y) and the twist component along the body's long axis at take-off.
  Eigen::Vector3d H_Scm_W = Eigen::Vector3d::Zero();
  double somersault_momentum = 0.0;             ///< |H_y|
  double twist_momentum = 0.0;                  ///< the contact twist's component (0 without one)
  double normalized_somersault_momentum = 0.0;  ///< |H_y| / (m h²), 1/s
  /// The asymmetric arm (and hip) action of each twist started in the air (rad of arm abduction;
  /// its sign sets the direction), in somersault order.
  std::vector<double> aerial_twist_actions_rad;
  /// The simulated flight the keyframes come from: somersault and twist turned in the air (rad,
  /// signed), half twists in each somersault (as the analysis counts them: by the nominal
  /// somersault angle, 45° of bed rotation before take-off), the largest tilt (rad), the time
  /// from the end of the last twist or opening to the landing (s), and the shooting's largest
  /// residual (rad).
  double air_somersault_rad = 0.0;
  double air_twist_rad = 0.0;  ///< positive to the athlete's left
  fig::TwistDirection twist_direction =
      fig::TwistDirection::kNone;  ///< of air_twist_rad; none without twist
  std::vector<double> half_twists_per_somersault;
  double max_tilt_rad = 0.0;
  double landing_tilt_rad = 0.0;
  double time_to_prepare_landing_s = 0.0;
  double shooting_residual_rad = 0.0;
  int shooting_simulations = 0;
  /// What a routine needs to fly the skill again from a bed contact (routine_design.h): the joints'
  /// schedule over the flight (t = 0 at take-off), the somersault done on the bed before take-off
  /// and still to do after landing (rad, magnitudes), and the take-off momentum's somersault
  /// component (along W's y) and contact-twist component (along the body's long axis at take-off)
  /// as the shooting found them (kg·m²/s, signed).
  PostureTrack track;
  double takeoff_lean_rad = 0.0;
  double landing_short_rad = 0.0;
  Eigen::Vector2d momentum_components = Eigen::Vector2d::Zero();
  /// Empty when the athlete can do it; otherwise each reason in one line with its numbers.
  std::vector<std::string> not_feasible;
  bool feasible() const { return not_feasible.empty(); }
};

/// Designs the keyframes of the skill `code` ("821o", "42/", "00") for the athlete whose profile
/// is at `athlete_path` (kept in the skill as its athlete). Throws acro::InputError with one line
/// for a code it cannot read or build (landings on the back, front or seat; more than four
/// somersaults; a jump with a shape and twists) and when shooting finds no flight that turns the
/// code's rotation.
SkillFromCodeResult DesignSkillFromCode(const std::string& code,
                                        const std::filesystem::path& athlete_path,
                                        const SkillFromCodeOptions& options = {});

/// The flight time chosen for a skill when none is given (s), and its part from the somersaults.
double DefaultFlightTime(const fig::FigSkill& skill);
double BaseFlightTime(const fig::FigSkill& skill);

/// The take-off and feasibility in a few lines (what `acrolab design` prints and writes).
std::string FormatSkillFromCode(const SkillFromCodeResult& result);

}  // namespace acro::analysis
