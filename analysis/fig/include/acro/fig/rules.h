#pragma once

// Routine rules as data (docs/scoring.md): how many elements, whether they must differ, which
// difficulty counts and up to what, the special requirements of a first routine or an age group,
// the time-of-flight truncation and the horizontal-displacement zones. One YAML file per level and
// cycle, each citing its source (rules/*.yaml); a club edits a copy.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "acro/fig/skill.h"
#include "acro/fig/trampoline.h"

namespace acro::fig {

/// One special requirement: an element that has all of the listed properties. Each requirement
/// needs an element of its own ("cannot be fulfilled by combining them into one element").
struct ElementRequirement {
  std::string name;  ///< as the rule's source says it ("one double somersault with twist")
  int min_quarter_somersaults = 0;
  int min_half_twists = 0;
  /// Empty: any. Otherwise the element must land in (take off from) one of these positions.
  std::vector<BodyPosition> landing;
  std::vector<BodyPosition> takeoff;
  SomersaultDirection direction = SomersaultDirection::kNone;  ///< kNone: either
};

enum class DifficultyCounted { kAll, kNone };

/// How one measured execution fault becomes a suggested deduction: the deduction from each
/// threshold on (the Code of Points gives drawings, not angles — the defaults and why they are
/// what they are: docs/scoring.md; a club edits them in its rule file).
struct FaultRule {
  std::string fault;  ///< the key: knees_bent, arms_bent, arms_out, legs_apart, body_bent,
                      ///< pike_open, tuck_open, late_opening, travel, height_loss
  std::string unit;   ///< "deg", "m", "s"
  /// (threshold, deduction), thresholds in the order they are reached.
  std::vector<std::pair<double, double>> steps;
  /// For late_opening: a smaller value is worse (the opening's time before landing).
  bool smaller_is_worse = false;
  /// The deduction for `value`: that of the last threshold reached, 0 before the first.
  double DeductionFor(double value) const;
  /// Whether `value` passes the first threshold by more than `uncertainty` (a fault that is there
  /// whatever the measurement's noise).
  bool Exceeds(double value, double uncertainty) const;
};

struct ExecutionRules {
  std::vector<FaultRule> faults;
  /// The defaults (docs/scoring.md, "Execution").
  static ExecutionRules Default();
  const FaultRule* Find(std::string_view fault) const;
};

/// How a synchro pair's landing-time differences become the synchronisation score
/// (acro/fig/synchro.h). The default is an assumption (the Code's conversion was not found in a
/// stored source), said on every sheet; a rule file's `synchronisation:` section replaces it.
struct SynchroRules {
  /// What one element's synchronisation is worth (2.0: a routine of ten at most 20), and what each
  /// second of landing-time difference costs it, to zero at the most.
  double element_points = 2.0;
  double points_lost_per_s = 10.0;
  /// A difference this small is no difference (the measurement's resolution).
  double tolerance_s = 0.0;
  std::string source =
      "assumed, not from the Code of Points: 2.0 points per element (20 for ten), less 0.1 per "
      "10 ms of landing-time difference";
  bool IsValid(std::string* why) const;
};

struct RoutineRules {
  std::string name;
  std::string source;  ///< the rule's citation, printed on every sheet
  int elements = 10;
  /// A repeated element (same code, direction, take-off and landing) gets no difficulty.
  bool different_elements = true;
  DifficultyCounted difficulty = DifficultyCounted::kAll;
  /// A league's cap on the routine's difficulty (the excess is not counted); none when unset.
  std::optional<double> max_difficulty;
  /// Elements allowed with less than 270° of somersault (three quarters); none: no limit.
  std::optional<int> max_elements_below_270;
  std::vector<ElementRequirement> requirements;
  /// What the chair deducts for each requirement not performed.
  double missing_requirement_penalty = 1.0;
  /// Time of flight: 1 s = 1 point, truncated to this step.
  double time_of_flight_step = 0.005;
  HdZones zones = HdZones::Default();
  ExecutionRules execution = ExecutionRules::Default();
  SynchroRules synchro;

  /// The FIG senior routine with no special requirement (rules/fig-2025-senior.yaml's content).
  static RoutineRules FigSenior();
  bool IsValid(std::string* why) const;
};

/// Reads a rule file (YAML; keys in docs/scoring.md). Throws acro::InputError naming the file,
/// line and key for an unknown key, a wrong type or an impossible value.
RoutineRules LoadRules(const std::filesystem::path& path);
/// The same from text; `origin` names it in messages.
RoutineRules ParseRules(std::string_view text, const std::string& origin);

/// "feet", "front", "back".
const char* BodyPositionName(BodyPosition position);

}  // namespace acro::fig
