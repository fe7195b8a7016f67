#include "acro/scene/compare_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/configuration.h"

namespace acro::analysis {

namespace {

constexpr double kTailS = 0.25;  // shown after the later landing

const JumpMetrics& FindJump(const TrialAnalysis& analysis, int jump) {
  for (const JumpMetrics& j : analysis.jumps)
    if (j.index == jump) return j;
  throw InputError(analysis.trial_name,
                   "jump",
                   std::to_string(jump) + " is not a jump of this trial (it has " +
                       std::to_string(analysis.jumps.size()) + ")");
}

// The sample at time t (s from the trial's first sample), clamped to the motion.
int SampleAt(const Motion& m, double t) {
  const double rate = m.rate_hz > 0 ? m.rate_hz : 1.0;
  return std::clamp(static_cast<int>(std::lround(t * rate)), 0, m.num_frames() - 1);
}

// The pelvis's forward axis in configuration q, horizontal and unit.
Eigen::Vector3d Heading(const Eigen::VectorXd& q) {
  Eigen::Vector3d forward = dynamics::GetRootQuaternion(q) * Eigen::Vector3d::UnitX();
  forward.z() = 0.0;
  return forward.norm() > 1e-6 ? Eigen::Vector3d(forward.normalized()) : Eigen::Vector3d::UnitX();
}

// The athlete of a jump (or of a design), checked.
AthleteScene MakeScene(const CompareJump& j, const char* which) {
  if (j.design != nullptr && j.body != nullptr)
    return AthleteScene(*j.body, j.mesh, j.design->motion);
  if (j.trial == nullptr || j.analysis == nullptr || j.body == nullptr)
    throw std::invalid_argument(std::string("CompareScene: jump ") + which +
                                " lacks its trial, analysis or body");
  return AthleteScene(
      *j.body, j.mesh, j.analysis->reconstruction.motion, j.analysis->reconstruction.model);
}

const Motion& MotionOf(const CompareJump& j) {
  return j.design != nullptr ? j.design->motion : j.analysis->reconstruction.motion;
}

// The frame of the jump's motion τ after its take-off `p`.
int FrameAt(const CompareJump& j, const TakeoffPlacement& p, double tau_s) {
  return j.design != nullptr ? FrameNearestTime(j.design->motion, p.takeoff_s + tau_s)
                             : SampleAt(j.analysis->reconstruction.motion, p.takeoff_s + tau_s);
}

}  // namespace

Eigen::Isometry3d PlaceAtTakeoff(const TakeoffPlacement& from, const TakeoffPlacement& onto) {
  const double yaw = std::atan2(onto.heading_W.y(), onto.heading_W.x()) -
                     std::atan2(from.heading_W.y(), from.heading_W.x());
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = onto.feet_W - X.linear() * from.feet_W;
  return X;
}

void TransformPose(const Eigen::Isometry3d& X, AthletePose* pose) {
  pose->mesh.vertices_W = (X.linear() * pose->mesh.vertices_W).colwise() + X.translation();
  pose->skeleton.points_W = (X.linear() * pose->skeleton.points_W).colwise() + X.translation();
  pose->com_W = X * pose->com_W;
}

TakeoffPlacement FindTakeoff(const TrialAnalysis& analysis, int jump) {
  const JumpMetrics& j = FindJump(analysis, jump);
  const Motion& m = analysis.reconstruction.motion;
  TakeoffPlacement p;
  p.feet_W = j.takeoff_feet_W;
  p.takeoff_s = j.flight.takeoff_s;
  p.landing_s = j.flight.landing_s;
  p.heading_W = Heading(m.q.col(std::clamp(j.flight.takeoff_frame, 0, m.num_frames() - 1)));
  return p;
}

std::string JumpLabel(const TrialAnalysis& analysis, int jump) {
  for (const JumpMetrics& j : analysis.jumps)
    if (j.index == jump)
      return j.fig_code + " " + j.skill_name + " (jump " + std::to_string(jump) + ")";
  return "";
}

TakeoffPlacement FindDesignTakeoff(const SkillGhost& design,
                                   const dynamics::Model<double>& model) {
  TakeoffPlacement p;
  const Eigen::VectorXd q0 = design.motion.q.col(0);
  p.feet_W = CalcFeetCentre(model, q0);
  p.heading_W = Heading(q0);
  p.takeoff_s = 0.0;
  p.landing_s = design.flight_time_s;
  return p;
}

CompareScene::CompareScene(CompareJump a, CompareJump b)
    : a_(std::move(a)),
      b_(std::move(b)),
      scene_a_(MakeScene(a_, "A")),
      scene_b_(MakeScene(b_, "B")) {
  const auto place = [](const CompareJump& j, AthleteScene& scene, Eigen::Matrix3Xd* com) {
    if (j.design == nullptr) return FindTakeoff(*j.analysis, j.jump);
    *com = scene.CalcComPath();
    return FindDesignTakeoff(*j.design, MakeStandardHumanModel(*j.body));
  };
  pa_ = place(a_, scene_a_, &design_com_a_);
  pb_ = place(b_, scene_b_, &design_com_b_);
  b_to_a_ = PlaceAtTakeoff(pb_, pa_);
  start_s_ = 0.0;
  end_s_ = std::max(pa_.landing_s - pa_.takeoff_s, pb_.landing_s - pb_.takeoff_s) + kTailS;
}

void CompareScene::Frame(double tau_s, CompareFrame* out) {
  out->tau_s = tau_s;
  scene_a_.Pose(FrameAt(a_, pa_, tau_s), &out->a);
  scene_b_.Pose(FrameAt(b_, pb_, tau_s), &out->b);
  TransformPose(b_to_a_, &out->b);
  out->a_in_flight = tau_s >= 0 && tau_s < pa_.landing_s - pa_.takeoff_s;
  out->b_in_flight = tau_s >= 0 && tau_s < pb_.landing_s - pb_.takeoff_s;
}

JumpCurves CompareScene::Curves(const CompareJump& j,
                                const TakeoffPlacement& p,
                                const Eigen::Matrix3Xd& design_com,
                                const Eigen::Isometry3d& to_a) const {
  const Motion& m = MotionOf(j);
  const Eigen::Matrix3Xd& com = j.design != nullptr ? design_com : j.analysis->check.frames.com_W;
  JumpCurves c;
  const FlightRotation rotation = j.design != nullptr
                                      ? CalcMotionRotation(m, 0, FrameNearestTime(m, p.landing_s))
                                      : CalcFlightRotation(*j.analysis, j.jump);
  if (rotation.frames.size() < 2) return c;
  for (size_t k = 0; k < rotation.frames.size(); ++k) {
    const int f = rotation.frames[k];
    c.tau_s.push_back(m.time_s(f) - p.takeoff_s);
    c.com_height_m.push_back((to_a * Eigen::Vector3d(com.col(f))).z());
    c.somersault_deg.push_back(rotation.somersault_deg[k]);
    c.twist_deg.push_back(rotation.twist_deg[k]);
  }
  return c;
}

JumpCurves CompareScene::CurvesA() const {
  return Curves(a_, pa_, design_com_a_, Eigen::Isometry3d::Identity());
}
JumpCurves CompareScene::CurvesB() const {
  return Curves(b_, pb_, design_com_b_, b_to_a_);
}

}  // namespace acro::analysis
