#pragma once

// The standard human the product ships (analysis::MakeStandardHumanModel of a de Leva body), for
// the engine's tests and benchmarks: the Simbody oracle, the no-allocation, M·a + h and momentum
// tests run on the model users get, not on a test-only copy. Declared with dynamics types only, so
// that a test compiled in another language mode (Simbody's, C++17) can include it.

#include "acro/dynamics/model.h"

namespace acro::dynamics::testing {

/// The shipped standard human (de Leva 1996, male) of the given stature and mass, 38 DoF.
Model<double> MakeStandardHuman(double height_m = 1.75, double mass_kg = 70.0);

}  // namespace acro::dynamics::testing
