#include "acro/athlete/yeadon_human.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"

namespace acro::analysis {

std::string_view DensitySetName(DensitySet set) {
  switch (set) {
    case DensitySet::kDempster:
      return "dempster";
    case DensitySet::kChandler:
      return "chandler";
    case DensitySet::kClauser:
      return "clauser";
  }
  return "?";
}

bool ParseDensitySet(std::string_view name, DensitySet* set) {
  for (DensitySet s : {DensitySet::kDempster, DensitySet::kChandler, DensitySet::kClauser}) {
    if (DensitySetName(s) == name) {
      *set = s;
      return true;
    }
  }
  return false;
}

YeadonDensities DensitiesOf(DensitySet set) {
  // Region densities in kg/m³ (Yeadon 1990, density table, from Dempster 1955, Chandler et al. 1975
  // and Clauser et al. 1969; the values the yeadon package uses, there given in kg/L × 1000).
  // Order: head-neck, shoulders, thorax, abdomen-pelvis, upper arm, forearm, hand, thigh, lower
  // leg, foot.
  switch (set) {
    case DensitySet::kDempster:
      return {1110, 1040, 920, 1010, 1070, 1130, 1160, 1050, 1090, 1100};
    case DensitySet::kChandler:
      return {1056, 853, 853, 853, 1005, 1052, 1080, 1020, 1078, 1091};
    case DensitySet::kClauser:
      return {1070, 1019, 1019, 1019, 1056, 1089, 1109, 1044, 1085, 1084};
  }
  return {};
}

bool YeadonConfiguration::Set(std::string_view name, double angle_rad) {
  for (size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) {
      angles_rad[i] = angle_rad;
      return true;
    }
  }
  return false;
}

