#include "acro/reconstruct/flight_physics.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>

#include <ceres/ceres.h>
#include <ceres/dynamic_numeric_diff_cost_function.h>
#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/base/parallel.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/flight_rotation.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

#include "view_residuals.h"

namespace acro::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using view_residuals::FocalPx;
using view_residuals::Median;

// One detection of the flight: frame (from the flight's first), camera, model marker, where the
// camera saw it (normalised coordinates) and its weight (√confidence × the marker's weight).
struct Detection {
  int frame = 0;
  int view = 0;
  int marker = 0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double weight = 1.0;
};

// A free flight: the root's orientation at the first frame (and at the start of each later
// segment, see Flight), the angular momentum about the centre of mass, and the centre of mass's
// position and velocity at the first frame.
struct FlightState {
  Eigen::Quaterniond q_WB0 = Eigen::Quaterniond::Identity();
  std::vector<Eigen::Quaterniond> q_segments;  ///< per segment, its first frame's (q_WB0 first)
  Eigen::Vector3d H_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d c0_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v0_W = Eigen::Vector3d::Zero();
};

// The first guess of the root's rotation: the take-off orientation and H whose flight turns as
// the frame-by-frame fit's roots do, robustly (Huber beyond 0.3 rad: that fit's twist jitters).
struct TurnCost {
  const dynamics::JointMotionSamples* samples;
  const std::vector<Eigen::Quaterniond>* frames;
  Eigen::Quaterniond reference;
  bool operator()(double const* const* parameters, double* residuals) const {
    const double* x = parameters[0];
    const std::vector<Eigen::Quaterniond> q = dynamics::SimulateFlightRotation(
        *samples,
        reference * dynamics::QuaternionExp<double>(Eigen::Vector3d(x[0], x[1], x[2])),
        Eigen::Vector3d(x[3], x[4], x[5]));
    constexpr double kScale = 0.3;
    for (size_t i = 0; i < frames->size(); ++i) {
      const Eigen::AngleAxisd turn((*frames)[i].conjugate() * q[i]);
      Eigen::Vector3d r = turn.angle() * turn.axis();
      const double n = r.norm();
      if (n > kScale) r *= std::sqrt(2 * kScale * n - kScale * kScale) / n;
      residuals[3 * i] = r.x();
      residuals[3 * i + 1] = r.y();
      residuals[3 * i + 2] = r.z();
    }
    return true;
  }
};

double FitTurns(const dynamics::JointMotionSamples& samples,
                const std::vector<Eigen::Quaterniond>& frames,
                FlightState* state) {
  TurnCost functor{&samples, &frames, state->q_WB0};
  double x[6] = {0, 0, 0, state->H_W.x(), state->H_W.y(), state->H_W.z()};
  auto* cost = new ceres::DynamicNumericDiffCostFunction<TurnCost>(new TurnCost(functor),
                                                                   ceres::TAKE_OWNERSHIP);
  cost->AddParameterBlock(6);
  cost->SetNumResiduals(3 * static_cast<int>(frames.size()));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 50;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  state->q_WB0 =
      functor.reference * dynamics::QuaternionExp<double>(Eigen::Vector3d(x[0], x[1], x[2]));
  state->H_W = Eigen::Vector3d(x[3], x[4], x[5]);
  return summary.final_cost;
}

// A flight's data and its model: the joint angles per frame (kept), the joints' inertia and
// momentum sampled once, the centre of mass in the root frame per frame.
class Flight {
 public:
  Flight(const ViewsToFit& views,
         const dynamics::Model<double>& model,
         const std::vector<ModelMarker>& markers,
         const std::vector<JointLimit>& limits,
         const InverseKinematicsOptions& ik_options,
         const Motion& motion,
         int first,
         int last,
         std::vector<Detection> detections,
         double robust_px,
         int segments,
         double continuity_px_per_rad)
      : views_(views),
        model_(model),
        ik_(model, markers, limits, ik_options),
        first_(first),
        frames_(last - first + 1),
        detections_(std::move(detections)),
        robust_px_(robust_px),
        continuity_px_per_rad_(continuity_px_per_rad) {
    const int nj = model.num_joint_dofs();
    dt_ = (motion.time_s[last] - motion.time_s[first]) / (frames_ - 1);
    const int S = std::clamp(segments, 1, (frames_ - 1) / 2);
    for (int k = 0; k <= S; ++k)
      segment_first_.push_back(int(std::lround(double(k) * (frames_ - 1) / S)));
    Eigen::MatrixXd joints(nj, frames_);
    for (int i = 0; i < frames_; ++i) joints.col(i) = motion.q.col(first + i).tail(nj);
    SetJoints(joints);
    gravity_W_ = model.gravity_W();
    by_frame_.assign(size_t(frames_), {});
    for (size_t d = 0; d < detections_.size(); ++d)
      by_frame_[size_t(detections_[d].frame)].push_back(int(d));
  }

