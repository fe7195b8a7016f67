#pragma once

// De Leva's adjustments of Zatsiorsky–Seluyanov's segment inertia parameters: P. de Leva,
// "Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters", J. Biomech. 29(9):1223–1230,
// 1996, Table 4 (segment lengths of the reference sample, mass as % of body mass, centre of mass
// as % of the segment length from the origin endpoint, radii of gyration as % of the length).

#include <array>
#include <map>
#include <string>
#include <string_view>

#include "acro/athlete/athlete_body.h"

namespace acro::analysis {

enum class Sex { kFemale, kMale };

/// One row of de Leva 1996, Table 4; index [0] female, [1] male.
struct DeLevaRow {
  std::string_view segment;  ///< "head", "trunk", "upper_trunk", …
  std::string_view origin;   ///< endpoint the centre of mass is measured from ("VERT", "SJC", …)
  std::string_view other;    ///< the other endpoint
  std::array<double, 2> length_mm;
  std::array<double, 2> mass_percent;
  std::array<double, 2> com_percent;
  /// Radii of gyration: about the sagittal (antero-posterior) axis, the transverse (medio-lateral)
  /// axis and the longitudinal axis.
  std::array<double, 2> r_sagittal_percent;
  std::array<double, 2> r_transverse_percent;
  std::array<double, 2> r_longitudinal_percent;
};

/// The 11 rows of Table 4: head, trunk, upper_trunk, mid_trunk, lower_trunk, upper_arm, forearm,
/// hand, thigh, shank, foot.
const std::array<DeLevaRow, 11>& DeLevaTable4();
/// The row of a segment name (ACRO_DEMAND on an unknown one).
const DeLevaRow& DeLevaRowOf(std::string_view segment);

/// Mean stature (mm) and body mass (kg) of de Leva's reference sample (Zatsiorsky's subjects):
/// female 1735 mm / 61.9 kg, male 1741 mm / 73.0 kg.
double DeLevaReferenceStatureMm(Sex sex);

/// Segment lengths (m) that replace the scaled table lengths: keys "pelvis" (lower trunk),
/// "thorax" (mid + upper trunk), "head", "upper_arm", "forearm", "hand", "thigh", "shank", "foot".
using SegmentLengths = std::map<std::string, double>;

/// The standard human from height, mass and sex. Table lengths are scaled by height / reference
/// stature unless given in `lengths`; masses are fractions of `mass_kg`; inertias m (r L)². Layout
/// (docs/athlete-model.md): pelvis = lower trunk, thorax = upper + mid trunk merged by the
/// parallel-axis theorem, head-neck jointed at SUPR; ankle height 0.039 H (Drillis & Contini 1966);
/// shoulder joint centres ±0.11 H lateral at SUPR height, hip joint centres ±0.05 H; the heel 20 %
/// of the foot length behind the ankle. Throws acro::InputError (where "height_m", "mass_kg" or
/// "segment_lengths_m.<name>") for a non-positive or unknown input.
AthleteBody MakeDeLevaBody(double height_m,
                           double mass_kg,
                           Sex sex,
                           const SegmentLengths& lengths = {});

}  // namespace acro::analysis