double YeadonConfiguration::Get(std::string_view name) const {
  for (size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return angles_rad[i];
  ACRO_DEMAND(false);
  return 0.0;
}

Eigen::Matrix3d YeadonAxesToBodyAxes() {
  // Columns: yeadon's x (left), y (posterior), z (up) expressed in H (x anterior, y left, z up).
  Eigen::Matrix3d R;
  R << 0, -1, 0,  //
      1, 0, 0,    //
      0, 0, 1;
  return R;
}

int YeadonHuman::FindSegment(std::string_view label) const {
  for (size_t i = 0; i < segments_.size(); ++i)
    if (segments_[i].label == label) return static_cast<int>(i);
  return -1;
}

int YeadonHuman::FindSolid(std::string_view label) const {
  for (size_t i = 0; i < solids_.size(); ++i)
    if (solids_[i].label == label) return static_cast<int>(i);
  return -1;
}

namespace {

constexpr double kPi = std::numbers::pi;

// A stadium: two half circles of radius r joined by straight sides of length 2t.
struct Stadium {
  double r = 0.0;
  double t = 0.0;
  double width = 0.0;  // 2t + 2r
  bool anteroposterior = false;
};

// Yeadon 1990, Appendix: the stadium from its perimeter p and width w, p = 4t + 2πr, w = 2t + 2r,
// so t = (πw − p)/(2π − 4) and r = (p − 2w)/(2π − 4); from a depth d = 2r and width w likewise.
// When 2 < p/w < π fails the stadium is replaced by a circle (of perimeter p, or of diameter w),
// as Yeadon's ISEG program and the yeadon package do.
class StadiumMaker {
 public:
  StadiumMaker(std::string source, std::vector<std::string>* warnings)
      : source_(std::move(source)), warnings_(warnings) {}

  Stadium Circle(const std::string& what, double perimeter) const {
    Stadium s;
    s.r = perimeter / (2.0 * kPi);
    s.width = 2.0 * s.r;
    Check(what, s);
    return s;
  }
  Stadium PerimeterWidth(const std::string& what, double p, double w, bool ap = false) const {
    Stadium s;
    s.t = (kPi * w - p) / (2.0 * kPi - 4.0);
    s.r = (p - 2.0 * w) / (2.0 * kPi - 4.0);
    s.width = w;
    s.anteroposterior = ap;
    if (s.r < 0.0 || s.t < 0.0) {
      Warn(what, s, p / w, "set as a circle of the given perimeter");
      s = Circle(what, p);
      s.anteroposterior = ap;
    }
    Check(what, s);
    return s;
  }
  Stadium DepthWidth(const std::string& what, double d, double w) const {
    const double p = 2.0 * w + (kPi - 2.0) * d;
    Stadium s;
    s.t = (kPi * w - p) / (2.0 * kPi - 4.0);
    s.r = (p - 2.0 * w) / (2.0 * kPi - 4.0);
    s.width = w;
    if (s.r < 0.0 || s.t < 0.0) {
      Warn(what, s, p / w, "set as a circle of diameter the given width");
      s = Circle(what, kPi * w);
    }
    Check(what, s);
    return s;
  }
  Stadium ThicknessRadius(const std::string& what, double t, double r) const {
    Stadium s;
    s.t = t;
    s.r = r;
    s.width = 2.0 * t + 2.0 * r;
    if (s.r < 0.0 || s.t < 0.0)
      throw InputError(source_, what, "negative stadium radius or thickness cannot be corrected");
    Check(what, s);
    return s;
  }

 private:
  void Check(const std::string& what, const Stadium& s) const {
    if (!(s.r > 0.0) || !std::isfinite(s.t))
      throw InputError(source_, what, "the stadium's radius is not positive");
  }
  void Warn(const std::string& what, const Stadium& s, double ratio, const char* fix) const {
    std::ostringstream out;
    out << source_ << ": " << what << ": perimeter/width = " << ratio
        << " is outside (2, pi) (r = " << s.r << " m, t = " << s.t << " m); " << fix;
    warnings_->push_back(out.str());
  }
  std::string source_;
  std::vector<std::string>* warnings_;
};

// Yeadon 1990, Appendix: integrals of polynomials in the taper ratios a (radius) and b (thickness)
// over a stadium solid of unit height.
double F1(double a, double b) {
  return 1.0 + (a + b) * 0.5 + a * b / 3.0;
}
double F2(double a, double b) {
  return 0.5 + (a + b) / 3.0 + a * b * 0.25;
}
double F3(double a, double b) {
  return 1.0 / 3.0 + (a + b) / 4.0 + a * b * 0.2;
}
double F4(double a, double b) {
  return 1.0 + (a + 3.0 * b) * 0.5 + (a * b + b * b) + (3.0 * a * b * b + b * b * b) * 0.25 +
         a * b * b * b * 0.2;
}
double F5(double a, double b) {
  return 1.0 + (a + b) + (a * a + 4.0 * a * b + b * b) / 3.0 + a * b * (a + b) * 0.5 +
         a * a * b * b * 0.2;
}

// Mass, centroid height above stadium 0 and inertia about the centroid of a stadium solid, in
// yeadon's local axes (x along the stadia's long axis, z along the solid). Yeadon 1990, Appendix:
// with r(z) = r0(1 + a z/h), t(z) = t0(1 + b z/h):
//   m    = D h r0 (4 t0 F1(a,b) + π r0 F1(a,a))
//   z̄    = D h² (4 r0 t0 F2(a,b) + π r0² F2(a,a)) / m
//   I_z  = D h (4 r0 t0³ F4(a,b)/3 + π r0² t0² F5(a,b) + 4 r0³ t0 F4(b,a) + π r0⁴ F4(a,a)/2)
//   I_y⁰ = D h (4 r0 t0³ F4(a,b)/3 + π r0² t0² F5(a,b) + 8 r0³ t0 F4(b,a)/3 + π r0⁴ F4(a,a)/4)
//          + D h³ (4 r0 t0 F3(a,b) + π r0² F3(a,a))        (about the base; Yeadon's printed
//          formula lacks the h³ factor of the second term, as the yeadon package notes)
//   I_x⁰ = D h (4 t0 r0³ F4(b,a)/3 + π r0⁴ F4(a,a)/4) + D h³ (4 r0 t0 F3(a,b) + π r0² F3(a,a))
//          (Yeadon prints 4 r0 t0³ F4(a,b)/3 for the first term; see below)
// and I_x, I_y about the centroid by the parallel-axis theorem. The formulas need t0 ≠ 0 when
// t1 ≠ 0 (b = (t1 − t0)/t0): a solid whose base is a circle but whose top is not is computed
// upside down (swapping the stadia) and its centroid height mirrored back.
//
// `package_compatible` reproduces the yeadon package instead, with two differences: (1) it swaps
// the stadia whenever the base is a circle, including truncated cones (both circles), but mirrors
// the centroid back only when the top is not a circle, so a truncated cone's centroid is measured
// from the wrong end; (2) its I_x⁰ (about the stadia's long axis) uses Yeadon's printed 4 r t³/3
// for the straight part's second moment where the geometry gives 4 t r³/3 (the two agree only for t
// = 0 or t = r). Masses and the inertia about the solid's axis are the same in both modes.
struct SolidLocal {
  double mass = 0.0;
  double z_com = 0.0;
  Eigen::Matrix3d I_local = Eigen::Matrix3d::Zero();  // yeadon's local axes, about the centroid
};

SolidLocal StadiumSolidLocal(
    double D, const Stadium& s0, const Stadium& s1, double h, bool package_compatible) {
  const bool flipped = s0.t == 0.0 && s1.t != 0.0;
  const bool swapped = flipped || (package_compatible && s0.t == 0.0);
  const Stadium& lo = swapped ? s1 : s0;
  const Stadium& hi = swapped ? s0 : s1;
  const double r0 = lo.r, t0 = lo.t, r1 = hi.r, t1 = hi.t;
  const double a = (r1 - r0) / r0;
  const double b = t0 == 0.0 ? 1.0 : (t1 - t0) / t0;  // t ≡ 0 whatever b when t0 = t1 = 0
  SolidLocal out;
  out.mass = D * h * r0 * (4.0 * t0 * F1(a, b) + kPi * r0 * F1(a, a));
  const double z = D * h * h * (4.0 * r0 * t0 * F2(a, b) + kPi * r0 * r0 * F2(a, a)) / out.mass;
  out.z_com = flipped ? h - z : z;
  const double Iz = D * h *
                    (4.0 * r0 * t0 * t0 * t0 * F4(a, b) / 3.0 + kPi * r0 * r0 * t0 * t0 * F5(a, b) +
                     4.0 * r0 * r0 * r0 * t0 * F4(b, a) + kPi * r0 * r0 * r0 * r0 * F4(a, a) * 0.5);
  const double Iy0 =
      D * h *
          (4.0 * r0 * t0 * t0 * t0 * F4(a, b) / 3.0 + kPi * r0 * r0 * t0 * t0 * F5(a, b) +
           8.0 * r0 * r0 * r0 * t0 * F4(b, a) / 3.0 + kPi * r0 * r0 * r0 * r0 * F4(a, a) * 0.25) +
      D * h * h * h * (4.0 * r0 * t0 * F3(a, b) + kPi * r0 * r0 * F3(a, a));
  // The planar second moment about the stadium's long axis is ∫y² dA = 4 t r³/3 + π r⁴/4 (the
  // perpendicular-axis theorem then gives I_z); Yeadon's printed I_x⁰, which the yeadon package
  // uses, has 4 r t³/3 instead — kept in package-compatible mode only.
  const double rect_x = package_compatible ? 4.0 * r0 * t0 * t0 * t0 * F4(a, b) / 3.0
                                           : 4.0 * t0 * r0 * r0 * r0 * F4(b, a) / 3.0;
  const double Ix0 = D * h * (rect_x + kPi * r0 * r0 * r0 * r0 * F4(a, a) * 0.25) +
                     D * h * h * h * (4.0 * r0 * t0 * F3(a, b) + kPi * r0 * r0 * F3(a, a));
  // Parallel axis from the base of the (possibly flipped) solid to its centroid.
  const double Ix = Ix0 - out.mass * z * z;
  const double Iy = Iy0 - out.mass * z * z;
  // Antero-posterior stadia (the heel): the long axis is yeadon's local y, not x.
  if (s0.anteroposterior || s1.anteroposterior) {
    out.I_local.diagonal() << Iy, Ix, Iz;
  } else {
    out.I_local.diagonal() << Ix, Iy, Iz;
  }
  return out;
}

// A semi-ellipsoid with a circular base of radius r and height h (the top of the head):
// m = D 2πr²h/3, z̄ = 3h/8, I_z = D 4πr⁴h/15, I_x = I_y = D π (2r²h(r² + h²)/15 − 3r²h³/32).
SolidLocal SemiEllipsoidLocal(double D, double r, double h) {
  SolidLocal out;
  out.mass = D * 2.0 / 3.0 * kPi * r * r * h;
  out.z_com = 3.0 / 8.0 * h;
  const double Iz = D * 4.0 / 15.0 * kPi * r * r * r * r * h;
  const double Ixy =
      D * kPi * (2.0 / 15.0 * r * r * h * (r * r + h * h) - 3.0 / 32.0 * r * r * h * h * h);
  out.I_local.diagonal() << Ixy, Ixy, Iz;
  return out;
}

// Euler 1-2-3 (body-fixed x, then y, then z) rotation matrix.
Eigen::Matrix3d Euler123(double x, double y, double z) {
  return (Eigen::AngleAxisd(x, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(y, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(z, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

// A solid before posing: its shape and yeadon-local mass properties.
struct SolidShape {
  std::string label;
  bool semi_ellipsoid = false;
  Stadium s0, s1;
  double height = 0.0;
  double density = 0.0;
  SolidLocal local;
};

// ---- YeadonHuman::Make's steps: measurements → solids (shapes, then mass properties) → pose ----

// Left and right limbs averaged (the yeadon package's `symmetric` option): measurement names
// La… ↔ Lb… and Lj… ↔ Lk… with the same suffix.
YeadonMeasurements SymmetrisedMeasurements(const YeadonMeasurements& measurements) {
  YeadonMeasurements meas = measurements;
  for (std::string_view name : kYeadonMeasurementNames) {
    if (name.size() < 3 || (name[1] != 'a' && name[1] != 'j')) continue;
    std::string other(name);
    other[1] = name[1] == 'a' ? 'b' : 'k';
    const double mean = 0.5 * (meas.Get(name) + meas.Get(other));
    meas.Set(name, mean);
    meas.Set(other, mean);
  }
  return meas;
}

// Appends a stadium solid from stadium s0 to s1; a non-positive height (lengths not increasing
// along the limb) is refused, naming `source`.
void AddSolid(const std::string& source,
              std::string label,
              double density,
              const Stadium& s0,
              const Stadium& s1,
              double height,
              std::vector<SolidShape>& shapes) {
  SolidShape s;
  s.label = std::move(label);
  s.s0 = s0;
  s.s1 = s1;
  s.height = height;
  s.density = density;
  if (!(height > 0.0))
    throw InputError(source,
                     "solid " + s.label,
                     "non-positive height " + std::to_string(height) +
                         " m (the length measurements must increase along the limb)");
  shapes.push_back(s);
}

// Torso levels Ls0…Ls7 (Yeadon 1990, Fig. 2), nine stadia with Ls5 twice (acromion, bottom of
// neck). Ls5 (acromion) cannot be measured: its radius is 0.57 of Ls4's and its width Ls4's
// (Yeadon's ISEG program, as in the yeadon package).
std::vector<Stadium> MakeTorsoLevels(const StadiumMaker& stadium, const YeadonMeasurements& meas) {
  auto m = [&](std::string_view name) { return meas.Get(name); };
  std::vector<Stadium> Ls;
  Ls.push_back(stadium.PerimeterWidth("Ls0 (hip joint centre)", m("Ls0p"), m("Ls0w")));
  Ls.push_back(stadium.PerimeterWidth("Ls1 (umbilicus)", m("Ls1p"), m("Ls1w")));
  Ls.push_back(stadium.PerimeterWidth("Ls2 (lowest front rib)", m("Ls2p"), m("Ls2w")));
  Ls.push_back(stadium.PerimeterWidth("Ls3 (nipple)", m("Ls3p"), m("Ls3w")));
  Ls.push_back(stadium.DepthWidth("Ls4 (shoulder joint centre)", m("Ls4d"), m("Ls4w")));
  const double r5 = 0.57 * Ls[4].r;
  Ls.push_back(stadium.ThicknessRadius("Ls5 (acromion)", Ls[4].width / 2.0 - r5, r5));
  Ls.push_back(stadium.Circle("Ls5 (bottom of neck)", m("Ls5p")));
  Ls.push_back(stadium.Circle("Ls6 (beneath nose)", m("Ls6p")));
  Ls.push_back(stadium.Circle("Ls7 (above ear)", m("Ls7p")));
  return Ls;
}

// The torso's solids s0…s6 between the levels, and the head s7, a semi-ellipsoid on Ls7.
void AddTorsoSolids(const std::vector<Stadium>& Ls,
                    const YeadonMeasurements& meas,
                    const YeadonDensities& rho,
                    double scale,
                    std::vector<SolidShape>& shapes) {
  auto m = [&](std::string_view name) { return meas.Get(name); };
  const std::string& source = meas.source;
  AddSolid(source, "s0", scale * rho.abdomen_pelvis, Ls[0], Ls[1], m("Ls1L"), shapes);
  AddSolid(source, "s1", scale * rho.abdomen_pelvis, Ls[1], Ls[2], m("Ls2L") - m("Ls1L"), shapes);
  AddSolid(source, "s2", scale * rho.thorax, Ls[2], Ls[3], m("Ls3L") - m("Ls2L"), shapes);
  AddSolid(source, "s3", scale * rho.thorax, Ls[3], Ls[4], m("Ls4L") - m("Ls3L"), shapes);
  AddSolid(source, "s4", scale * rho.shoulders, Ls[4], Ls[5], m("Ls5L") - m("Ls4L"), shapes);
  AddSolid(source, "s5", scale * rho.head_neck, Ls[6], Ls[7], m("Ls6L"), shapes);
  AddSolid(source, "s6", scale * rho.head_neck, Ls[7], Ls[8], m("Ls7L") - m("Ls6L"), shapes);
  SolidShape head;
  head.label = "s7";
  head.semi_ellipsoid = true;
  head.s0 = Ls[8];
  head.s1 = Ls[8];
  head.height = m("Ls8L") - m("Ls7L");
  head.density = scale * rho.head_neck;
  if (!(head.height > 0.0)) throw InputError(source, "solid s7", "Ls8L must exceed Ls7L");
  shapes.push_back(head);
}

// One arm (side 'a' left, 'b' right): levels 0…3 circles, 4…7 stadia; solid i joins level i+1
// (stadium 0, distal) to level i.
void AddArmSolids(char side,
                  const StadiumMaker& stadium,
                  const YeadonMeasurements& meas,
                  const YeadonDensities& rho,
                  double scale,
                  std::vector<SolidShape>& shapes) {
  auto m = [&](std::string_view name) { return meas.Get(name); };
  const std::string L = std::string("L") + side;
  auto name = [&](const char* suffix) { return L + suffix; };
  // The levels.
  std::vector<Stadium> La;
  La.push_back(stadium.Circle(name("0 (shoulder joint centre)"), m(name("0p"))));
  La.push_back(stadium.Circle(name("1 (mid-arm)"), m(name("1p"))));
  La.push_back(stadium.Circle(name("2 (elbow joint centre)"), m(name("2p"))));
  La.push_back(stadium.Circle(name("3 (maximum forearm perimeter)"), m(name("3p"))));
  La.push_back(
      stadium.PerimeterWidth(name("4 (wrist joint centre)"), m(name("4p")), m(name("4w"))));
  La.push_back(stadium.PerimeterWidth(name("5 (base of thumb)"), m(name("5p")), m(name("5w"))));
  La.push_back(stadium.PerimeterWidth(name("6 (knuckles)"), m(name("6p")), m(name("6w"))));
  La.push_back(stadium.PerimeterWidth(name("7 (fingernails)"), m(name("7p")), m(name("7w"))));
  // The solids between them; the mid-arm level halves the upper arm.
  const double L2 = m(name("2L"));
  const double heights[7] = {L2 * 0.5,
                             L2 - L2 * 0.5,
                             m(name("3L")) - L2,
                             m(name("4L")) - m(name("3L")),
                             m(name("5L")),
                             m(name("6L")) - m(name("5L")),
                             m(name("7L")) - m(name("6L"))};
  const double density[7] = {
      rho.upper_arm, rho.upper_arm, rho.forearm, rho.forearm, rho.hand, rho.hand, rho.hand};
  for (int i = 0; i < 7; ++i)
    AddSolid(meas.source,
             std::string(1, side) + std::to_string(i),
             scale * density[i],
             La[i + 1],
             La[i],
             heights[i],
             shapes);
}

// One leg (side 'j' left, 'k' right): Lj0's perimeter from Ls0 (2π · ½√(r w)); Lj6 (heel) an
// antero-posterior stadium from its perimeter and depth; Lj2 and Lj7 halfway between their
// neighbours.
void AddLegSolids(char side,
                  const Stadium& Ls0,
                  const StadiumMaker& stadium,
                  const YeadonMeasurements& meas,
                  const YeadonDensities& rho,
                  double scale,
                  std::vector<SolidShape>& shapes) {
  auto m = [&](std::string_view name) { return meas.Get(name); };
  const std::string L = std::string("L") + side;
  auto name = [&](const char* suffix) { return L + suffix; };
  // The levels.
  std::vector<Stadium> Lj;
  Lj.push_back(stadium.Circle(name("0 (hip joint centre)"),
                              2.0 * kPi * 0.5 * std::sqrt(std::abs(Ls0.r * Ls0.width))));
  Lj.push_back(stadium.Circle(name("1 (crotch)"), m(name("1p"))));
  Lj.push_back(stadium.Circle(name("2 (mid-thigh)"), m(name("2p"))));
  Lj.push_back(stadium.Circle(name("3 (knee joint centre)"), m(name("3p"))));
  Lj.push_back(stadium.Circle(name("4 (maximum calf perimeter)"), m(name("4p"))));
  Lj.push_back(stadium.Circle(name("5 (ankle joint centre)"), m(name("5p"))));
  Lj.push_back(stadium.PerimeterWidth(name("6 (heel)"), m(name("6p")), m(name("6d")), true));
  Lj.push_back(stadium.Circle(name("7 (arch)"), m(name("7p"))));
  Lj.push_back(stadium.PerimeterWidth(name("8 (ball)"), m(name("8p")), m(name("8w"))));
  Lj.push_back(stadium.PerimeterWidth(name("9 (toe nails)"), m(name("9p")), m(name("9w"))));
  // The solids between them.
  const double L1 = m(name("1L")), L3 = m(name("3L")), L6 = m(name("6L")), L8 = m(name("8L"));
  const double heights[9] = {L1,
                             (L3 + L1) * 0.5 - L1,
                             L3 - (L3 + L1) * 0.5,
                             m(name("4L")) - L3,
                             m(name("5L")) - m(name("4L")),
                             L6,
                             (L8 + L6) * 0.5 - L6,
                             L8 - (L8 + L6) * 0.5,
                             m(name("9L")) - L8};
  const double density[9] = {rho.thigh,
                             rho.thigh,
                             rho.thigh,
                             rho.lower_leg,
                             rho.lower_leg,
                             rho.foot,
                             rho.foot,
                             rho.foot,
                             rho.foot};
  for (int i = 0; i < 9; ++i)
    AddSolid(meas.source,
             std::string(1, side) + std::to_string(i),
             scale * density[i],
             Lj[i + 1],
             Lj[i],
             heights[i],
             shapes);
}

// The body's 40 solids before posing, densities times `scale`, with their local mass properties;
// and the torso levels (the shoulders and hips are placed from Ls4 and Ls0).
struct BodyShape {
  std::vector<Stadium> Ls;
  std::vector<SolidShape> solids;
};

BodyShape MakeBodyShape(const YeadonMeasurements& meas,
                        const StadiumMaker& stadium,
                        const YeadonDensities& rho,
                        double scale,
                        bool package_compatible) {
  BodyShape body;
  // Torso, arms, legs.
  body.Ls = MakeTorsoLevels(stadium, meas);
  AddTorsoSolids(body.Ls, meas, rho, scale, body.solids);
  for (char side : {'a', 'b'}) AddArmSolids(side, stadium, meas, rho, scale, body.solids);
  for (char side : {'j', 'k'})
    AddLegSolids(side, body.Ls[0], stadium, meas, rho, scale, body.solids);
  // Local mass properties of every solid.
  for (SolidShape& s : body.solids) {
    s.local = s.semi_ellipsoid
                  ? SemiEllipsoidLocal(s.density, s.s0.r, s.height)
                  : StadiumSolidLocal(s.density, s.s0, s.s1, s.height, package_compatible);
  }
  return body;
}

// A placed segment, in yeadon's axes Y.
struct Placed {
  Eigen::Matrix3d R_Y;                        // segment orientation in Y
  Eigen::Vector3d proximal;                   // in Y
  Eigen::Vector3d end;                        // in Y
  std::vector<Eigen::Vector3d> solid_origin;  // stadium-0 centre of each solid, in Y
};

// Places segments, each a chain of solids, in yeadon's axes Y, and keeps them and their solids
// rotated into the body axes H.
class SegmentPlacer {
 public:
  explicit SegmentPlacer(const std::vector<SolidShape>& shapes)
      : shapes_(shapes), C_(YeadonAxesToBodyAxes()) {}

  const SolidShape& Shape(std::string_view label) const {
    for (const SolidShape& shape : shapes_)
      if (shape.label == label) return shape;
    ACRO_DEMAND(false);
    return shapes_.front();
  }

  // Segment `label` with orientation R in Y, its solids stacked from `proximal` along R's z
  // (toward positive z, or toward negative z for the limbs).
  Placed Place(const char* label,
               const char* seg_name,
               const Eigen::Vector3d& proximal,
               const Eigen::Matrix3d& R,
               const std::vector<std::string>& solid_labels,
               bool toward_positive_z) {
    const Eigen::Matrix3d& C = C_;
    YeadonSegment seg;
    seg.label = label;
    seg.name = seg_name;
    Placed p{R, proximal, proximal, {}};
    Eigen::Vector3d cursor = proximal;
    const int seg_index = static_cast<int>(segments_.size());
    std::vector<InertialProperties> parts;
    for (const std::string& sl : solid_labels) {
      const SolidShape& shape = Shape(sl);
      // The solid's stadium-0 centre, and the cursor moved to its other end.
      const Eigen::Vector3d axis = shape.height * (R * Eigen::Vector3d::UnitZ());
      Eigen::Vector3d origin;
      if (toward_positive_z) {
        origin = cursor;
        cursor = cursor + axis;
      } else {
        origin = cursor - axis;
        cursor = origin;
      }
      p.solid_origin.push_back(origin);
      const YeadonSolid solid = MakeSolid(shape, seg_index, R, origin);
      parts.push_back(solid.in_H);
      seg.solids.push_back(static_cast<int>(solids_.size()));
      solids_.push_back(solid);
    }
    p.end = cursor;
    seg.R_HB = C * R * C.transpose();
    seg.p_HoBo_H = C * proximal;
    seg.p_HoBend_H = C * cursor;
    seg.in_H = CombineInertia(parts);
    segments_.push_back(seg);
    return p;
  }

  std::vector<YeadonSolid>& solids() { return solids_; }
  std::vector<YeadonSegment>& segments() { return segments_; }

 private:
  // The solid of `shape` in segment seg_index, oriented R with its stadium-0 centre at `origin`
  // (in Y), and its inertia in its own axes S and in H.
  YeadonSolid MakeSolid(const SolidShape& shape,
                        int seg_index,
                        const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& origin) const {
    const Eigen::Matrix3d& C = C_;
    YeadonSolid solid;
    solid.label = shape.label;
    solid.semi_ellipsoid = shape.semi_ellipsoid;
    solid.anteroposterior = shape.s0.anteroposterior || shape.s1.anteroposterior;
    solid.r0_m = shape.s0.r;
    solid.t0_m = shape.s0.t;
    solid.r1_m = shape.semi_ellipsoid ? 0.0 : shape.s1.r;
    solid.t1_m = shape.semi_ellipsoid ? 0.0 : shape.s1.t;
    solid.height_m = shape.height;
    solid.density_kg_m3 = shape.density;
    solid.segment = seg_index;
    solid.R_HS = C * R * C.transpose();
    solid.p_HoSo_H = C * origin;
    solid.in_S.mass_kg = shape.local.mass;
    solid.in_S.p_HoCm_H = Eigen::Vector3d(0.0, 0.0, shape.local.z_com);
    solid.in_S.I_Cm_H = C * shape.local.I_local * C.transpose();
    solid.in_H = TransformInertia(solid.in_S, solid.R_HS, solid.p_HoSo_H);
    return solid;
  }

  const std::vector<SolidShape>& shapes_;
  const Eigen::Matrix3d C_;
  std::vector<YeadonSolid> solids_;
  std::vector<YeadonSegment> segments_;
};

// The torso: pelvis at the origin in the configuration's somersault, tilt and twist, thorax on
// it, chest-head on the thorax. Returns the pelvis and the chest-head.
std::pair<Placed, Placed> PlaceTorso(SegmentPlacer& placer, const YeadonConfiguration& cfg) {
  auto a = [&](std::string_view n) { return cfg.Get(n); };
  const Eigen::Matrix3d R_P = Euler123(a("somersault"), a("tilt"), a("twist"));
  const Placed P = placer.Place("P", "pelvis", Eigen::Vector3d::Zero(), R_P, {"s0", "s1"}, true);
  const Eigen::Matrix3d R_T = R_P * Euler123(a("PTsagittalFlexion"), a("PTbending"), 0.0);
  const Placed T = placer.Place("T", "thorax", P.end, R_T, {"s2"}, true);
  const Eigen::Matrix3d R_C =
      R_T * Euler123(a("TCsagittalSpinalFlexion"), 0.0, a("TCspinalTorsion"));
  const Placed Cs =
      placer.Place("C", "chest-head", T.end, R_C, {"s3", "s4", "s5", "s6", "s7"}, true);
  return {P, Cs};
}

// The arms from the shoulders: ±(Ls4 width)/2 laterally at the top of solid s3 (Ls4 level).
void PlaceArms(SegmentPlacer& placer,
               const YeadonConfiguration& cfg,
               const Placed& Cs,
               const Stadium& Ls4) {
  auto a = [&](std::string_view n) { return cfg.Get(n); };
  const Eigen::Matrix3d& R_C = Cs.R_Y;
  const double shoulder_half_width = Ls4.width / 2.0;
  const double s3_height = placer.Shape("s3").height;
  // Left.
  const Eigen::Matrix3d R_A1 =
      R_C * Euler123(a("CA1extension"), a("CA1adduction"), a("CA1rotation"));
  const Placed A1 =
      placer.Place("A1",
                   "left upper arm",
                   Cs.solid_origin[0] + R_C * Eigen::Vector3d(shoulder_half_width, 0, s3_height),
                   R_A1,
                   {"a0", "a1"},
                   false);
  placer.Place("A2",
               "left forearm-hand",
               A1.end,
               R_A1 * Euler123(a("A1A2extension"), 0.0, 0.0),
               {"a2", "a3", "a4", "a5", "a6"},
               false);
  // Right.
  const Eigen::Matrix3d R_B1 =
      R_C * Euler123(a("CB1extension"), a("CB1abduction"), a("CB1rotation"));
  const Placed B1 =
      placer.Place("B1",
                   "right upper arm",
                   Cs.solid_origin[0] + R_C * Eigen::Vector3d(-shoulder_half_width, 0, s3_height),
                   R_B1,
                   {"b0", "b1"},
                   false);
  placer.Place("B2",
               "right forearm-hand",
               B1.end,
               R_B1 * Euler123(a("B1B2extension"), 0.0, 0.0),
               {"b2", "b3", "b4", "b5", "b6"},
               false);
}

// The legs from the hips: ±(t + r)/2 of Ls0 laterally, at the Ls0 level.
void PlaceLegs(SegmentPlacer& placer,
               const YeadonConfiguration& cfg,
               const Placed& P,
               const Stadium& Ls0) {
  auto a = [&](std::string_view n) { return cfg.Get(n); };
  const Eigen::Matrix3d& R_P = P.R_Y;
  const double hip_half_width = (Ls0.t + Ls0.r) / 2.0;
  // Left.
  const Eigen::Matrix3d R_J1 = R_P * Euler123(a("PJ1extension"), a("PJ1adduction"), 0.0);
  const Placed J1 = placer.Place("J1",
                                 "left thigh",
                                 P.solid_origin[0] + R_P * Eigen::Vector3d(hip_half_width, 0, 0),
                                 R_J1,
                                 {"j0", "j1", "j2"},
                                 false);
  placer.Place("J2",
               "left shank-foot",
               J1.end,
               R_J1 * Euler123(a("J1J2flexion"), 0.0, 0.0),
               {"j3", "j4", "j5", "j6", "j7", "j8"},
               false);
  // Right.
  const Eigen::Matrix3d R_K1 = R_P * Euler123(a("PK1extension"), a("PK1abduction"), 0.0);
  const Placed K1 = placer.Place("K1",
                                 "right thigh",
                                 P.solid_origin[0] + R_P * Eigen::Vector3d(-hip_half_width, 0, 0),
                                 R_K1,
                                 {"k0", "k1", "k2"},
                                 false);
  placer.Place("K2",
               "right shank-foot",
               K1.end,
               R_K1 * Euler123(a("K1K2flexion"), 0.0, 0.0),
               {"k3", "k4", "k5", "k6", "k7", "k8"},
               false);
}

}  // namespace

YeadonHuman YeadonHuman::Make(const YeadonMeasurements& measurements_in,
                              const YeadonOptions& options,
                              const YeadonConfiguration& cfg) {
  YeadonHuman human;
  human.options_ = options;
  const YeadonMeasurements meas =
      options.symmetric ? SymmetrisedMeasurements(measurements_in) : measurements_in;
  const StadiumMaker stadium(measurements_in.source, &human.warnings_);

  // One pass builds the solids at a density multiplier; a second pass rescales to a measured mass.
  auto build = [&](double scale) {
    human.warnings_.clear();
    // The solids' shapes and mass properties.
    const BodyShape body = MakeBodyShape(
        meas, stadium, DensitiesOf(options.density), scale, options.package_compatible);
    // Pose: segments placed from the pelvis outwards, in yeadon's axes Y, then rotated into H.
    SegmentPlacer placer(body.solids);
    const auto [P, Cs] = PlaceTorso(placer, cfg);
    PlaceArms(placer, cfg, Cs, body.Ls[4]);
    PlaceLegs(placer, cfg, P, body.Ls[0]);
    human.solids_ = std::move(placer.solids());
    human.segments_ = std::move(placer.segments());
    // The whole body.
    std::vector<InertialProperties> parts;
    for (const YeadonSegment& s : human.segments_) parts.push_back(s.in_H);
    human.total_ = CombineInertia(parts);
  };

  build(1.0);
  if (measurements_in.total_mass_kg) {
    human.density_scale_ = *measurements_in.total_mass_kg / human.total_.mass_kg;
    build(human.density_scale_);
  }
  return human;
}

}  // namespace acro::analysis