  // The joint angles per frame, and what follows from them: the joints' inertia and momentum
  // at RK4's steps and half steps, the centre of mass in the root frame per frame.
  void SetJoints(const Eigen::MatrixXd& joints) {
    const int nj = model_.num_joint_dofs();
    joints_ = joints;
    // Each frame's joint angles and rates, Hermite-interpolated between frames (the rates from
    // central differences).
    auto joints_at = [this](double t,
                            dynamics::VectorXRef<double> q,
                            dynamics::VectorXRef<double> v,
                            dynamics::VectorXRef<double> a) {
      const double u = std::clamp(t / dt_, 0.0, double(frames_ - 1));
      const int i = std::min(int(u), frames_ - 2);
      const double s = u - i;
      auto slope = [&](int k) -> Eigen::VectorXd {
        const int lo = std::max(0, k - 1), hi = std::min(frames_ - 1, k + 1);
        return (joints_.col(hi) - joints_.col(lo)) / double(hi - lo);
      };
      const Eigen::VectorXd p0 = joints_.col(i), p1 = joints_.col(i + 1);
      const Eigen::VectorXd m0 = slope(i), m1 = slope(i + 1);
      const double s2 = s * s, s3 = s2 * s;
      q = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 +
          (s3 - s2) * m1;
      v = ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * p1 +
           (3 * s2 - 2 * s) * m1) /
          dt_;
      a.setZero();
    };
    samples_ = dynamics::SampleJointMotion(model_, dt_ * (frames_ - 1), frames_ - 1, joints_at);
    segment_samples_.clear();
    for (size_t k = 0; k + 1 < segment_first_.size(); ++k) {
      const int a = segment_first_[k], b = segment_first_[k + 1];
      dynamics::JointMotionSamples part;
      part.step_s = samples_.step_s;
      part.num_steps = b - a;
      part.I_Scm_B_inverse.assign(samples_.I_Scm_B_inverse.begin() + 2 * a,
                                  samples_.I_Scm_B_inverse.begin() + 2 * b + 1);
      part.H_joints_Scm_B.assign(samples_.H_joints_Scm_B.begin() + 2 * a,
                                 samples_.H_joints_Scm_B.begin() + 2 * b + 1);
      segment_samples_.push_back(std::move(part));
    }
    dynamics::Workspace<double> ws(model_);
    Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(model_);
    com_B_.resize(3, frames_);
    for (int i = 0; i < frames_; ++i) {
      q.tail(nj) = joints_.col(i);
      dynamics::CalcForwardKinematics(model_, ws, q);
      com_B_.col(i) = dynamics::CalcCenterOfMassPosition(model_, ws);
    }
  }

  // Each frame's joints refitted to its detections with the root held near Q's (the flight's):
  // the frame-by-frame fit traded the root's turns against the joints; with the root now
  // physical, the joints follow the picture again.
  Eigen::MatrixXd RefitJoints(const Eigen::MatrixXd& Q, const RootPrior& prior) {
    Eigen::MatrixXd out = Q;
    std::vector<MarkerRay> rays;
    for (int i = 0; i < frames_; ++i) {
      const std::vector<int>& seen = by_frame_[size_t(i)];
      if (seen.size() < 3) continue;
      rays.clear();
      for (const int d : seen) {
        const Detection& det = detections_[size_t(d)];
        const vision::Camera& cam = views_.views[size_t(det.view)].camera;
        int n = 0;
        for (const int e : seen) n += detections_[size_t(e)].marker == det.marker;
        MarkerRay ray;
        ray.marker = det.marker;
        ray.origin_W = cam.CentreInWorld();
        ray.direction_W = cam.R_KW.transpose() * Eigen::Vector3d(det.xy.x(), det.xy.y(), 1.0);
        ray.weight = det.weight * std::sqrt(1.5 / n);
        rays.push_back(ray);
      }
      Eigen::VectorXd q = Q.col(i);
      ik_.SolveRays(rays, q, &prior);
      if (q.allFinite()) out.col(i) = q;
    }
    return out;
  }

  int frames() const { return frames_; }
  const Eigen::MatrixXd& Joints() const { return joints_; }
  double dt() const { return dt_; }
  int num_segments() const { return static_cast<int>(segment_samples_.size()); }
  int num_residuals() const { return 2 * int(detections_.size()) + 3 * (num_segments() - 1); }

  // The root's orientation at every frame: each segment turned from its first frame's orientation
  // by the one angular momentum; `mismatch` (if given) gets, per later segment, the turn from
  // where the segment before ended to where it starts (rad).
  std::vector<Eigen::Quaterniond> Turns(const FlightState& state,
                                        std::vector<Eigen::Vector3d>* mismatch = nullptr) const {
    std::vector<Eigen::Quaterniond> out(static_cast<size_t>(frames_));
    if (mismatch) mismatch->clear();
    for (int k = 0; k < num_segments(); ++k) {
      const std::vector<Eigen::Quaterniond> q = dynamics::SimulateFlightRotation(
          segment_samples_[size_t(k)], state.q_segments[size_t(k)], state.H_W);
      const int a = segment_first_[size_t(k)];
      for (size_t i = 0; i < q.size(); ++i) out[size_t(a) + i] = q[i];
      if (mismatch && k + 1 < num_segments()) {
        const Eigen::AngleAxisd turn(q.back().conjugate() * state.q_segments[size_t(k + 1)]);
        mismatch->push_back(turn.angle() * turn.axis());
      }
    }
    return out;
  }

  // The root configuration q at every frame for the flight `state` (the joints kept).
  Eigen::MatrixXd Configurations(const FlightState& state,
                                 std::vector<Eigen::Vector3d>* mismatch = nullptr) {
    const std::vector<Eigen::Quaterniond> q_WB = Turns(state, mismatch);
    const int nj = model_.num_joint_dofs();
    Eigen::MatrixXd Q(dynamics::kRootNq + nj, frames_);
    for (int i = 0; i < frames_; ++i) {
      const double t = i * dt_;
      const Eigen::Vector3d c = state.c0_W + state.v0_W * t + 0.5 * gravity_W_ * t * t;
      Eigen::VectorXd q(dynamics::kRootNq + nj);
      q.head<3>() = c - q_WB[size_t(i)] * com_B_.col(i);
      dynamics::SetRootQuaternion<double>(q_WB[size_t(i)], q);
      q.tail(nj) = joints_.col(i);
      Q.col(i) = q;
    }
    ShiftAcrossThePicture(Q);
    return Q;
  }

  // The segments' first orientations of a flight turned as one from state.q_WB0.
  void StartSegments(FlightState* state) const {
    const std::vector<Eigen::Quaterniond> q =
        dynamics::SimulateFlightRotation(samples_, state->q_WB0, state->H_W);
    state->q_segments.clear();
    for (int k = 0; k < num_segments(); ++k)
      state->q_segments.push_back(q[size_t(segment_first_[size_t(k)])]);
  }

  // One camera: each frame's root moved square to the camera's axis so that its keypoints'
  // projections match the detections' in the median — the picture fixes where the body is across
  // it better than a centre of mass on a parabola does, the centre of mass from a generic body's
  // segments being centimetres off the athlete's as the shape changes; the parabola keeps the
  // depth, which the picture cannot give.
  void ShiftAcrossThePicture(Eigen::MatrixXd& Q) {
    if (views_.views.size() != 1) return;
    const vision::Camera& cam = views_.views[0].camera;
    Eigen::Matrix3Xd p_WM;
    std::vector<double> dx, dy;
    for (int i = 0; i < frames_; ++i) {
      const std::vector<int>& seen = by_frame_[size_t(i)];
      if (seen.size() < 3) continue;
      for (int pass = 0; pass < 2; ++pass) {
        ik_.CalcMarkerPositions(Q.col(i), p_WM);
        dx.clear();
        dy.clear();
        double z = 0;
        for (const int d : seen) {
          const Detection& det = detections_[size_t(d)];
          const Eigen::Vector3d p = cam.R_KW * p_WM.col(det.marker) + cam.t_KW;
          if (!(p.z() > 1e-3)) continue;
          dx.push_back(det.xy.x() * p.z() - p.x());
          dy.push_back(det.xy.y() * p.z() - p.y());
          z += p.z();
        }
        if (dx.size() < 3) break;
        const Eigen::Vector3d shift_K(Median(dx), Median(dy), 0.0);
        Q.col(i).head<3>() += cam.R_KW.transpose() * shift_K;
      }
    }
  }

  // Every residual: the detections' (px) and the segments' continuity (rad × px per rad).
  void AllResiduals(const FlightState& state, double* residuals) {
    std::vector<Eigen::Vector3d> mismatch;
    Residuals(Configurations(state, &mismatch), residuals);
    double* r = residuals + 2 * detections_.size();
    for (const Eigen::Vector3d& m : mismatch)
      for (int c = 0; c < 3; ++c) *r++ = continuity_px_per_rad_ * m[c];
  }

  // Every detection of the flight with its marker's position for the configurations Q:
  // use(frame, detection index, detection, its camera, p_WM).
  template <typename Use>
  void ForEachDetection(const Eigen::MatrixXd& Q, Use&& use) {
    Eigen::Matrix3Xd p_WM;
    for (int i = 0; i < frames_; ++i) {
      if (by_frame_[size_t(i)].empty()) continue;
      ik_.CalcMarkerPositions(Q.col(i), p_WM);
      for (const int d : by_frame_[size_t(i)]) {
        const Detection& det = detections_[size_t(d)];
        use(i, d, det, views_.views[size_t(det.view)].camera, p_WM.col(det.marker));
      }
    }
  }

  // Each detection's reprojection error (px, a 2-vector; NaN behind the camera) for the
  // configurations Q, given to `use(detection index, error)`.
  template <typename Use>
  void ForEachError(const Eigen::MatrixXd& Q, Use&& use) {
    ForEachDetection(Q,
                     [&](int,
                         int d,
                         const Detection& det,
                         const vision::Camera& cam,
                         const Eigen::Vector3d& p_W) {
                       const Eigen::Vector3d p = cam.R_KW * p_W + cam.t_KW;
                       use(d,
                           p.z() > 1e-3
                               ? Eigen::Vector2d(FocalPx(cam) * (p.head<2>() / p.z() - det.xy))
                               : Eigen::Vector2d::Constant(kNaN));
                     });
  }

  // Robust reprojection residuals (px) of every detection for the configurations Q: weighted,
  // Huber's loss as the residual's square, a point behind the camera 1000 px off.
  void Residuals(const Eigen::MatrixXd& Q, double* residuals) {
    ForEachError(Q, [&](int d, Eigen::Vector2d e) {
      e = e.allFinite() ? Eigen::Vector2d(detections_[size_t(d)].weight * e)
                        : Eigen::Vector2d::Constant(1e3);
      const double n = e.norm();
      if (n > robust_px_) e *= std::sqrt(2 * robust_px_ * n - robust_px_ * robust_px_) / n;
      residuals[2 * d] = e.x();
      residuals[2 * d + 1] = e.y();
    });
  }

  // Per frame: each detection's marker and its distance from the detection's ray (m) for Q.
  std::vector<std::vector<std::pair<int, double>>> RayErrors(const Eigen::MatrixXd& Q) {
    std::vector<std::vector<std::pair<int, double>>> out(static_cast<size_t>(frames_));
    ForEachDetection(
        Q,
        [&](int i,
            int,
            const Detection& det,
            const vision::Camera& cam,
            const Eigen::Vector3d& p_W) {
          const Eigen::Vector3d dir =
              (cam.R_KW.transpose() * Eigen::Vector3d(det.xy.x(), det.xy.y(), 1.0)).normalized();
          const Eigen::Vector3d r = p_W - cam.CentreInWorld();
          out[size_t(i)].push_back({det.marker, (r - dir * dir.dot(r)).norm()});
        });
    return out;
  }

  // Plain reprojection errors (px) of every detection for Q.
  std::vector<double> Errors(const Eigen::MatrixXd& Q) {
    std::vector<double> out;
    ForEachError(Q, [&](int, const Eigen::Vector2d& e) {
      if (e.allFinite()) out.push_back(e.norm());
    });
    return out;
  }

  // The flight state that the frame-by-frame configurations Q0 suggest: the orientation at the
  // first frame, the median of the angular momentum each frame's rates give, the least-squares
  // parabola through the centres of mass.
  FlightState Initial(const Eigen::MatrixXd& Q0) const {
    std::vector<Eigen::Quaterniond> turns;
    for (int i = 0; i < frames_; ++i)
      turns.push_back(dynamics::GetRootQuaternion(Q0.col(i)).normalized());
    // H from the turns over 2, 4 and 8 frame intervals (the shorter follow the motion, the longer
    // average the fit's jitter), each the start of a fit of the turns; the best fit kept.
    FlightState s;
    double best = std::numeric_limits<double>::infinity();
    for (const int span : {1, 2, 4}) {
      std::vector<double> H[3];
      for (int i = span; i + span < frames_; ++i) {
        const Eigen::Quaterniond& a = turns[size_t(i - span)];
        const Eigen::Quaterniond& b = turns[size_t(i + span)];
        const Eigen::Quaterniond& m = turns[size_t(i)];
        // ω in the frame's root frame: the turn from the frame before to the frame after.
        const Eigen::AngleAxisd turn(m.conjugate() * b * (m.conjugate() * a).conjugate());
        const Eigen::Vector3d w_B = turn.angle() * turn.axis() / (2 * span * dt_);
        const size_t k = size_t(2 * i);
        const Eigen::Vector3d H_W =
            m * (samples_.I_Scm_B_inverse[k].inverse() * w_B + samples_.H_joints_Scm_B[k]);
        for (int r = 0; r < 3; ++r) H[r].push_back(H_W[r]);
      }
      if (H[0].empty()) continue;
      FlightState start;
      start.q_WB0 = turns[0];
      for (int r = 0; r < 3; ++r) start.H_W[r] = Median(H[r]);
      const double cost = FitTurns(samples_, turns, &start);
      if (cost < best) {
        best = cost;
        s = start;
      }
    }
    // c_i − ½ g t² = c0 + v0 t, least squares.
    Eigen::MatrixXd A(frames_, 2);
    Eigen::MatrixXd B(frames_, 3);
    for (int i = 0; i < frames_; ++i) {
      const double t = i * dt_;
      const Eigen::Quaterniond q = dynamics::GetRootQuaternion(Q0.col(i)).normalized();
      const Eigen::Vector3d c = Q0.col(i).head<3>() + q * com_B_.col(i);
      A.row(i) << 1.0, t;
      B.row(i) = (c - 0.5 * gravity_W_ * t * t).transpose();
    }
    const Eigen::MatrixXd x = A.colPivHouseholderQr().solve(B);
    s.c0_W = x.row(0).transpose();
    s.v0_W = x.row(1).transpose();
    StartSegments(&s);
    return s;
  }

 private:
  const ViewsToFit& views_;
  const dynamics::Model<double>& model_;
  InverseKinematics ik_;
  int first_ = 0;
  int frames_ = 0;
  double dt_ = 0.0;
  Eigen::MatrixXd joints_;
  Eigen::Matrix3Xd com_B_;
  Eigen::Vector3d gravity_W_ = Eigen::Vector3d::Zero();
  dynamics::JointMotionSamples samples_;
  std::vector<Detection> detections_;
  std::vector<std::vector<int>> by_frame_;
  double robust_px_ = 5.0;
  double continuity_px_per_rad_ = 0.0;
  std::vector<int> segment_first_;  // segment k: frames segment_first_[k] … segment_first_[k + 1]
  std::vector<dynamics::JointMotionSamples> segment_samples_;
};

