#pragma once

// Yeadon's geometric inertia model of the human body (M. R. Yeadon, "The simulation of aerial
// movement — II. A mathematical inertia model of the human body", J. Biomech. 23(1):67–74, 1990):
// 40 solids — stadium solids (a stadium cross-section whose radius r and half straight length t
// vary linearly along the axis), one semi-ellipsoid (the top of the head) — grouped into 11
// segments: P pelvis, T thorax, C chest-head, A1/A2 left upper arm and forearm-hand, B1/B2 right,
// J1/J2 left thigh and shank-foot, K1/K2 right. Uniform density per body region from one of three
// cadaver studies. The configuration angles of the yeadon package (21 angles) pose the body.
//
// Frame H (docs/athlete-model.md): origin at the centre of the Ls0 stadium (hip-joint level, on the
// midline), x anterior, y to the athlete's left, z up in the zero configuration — the project's
// body convention. (The yeadon package's own frame has x to the left, y posterior, z up; results
// are rotated into H, so yeadon's I_xx is our I_yy.)

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/inertial_properties.h"
#include "acro/athlete/yeadon_measurements.h"

namespace acro::analysis {

/// Density sets tabulated by Yeadon (1990) from cadaver studies: Dempster (1955), Chandler et al.
/// (1975), Clauser et al. (1969).
enum class DensitySet { kDempster, kChandler, kClauser };

/// "dempster", "chandler", "clauser".
std::string_view DensitySetName(DensitySet set);
/// Parses a lower-case set name; false when unknown.
bool ParseDensitySet(std::string_view name, DensitySet* set);

/// Region densities in kg/m³.
struct YeadonDensities {
  double head_neck = 0.0;
  double shoulders = 0.0;
  double thorax = 0.0;
  double abdomen_pelvis = 0.0;
  double upper_arm = 0.0;
  double forearm = 0.0;
  double hand = 0.0;
  double thigh = 0.0;
  double lower_leg = 0.0;
  double foot = 0.0;
};
YeadonDensities DensitiesOf(DensitySet set);

/// The configuration of the yeadon package (angles in radians, all zero = standing, arms down,
/// toes pointed). Each segment's orientation is its parent's times an Euler 1-2-3 (body-fixed
/// x, y, z) rotation in yeadon's axes (x left, y posterior, z up): P = E(somersault, tilt, twist);
/// T = P·E(PTsagittalFlexion, PTbending, 0); C = T·E(TCsagittalSpinalFlexion, 0, TCspinalTorsion);
/// A1 = C·E(CA1extension, CA1adduction, CA1rotation); A2 = A1·E(A1A2extension, 0, 0); B1, B2 the
/// same with CB1…, B1B2extension; J1 = P·E(PJ1extension, PJ1adduction, 0); J2 = J1·E(J1J2flexion,
/// 0, 0); K1, K2 the same. Positive x rotations move a limb that points down backwards (so hip
/// flexion is a negative PJ1extension and knee flexion a positive J1J2flexion).
struct YeadonConfiguration {
  static constexpr std::array<std::string_view, 21> kNames = {"somersault",
                                                              "tilt",
                                                              "twist",
                                                              "PTsagittalFlexion",
                                                              "PTbending",
                                                              "TCspinalTorsion",
                                                              "TCsagittalSpinalFlexion",
                                                              "CA1extension",
                                                              "CA1adduction",
                                                              "CA1rotation",
                                                              "CB1extension",
                                                              "CB1abduction",
                                                              "CB1rotation",
                                                              "A1A2extension",
                                                              "B1B2extension",
                                                              "PJ1extension",
                                                              "PJ1adduction",
                                                              "PK1extension",
                                                              "PK1abduction",
                                                              "J1J2flexion",
                                                              "K1K2flexion"};
  std::array<double, 21> angles_rad{};

