#pragma once

// A routine from its FIG codes (docs/skill-design.md, "Routines"): every skill designed from its
// code for the athlete (skill_from_code.h), checked against the FIG rules that apply to a
// routine's composition and against what the athlete can reach, then flown one after the other
// through bed contacts (routine_simulation.h): each contact turns the landing state of one skill
// into the take-off state of the next with a push the athlete can give.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "acro/base/yaml.h"
#include "acro/design/routine_simulation.h"
#include "acro/design/skill_from_code.h"
#include "acro/fig/score_sheet.h"

namespace acro::analysis {

/// One skill of a routine as the designer writes it.
struct RoutineSkillSpec {
  std::string code;
  double flight_time_s = 0.0;  ///< 0: chosen (routine_design.h, RoutineDesignOptions)
  std::string where;           ///< "skill 3" or "routine.yaml: line 7", for messages
};

/// A routine file (docs/formats/routine.md) or a list of codes: the athlete and the skills.
struct RoutineSpec {
  std::string name;
  std::filesystem::path athlete_path;
  std::vector<RoutineSkillSpec> skills;
};

/// Reads a routine file (YAML: `athlete`, `skills` as codes or maps with `code` and
/// `flight_time_s`, optional `name`); a relative athlete path is taken from the file's folder.
/// Throws acro::InputError naming the file, line and key at fault.
RoutineSpec ReadRoutineSpec(const std::filesystem::path& path);

/// The same from a parsed YAML tree; a relative athlete path is taken from `base_dir`.
RoutineSpec RoutineSpecFromYaml(const YamlNode& root, const std::filesystem::path& base_dir);

/// The skills of "821o 42/ 812/" (spaces or commas between codes).
RoutineSpec RoutineSpecFromCodes(const std::string& codes,
                                 const std::filesystem::path& athlete_path);

struct RoutineDesignOptions {
  /// Each skill's design and the bounds of what the athlete can reach (its flight_time_s and
  /// takeoff_vertical_velocity_mps are ignored: the routine chooses every flight's).
  SkillFromCodeOptions skill;
  RoutineSimulationOptions simulation;
  /// Flights: each skill's own flight time (DefaultFlightTime) unless the spec gives one, raised
  /// where the next skill needs more height than one contact can add: a contact changes the flight
  /// time by at most this much (s).
  double max_flight_time_change_s = 0.25;
  /// The largest push of a contact (rad of hip flexion of the squat, knees twice as much; 60°):
  /// a contact that needs more is refused naming the skill after it. A bound of the bed model
  /// (its damping sets what a push gives), not a measured human limit: the ten-skill routine of
  /// docs/skill-design.md needs up to 40°, a single to a double piked (41/ → 800<) 47°.
  double max_push_rad = 1.0471975511965976;
  /// The FIG composition (Code of Points, trampoline: an exercise has ten elements); another
  /// count is a note, not a refusal.
  int fig_skill_count = 10;
  /// Skills designed at once (0: the hardware's concurrency).
  int threads = 0;
  std::function<void(const std::string&)> progress;
};

struct RoutineDesignResult {
  RoutineSpec spec;
  std::vector<SkillFromCodeResult> skills;  ///< in routine order
  SimulatedRoutine simulation;
  double difficulty = 0.0;        ///< the sum of the skills' FIG difficulties
  double time_of_flight_s = 0.0;  ///< the sum of the simulated flights
  /// What does not make a FIG routine but is still designed (another count of skills).
  std::vector<std::string> notes;
};

/// The designed routine as the score sheet reads it (docs/scoring.md): each skill from the feet to
/// the feet with its simulated flight time; no landing zone (a design lands where it is aimed).
std::vector<fig::PerformedFlight> DesignedFlights(const RoutineDesignResult& result);

/// Designs every skill, checks the composition and the athlete's reach, chooses the flights and
/// simulates the routine through the bed. Throws acro::InputError with one line naming the skill
/// for a code it cannot build, a skill repeated, a skill the athlete cannot reach (its first
/// reason) or a contact that would need more push than `max_push_rad`.
RoutineDesignResult DesignRoutine(const RoutineSpec& spec, const RoutineDesignOptions& options);

/// The flight times of a routine whose skills need `needed` (s): each raised where the next needs
/// more than one contact adds (max_change per contact), from the last back to the first.
std::vector<double> ChooseFlightTimes(const std::vector<double>& needed, double max_change);

}  // namespace acro::analysis
