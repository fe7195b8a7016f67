// Somersault/twist counting against synthetic flights whose nominal skill is known: the root turns
// about a horizontal lateral axis (any heading), leans at take-off and landing as on a real bed (a
// quarter of the nominal rotation happens on the bed), tilts a little, and twists within chosen
// somersaults.
#include "acro/assess/jump_rotation.h"

#include <cmath>
#include <cstdint>
#include <functional>

#include <gtest/gtest.h>

namespace acro::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

struct Synthetic {
  std::vector<Eigen::Quaterniond> q_WB;
  Eigen::VectorXd hip, knee;
};

// `quarters` nominal (signed: forward positive), half twists per somersault, heading of the lateral
// axis, and the shape's hip/knee flexion at mid-flight.
Synthetic MakeFlight(int quarters,
                     const std::vector<int>& half_twists,
                     double heading_deg,
                     double hip_deg,
                     double knee_deg) {
  const int n = 300;
  const double s = quarters >= 0 ? 1 : -1;
  // On the bed: half a quarter before take-off and half a quarter after landing (feet to feet).
  const double phi0 = quarters == 0 ? 0.0 : s * 45 * kDeg;
  const double phi1 = quarters == 0 ? 0.0 : (quarters * 90 - s * 45) * kDeg;
  const Eigen::Matrix3d R_WS =
      Eigen::AngleAxisd(heading_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Synthetic out;
  out.hip.resize(n);
  out.knee.resize(n);
  const int slots = static_cast<int>(half_twists.size());
  for (int i = 0; i < n; ++i) {
    const double u = double(i) / (n - 1);
    const double phi = phi0 + u * (phi1 - phi0);
    // Nominal progress in turns; each somersault twists in the middle 80 % of its in-air part (the
    // twist starts after take-off and ends before landing).
    const double bed = quarters == 0 ? 0.0 : 45 * kDeg;
    const double progress = (std::abs(phi) + bed) / (2 * kPi);
    const double p0 = bed / (2 * kPi), p1 = (std::abs(phi1) + bed) / (2 * kPi);
    double psi = 0;
    for (int k = 0; k < slots; ++k) {
      const double from = quarters == 0 ? 0.0 : std::max<double>(k, p0);
      const double to = quarters == 0 ? 1.0 : std::min<double>(k + 1, p1);
      const double local =
          quarters == 0 ? u : std::clamp((progress - from) / (to - from), 0.0, 1.0);
      psi += half_twists[static_cast<std::size_t>(k)] * kPi *
             std::clamp((local - 0.1) / 0.8, 0.0, 1.0);
    }
    const double tilt = 8 * kDeg * std::sin(2 * kPi * u);
    const Eigen::Matrix3d R_SB = (Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()))
                                     .toRotationMatrix();
    out.q_WB.emplace_back(R_WS * R_SB);
    const double shape = std::sin(kPi * u);  // open at take-off and landing, most flexed mid-flight
    out.hip[i] = hip_deg * kDeg * shape;
    out.knee[i] = knee_deg * kDeg * shape;
  }
  return out;
}

struct Case {
  const char* code;
  int signed_quarters;
  std::vector<int> half_twists;
  double hip_deg, knee_deg;
};

TEST(JumpRotation, RecoversTheNominalSkillFromTheFlight) {
  const Case cases[] = {
      {"00", 0, {0}, 5, 5},
      {"01", 0, {1}, 5, 5},
      {"40o", -4, {0}, 120, 130},
      {"40<", -4, {0}, 110, 10},
      {"41/", 4, {1}, 10, 5},
      {"42/", -4, {2}, 10, 5},
      {"43/", 4, {3}, 10, 5},
      {"800o", -8, {0, 0}, 125, 130},
      {"822o", -8, {2, 2}, 120, 120},
      {"825<", 8, {2, 5}, 100, 15},
      {"803o", 8, {0, 3}, 120, 120},
      {"12222o", -12, {2, 2, 2}, 125, 125},
      {"161003o", -16, {1, 0, 0, 3}, 130, 130},
  };
  for (double heading : {0.0, 37.0, -120.0}) {
    for (const Case& c : cases) {
      SCOPED_TRACE(std::string(c.code) + " heading " + std::to_string(heading));
      const Synthetic flight =
          MakeFlight(c.signed_quarters, c.half_twists, heading, c.hip_deg, c.knee_deg);
      const JumpRotation r = CountJumpRotation(
          flight.q_WB, 0, static_cast<int>(flight.q_WB.size()) - 1, flight.hip, flight.knee);
      EXPECT_EQ(fig::FormatFigCode(r.skill), c.code)
          << "measured " << r.measured_somersault_rad / kDeg << " deg";
      EXPECT_EQ(r.takeoff_position, fig::BodyPosition::kFeet);
      EXPECT_EQ(r.landing_position, fig::BodyPosition::kFeet);
      if (c.signed_quarters != 0) {
        EXPECT_EQ(r.skill.direction,
                  c.signed_quarters > 0 ? fig::SomersaultDirection::kForward
                                        : fig::SomersaultDirection::kBackward);
        // In the air: one quarter short of the nominal (the synthetic bed's share), to the accuracy
        // of the fitted somersault plane.
        EXPECT_NEAR(std::abs(r.measured_somersault_rad),
                    (std::abs(c.signed_quarters) - 1) * kPi / 2,
                    2 * kDeg);  // the ±8° tilt oscillation moves the fitted plane: 0.4° measured
      }
    }
  }
}