// The flight's residuals as a function of x = [φ_0 … φ_{S−1}, H, c0, v0], segment k's first
// orientation being reference_k ⊗ exp(φ_k).
struct FlightCost {
  Flight* flight;
  std::vector<Eigen::Quaterniond> reference;
  FlightState State(const double* x) const {
    FlightState s;
    const size_t S = reference.size();
    for (size_t k = 0; k < S; ++k)
      s.q_segments.push_back(reference[k] * dynamics::QuaternionExp<double>(Eigen::Vector3d(
                                                x[3 * k], x[3 * k + 1], x[3 * k + 2])));
    s.q_WB0 = s.q_segments[0];
    const double* y = x + 3 * S;
    s.H_W = Eigen::Vector3d(y[0], y[1], y[2]);
    s.c0_W = Eigen::Vector3d(y[3], y[4], y[5]);
    s.v0_W = Eigen::Vector3d(y[6], y[7], y[8]);
    return s;
  }
  bool operator()(double const* const* parameters, double* residuals) const {
    flight->AllResiduals(State(parameters[0]), residuals);
    return true;
  }
};

struct Solved {
  FlightState state;
  double cost = kNaN;
  bool converged = false;
};

Solved Solve(Flight& flight, const FlightState& start, int max_iterations) {
  FlightCost functor{&flight, start.q_segments};
  const size_t S = start.q_segments.size();
  std::vector<double> x(3 * S + 9, 0.0);
  for (int r = 0; r < 3; ++r) {
    x[3 * S + r] = start.H_W[r];
    x[3 * S + 3 + r] = start.c0_W[r];
    x[3 * S + 6 + r] = start.v0_W[r];
  }
  auto* cost = new ceres::DynamicNumericDiffCostFunction<FlightCost>(new FlightCost(functor),
                                                                     ceres::TAKE_OWNERSHIP);
  cost->AddParameterBlock(static_cast<int>(x.size()));
  cost->SetNumResiduals(flight.num_residuals());
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  Solved out;
  out.state = functor.State(x.data());
  out.cost = summary.final_cost;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  return out;
}

