// The flights held to free-flight physics (flight_physics.h, docs/one-camera.md "Flight
// physics"): a flight that obeys the physics — the sample routine's joint angles in one of its
// flights, the root turned by the constant angular momentum and carried on gravity's parabola —
// seen by the sample's side camera at 30 fps, its root then spoiled as a frame-by-frame fit from
// one camera spoils it (the twist jittering, the depth off): the fit gives the root back.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/capture/trial_io.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/flight_rotation.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/reconstruct/flight_physics.h"
#include "acro/reconstruct/reconstruction.h"
#include "acro/vision/camera.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::filesystem::path Sample(const std::string& name) {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine" / name;
}

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

Eigen::Quaterniond Root(const Eigen::VectorXd& q) {
  return dynamics::GetRootQuaternion(q).normalized();
}

double AngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return Eigen::AngleAxisd(a.conjugate() * b).angle() / kDeg;
}

// The sample routine's motion capture, reconstructed once.
const ReconstructionResult& SampleTruth() {
  static const ReconstructionResult truth = [] {
    const capture::Trial trial = capture::ReadTrial(Sample("trampoline_routine.c3d"));
    return Reconstruct(trial, nullptr, MakeDeLevaBody(1.75, 65.0, Sex::kFemale), {});
  }();
  return truth;
}

struct PhysicalFlight {
  dynamics::Model<double> model;
  std::vector<ModelMarker> keypoints;
  Motion truth;   // 30 Hz, the flight physical, the contacts around it as recorded
  int first = 0;  // first and last frame in the air
  int last = 0;
  Eigen::Vector3d H_W = Eigen::Vector3d::Zero();
  ViewsToFit views;  // the side camera's exact projections (+ noise)
};

