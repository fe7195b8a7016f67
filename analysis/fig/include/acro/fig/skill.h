#pragma once

// The FIG's words for a trampoline skill (Code of Points 2025–2028, trampoline): the numeric code,
// its shape, direction and landing positions, and the difficulty. Vocabulary for every layer above
// (assess counts skills in it, design builds them from it, the score sheet sums it).

#include <string>
#include <string_view>
#include <vector>

namespace acro::fig {

/// Body position at a take-off or a landing, in somersault quarters from upright (the Code's
/// landing positions; a seat landing is not told apart from the feet by the analysis).
enum class BodyPosition { kFeet = 0, kFront = 1, kBack = -1 };

/// The way a flight twists, as the athlete says it: left when her front turns toward her left
/// hand, as a person turning left on the spot (positive about the body's long axis z, with x
/// forward and y left), whatever the somersault; none without a counted half twist.
enum class TwistDirection { kNone, kLeft, kRight };

/// Body shape of a skill as the FIG numeric code writes it: `o` tuck, `<` pike, `/` straight.
enum class SkillShape { kTuck, kPike, kStraight };

/// Somersault direction at take-off (FIG: a skill whose twists end in an odd number of half twists
/// is performed as a forward somersault, e.g. barani, rudolph, randolph).
enum class SomersaultDirection { kNone, kForward, kBackward };

/// What a trampoline skill is, in the terms of the FIG numeric system (Code of Points 2025–2028,
/// trampoline difficulty): quarter somersaults, half twists in each somersault, shape, direction.
struct FigSkill {
  int quarter_somersaults = 0;
  /// Half twists in each somersault, first to last. A last, incomplete somersault has its own entry
  /// (the twist performed in it belongs to it); a jump (no somersault) has one entry.
  std::vector<int> half_twists;
  SkillShape shape = SkillShape::kStraight;
  SomersaultDirection direction = SomersaultDirection::kNone;

  int total_half_twists() const;
  /// Number of entries `half_twists` must have for `quarter_somersaults` (1 for jumps).
  static int SomersaultSlots(int quarter_somersaults);
};

/// The FIG numeric code: quarter somersaults, one digit per somersault with its half twists, then
/// the shape for somersaults (`821o`, `42/`, `12222o`, `161003<`). Jumps write no shape for
/// straight
/// (`00`, `01`, `02`) and `o`/`<` for tuck and pike jumps.
std::string FormatFigCode(const FigSkill& skill);

/// Parses a FIG numeric code; the direction cannot be read from the code and is taken from the
/// parity rule (odd total half twists → forward, even → backward) unless given. Throws
/// acro::InputError naming the code for malformed input.
FigSkill ParseFigCode(std::string_view code,
                      SomersaultDirection direction = SomersaultDirection::kNone);

/// The difficulty of a skill, in tenths of a point, with its parts so a coach can see where it
/// comes from (FIG Code of Points 2025–2028, trampoline; see docs/metrics.md for the rules and
/// examples).
struct FigDifficulty {
  int somersault_tenths =
      0;  ///< 0.1 per quarter; complete single/double/triple/quadruple 0.5/1.0/1.6/2.2
  int twist_tenths = 0;  ///< 0.1 per half twist
  int shape_bonus_tenths =
      0;  ///< pike/straight: +0.1 single without twist, +0.1 per somersault from 720°
  int backward_bonus_tenths = 0;  ///< backward double/triple/quadruple: +0.1/+0.2/+0.3
  int twisting_bonus_tenths = 0;  ///< twisting multiples (see CalcFigDifficulty)
  int total_tenths() const;
  double total() const { return total_tenths() / 10.0; }
  /// e.g. "1.0 double + 0.4 twist + 0.1 backward = 1.5"
  std::string Explain() const;
};

/// Computes the FIG difficulty of a skill. The twisting-multiple bonus: in doubles +0.1 per half
/// twist beyond 720° of twist, in triples +0.2 per half twist beyond 360°, in quadruples +0.2 per
/// half twist (the last rule inferred from the code's worked example "half-in rudy-out quadriffis
/// tuck 3.7").
FigDifficulty CalcFigDifficulty(const FigSkill& skill);

/// Common names of the skills coaches say aloud ("barani", "rudolph", "full-in full-out", ...), or
/// empty when the skill has no usual name.
std::string FigSkillName(const FigSkill& skill);

}  // namespace acro::fig