// The picture's mirror image through the depth along `axis_W` (a unit vector from the camera to
// the athlete): the body reflected by M = I − 2 a aᵀ and its left and right exchanged (the root
// frame's y, lateral, reflected) — the same first picture when the body's left–right axis lies
// along the line of sight (a side camera's somersault; otherwise a start near it) — and the
// angular momentum, a pseudovector, becomes −M H: the twist turns the other way.
FlightState Mirror(const FlightState& s, const Eigen::Vector3d& axis_W) {
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - 2 * axis_W * axis_W.transpose();
  const Eigen::Matrix3d M_B = Eigen::Vector3d(1, -1, 1).asDiagonal();
  FlightState out = s;
  out.q_WB0 = Eigen::Quaterniond(Eigen::Matrix3d(M * s.q_WB0.toRotationMatrix() * M_B));
  for (Eigen::Quaterniond& q : out.q_segments)
    q = Eigen::Quaterniond(Eigen::Matrix3d(M * q.toRotationMatrix() * M_B));
  out.H_W = -M * s.H_W;
  return out;
}

}  // namespace

bool FlightPhysicsOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (!(gate_px > 0 && std::isfinite(gate_px))) return fail("gate_px must be finite and > 0");
  if (!(robust_px > 0 && std::isfinite(robust_px))) return fail("robust_px must be finite and > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (min_frames < 3) return fail("min_frames must be >= 3");
  if (rounds < 0) return fail("rounds must be >= 0");
  if (num_threads < 0) return fail("num_threads must be >= 0");
  if (!(root_prior >= 0 && std::isfinite(root_prior) && root_prior_m_per_rad >= 0 &&
        std::isfinite(root_prior_m_per_rad)))
    return fail("root_prior and root_prior_m_per_rad must be finite and >= 0");
  if (blend_frames < 0) return fail("blend_frames must be >= 0");
  if (!(ambiguous_ratio >= 1)) return fail("ambiguous_ratio must be >= 1");
  if (!(distinct_deg >= 0 && distinct_deg <= 180)) return fail("distinct_deg must be 0–180");
  if (!(worse_factor >= 1 && std::isfinite(worse_factor) && worse_px >= 0 &&
        std::isfinite(worse_px)))
    return fail("worse_factor must be finite and >= 1, worse_px finite and >= 0");
  if (!(segment_s > 0 && std::isfinite(segment_s))) return fail("segment_s must be finite and > 0");
  if (!(continuity_px_per_rad >= 0 && std::isfinite(continuity_px_per_rad)))
    return fail("continuity_px_per_rad must be finite and >= 0");
  return true;
}

