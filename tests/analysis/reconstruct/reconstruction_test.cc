// Synthetic round trip: motions simulated by the dynamics engine (joint trajectories prescribed,
// the root in free flight) → markers with 1 mm noise and gaps of up to 20 frames → Reconstruct →
// joint angles and root orientation against the simulated truth.
#include "acro/reconstruct/reconstruction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/capture/c3d.h"
#include "acro/capture/trial_io.h"
#include "acro/dynamics/flight_simulation.h"
#include "acro/dynamics/kinematics.h"
#include "acro/reconstruct/motion_export.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// Smooth step from 0 (t ≤ t0) to 1 (t ≥ t1): ½ − ½ cos(π u), with its first two derivatives.
void SmoothStep(double t, double t0, double t1, double* s, double* ds, double* dds) {
  const double u = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  const double k = std::numbers::pi / (t1 - t0);
  const bool inside = t > t0 && t < t1;
  *s = 0.5 - 0.5 * std::cos(std::numbers::pi * u);
  *ds = inside ? 0.5 * k * std::sin(std::numbers::pi * u) : 0.0;
  *dds = inside ? 0.5 * k * k * std::cos(std::numbers::pi * u) : 0.0;
}

struct Synthetic {
  dynamics::Model<double> model;
  double rate_hz = 200.0;
  std::vector<Eigen::VectorXd> q;  // truth per frame
};

/// A double somersault with two twists: arms from overhead to the chest, a tuck between 0.25 s and
/// 1.0 s, asymmetric arms for the twist, and a small oscillation on every other joint angle so
/// that every coordinate is exercised. Take-off: COM velocity (0, 0, 7.4) m/s, angular momentum
/// about the somersault (y) and twist (z) axes.
Synthetic MakeDoubleTwistingDouble(const AthleteBody& body, double Hy, double Hz) {
  Synthetic s{MakeStandardHumanModel(body), 200.0, {}};
  const dynamics::Model<double>& model = s.model;
  const std::vector<std::string> names = MakeCoordinateNames(model);
  auto index = [&](const std::string& n) {
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return static_cast<int>(i) - 7;
    ADD_FAILURE() << n;
    return 0;
  };
  struct Ramp {
    int joint;
    double start_deg, end_deg, t0, t1;
  };
  const std::vector<Ramp> ramps = {
      {index("l_shoulder_flexion"), -170, -40, 0.0, 0.3},
      {index("r_shoulder_flexion"), -170, -55, 0.0, 0.3},
      {index("l_shoulder_abduction"), 10, 5, 0.0, 0.3},
      {index("r_shoulder_abduction"), -10, -30, 0.0, 0.3},
      {index("l_elbow_flexion"), -10, -90, 0.05, 0.35},
      {index("r_elbow_flexion"), -10, -80, 0.05, 0.35},
      {index("l_hip_flexion"), -5, -115, 0.25, 0.5},
      {index("r_hip_flexion"), -5, -115, 0.25, 0.5},
      {index("l_knee_flexion"), 5, 115, 0.25, 0.5},
      {index("r_knee_flexion"), 5, 115, 0.25, 0.5},
      {index("lumbar_flexion"), 0, 25, 0.25, 0.5},
      {index("l_ankle_flexion"), 30, 45, 0.0, 0.5},
      {index("r_ankle_flexion"), 30, 45, 0.0, 0.5},
  };
  // The tuck opens again between 1.0 and 1.3 s (hips, knees, trunk back to their start).
  const std::vector<int> opening = {index("l_hip_flexion"),
                                    index("r_hip_flexion"),
                                    index("l_knee_flexion"),
                                    index("r_knee_flexion"),
                                    index("lumbar_flexion")};
  const int n = model.num_joint_dofs();
  dynamics::JointTrajectory<double> joints = [&, n](const double& t,
                                                    dynamics::VectorXRef<double> qj,
                                                    dynamics::VectorXRef<double> vj,
                                                    dynamics::VectorXRef<double> aj) {
    // Small oscillations everywhere (4°, distinct frequencies), ramps on top.
    for (int j = 0; j < n; ++j) {
      const double w = 2.0 * std::numbers::pi * (0.7 + 0.13 * j);
      const double a = 4.0 * kDeg;
      qj[j] = a * std::sin(w * t + j);
      vj[j] = a * w * std::cos(w * t + j);
      aj[j] = -a * w * w * std::sin(w * t + j);
    }
    for (const Ramp& r : ramps) {
      double u, du, ddu;
      SmoothStep(t, r.t0, r.t1, &u, &du, &ddu);
      double span = (r.end_deg - r.start_deg) * kDeg;
      double base = r.start_deg * kDeg + span * u;
      double rate = span * du, acc = span * ddu;
      if (std::find(opening.begin(), opening.end(), r.joint) != opening.end()) {
        double o, dout, ddo;
        SmoothStep(t, 1.0, 1.3, &o, &dout, &ddo);
        base -= span * o;
        rate -= span * dout;
        acc -= span * ddo;
      }
      qj[r.joint] += base;
      vj[r.joint] += rate;
      aj[r.joint] += acc;
    }
  };
  // Take-off state: root at 1.1 m, upright; root velocity from the wanted momentum.
  Eigen::Matrix<double, 7, 1> q_root0;
  q_root0 << 0, 0, 1.1, 1, 0, 0, 0;
  Eigen::VectorXd q0 = dynamics::MakeNeutralConfiguration(model);
  q0.head<7>() = q_root0;
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(model.nv());
  {
    Eigen::VectorXd qj(n), vj(n), aj(n);
    joints(0.0, qj, vj, aj);
    q0.tail(n) = qj;
    v0.tail(n) = vj;
  }
  dynamics::Workspace<double> ws(model);
  const dynamics::Vector6<double> v_root0 = dynamics::CalcRootVelocityFromMomentum<double>(
      model, ws, q0, v0, Eigen::Vector3d(0, 0, 7.4), Eigen::Vector3d(0, Hy, Hz));
  dynamics::FlightSimulationOptions options;
  options.duration_s = 1.5;
  options.step_s = 1e-3;
  options.output_interval_s = 1.0 / s.rate_hz;
  const dynamics::FlightSimulationResult<double> sim =
      dynamics::SimulateFlight<double>(model, options, q_root0, v_root0, joints);
  EXPECT_EQ(sim.summary.status, dynamics::FlightSimulationStatus::kSuccess);
  s.q = sim.q;
  return s;
}