  /// Sets one angle by name; false when the name is unknown.
  bool Set(std::string_view name, double angle_rad);
  /// The angle of a known name (ACRO_DEMAND otherwise).
  double Get(std::string_view name) const;
};

/// One solid in H. Its frame S has its origin at the centre of stadium 0 and z along the solid's
/// axis towards stadium 1; the stadia's long axis is S's y (medio-lateral), or S's x for the two
/// heel solids (antero-posterior stadia). A semi-ellipsoid has a circular base of radius r0 at S's
/// origin and its apex at z = height.
struct YeadonSolid {
  std::string label;  ///< "s0"…"s7", "a0"…"a6", "b0"…"b6", "j0"…"j8", "k0"…"k8"
  bool semi_ellipsoid = false;
  bool anteroposterior = false;
  double r0_m = 0.0;  ///< stadium 0: radius of the round ends
  double t0_m = 0.0;  ///< stadium 0: half the straight length (0 for a circle)
  double r1_m = 0.0;
  double t1_m = 0.0;
  double height_m = 0.0;
  double density_kg_m3 = 0.0;
  int segment = 0;  ///< index into YeadonHuman::segments()
  Eigen::Matrix3d R_HS = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_HoSo_H = Eigen::Vector3d::Zero();
  /// Mass properties in S (centre of mass on S's z axis).
  InertialProperties in_S;
  /// The same in H.
  InertialProperties in_H;
};

/// One of the 11 segments in H. Its frame B has its origin at the proximal joint (the pelvis: the
/// centre of Ls0) and B's axes are the segment's orientation.
struct YeadonSegment {
  std::string label;  ///< "P", "T", "C", "A1", "A2", "B1", "B2", "J1", "J2", "K1", "K2"
  std::string name;   ///< "pelvis", "thorax", "chest-head", "left upper arm", …
  std::vector<int> solids;
  Eigen::Matrix3d R_HB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_HoBo_H = Eigen::Vector3d::Zero();
  /// The far end of the segment's last solid (distal joint or tip).
  Eigen::Vector3d p_HoBend_H = Eigen::Vector3d::Zero();
  InertialProperties in_H;
};

struct YeadonOptions {
  DensitySet density = DensitySet::kDempster;
  /// Average left and right limb measurements first (the yeadon package's default).
  bool symmetric = true;
  /// Reproduce the yeadon package's numbers exactly (its tests' values,
  /// refdata/yeadon/expected.md). The package (1) measures the centroid of a truncated cone (a
  /// solid between two circular stadia: thigh, upper-arm, forearm, shank solids) from the wrong
  /// end, and (2) uses Yeadon's printed formula for the inertia about a stadium's long axis, whose
  /// straight-part term has t and r exchanged. Off by default: the geometric values, which the body
  /// mesh's exact integration confirms (docs/athlete-model.md).
  bool package_compatible = false;
};

/// The posed Yeadon human. Const once made.
class YeadonHuman {
 public:
  /// Builds the solids from the measurements, poses them and computes every mass property. When
  /// the measurements carry a measured total mass the densities are scaled to reproduce it.
  /// Throws acro::InputError (naming the measurement source) when a stadium cannot be formed
  /// (a radius of zero, or a negative radius or thickness that the perimeter/width fallbacks of
  /// Yeadon's ISEG program cannot repair).
  static YeadonHuman Make(const YeadonMeasurements& measurements,
                          const YeadonOptions& options = {},
                          const YeadonConfiguration& configuration = {});

  const std::vector<YeadonSolid>& solids() const { return solids_; }
  const std::vector<YeadonSegment>& segments() const { return segments_; }
  /// Whole body in H, inertia about the whole-body centre of mass.
  const InertialProperties& total() const { return total_; }
  /// Index of the segment with this label ("J1"), or −1.
  int FindSegment(std::string_view label) const;
  /// Index of the solid with this label ("j5"), or −1.
  int FindSolid(std::string_view label) const;
  /// Fallbacks taken while forming stadia (a stadium replaced by a circle), one line each.
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// The density multiplier applied to match the measured mass (1 when none was given).
  double density_scale() const { return density_scale_; }
  const YeadonOptions& options() const { return options_; }

 private:
  YeadonOptions options_;
  std::vector<YeadonSolid> solids_;
  std::vector<YeadonSegment> segments_;
  InertialProperties total_;
  std::vector<std::string> warnings_;
  double density_scale_ = 1.0;
};

/// The rotation from yeadon's axes (x left, y posterior, z up) to H's (x anterior, y left, z up).
Eigen::Matrix3d YeadonAxesToBodyAxes();

}  // namespace acro::analysis
