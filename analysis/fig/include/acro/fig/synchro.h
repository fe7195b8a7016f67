#pragma once

// Synchronised trampoline: two routines performed side by side, element by element — the
// difference of the two landing times of each element, whether the skills and their shapes
// matched, and the synchronisation score from the differences (docs/scoring.md, "Synchro").
//
// The Code of Points scores synchronisation from the landing-time differences that the
// competition's electronic system measures. Its conversion (how many points a difference costs)
// was not found in a stored source: the default (SynchroRules, acro/fig/rules.h) is an assumption,
// said on every sheet, that a rule file's `synchronisation:` section replaces (as the outer HD
// zones are).

#include <optional>
#include <string>
#include <vector>

#include "acro/fig/score_sheet.h"

namespace acro::fig {

/// One element of a synchro pair.
struct SynchroElement {
  int element = 0;  ///< 1-based, as on both score sheets
  std::string code_a, code_b;
  bool skills_match = false;  ///< the same FIG code (somersaults, twists, shape)
  bool shapes_match = false;
  /// Landing time of B less that of A (s): positive when B lands later.
  double landing_difference_s = 0;
  /// Counted for synchronisation (before the first mismatch and the shorter routine's end).
  bool counted = false;
  double points = 0;
};

struct SynchroScore {
  std::string source;  ///< the conversion's (SynchroRules::source)
  std::vector<SynchroElement> elements;
  int elements_counted = 0;
  /// Where the pair stopped being synchronised: the first element whose skills differ, or the
  /// shorter routine's end; 0 when the whole routine was synchronised.
  int ended_at_element = 0;
  std::string ending;  ///< one line, or empty
  double mean_abs_difference_s = 0;
  double max_abs_difference_s = 0;
  double score = 0;  ///< S
};

/// The two routines' score sheets (each from its own trial) → the pair's. `b_clock_offset_s` is
/// added to B's landing times to put them on A's clock (0 when recorded together). Elements are
/// compared in order; the pair is scored up to the first element whose skills differ, which the
/// Code treats as the end of the synchronised routine (an interruption: the elements after it are
/// not synchronised).
SynchroScore ScoreSynchro(const SynchroRules& rules,
                          const RoutineScore& a,
                          const RoutineScore& b,
                          double b_clock_offset_s = 0.0);

}  // namespace acro::fig