std::string FlightPhysicsSummary::Report() const {
  std::string s = fmt::format(
      "flight physics: {} flights fitted as free flights, {} kept\n",
      flights.size(),
      std::count_if(
          flights.begin(), flights.end(), [](const FlightPhysicsFit& f) { return f.kept; }));
  for (const FlightPhysicsFit& f : flights) {
    s += fmt::format(
        "  frames {}–{}: {} detections, reprojection median {:.1f} → {:.1f} px, H = ({:.1f}, "
        "{:.1f}, {:.1f}) kg·m²/s",
        f.first_frame,
        f.last_frame,
        f.detections,
        f.median_before_px,
        f.median_after_px,
        f.H_Scm_W.x(),
        f.H_Scm_W.y(),
        f.H_Scm_W.z());
    if (std::isfinite(f.mirror_cost_ratio))
      s += fmt::format(", mirror image {:.2f}× the cost and up to {:.0f}° apart{}{}",
                       f.mirror_cost_ratio,
                       f.mirror_apart_deg,
                       f.mirror_chosen ? " (the mirror image chosen)" : "",
                       f.ambiguous ? ": twist direction not told" : "");
    if (!f.kept) s += "; not kept (worse than frame by frame)";
    s += "\n";
  }
  return s;
}

namespace {

// What every flight's fit reads.
struct FlightInputs {
  const ViewsToFit& views;
  const std::vector<int>& marker_of_point;
  const dynamics::Model<double>& model;
  const std::vector<ModelMarker>& markers;
  const std::vector<JointLimit>& limits;
  const InverseKinematicsOptions& ik_options;
  const FlightPhysicsOptions& options;
  const Motion& motion;
  int P = 0;  // keypoints
  int V = 0;  // cameras
  int F = 0;  // frames fitted
};

// One flight's outcome: fitted (its configurations and ray errors) or skipped (why).
struct FlightOutcome {
  std::optional<FlightPhysicsFit> fit;
  Eigen::MatrixXd Q;
  std::vector<std::vector<std::pair<int, double>>> ray_errors;  // per frame: (marker, m)
  std::string skipped;
};

// The detections of frames first..last within the gate of the frame-by-frame fit.
std::vector<Detection> GatedDetections(const FlightInputs& in, int first, int last) {
  InverseKinematics ik(in.model, in.markers, in.limits, in.ik_options);
  std::vector<Detection> detections;
  Eigen::Matrix3Xd p_WM;
  for (int k = first; k <= last; ++k) {
    if (!in.motion.fit[size_t(k)].valid) continue;
    ik.CalcMarkerPositions(in.motion.q.col(k), p_WM);
    for (int j = 0; j < in.P; ++j) {
      const int m = in.marker_of_point[size_t(j)];
      if (m < 0) continue;
      for (int v = 0; v < in.V; ++v) {
        const ViewKeypoints& view = in.views.views[size_t(v)];
        const double conf = view.confidence(j, k);
        const Eigen::Vector2d xy = view.xy.col(Eigen::Index(k) * in.P + j);
        if (!(conf > 0) || !xy.allFinite()) continue;
        const Eigen::Vector3d p = view.camera.R_KW * p_WM.col(m) + view.camera.t_KW;
        if (!(p.z() > 1e-3) ||
            !(FocalPx(view.camera) * (p.head<2>() / p.z() - xy).norm() <= in.options.gate_px))
          continue;
        detections.push_back({k - first, v, m, xy, std::sqrt(conf) * in.markers[size_t(m)].weight});
      }
    }
  }
  return detections;
}

// The flight solved from each start (the frame-by-frame fit's, and with one camera its mirror
// image through the depth), its joints refitted between rounds; the better kept, and with two
// starts how much better and how differently the other turns (`fit`'s mirror fields).
Solved SolveFromStarts(const FlightInputs& in,
                       Flight& flight,
                       const Eigen::MatrixXd& Q0,
                       FlightPhysicsFit* fit) {
  const FlightPhysicsOptions& options = in.options;
  const FlightState start = flight.Initial(Q0);
  std::vector<FlightState> starts = {start};
  if (in.V == 1) {
    const Eigen::Vector3d centre = in.views.views[0].camera.CentreInWorld();
    starts.push_back(Mirror(start, (start.c0_W - centre).normalized()));
  }
  const RootPrior prior{options.root_prior, options.root_prior_m_per_rad};
  std::vector<Solved> results;
  std::vector<Eigen::MatrixXd> joints;
  for (const FlightState& from : starts) {
    flight.SetJoints(Q0.bottomRows(Q0.rows() - dynamics::kRootNq));
    Solved solved = Solve(flight, from, options.max_iterations);
    for (int round = 0; round < options.rounds; ++round) {
      const Eigen::MatrixXd Q = flight.RefitJoints(flight.Configurations(solved.state), prior);
      flight.SetJoints(Q.bottomRows(Q.rows() - dynamics::kRootNq));
      solved = Solve(flight, solved.state, options.max_iterations);
    }
    results.push_back(solved);
    joints.push_back(flight.Joints());
  }
  size_t chosen = 0;
  if (results.size() == 2) {
    chosen = results[1].cost < results[0].cost ? 1 : 0;
    fit->mirror_chosen = chosen == 1;
    fit->mirror_cost_ratio = results[1 - chosen].cost / std::max(results[chosen].cost, 1e-12);
    // Ambiguous: two flights that turn differently (apart by more than options.distinct_deg
    // somewhere) fit alike. A flight without twist is its own mirror image: nothing to tell.
    flight.SetJoints(joints[0]);
    const std::vector<Eigen::Quaterniond> a = flight.Turns(results[0].state);
    flight.SetJoints(joints[1]);
    const std::vector<Eigen::Quaterniond> b = flight.Turns(results[1].state);
    for (size_t i = 0; i < a.size(); ++i)
      fit->mirror_apart_deg =
          std::max(fit->mirror_apart_deg,
                   Eigen::AngleAxisd(a[i].conjugate() * b[i]).angle() * 180 / std::numbers::pi);
    fit->ambiguous = fit->mirror_cost_ratio < options.ambiguous_ratio &&
                     fit->mirror_apart_deg > options.distinct_deg;
  }
  flight.SetJoints(joints[chosen]);
  return results[chosen];
}

// Frames first..last fitted as one free flight, or skipped with the reason.
FlightOutcome FitOneFlight(const FlightInputs& in, int first, int last) {
  const FlightPhysicsOptions& options = in.options;
  FlightOutcome out;
  if (first < 0 || last >= in.F) {
    out.skipped =
        fmt::format("frames {}–{}: outside the fitted frames (0–{}): left as fitted frame by frame",
                    first,
                    last,
                    in.F - 1);
    return out;
  }
  if (last - first + 1 < options.min_frames) {
    out.skipped =
        fmt::format("frames {}–{}: too short to fit as a free flight (fewer than {} frames)",
                    first,
                    last,
                    options.min_frames);
    return out;
  }
  const std::vector<Detection> detections = GatedDetections(in, first, last);
  if (int(detections.size()) < 6 * (last - first + 1) / 2) {
    out.skipped = fmt::format("frames {}–{}: {} detections, too few to fit as a free flight",
                              first,
                              last,
                              detections.size());
    return out;
  }
  const Motion& motion = in.motion;
  Flight flight(in.views,
                in.model,
                in.markers,
                in.limits,
                in.ik_options,
                motion,
                first,
                last,
                detections,
                options.robust_px,
                std::max(1, int(std::lround((last - first) / motion.rate_hz / options.segment_s))),
                options.continuity_px_per_rad);
  const Eigen::MatrixXd Q0 = motion.q.middleCols(first, last - first + 1);
  FlightPhysicsFit fit;
  fit.first_frame = first;
  fit.last_frame = last;
  fit.detections = static_cast<int>(detections.size());
  fit.mirror_cost_ratio = kNaN;
  const Solved best = SolveFromStarts(in, flight, Q0, &fit);
  const Eigen::MatrixXd Q = flight.Configurations(best.state);
  fit.median_before_px = Median(flight.Errors(Q0));
  fit.median_after_px = Median(flight.Errors(Q));
  // A free flight that explains the picture worse than the frame-by-frame fit by more than the
  // options allow is not kept: the joints it was given cannot fly that way.
  fit.kept = fit.median_after_px <= options.worse_factor * fit.median_before_px + options.worse_px;
  fit.H_Scm_W = best.state.H_W;
  fit.c0_W = best.state.c0_W;
  fit.v0_W = best.state.v0_W;
  fit.converged = best.converged;
  out.fit = fit;
  out.Q = Q;
  out.ray_errors = flight.RayErrors(Q);
  return out;
}

// The flight's roots into the motion (frames first..), the change blended out over a few frames
// of each contact on either side, within before_limit..after_limit (never into another flight).
void BlendIntoMotion(const Eigen::MatrixXd& Q,
                     int first,
                     int before_limit,
                     int after_limit,
                     int blend_frames,
                     Motion* motion) {
  const int last = first + int(Q.cols()) - 1;
  auto change_at = [&](int k, const Eigen::VectorXd& q_new) {
    const Eigen::VectorXd q_old = motion->q.col(k);
    Eigen::Matrix<double, 6, 1> d;
    d.head<3>() = q_new.head<3>() - q_old.head<3>();
    const Eigen::AngleAxisd turn(dynamics::GetRootQuaternion(q_old).normalized().conjugate() *
                                 dynamics::GetRootQuaternion(q_new).normalized());
    d.tail<3>() = turn.angle() * turn.axis();
    return d;
  };
  const Eigen::Matrix<double, 6, 1> d_first = change_at(first, Q.col(0));
  const Eigen::Matrix<double, 6, 1> d_last = change_at(last, Q.col(Q.cols() - 1));
  auto apply = [&](int k, const Eigen::Matrix<double, 6, 1>& d, double w) {
    Eigen::VectorXd q = motion->q.col(k);
    q.head<3>() += w * d.head<3>();
    dynamics::SetRootQuaternion<double>(
        dynamics::GetRootQuaternion(q).normalized() *
            dynamics::QuaternionExp<double>(Eigen::Vector3d(w * d.tail<3>())),
        q);
    motion->q.col(k) = q;
  };
  const int gap_before = (first - before_limit) / 2, gap_after = (after_limit - last) / 2;
  for (int j = 1; j <= std::min(blend_frames, gap_before); ++j)
    apply(first - j, d_first, 1.0 - double(j) / (blend_frames + 1));
  for (int j = 1; j <= std::min(blend_frames, gap_after); ++j)
    apply(last + j, d_last, 1.0 - double(j) / (blend_frames + 1));
  motion->q.middleCols(first, Q.cols()) = Q;
}

// The frames' fit quality as the fit to the views reports it: per marker the RMS distance from
// its detections' rays.
void RecordRayErrors(const std::vector<std::vector<std::pair<int, double>>>& ray_errors,
                     int first,
                     Motion* motion) {
  for (size_t i = 0; i < ray_errors.size(); ++i) {
    const int k = first + int(i);
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(motion->marker_error_m.rows());
    Eigen::VectorXi count = Eigen::VectorXi::Zero(sum.size());
    for (const auto& [m, d] : ray_errors[i]) {
      if (m >= sum.size()) continue;
      sum[m] += d * d;
      ++count[m];
    }
    if (count.sum() == 0) continue;
    FrameFit& frame_fit = motion->fit[size_t(k)];
    double total = 0;
    int seen = 0;
    frame_fit.max_m = 0;
    for (Eigen::Index m = 0; m < sum.size(); ++m) {
      motion->marker_error_m(m, k) = count[m] > 0 ? std::sqrt(sum[m] / count[m]) : kNaN;
      if (count[m] == 0) continue;
      total += sum[m] / count[m];
      ++seen;
      frame_fit.max_m = std::max(frame_fit.max_m, motion->marker_error_m(m, k));
    }
    frame_fit.rms_m = std::sqrt(total / seen);
  }
}

}  // namespace

