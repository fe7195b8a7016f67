#include "standard_human_fixture.h"

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"

namespace acro::dynamics::testing {

Model<double> MakeStandardHuman(double height_m, double mass_kg) {
  return analysis::MakeStandardHumanModel(
      analysis::MakeDeLevaBody(height_m, mass_kg, analysis::Sex::kMale));
}

}  // namespace acro::dynamics::testing