// The sample's flight `index` at 30 Hz, made physical, seen by the side camera with `noise_px`.
PhysicalFlight MakePhysicalFlight(int index, double noise_px) {
  const ReconstructionResult& t = SampleTruth();
  PhysicalFlight out;
  out.model = t.model;
  out.keypoints = PlaceMarkers(BuiltinMarkerSet("body25b"), t.model, 1.75);
  const int step = static_cast<int>(std::lround(t.motion.rate_hz / 30.0));
  const FlightFit& flight = t.summary.flights.at(size_t(index));
  const int margin = 6;
  std::vector<int> source;
  for (int f = flight.first_frame - margin * step; f <= flight.last_frame + margin * step;
       f += step)
    if (f >= 0 && f < t.motion.num_frames()) source.push_back(f);
  const int F = static_cast<int>(source.size());
  Motion& m = out.truth;
  m.coordinate_names = t.motion.coordinate_names;
  m.rate_hz = t.motion.rate_hz / step;
  m.time_s.resize(F);
  m.q.resize(t.motion.nq(), F);
  m.fit.assign(size_t(F), FrameFit{});
  bool in_air = false;
  for (int k = 0; k < F; ++k) {
    m.time_s[k] = k / m.rate_hz;
    m.q.col(k) = t.motion.q.col(source[size_t(k)]);
    m.fit[size_t(k)].valid = true;
    m.fit[size_t(k)].num_markers = 25;
    if (source[size_t(k)] >= flight.first_frame && !in_air) out.first = k;
    in_air = in_air || source[size_t(k)] >= flight.first_frame;
    if (source[size_t(k)] <= flight.last_frame) out.last = k;
  }
  // The root made physical over the flight: H from the recorded turn in its middle third,
  // the orientation at take-off as recorded, the centre of mass on the parabola through the
  // recorded take-off position with the recorded mean horizontal velocity.
  const int n = out.last - out.first;
  const double dt = 1.0 / m.rate_hz;
  const int nj = out.model.num_joint_dofs();
  const Eigen::MatrixXd joints = m.q.block(dynamics::kRootNq, out.first, nj, n + 1);
  auto joints_at = [&](double time,
                       dynamics::VectorXRef<double> q,
                       dynamics::VectorXRef<double> v,
                       dynamics::VectorXRef<double> a) {
    const double u = std::clamp(time / dt, 0.0, double(n));
    const int i = std::min(int(u), n - 1);
    const double s = u - i;
    q = (1 - s) * joints.col(i) + s * joints.col(i + 1);
    v = (joints.col(i + 1) - joints.col(i)) / dt;
    a.setZero();
  };
  const dynamics::JointMotionSamples samples =
      dynamics::SampleJointMotion(out.model, n * dt, n, joints_at);
  {
    const int i = out.first + n / 2;
    const Eigen::Quaterniond a = Root(m.q.col(i - 1)), b = Root(m.q.col(i + 1)),
                             c = Root(m.q.col(i));
    const Eigen::AngleAxisd turn(c.conjugate() * b * (c.conjugate() * a).conjugate());
    const Eigen::Vector3d w_B = turn.angle() * turn.axis() / (2 * dt);
    const size_t k = size_t(2 * (n / 2));
    out.H_W = c * (samples.I_Scm_B_inverse[k].inverse() * w_B + samples.H_joints_Scm_B[k]);
  }
  const std::vector<Eigen::Quaterniond> turns =
      dynamics::SimulateFlightRotation(samples, Root(m.q.col(out.first)), out.H_W);
  dynamics::Workspace<double> ws(out.model);
  auto com = [&](const Eigen::VectorXd& q) {
    dynamics::CalcForwardKinematics(out.model, ws, q);
    return Eigen::Vector3d(dynamics::CalcCenterOfMassPosition(out.model, ws));
  };
  const Eigen::Vector3d c0 = com(m.q.col(out.first));
  Eigen::Vector3d v0 = (com(m.q.col(out.last)) - c0) / (n * dt);
  v0.z() = -0.5 * out.model.gravity_W().z() * n * dt;  // lands at its take-off height
  for (int i = 0; i <= n; ++i) {
    Eigen::VectorXd q = m.q.col(out.first + i);
    dynamics::SetRootQuaternion<double>(turns[size_t(i)], q);
    q.head<3>().setZero();
    const Eigen::Vector3d offset = com(q);  // the COM from the root origin, in W
    const double time = i * dt;
    q.head<3>() = c0 + v0 * time + 0.5 * out.model.gravity_W() * time * time - offset;
    m.q.col(out.first + i) = q;
  }
  // The side camera's view of the body25b keypoints.
  const std::vector<vision::Camera> cameras = vision::ReadCameras(Sample("views.toml"));
  const auto side = std::find_if(
      cameras.begin(), cameras.end(), [](const vision::Camera& c) { return c.name == "side"; });
  EXPECT_NE(side, cameras.end());
  ViewKeypoints view;
  view.camera = *side;
  const int P = static_cast<int>(out.keypoints.size());
  view.xy.resize(2, Eigen::Index(F) * P);
  view.confidence = Eigen::ArrayXXd::Constant(P, F, 0.9);
  view.agreed = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(P, F, true);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, noise_px / side->K(0, 0));
  InverseKinematics ik(out.model, out.keypoints, StandardJointLimits(out.model), {});
  Eigen::Matrix3Xd p_WM;
  for (int k = 0; k < F; ++k) {
    ik.CalcMarkerPositions(m.q.col(k), p_WM);
    for (int j = 0; j < P; ++j) {
      const Eigen::Vector3d p = side->R_KW * p_WM.col(j) + side->t_KW;
      view.xy.col(Eigen::Index(k) * P + j) =
          p.head<2>() / p.z() + Eigen::Vector2d(noise(rng), noise(rng));
    }
  }
  for (const ModelMarker& k : out.keypoints) out.views.names.push_back(k.name);
  out.views.views = {view};
  out.views.num_frames = F;
  return out;
}

// The root spoiled as one camera's frame-by-frame fit spoils it: each frame turned by up to
// `jitter_deg` about a random axis, the whole flight pushed 0.4 m in depth.
Motion Spoil(const PhysicalFlight& f, double jitter_deg) {
  Motion m = f.truth;
  std::mt19937 rng(5);
  std::normal_distribution<double> axis(0.0, 1.0);
  std::uniform_real_distribution<double> angle(-jitter_deg * kDeg, jitter_deg * kDeg);
  const vision::Camera& cam = f.views.views[0].camera;
  const Eigen::Vector3d depth = cam.R_KW.transpose().col(2);
  for (int k = f.first; k <= f.last; ++k) {
    Eigen::VectorXd q = m.q.col(k);
    const Eigen::Vector3d a = Eigen::Vector3d(axis(rng), axis(rng), axis(rng)).normalized();
    dynamics::SetRootQuaternion<double>(
        Root(q) * Eigen::Quaterniond(Eigen::AngleAxisd(angle(rng), a)), q);
    q.head<3>() += 0.4 * depth;
    m.q.col(k) = q;
  }
  return m;
}

