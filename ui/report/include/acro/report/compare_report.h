#pragma once

// The charts under `acrolab compare`'s views: the two jumps' centre-of-mass heights, and their
// somersault and twist angles, over the time from take-off — side by side as one RGB strip, with
// where each plot's time axis runs so that a video can draw its cursor.

#include <string>

#include "acro/scene/compare_scene.h"

namespace acro::ui {

/// The two charts, each `width / 2` × `height`, for τ from `start_s` to `end_s`, as a panel with
/// the cursor's span on each. Labels name the jumps in the legends. Throws acro::InputError when a
/// chart cannot be drawn.
analysis::TimedPanel MakeCompareCharts(const analysis::JumpCurves& a,
                                       const analysis::JumpCurves& b,
                                       const std::string& label_a,
                                       const std::string& label_b,
                                       double start_s,
                                       double end_s,
                                       int width,
                                       int height);

}  // namespace acro::ui