/// Somersaults and twists of the root: the integral of the angular velocity about the world's
/// lateral axis and about the body's longitudinal axis, in turns.
std::pair<double, double> CountRotations(const Synthetic& s) {
  double som = 0, twist = 0;
  for (size_t f = 1; f < s.q.size(); ++f) {
    const Eigen::Quaterniond a(s.q[f - 1][3], s.q[f - 1][4], s.q[f - 1][5], s.q[f - 1][6]);
    const Eigen::Quaterniond b(s.q[f][3], s.q[f][4], s.q[f][5], s.q[f][6]);
    const Eigen::AngleAxisd world(b * a.conjugate());  // rotation in W
    const Eigen::AngleAxisd body(a.conjugate() * b);   // rotation in B
    som += world.angle() * world.axis().y();
    twist += body.angle() * body.axis().z();
  }
  return {som / (2 * std::numbers::pi), twist / (2 * std::numbers::pi)};
}

capture::Trial MakeMarkerTrial(const Synthetic& s,
                               const MarkerSet& set,
                               const std::vector<ModelMarker>& markers,
                               double noise_m,
                               int max_gap,
                               int num_gaps,
                               std::mt19937& rng) {
  capture::Trial trial;
  trial.point_rate_hz = s.rate_hz;
  trial.num_frames = static_cast<int>(s.q.size());
  const int M = static_cast<int>(markers.size());
  for (const ModelMarker& m : markers) trial.points.push_back({"Athlete:" + m.name, "", {}, "m"});
  trial.positions.resize(3, Eigen::Index(trial.num_frames) * M);
  dynamics::Workspace<double> ws(s.model);
  std::normal_distribution<double> noise(0.0, noise_m);
  for (int f = 0; f < trial.num_frames; ++f) {
    dynamics::CalcForwardKinematics(s.model, ws, s.q[size_t(f)]);
    for (int m = 0; m < M; ++m) {
      Eigen::Vector3d p = ws.X_WB[size_t(markers[size_t(m)].segment)] * markers[size_t(m)].p_BoM_B;
      for (int d = 0; d < 3; ++d) p[d] += noise(rng);
      trial.position(f, m) = p;
    }
  }
  std::uniform_int_distribution<int> which(0, M - 1), length(5, max_gap),
      start(5, trial.num_frames - max_gap - 5);
  for (int g = 0; g < num_gaps; ++g) {
    const int m = which(rng), len = length(rng), f0 = start(rng);
    for (int f = f0; f < f0 + len; ++f) trial.position(f, m).setConstant(std::nan(""));
  }
  (void)set;
  return trial;
}