TEST(JumpRotation, AnglesRoundTripThroughTheDecomposition) {
  std::vector<Eigen::Quaterniond> q;
  std::vector<double> phi, theta, psi;
  for (int i = 0; i < 200; ++i) {
    phi.push_back(-0.05 * i);  // 10 rad of back somersault: unwrapping across ±π
    theta.push_back(0.3 * std::sin(0.1 * i));
    psi.push_back(0.07 * i);
    q.emplace_back(Eigen::AngleAxisd(phi.back(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(theta.back(), Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(psi.back(), Eigen::Vector3d::UnitZ()));
  }
  const RotationAngles a = CalcRotationAngles(q, Eigen::Vector3d::UnitY());
  for (int i = 0; i < 200; ++i) {
    EXPECT_NEAR(a.somersault_rad[i], phi[static_cast<std::size_t>(i)], 1e-12);
    EXPECT_NEAR(a.tilt_rad[i], theta[static_cast<std::size_t>(i)], 1e-12);
    EXPECT_NEAR(a.twist_rad[i], psi[static_cast<std::size_t>(i)], 1e-12);
  }
}

TEST(JumpRotation, DropPositionsChangeTheNominalCount) {
  // Feet to back drop: the body ends horizontal facing up after a quarter of back rotation.
  std::vector<Eigen::Quaterniond> q;
  for (int i = 0; i < 100; ++i)
    q.emplace_back(Eigen::AngleAxisd(-i / 99.0 * 80 * kDeg, Eigen::Vector3d::UnitY()));
  const JumpRotation r = CountJumpRotation(q, 0, 99, Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_EQ(r.landing_position, fig::BodyPosition::kBack);
  EXPECT_EQ(r.skill.quarter_somersaults, 1);
  EXPECT_EQ(r.skill.direction, fig::SomersaultDirection::kBackward);
}

}  // namespace
}  // namespace acro::analysis

namespace acro::analysis {
namespace {

// Orientation from cumulative somersault and twist curves (turns), sampled linearly between points.
std::vector<Eigen::Quaterniond> FromCurves(const std::vector<double>& somersault_turns,
                                           const std::vector<double>& twist_turns) {
  std::vector<Eigen::Quaterniond> q;
  const int per_segment = 50;
  for (std::size_t k = 0; k + 1 < somersault_turns.size(); ++k) {
    for (int i = 0; i < per_segment + (k + 2 == somersault_turns.size() ? 1 : 0); ++i) {
      const double u = double(i) / per_segment;
      const double phi =
          2 * kPi * (somersault_turns[k] + u * (somersault_turns[k + 1] - somersault_turns[k]));
      const double psi = 2 * kPi * (twist_turns[k] + u * (twist_turns[k + 1] - twist_turns[k]));
      q.emplace_back(Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()));
    }
  }
  return q;
}

TEST(JumpRotation, PublicCountingRulesOfTheTrampolineSuite) {
  // ../shared/refdata/s2mLab-EKF_multicamera-trampoline/expected.md: cumulative rotation curves in
  // turns.
  const auto a = FromCurves({0.0, -0.60, -1.05, -1.70, -2.02}, {0.0, 0.60, 1.52, 1.80, 2.01});
  const JumpRotation ra =
      CountJumpRotation(a, 0, static_cast<int>(a.size()) - 1, Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_EQ(ra.skill.quarter_somersaults, 8);
  EXPECT_EQ(ra.skill.half_twists, (std::vector<int>{3, 1}));  // code 831
  EXPECT_EQ(ra.skill.direction, fig::SomersaultDirection::kBackward);
  const auto b = FromCurves({0.0, 0.55, 1.02, 1.55, 1.94}, {0.0, 0.45, 1.02, 1.32, 1.53});
  const JumpRotation rb =
      CountJumpRotation(b, 0, static_cast<int>(b.size()) - 1, Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_EQ(rb.skill.quarter_somersaults, 8);
  EXPECT_EQ(rb.skill.half_twists, (std::vector<int>{2, 1}));  // code 821
  EXPECT_EQ(rb.skill.direction, fig::SomersaultDirection::kForward);
}

// Left and right as the athlete says them, checked on the geometry rather than on the angles: in a
// twist to the left her front (body x) turns, at first, toward where her left hand (body y)
// pointed. Backward and forward somersaults, twisting either way, and a somersault alone.
TEST(JumpRotation, TwistDirectionIsTheAthletesLeftOrRight) {
  struct TwistCase {
    std::vector<double> somersault, twist;
    fig::TwistDirection want;
  };
  const std::vector<TwistCase> cases = {
      {{0.0, -0.5, -1.0}, {0.0, 0.5, 1.0}, fig::TwistDirection::kLeft},     // back full, left
      {{0.0, -0.5, -1.0}, {0.0, -0.5, -1.0}, fig::TwistDirection::kRight},  // back full, right
      {{0.0, 0.5, 1.0}, {0.0, 0.25, 0.5}, fig::TwistDirection::kLeft},      // barani-like, left
      {{0.0, 0.5, 1.0}, {0.0, -0.25, -0.5}, fig::TwistDirection::kRight},
      {{0.0, -0.5, -1.0}, {0.0, 0.0, 0.0}, fig::TwistDirection::kNone},  // back somersault
  };
  for (const TwistCase& c : cases) {
    const auto q = FromCurves(c.somersault, c.twist);
    const JumpRotation r = CountJumpRotation(
        q, 0, static_cast<int>(q.size()) - 1, Eigen::VectorXd(), Eigen::VectorXd());
    EXPECT_EQ(TwistDirectionOf(r), c.want) << TwistDirectionName(TwistDirectionOf(r));
    if (c.want == fig::TwistDirection::kNone) continue;
    // The front a frame later, seen in the body's own first frame: its y component is positive
    // when it turned toward the left hand (the somersault, about y, moves no front toward y).
    const Eigen::Vector3d front_1 = q[0].conjugate() * (q[1] * Eigen::Vector3d::UnitX());
    EXPECT_EQ(front_1.y() > 0, c.want == fig::TwistDirection::kLeft) << front_1.transpose();
  }
  EXPECT_STREQ(TwistDirectionName(fig::TwistDirection::kLeft), "left");
  EXPECT_STREQ(TwistDirectionName(fig::TwistDirection::kRight), "right");
  EXPECT_STREQ(TwistDirectionName(fig::TwistDirection::kNone), "none");
}

TEST(JumpRotation, ShapeRulesOfTheTrampolineSuite) {
  // Hip 80° with knee 85° is tucked; hip 85–90° with knee 5–15° is piked; open hips are straight.
  std::vector<Eigen::Quaterniond> q;
  for (int i = 0; i < 100; ++i)
    q.emplace_back(Eigen::AngleAxisd(-i / 99.0 * 3 * kPi / 2, Eigen::Vector3d::UnitY()));
  auto shape = [&](double hip_deg, double knee_deg) {
    const Eigen::VectorXd hip = Eigen::VectorXd::Constant(100, hip_deg * kDeg);
    const Eigen::VectorXd knee = Eigen::VectorXd::Constant(100, knee_deg * kDeg);
    return CountJumpRotation(q, 0, 99, hip, knee).skill.shape;
  };
  EXPECT_EQ(shape(80, 85), fig::SkillShape::kTuck);
  EXPECT_EQ(shape(85, 5), fig::SkillShape::kPike);
  EXPECT_EQ(shape(90, 15), fig::SkillShape::kPike);
  EXPECT_EQ(shape(20, 10), fig::SkillShape::kStraight);
}

// The FIG definition (Code of Points, trampoline, body positions): closed at or below 135° between
// trunk and thighs (hip flexion 45°) and between thigh and shank; held over part of the flight, not
// at one instant; robust to a frame of noise or of left/right swap.
TEST(JumpRotation, ShapeIsTheFigBodyPositionHeld) {
  const int n = 120;
  std::vector<Eigen::Quaterniond> q;
  for (int i = 0; i < n; ++i)
    q.emplace_back(Eigen::AngleAxisd(-i / (n - 1.0) * 3 * kPi / 2, Eigen::Vector3d::UnitY()));
  // Hip and knee flexion (deg) constant over frames [from, to), zero elsewhere.
  auto count = [&](double hip_deg,
                   double knee_deg,
                   int from,
                   int to,
                   const std::function<void(Eigen::VectorXd&, Eigen::VectorXd&)>& edit = {}) {
    Eigen::VectorXd hip = Eigen::VectorXd::Zero(n), knee = Eigen::VectorXd::Zero(n);
    for (int i = from; i < to; ++i) {
      hip[i] = hip_deg * kDeg;
      knee[i] = knee_deg * kDeg;
    }
    if (edit) edit(hip, knee);
    return CountJumpRotation(q, 0, n - 1, hip, knee);
  };
  // 135° is the line: trunk–thigh 133° is closed, 137° is not.
  EXPECT_EQ(count(47, 10, 20, 100).skill.shape, fig::SkillShape::kPike);
  EXPECT_EQ(count(43, 10, 20, 100).skill.shape, fig::SkillShape::kStraight);
  EXPECT_EQ(count(47, 47, 20, 100).skill.shape, fig::SkillShape::kTuck);
  EXPECT_EQ(count(47, 43, 20, 100).skill.shape, fig::SkillShape::kPike);
  // Held: a closure over 10 % of the flight is a passing moment (the kick-out, the opening); over
  // 20 % it is the shape.
  EXPECT_EQ(count(110, 120, 50, 62).skill.shape, fig::SkillShape::kStraight);
  EXPECT_EQ(count(110, 120, 50, 74).skill.shape, fig::SkillShape::kTuck);
  // One frame of a left/right swap (the knees read straight for a frame, the hips open for
  // another) neither breaks a tuck nor makes a straight jump a pike.
  const JumpRotation swapped =
      count(110, 120, 20, 100, [](Eigen::VectorXd& hip, Eigen::VectorXd& knee) {
        knee[50] = 0;
        hip[70] = 0;
      });
  EXPECT_EQ(swapped.skill.shape, fig::SkillShape::kTuck);
  EXPECT_GT(swapped.shape_hold_fraction, 0.6);
  EXPECT_EQ(count(0, 0, 0, 0, [](Eigen::VectorXd& hip, Eigen::VectorXd&) { hip[60] = 120 * kDeg; })
                .skill.shape,
            fig::SkillShape::kStraight);
  // Keypoint noise (±8°, fixed pseudo-random) on a held pike.
  const JumpRotation noisy = count(70, 5, 20, 100, [](Eigen::VectorXd& hip, Eigen::VectorXd& knee) {
    std::uint64_t seed = 7;
    for (int i = 0; i < hip.size(); ++i) {
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      const double u = double(seed >> 11) / double(1ULL << 53) - 0.5;
      hip[i] += 16 * u * kDeg;
      knee[i] += std::abs(16 * u) * kDeg;
    }
  });
  EXPECT_EQ(noisy.skill.shape, fig::SkillShape::kPike);
  // The reason, in words: the shape, the angles held and for how long.
  const JumpRotation tuck = count(110, 120, 20, 100);
  EXPECT_NEAR(tuck.shape_hip_angle_deg, 70, 1e-9);
  EXPECT_NEAR(tuck.shape_knee_angle_deg, 60, 1e-9);
  EXPECT_NEAR(tuck.shape_hold_fraction, 80.0 / n, 0.02);
  EXPECT_EQ(tuck.shape_reason,
            "tuck: trunk–thigh 70°, thigh–shank 60° (medians) held over 67 % of the flight (FIG: "
            "both at or below 135°)");
  EXPECT_TRUE(tuck.shape_alternative.empty());
  // Close calls: the knees within 5° of 135° (a tuck or a pike), the hips (closed or straight).
  EXPECT_EQ(count(70, 47, 20, 100).shape_alternative, "pike");  // a tuck at 133°
  EXPECT_EQ(count(70, 43, 20, 100).shape_alternative, "tuck");  // a pike at 137°
  EXPECT_EQ(count(47, 10, 20, 100).shape_alternative, "straight");
  EXPECT_TRUE(count(70, 10, 20, 100).shape_alternative.empty());
  EXPECT_TRUE(count(70, 55, 20, 100).shape_alternative.empty());  // 125°: a clear tuck
  EXPECT_NE(count(70, 47, 20, 100)
                .shape_reason.find("a close call (within 5° of 135°): it could be read as a pike"),
            std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