FlightPhysicsSummary FitFlightsToPhysics(const ViewsToFit& views,
                                         const std::vector<int>& marker_of_point,
                                         const dynamics::Model<double>& model,
                                         const std::vector<ModelMarker>& markers,
                                         const std::vector<JointLimit>& limits,
                                         const InverseKinematicsOptions& ik_options,
                                         const std::vector<std::pair<int, int>>& given,
                                         const FlightPhysicsOptions& options,
                                         Motion* motion,
                                         const Progress& progress) {
  DemandValidOptions(options, "flight physics");
  // In time order, so that each flight's neighbours bound the blends into its contacts.
  std::vector<std::pair<int, int>> flights = given;
  std::sort(flights.begin(), flights.end());
  const FlightInputs in{views,
                        marker_of_point,
                        model,
                        markers,
                        limits,
                        ik_options,
                        options,
                        *motion,
                        static_cast<int>(views.names.size()),
                        static_cast<int>(views.views.size()),
                        std::min(motion->num_frames(), views.num_frames)};
  ACRO_DEMAND(static_cast<int>(marker_of_point.size()) == in.P);
  std::vector<FlightOutcome> outcomes(flights.size());
  int done = 0;
  std::atomic<bool> stop{false};
  std::mutex mutex;
  ParallelFor(
      static_cast<int>(flights.size()),
      options.num_threads,
      [&](int f) {
        outcomes[size_t(f)] = FitOneFlight(in, flights[size_t(f)].first, flights[size_t(f)].second);
        // One more flight done (fitted or left), told in order under the lock.
        std::lock_guard<std::mutex> lock(mutex);
        if (!progress.Report("flight physics", ++done, static_cast<int>(flights.size())))
          stop = true;
      },
      [&] { return !stop; });
  if (stop) throw Cancelled("flight physics: cancelled");

  FlightPhysicsSummary summary;
  for (size_t f = 0; f < flights.size(); ++f) {
    const FlightOutcome& o = outcomes[f];
    if (!o.fit) {
      summary.warnings.push_back(o.skipped);
      continue;
    }
    const auto [first, last] = flights[f];
    summary.flights.push_back(*o.fit);
    if (!o.fit->kept) {
      summary.warnings.push_back(fmt::format(
          "frames {}–{}: the free flight fits the picture worse ({:.1f} px against {:.1f} px frame "
          "by frame, median): kept as fitted frame by frame",
          first,
          last,
          o.fit->median_after_px,
          o.fit->median_before_px));
      continue;
    }
    const int before_limit = f > 0 ? flights[f - 1].second + 1 : 0;
    const int after_limit = f + 1 < flights.size() ? flights[f + 1].first - 1 : in.F - 1;
    BlendIntoMotion(o.Q, first, before_limit, after_limit, options.blend_frames, motion);
    RecordRayErrors(o.ray_errors, first, motion);
    if (o.fit->ambiguous)
      summary.warnings.push_back(fmt::format(
          "frames {}–{}: the picture does not tell which way the body twists (its mirror image "
          "through the depth, turning up to {:.0f}° apart, fits within {:.0f} %): the twist's "
          "direction is a guess",
          first,
          last,
          o.fit->mirror_apart_deg,
          100 * (o.fit->mirror_cost_ratio - 1)));
  }
  return summary;
}

}  // namespace acro::analysis