struct RoundTrip {
  double worst_joint_rms_deg = 0;
  std::string worst_joint;
  double all_joint_rms_deg = 0;
  double max_joint_error_deg = 0;
  double max_root_error_deg = 0;
  double rms_root_error_deg = 0;
  double median_marker_rms_mm = 0;
};

RoundTrip Compare(const Synthetic& s, const Motion& motion) {
  RoundTrip r;
  const int n = s.model.num_joint_dofs();
  const int F = static_cast<int>(s.q.size());
  double all = 0, root_sum = 0;
  for (int j = 0; j < n; ++j) {
    double sum = 0;
    for (int f = 0; f < F; ++f) {
      const double e = (motion.q(7 + j, f) - s.q[size_t(f)][7 + j]) / kDeg;
      sum += e * e;
      r.max_joint_error_deg = std::max(r.max_joint_error_deg, std::abs(e));
    }
    all += sum;
    const double rms = std::sqrt(sum / F);
    if (rms > r.worst_joint_rms_deg) {
      r.worst_joint_rms_deg = rms;
      r.worst_joint = motion.coordinate_names[size_t(7 + j)];
    }
  }
  r.all_joint_rms_deg = std::sqrt(all / (double(F) * n));
  for (int f = 0; f < F; ++f) {
    const Eigen::Quaterniond a(
        s.q[size_t(f)][3], s.q[size_t(f)][4], s.q[size_t(f)][5], s.q[size_t(f)][6]);
    const Eigen::Quaterniond b(motion.q(3, f), motion.q(4, f), motion.q(5, f), motion.q(6, f));
    const double e = Eigen::AngleAxisd(a.conjugate() * b).angle() / kDeg;
    r.max_root_error_deg = std::max(r.max_root_error_deg, e);
    root_sum += e * e;
  }
  r.rms_root_error_deg = std::sqrt(root_sum / F);
  r.median_marker_rms_mm = Percentile(SortedFrameRms(motion), 50) * 1e3;
  return r;
}

class SyntheticRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(SyntheticRoundTrip, DoubleSomersaultWithTwoTwists) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const Synthetic s = MakeDoubleTwistingDouble(body, -55.0, 9.0);
  const auto [som, twist] = CountRotations(s);
  std::printf("simulated: %.2f somersaults, %.2f twists, %zu frames\n", som, twist, s.q.size());
  EXPECT_GT(std::abs(som), 1.75);
  EXPECT_GT(std::abs(twist), 1.75);

  const MarkerSet set = BuiltinMarkerSet(GetParam());
  const std::vector<ModelMarker> markers = PlaceMarkers(set, s.model, body.height_m);
  std::mt19937 rng(12345);
  const capture::Trial trial = MakeMarkerTrial(s, set, markers, 1e-3, 20, 25, rng);

  ReconstructionOptions options;
  options.scale = false;  // the model that made the markers; scaling is tested on its own
  options.min_chunk_frames = 60;
  const ReconstructionResult result = Reconstruct(trial, nullptr, body, options);
  std::printf("%s", result.summary.BriefReport().c_str());
  EXPECT_EQ(result.summary.markerset, GetParam());
  EXPECT_EQ(result.summary.frames_fitted, trial.num_frames);
  const RoundTrip r = Compare(s, result.motion);
  std::printf(
      "%s: joint angles RMS %.3f° (worst %s %.3f°, max error %.2f°), root orientation RMS "
      "%.3f°, max %.3f°, marker RMS median %.2f mm\n",
      GetParam(),
      r.all_joint_rms_deg,
      r.worst_joint.c_str(),
      r.worst_joint_rms_deg,
      r.max_joint_error_deg,
      r.rms_root_error_deg,
      r.max_root_error_deg,
      r.median_marker_rms_mm);
  // The acceptance: every joint angle within 1° RMS, root orientation within 1°.
  EXPECT_LT(r.worst_joint_rms_deg, 1.0);
  EXPECT_LT(r.max_root_error_deg, 1.0);
  // No branch flips: no frame departs from the truth by more than a few degrees anywhere.
  EXPECT_LT(r.max_joint_error_deg, 10.0);
}

