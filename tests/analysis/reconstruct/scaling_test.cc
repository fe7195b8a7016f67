// Scaling recovers known segment factors from markers of a scaled model (static pose and a window
// of moving frames), and the scaled model's mass properties follow the factors.
#include "acro/reconstruct/scaling.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/dynamics/kinematics.h"

namespace acro::analysis {
namespace {

struct Case {
  dynamics::Model<double> model;     // unscaled
  dynamics::Model<double> truth;     // scaled
  std::vector<ModelMarker> markers;  // on the unscaled model
  std::vector<ModelMarker> truth_markers;
  std::map<std::string, double> scale;
};

Case MakeCase() {
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  Case c{MakeStandardHumanModel(body), {}, {}, {}, {}};
  c.scale = {{"thigh", 1.08},
             {"shank", 0.94},
             {"upper_arm", 1.05},
             {"forearm", 0.95},
             {"thorax", 1.04},
             {"pelvis", 0.97}};
  c.truth = MakeScaledModel(c.model, c.scale);
  c.markers = PlaceMarkers(BuiltinMarkerSet("trampoline"), c.model, 1.75);
  c.truth_markers = c.markers;
  for (ModelMarker& m : c.truth_markers) {
    const auto it = c.scale.find(ScaleGroupOf(c.model.segment(m.segment).name));
    if (it != c.scale.end()) m.p_BoM_B *= it->second;
  }
  return c;
}

Eigen::Matrix3Xd Observe(const Case& c, const Eigen::VectorXd& q, std::mt19937& rng, double noise) {
  dynamics::Workspace<double> ws(c.truth);
  dynamics::CalcForwardKinematics(c.truth, ws, q);
  std::normal_distribution<double> n(0.0, noise);
  Eigen::Matrix3Xd obs(3, static_cast<Eigen::Index>(c.truth_markers.size()));
  for (size_t m = 0; m < c.truth_markers.size(); ++m)
    obs.col(Eigen::Index(m)) =
        ws.X_WB[size_t(c.truth_markers[m].segment)] * c.truth_markers[m].p_BoM_B +
        Eigen::Vector3d(n(rng), n(rng), n(rng));
  return obs;
}

TEST(Scaling, ScaledModelMassProperties) {
  const Case c = MakeCase();
  const int thigh = c.model.FindSegment("l_thigh");
  EXPECT_DOUBLE_EQ(c.truth.segment(thigh).mass, c.model.segment(thigh).mass);
  EXPECT_TRUE(c.truth.segment(thigh).p_BoBcm_B.isApprox(1.08 * c.model.segment(thigh).p_BoBcm_B));
  // The knee sits 1.08 times further from the hip.
  const int shank = c.model.FindSegment("l_shank");
  EXPECT_TRUE(c.truth.segment(shank).X_PJ.translation().isApprox(
      1.08 * c.model.segment(shank).X_PJ.translation()));
}

TEST(Scaling, RecoversFactorsFromMovingFrames) {
  const Case c = MakeCase();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  std::vector<Eigen::Matrix3Xd> frames;
  for (int k = 0; k < 8; ++k) {
    Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(c.truth);
    q.head<3>() << 0.3 * k, -0.1 * k, 1.0;
    const Eigen::Quaterniond r =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * k, Eigen::Vector3d::UnitZ()));
    q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
    for (int j = 7; j < q.size(); ++j) q[j] = angle(rng);
    frames.push_back(Observe(c, q, rng, 1e-3));
  }
  const ScalingResult r =
      ScaleModel(c.model, c.markers, StandardJointLimits(c.model), frames, ScalingOptions{});
  std::printf("%s\n", r.BriefReport().c_str());
  // 1 mm noise over 8 frames, with the priors pulling towards 1: within 1.5 % of the truth.
  for (const auto& [group, s] : c.scale) EXPECT_NEAR(r.scale.at(group), s, 0.015) << group;
  EXPECT_LT(r.rms_after_m, 2e-3);
  EXPECT_LT(r.rms_after_m, r.rms_before_m);
  // Inverse kinematics with the scaled model from the fitted poses keeps (or improves) the fit:
  // scaling and inverse kinematics minimise the same objective.
  InverseKinematics ik(r.model, r.markers, StandardJointLimits(r.model));
  for (size_t k = 0; k < frames.size(); ++k) {
    Eigen::VectorXd q = r.poses[k];
    const double before = ik.Evaluate(frames[k], q, nullptr).rms_m;
    const IkFrameResult after = ik.Solve(frames[k], q, false);
    std::printf("frame %zu: %.2f mm at the scaling pose, %.2f mm after inverse kinematics\n",
                k,
                before * 1e3,
                after.rms_m * 1e3);
    EXPECT_LT(after.rms_m, before + 1e-4);
  }
}

}  // namespace
}  // namespace acro::analysis