std::vector<int> KeypointMarkers(const PhysicalFlight& f) {
  std::vector<int> out;
  for (size_t j = 0; j < f.keypoints.size(); ++j) out.push_back(int(j));
  return out;
}

FlightPhysicsFit ExpectRootBack(int flight_index) {
  const PhysicalFlight f = MakePhysicalFlight(flight_index, 1.0);
  Motion motion = Spoil(f, 12.0);
  std::vector<double> before, after;
  for (int k = f.first; k <= f.last; ++k)
    before.push_back(AngleDeg(Root(motion.q.col(k)), Root(f.truth.q.col(k))));
  const FlightPhysicsOptions options;
  const FlightPhysicsSummary s = FitFlightsToPhysics(f.views,
                                                     KeypointMarkers(f),
                                                     f.model,
                                                     f.keypoints,
                                                     StandardJointLimits(f.model),
                                                     {},
                                                     {{f.first, f.last}},
                                                     options,
                                                     &motion);
  std::printf("%s", s.Report().c_str());
  EXPECT_EQ(s.flights.size(), 1u);
  if (s.flights.size() != 1) return {};
  std::vector<double> position;
  for (int k = f.first; k <= f.last; ++k) {
    after.push_back(AngleDeg(Root(motion.q.col(k)), Root(f.truth.q.col(k))));
    position.push_back((motion.q.col(k).head<3>() - f.truth.q.col(k).head<3>()).norm());
  }
  std::printf(
      "flight %d: root orientation median %.2f° (max %.2f°) from the truth, spoiled %.2f°; "
      "position median %.1f mm; H (%.1f %.1f %.1f) for (%.1f %.1f %.1f)\n",
      flight_index,
      Median(after),
      *std::max_element(after.begin(), after.end()),
      Median(before),
      1e3 * Median(position),
      s.flights[0].H_Scm_W.x(),
      s.flights[0].H_Scm_W.y(),
      s.flights[0].H_Scm_W.z(),
      f.H_W.x(),
      f.H_W.y(),
      f.H_W.z());
  EXPECT_LT(Median(after), 1.0);
  EXPECT_LT(*std::max_element(after.begin(), after.end()), 3.0);
  EXPECT_LT(Median(position), 0.02);
  EXPECT_LT(s.flights[0].median_after_px, 1.5);
  EXPECT_LT((s.flights[0].H_Scm_W - f.H_W).norm(), 0.05 * f.H_W.norm());
  return s.flights[0];
}

// The back somersault without twist (the sample's second flight): its mirror image through the
// depth is itself — the same cost, the same turns — so there is no twist direction to tell, and no
// warning.
TEST(FlightPhysics, APhysicalSomersaultSeenByOneCameraGetsItsRootBack) {
  const FlightPhysicsFit fit = ExpectRootBack(1);
  EXPECT_LT(fit.mirror_cost_ratio, 1.1);
  EXPECT_LT(fit.mirror_apart_deg, 5.0);
  EXPECT_FALSE(fit.ambiguous);
  EXPECT_TRUE(fit.kept);
}

// The full twist (the sample's fifth flight): the mirror image, twisting the other way, fits far
// worse than the truth and is not chosen.
TEST(FlightPhysics, APhysicalTwistSeenByOneCameraGetsItsRootBack) {
  const FlightPhysicsFit fit = ExpectRootBack(4);
  EXPECT_FALSE(fit.mirror_chosen);
  EXPECT_GT(fit.mirror_cost_ratio, 10.0);
  EXPECT_GT(fit.mirror_apart_deg, 90.0);
  EXPECT_FALSE(fit.ambiguous);
  EXPECT_TRUE(fit.kept);
}

TEST(FlightPhysics, OptionsOutOfRangeAreRefused) {
  std::string why;
  FlightPhysicsOptions o;
  EXPECT_TRUE(o.IsValid(&why));
  o.segment_s = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("segment_s"), std::string::npos);
  o = {};
  o.robust_px = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
  o = {};
  o.ambiguous_ratio = 0.5;
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace acro::analysis
