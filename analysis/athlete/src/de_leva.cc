#include "acro/athlete/de_leva.h"

#include <cmath>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"

namespace acro::analysis {

const std::array<DeLevaRow, 11>& DeLevaTable4() {
  // de Leva P. (1996) J. Biomech. 29(9):1223–1230, Table 4 (upper part): "Adjusted segment
  // inertia parameters". Columns {female, male}: length (mm), mass (% of body mass), CM position
  // (% of length from the origin endpoint), radii of gyration (% of length) about the sagittal,
  // transverse and longitudinal axes. Endpoints: VERT vertex, MIDG mid-gonion, SUPR suprasternale,
  // XIPH xiphion, OMPH omphalion, MIDH mid-hip (hip joint centres' midpoint), SJC/EJC/WJC shoulder,
  // elbow and wrist joint centres, MET3 third metacarpale, HJC/KJC hip and knee joint centres,
  // LMAL lateral malleolus, HEEL heel, TTIP tip of the longest toe.
  static const std::array<DeLevaRow, 11> kTable = {{
      {"head",
       "VERT",
       "MIDG",
       {200.2, 203.3},
       {6.68, 6.94},
       {58.94, 59.76},
       {33.0, 36.2},
       {35.9, 37.6},
       {31.8, 31.2}},
      {"trunk",
       "SUPR",
       "MIDH",
       {529.3, 531.9},
       {42.57, 43.46},
       {41.51, 44.86},
       {30.7, 32.8},
       {29.2, 30.6},
       {14.7, 16.9}},
      {"upper_trunk",
       "SUPR",
       "XIPH",
       {142.5, 170.7},
       {15.45, 15.96},
       {20.77, 29.99},
       {74.6, 71.6},
       {50.2, 45.4},
       {71.8, 65.9}},
      {"mid_trunk",
       "XIPH",
       "OMPH",
       {205.3, 215.5},
       {14.65, 16.33},
       {45.12, 45.02},
       {43.3, 48.2},
       {35.4, 38.3},
       {41.5, 46.8}},
      {"lower_trunk",
       "OMPH",
       "MIDH",
       {181.5, 145.7},
       {12.47, 11.17},
       {49.20, 61.15},
       {43.3, 61.5},
       {40.2, 55.1},
       {44.4, 58.7}},
      {"upper_arm",
       "SJC",
       "EJC",
       {275.1, 281.7},
       {2.55, 2.71},
       {57.54, 57.72},
       {27.8, 28.5},
       {26.0, 26.9},
       {14.8, 15.8}},
      {"forearm",
       "EJC",
       "WJC",
       {264.3, 268.9},
       {1.38, 1.62},
       {45.59, 45.74},
       {26.1, 27.6},
       {25.7, 26.5},
       {9.4, 12.1}},
      {"hand",
       "WJC",
       "MET3",
       {78.0, 86.2},
       {0.56, 0.61},
       {74.74, 79.00},
       {53.1, 62.8},
       {45.4, 51.3},
       {33.5, 40.1}},
      {"thigh",
       "HJC",
       "KJC",
       {368.5, 422.2},
       {14.78, 14.16},
       {36.12, 40.95},
       {36.9, 32.9},
       {36.4, 32.9},
       {16.2, 14.9}},
      {"shank",
       "KJC",
       "LMAL",
       {432.3, 434.0},
       {4.81, 4.33},
       {44.16, 44.59},
       {27.1, 25.5},
       {26.7, 24.9},
       {9.3, 10.3}},
      {"foot",
       "HEEL",
       "TTIP",
       {228.3, 258.1},
       {1.29, 1.37},
       {40.14, 44.15},
       {29.9, 25.7},
       {27.9, 24.5},
       {13.9, 12.4}},
  }};
  return kTable;
}

const DeLevaRow& DeLevaRowOf(std::string_view segment) {
  for (const DeLevaRow& row : DeLevaTable4())
    if (row.segment == segment) return row;
  ACRO_DEMAND(false);
  return DeLevaTable4()[0];
}

double DeLevaReferenceStatureMm(Sex sex) {
  // de Leva 1996, Table 1/4 caption: mean stature of Zatsiorsky's female and male samples.
  return sex == Sex::kFemale ? 1735.0 : 1741.0;
}

namespace {

// Mass properties of a de Leva segment: mass fraction × body mass, the centre of mass at
// com% of the length from `origin` towards `other`, principal inertias m (r% L)² about the axes
// given by (sagittal, transverse, longitudinal) → H axes `axes` (0 = x, 1 = y, 2 = z).
InertialProperties RowInertia(const DeLevaRow& row,
                              int k,
                              double body_mass_kg,
                              double length_m,
                              const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& other,
                              const std::array<int, 3>& axes) {
  InertialProperties out;
  out.mass_kg = row.mass_percent[static_cast<size_t>(k)] / 100.0 * body_mass_kg;
  out.p_HoCm_H = origin + row.com_percent[static_cast<size_t>(k)] / 100.0 * (other - origin);
  const double r[3] = {row.r_sagittal_percent[static_cast<size_t>(k)] / 100.0 * length_m,
                       row.r_transverse_percent[static_cast<size_t>(k)] / 100.0 * length_m,
                       row.r_longitudinal_percent[static_cast<size_t>(k)] / 100.0 * length_m};
  for (int j = 0; j < 3; ++j)
    out.I_Cm_H(axes[static_cast<size_t>(j)], axes[static_cast<size_t>(j)]) =
        out.mass_kg * r[j] * r[j];
  return out;
}

}  // namespace

namespace {

// The stature, the mass and the measured lengths: positive, finite, of known segments.
void CheckDeLevaInputs(double height_m, double mass_kg, const SegmentLengths& lengths) {
  if (!(height_m > 0.0) || !std::isfinite(height_m))
    throw InputError(
        "", "height_m", "must be a positive height in metres, found " + std::to_string(height_m));
  if (!(mass_kg > 0.0) || !std::isfinite(mass_kg))
    throw InputError(
        "", "mass_kg", "must be a positive mass in kg, found " + std::to_string(mass_kg));
  static const std::array<std::string_view, 9> kLengthNames = {
      "pelvis", "thorax", "head", "upper_arm", "forearm", "hand", "thigh", "shank", "foot"};
  for (const auto& [name, value] : lengths) {
    bool known = false;
    for (std::string_view n : kLengthNames) known = known || n == name;
    if (!known)
      throw InputError("",
                       "segment_lengths_m." + name,
                       "unknown segment (pelvis, thorax, head, upper_arm, forearm, hand, thigh, "
                       "shank, foot)");
    if (!(value > 0.0) || !std::isfinite(value))
      throw InputError("", "segment_lengths_m." + name, "must be a positive length in metres");
  }
}

}  // namespace

AthleteBody MakeDeLevaBody(double height_m,
                           double mass_kg,
                           Sex sex,
                           const SegmentLengths& lengths) {
  CheckDeLevaInputs(height_m, mass_kg, lengths);
  const int k = sex == Sex::kFemale ? 0 : 1;
  const double scale = height_m / (DeLevaReferenceStatureMm(sex) / 1000.0);
  auto table_length = [&](std::string_view segment) {
    return DeLevaRowOf(segment).length_mm[static_cast<size_t>(k)] / 1000.0 * scale;
  };
  auto length = [&](const char* name, std::string_view segment) {
    const auto it = lengths.find(name);
    return it != lengths.end() ? it->second : table_length(segment);
  };
  // Lengths (m). A measured thorax length is shared by upper and mid trunk in the table's ratio.
  const double L_lpt = length("pelvis", "lower_trunk");
  double L_upt = table_length("upper_trunk"), L_mpt = table_length("mid_trunk");
  if (const auto it = lengths.find("thorax"); it != lengths.end()) {
    const double f = it->second / (L_upt + L_mpt);
    L_upt *= f;
    L_mpt *= f;
  }
  const double L_head = length("head", "head");
  const double L_ua = length("upper_arm", "upper_arm");
  const double L_fa = length("forearm", "forearm");
  const double L_hand = length("hand", "hand");
  const double L_thigh = length("thigh", "thigh");
  const double L_shank = length("shank", "shank");
  const double L_foot = length("foot", "foot");

  // Landmarks of the reference pose in H (origin MIDH; x anterior, y left, z up).
  const double ankle_height = 0.039 * height_m;  // Drillis & Contini 1966 (Winter 2009, Fig. 4.1)
  const double midh_height = ankle_height + L_shank + L_thigh;
  const Eigen::Vector3d MIDH(0, 0, 0);
  const Eigen::Vector3d OMPH(0, 0, L_lpt);
  const Eigen::Vector3d XIPH(0, 0, L_lpt + L_mpt);
  const Eigen::Vector3d SUPR(0, 0, L_lpt + L_mpt + L_upt);
  const Eigen::Vector3d VERT(0, 0, height_m - midh_height);
  const Eigen::Vector3d MIDG = VERT - Eigen::Vector3d(0, 0, L_head);
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const std::array<int, 3> upright = {0, 1, 2};    // sagittal → x, transverse → y, long → z
  const std::array<int, 3> foot_axes = {2, 1, 0};  // the foot's long axis is x

  AthleteBody body;
  body.model = std::string("de Leva 1996 (") + (sex == Sex::kFemale ? "female" : "male") + ")";
  body.height_m = height_m;
  body.segments.resize(kStandardSegmentNames.size());
  for (size_t i = 0; i < body.segments.size(); ++i) {
    body.segments[i].name = std::string(kStandardSegmentNames[i]);
    body.segments[i].parent = kStandardSegmentParents[i];
  }
  auto set = [&](const char* name,
                 const Eigen::Vector3d& joint,
                 const Eigen::Vector3d& end,
                 const InertialProperties& in) {
    BodySegment& s = body.segments[static_cast<size_t>(body.Find(name))];
    s.p_HoJ_H = joint;
    s.p_HoE_H = end;
    s.in_H = in;
  };
  // Trunk: pelvis = lower trunk (OMPH→MIDH); thorax = upper (SUPR→XIPH) + mid (XIPH→OMPH) trunk.
  set("pelvis",
      MIDH,
      OMPH,
      RowInertia(DeLevaRowOf("lower_trunk"), k, mass_kg, L_lpt, OMPH, MIDH, upright));
  set("thorax",
      OMPH,
      SUPR,
      CombineInertia(
          {RowInertia(DeLevaRowOf("upper_trunk"), k, mass_kg, L_upt, SUPR, XIPH, upright),
           RowInertia(DeLevaRowOf("mid_trunk"), k, mass_kg, L_mpt, XIPH, OMPH, upright)}));
  set("head", SUPR, VERT, RowInertia(DeLevaRowOf("head"), k, mass_kg, L_head, VERT, MIDG, upright));
  // Arms hanging from the shoulder joint centres, legs from the hip joint centres.
  for (const char* side : {"l", "r"}) {
    const double sign = side[0] == 'l' ? 1.0 : -1.0;
    const std::string s(side);
    const Eigen::Vector3d SJC = SUPR + Eigen::Vector3d(0, sign * 0.11 * height_m, 0);
    const Eigen::Vector3d EJC = SJC - L_ua * ez;
    const Eigen::Vector3d WJC = EJC - L_fa * ez;
    const Eigen::Vector3d MET3 = WJC - L_hand * ez;
    set((s + "_upper_arm").c_str(),
        SJC,
        EJC,
        RowInertia(DeLevaRowOf("upper_arm"), k, mass_kg, L_ua, SJC, EJC, upright));
    set((s + "_forearm").c_str(),
        EJC,
        WJC,
        RowInertia(DeLevaRowOf("forearm"), k, mass_kg, L_fa, EJC, WJC, upright));
    set((s + "_hand").c_str(),
        WJC,
        MET3,
        RowInertia(DeLevaRowOf("hand"), k, mass_kg, L_hand, WJC, MET3, upright));
    const Eigen::Vector3d HJC(0, sign * 0.05 * height_m, 0);
    const Eigen::Vector3d KJC = HJC - L_thigh * ez;
    const Eigen::Vector3d LMAL = KJC - L_shank * ez;
    const Eigen::Vector3d HEEL = LMAL + Eigen::Vector3d(-0.2 * L_foot, 0, -ankle_height);
    const Eigen::Vector3d TTIP = HEEL + Eigen::Vector3d(L_foot, 0, 0);
    set((s + "_thigh").c_str(),
        HJC,
        KJC,
        RowInertia(DeLevaRowOf("thigh"), k, mass_kg, L_thigh, HJC, KJC, upright));
    set((s + "_shank").c_str(),
        KJC,
        LMAL,
        RowInertia(DeLevaRowOf("shank"), k, mass_kg, L_shank, KJC, LMAL, upright));
    set((s + "_foot").c_str(),
        LMAL,
        TTIP,
        RowInertia(DeLevaRowOf("foot"), k, mass_kg, L_foot, HEEL, TTIP, foot_axes));
  }
  std::vector<InertialProperties> all;
  for (const BodySegment& s : body.segments) all.push_back(s.in_H);
  body.total = CombineInertia(all);
  return body;
}

}  // namespace acro::analysis