TEST(Reconstruction, RepairsLeftRightSwaps) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const Synthetic s = MakeDoubleTwistingDouble(body, -55.0, 9.0);
  const MarkerSet set = BuiltinMarkerSet("plug_in_gait");
  const std::vector<ModelMarker> markers = PlaceMarkers(set, s.model, body.height_m);
  std::mt19937 rng(99);
  capture::Trial trial = MakeMarkerTrial(s, set, markers, 1e-3, 5, 0, rng);
  // Knees and wrists exchanged over 12 frames, as a video pipeline confuses sides.
  const int lk = set.Find("LKNE"), rk = set.Find("RKNE"), lw = set.Find("LWRA"),
            rw = set.Find("RWRA");
  for (int f = 150; f < 162; ++f) {
    trial.position(f, lk).swap(trial.position(f, rk));
    trial.position(f, lw).swap(trial.position(f, rw));
  }
  ReconstructionOptions options;
  options.scale = false;
  options.num_threads = 1;
  const ReconstructionResult fixed = Reconstruct(trial, nullptr, body, options);
  EXPECT_EQ(fixed.summary.swaps_repaired, 24);
  options.repair_swaps = false;
  const ReconstructionResult broken = Reconstruct(trial, nullptr, body, options);
  const RoundTrip a = Compare(s, fixed.motion), b = Compare(s, broken.motion);
  std::printf("swaps: worst joint RMS %.2f° repaired, %.2f° not\n",
              a.worst_joint_rms_deg,
              b.worst_joint_rms_deg);
  EXPECT_LT(a.worst_joint_rms_deg, 1.0);
  EXPECT_GT(b.worst_joint_rms_deg, a.worst_joint_rms_deg);
}

TEST(Reconstruction, ScalesToAStaticTrial) {
  // The markers come from a 1.75 m athlete; the reconstruction is given a 1.62 m one and a
  // static trial (one second standing, arms slightly abducted), and must scale to the truth.
  const AthleteBody truth_body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const Synthetic s = MakeDoubleTwistingDouble(truth_body, -55.0, 9.0);
  const MarkerSet set = BuiltinMarkerSet("trampoline");
  const std::vector<ModelMarker> markers = PlaceMarkers(set, s.model, truth_body.height_m);
  std::mt19937 rng(21);
  const capture::Trial trial = MakeMarkerTrial(s, set, markers, 1e-3, 20, 25, rng);
  Synthetic stand{s.model, s.rate_hz, {}};
  Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(s.model);
  q[2] = 0.95;
  q[s.model.segment(s.model.FindSegment("l_upper_arm")).q_start + 2] = 0.3;
  q[s.model.segment(s.model.FindSegment("r_upper_arm")).q_start + 2] = -0.3;
  stand.q.assign(200, q);
  const capture::Trial static_trial = MakeMarkerTrial(stand, set, markers, 1e-3, 5, 0, rng);
  ReconstructionOptions options;
  const ReconstructionResult r =
      Reconstruct(trial, &static_trial, MakeDeLevaBody(1.62, 65.0, Sex::kFemale), options);
  std::printf("%s", r.summary.BriefReport().c_str());
  EXPECT_NE(r.summary.scaling_report.find("static trial"), std::string::npos);
  const RoundTrip rt = Compare(s, r.motion);
  std::printf("scaled from 1.62 m: joint angles RMS %.3f° (worst %s %.3f°), root max %.3f°\n",
              rt.all_joint_rms_deg,
              rt.worst_joint.c_str(),
              rt.worst_joint_rms_deg,
              rt.max_root_error_deg);
  EXPECT_LT(r.summary.median_rms_m, 2e-3);
  EXPECT_LT(rt.worst_joint_rms_deg, 1.0);
  EXPECT_LT(rt.max_root_error_deg, 1.0);
}

TEST(Reconstruction, ExportsMotCsvAndC3dWithAngles) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const Synthetic s = MakeDoubleTwistingDouble(body, -55.0, 9.0);
  const MarkerSet set = BuiltinMarkerSet("trampoline");
  std::mt19937 rng(5);
  const capture::Trial trial =
      MakeMarkerTrial(s, set, PlaceMarkers(set, s.model, body.height_m), 1e-3, 5, 0, rng);
  ReconstructionOptions options;
  options.scale = false;
  const ReconstructionResult r = Reconstruct(trial, nullptr, body, options);
  const auto dir = testing::TempDir();
  WriteMotionMot(r.motion, dir / "m.mot");
  const capture::Storage mot = capture::ReadStorage(dir / "m.mot");
  EXPECT_TRUE(mot.in_degrees);
  const int knee = mot.FindColumn("l_knee_flexion");
  ASSERT_GE(knee, 0);
  const int k = static_cast<int>(std::find(r.motion.coordinate_names.begin(),
                                           r.motion.coordinate_names.end(),
                                           "l_knee_flexion") -
                                 r.motion.coordinate_names.begin());
  // Degrees in the file; %.9g-ish text round trip of the storage writer.
  EXPECT_NEAR(mot.data(200, knee), r.motion.q(k, 200) * 180 / std::numbers::pi, 1e-6);
  WriteMotionC3d(r, trial, dir / "m.c3d");
  const capture::Trial c3d = capture::ReadTrial(dir / "m.c3d");
  const int p = c3d.FindPoint("LKneeAngles");
  ASSERT_GE(p, 0);
  EXPECT_EQ(c3d.points[size_t(p)].type, capture::PointType::kAngle);
  // Stored as float: 1e-4° is within single precision for angles below 180°.
  EXPECT_NEAR(c3d.position(200, p).x(), r.motion.q(k, 200) * 180 / std::numbers::pi, 1e-4);
  EXPECT_EQ(c3d.points[0].type, capture::PointType::kMarker);
  EXPECT_NE(FormatMotionCsv(r.motion).find("l_knee_flexion_deg"), std::string::npos);
}

TEST(Reconstruction, RealDataHelenHayesAndKeypoints) {
  const auto jump = testing::RefdataFile(
      "c3dio-c3d_org_samples/sample_00/Motion Analysis Corporation/Sample_Jump2.c3d");
  ACRO_REQUIRE_REFDATA_FILE(jump);
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const ReconstructionResult a = Reconstruct(capture::ReadTrial(jump), nullptr, body, {});
  std::printf("%s", a.summary.BriefReport().c_str());
  EXPECT_EQ(a.summary.markerset, "helen_hayes");
  EXPECT_EQ(a.summary.frames_fitted, 264);
  // OpenSim's guideline for a good fit: RMS about 2 cm, largest below 4 cm.
  EXPECT_LT(a.summary.median_rms_m, 0.02);
  EXPECT_LT(a.summary.max_m, 0.04);
  const auto trc =
      testing::RefdataFile("s2mLab-EKF_multicamera-trampoline/inputs/trc/1_partie_0429_002.trc");
  ACRO_REQUIRE_REFDATA_FILE(trc);
  const ReconstructionResult b = Reconstruct(capture::ReadTrial(trc), nullptr, body, {});
  std::printf("%s", b.summary.BriefReport().c_str());
  EXPECT_EQ(b.summary.markerset, "coco17");
  EXPECT_EQ(b.summary.frames_fitted, 1261);
  EXPECT_GE(b.summary.flights.size(), 4u);
  // Video keypoints: the median frame near the guideline (measured 2.3 cm; docs/reconstruction.md).
  EXPECT_LT(b.summary.median_rms_m, 0.03);
  // What 17 keypoints on joint centres cannot see, said (and held at the reference pose): the
  // forearms' twist, the wrists, the ankles. Helen Hayes (no hand markers) cannot see the wrists,
  // and says so.
  const auto said = [](const ReconstructionResult& r) {
    for (const std::string& w : r.summary.warnings)
      if (w.find("cannot see") != std::string::npos) return w;
    return std::string();
  };
  EXPECT_EQ(said(b),
            "the coco17 keypoints on this trial cannot see 10 joint angles (r_elbow_pronation, "
            "r_wrist_flexion, r_wrist_deviation, l_elbow_pronation, l_wrist_flexion, "
            "l_wrist_deviation, r_ankle_flexion, r_ankle_inversion, l_ankle_flexion, "
            "l_ankle_inversion): held at the reference pose");
  EXPECT_EQ(said(a),
            "the helen_hayes markers on this trial cannot see 4 joint angles (r_wrist_flexion, "
            "r_wrist_deviation, l_wrist_flexion, l_wrist_deviation)");
  // Pose2Sim's BODY_25B (toes and heels): the ankles are seen, the forearms and wrists are not.
  const auto p2s = testing::RefdataFile(
      "pose2sim-demo/balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  ACRO_REQUIRE_REFDATA_FILE(p2s);
  const ReconstructionResult c = Reconstruct(capture::ReadTrial(p2s), nullptr, body, {});
  EXPECT_EQ(c.summary.markerset, "body25b");
  EXPECT_NE(said(c).find("cannot see 6 joint angles (r_elbow_pronation"), std::string::npos)
      << said(c);
  EXPECT_EQ(said(c).find("ankle"), std::string::npos) << said(c);
}

INSTANTIATE_TEST_SUITE_P(MarkerSets,
                         SyntheticRoundTrip,
                         ::testing::Values("trampoline", "plug_in_gait"));

}  // namespace
}  // namespace acro::analysis
