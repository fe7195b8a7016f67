#include "acro/assess/execution.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "acro/assess/trial_analysis.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis {

bool ExecutionOptions::IsValid(std::string* why) const {
  auto ok = [](double v, double hi) { return std::isfinite(v) && v >= 0 && v <= hi; };
  if (!ok(angle_uncertainty_deg, 90) || !ok(elbow_uncertainty_deg, 90) ||
      !ok(position_uncertainty_m, 1) || !ok(time_uncertainty_s, 1) || !ok(takeoff_edge_s, 1) ||
      !ok(landing_edge_s, 1)) {
    if (why) *why = "execution: the uncertainties must be 0–90°, 0–1 m, 0–1 s and the edges 0–1 s";
    return false;
  }
  return true;
}

ExecutionOptions ExecutionOptions::WithNoise(double noise_rms_m) const {
  ExecutionOptions o = *this;
  if (!std::isfinite(noise_rms_m)) return o;
  const double beyond_mm = std::max(0.0, 1000.0 * noise_rms_m - 2.0);
  o.angle_uncertainty_deg += 0.4 * beyond_mm;
  o.elbow_uncertainty_deg += 1.5 * beyond_mm;
  o.position_uncertainty_m += 0.0015 * beyond_mm;
  o.time_uncertainty_s += 0.001 * beyond_mm;
  return o;
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

int Column(const Motion& m, const std::string& name) {
  const auto it = std::find(m.coordinate_names.begin(), m.coordinate_names.end(), name);
  return it == m.coordinate_names.end() ? -1 : static_cast<int>(it - m.coordinate_names.begin());
}

// The largest of `value(frame)` over `frames`, and where.
template <typename Value>
std::pair<double, int> Worst(const std::vector<int>& frames, const Value& value) {
  double worst = -std::numeric_limits<double>::infinity();
  int at = -1;
  for (int f : frames) {
    const double v = value(f);
    if (std::isfinite(v) && v > worst) {
      worst = v;
      at = f;
    }
  }
  return {worst, at};
}

// Which model points the recording saw, frame by frame. A point is watched by the markers within
// kWatchRadiusM of it in the model's reference pose (a joint centre's own keypoint, the skin
// markers around a joint). It is seen in a frame where one of them was recorded, not filled in (a
// keypoint that fewer than two cameras agreed on, a marker's gap), and the fitted model holds that
// marker within kAgreeM of where it was recorded: a leg the fit left elsewhere than its keypoints
// (a gate, a left/right it did not follow) is the fit's guess there, not a measurement. A point no
// marker watches, or a reconstruction without its markers, counts as seen.
class SeenPoints {
 public:
  static constexpr double kWatchRadiusM = 0.10;
  static constexpr double kAgreeM = 0.10;

  SeenPoints(const ReconstructionResult& r, const std::optional<Eigen::Vector3d>& camera_W)
      : r_(r), camera_W_(camera_W), num_markers_(static_cast<int>(r.markers.size())) {
    const dynamics::Model<double>& model = r.model;
    if (num_markers_ == 0 ||
        r.recorded.size() != Eigen::Index(r.motion.num_frames()) * num_markers_ ||
        r.marker_positions.cols() != r.recorded.size())
      return;
    dynamics::Workspace<double> ws(model);
    dynamics::CalcForwardKinematics(model, ws, dynamics::MakeNeutralConfiguration(model));
    watchers_.resize(static_cast<size_t>(model.num_points()));
    for (int p = 0; p < model.num_points(); ++p) {
      const Eigen::Vector3d at = World(ws, model.point(p).segment, model.point(p).p_BoP_B);
      for (int m = 0; m < num_markers_; ++m) {
        const ModelMarker& marker = r.markers[static_cast<size_t>(m)];
        if ((World(ws, marker.segment, marker.p_BoM_B) - at).norm() <= kWatchRadiusM)
          watchers_[static_cast<size_t>(p)].push_back(m);
      }
    }
  }

  static Eigen::Vector3d World(const dynamics::Workspace<double>& ws,
                               int segment,
                               const Eigen::Vector3d& p_B) {
    const auto& X = ws.X_WB[static_cast<size_t>(segment)];
    return Eigen::Vector3d(X.rotation() * p_B + X.translation());
  }

  /// Whether `point` is seen in `frame`, `ws` holding the model posed at that frame.
  bool Seen(int point, int frame, const dynamics::Workspace<double>& ws) const {
    if (watchers_.empty() || point < 0) return true;
    const std::vector<int>& w = watchers_[static_cast<size_t>(point)];
    if (w.empty()) return true;
    for (int m : w) {
      const Eigen::Index column = Eigen::Index(frame) * num_markers_ + m;
      if (!r_.recorded[column]) continue;
      const ModelMarker& marker = r_.markers[static_cast<size_t>(m)];
      const Eigen::Vector3d recorded = r_.marker_positions.col(column);
      Eigen::Vector3d off = World(ws, marker.segment, marker.p_BoM_B) - recorded;
      if (camera_W_) {  // one camera: across its ray only
        const Eigen::Vector3d ray = (recorded - *camera_W_).normalized();
        off -= off.dot(ray) * ray;
      }
      if (off.norm() <= kAgreeM) return true;
    }
    return false;
  }

  bool everything_seen() const { return watchers_.empty(); }

 private:
  const ReconstructionResult& r_;
  std::optional<Eigen::Vector3d> camera_W_;
  int num_markers_;
  std::vector<std::vector<int>> watchers_;  // per model point, the markers near it
};

// A quantity seen in fewer of the element's frames than this is not measured.
constexpr int kMinSeenFrames = 3;

}  // namespace

namespace {

// One element's measurements, fault by fault (MeasureExecution).
class ElementMeasures {
 public:
  ElementMeasures(const TrialAnalysis& a,
                  size_t jump,
                  const fig::ExecutionRules& rules,
                  const ExecutionOptions& options)
      : a_(a),
        j_(a.jumps[jump]),
        m_(a.reconstruction.motion),
        model_(a.reconstruction.model),
        rules_(rules),
        options_(options),
        seen_(a.reconstruction, options.single_camera_centre_W),
        ws_(model_) {
    // The element's own frames: the flight less its edges.
    for (int f = std::max(0, j_.flight.takeoff_frame);
         f <= std::min(m_.num_frames() - 1, j_.flight.landing_frame);
         ++f)
      if (m_.time_s[f] > j_.flight.takeoff_s + options.takeoff_edge_s &&
          m_.time_s[f] < j_.flight.landing_s - options.landing_edge_s)
        frames_.push_back(f);
  }

  std::vector<fig::MeasuredFault> Run() {
    if (frames_.empty()) return {};
    LimbsAndArms();
    LegsApart();
    Shape();
    Opening();
    TravelAndHeight();
    return std::move(out_);
  }

 private:
  const fig::FigSkill& skill() const { return j_.rotation.skill; }

  void Add(const char* fault,
           const char* quantity,
           double value,
           double uncertainty,
           int frame,
           int frames = 0,
           int frames_seen = 0) {
    const fig::FaultRule* rule = rules_.Find(fault);
    if (rule == nullptr || (!std::isfinite(value) && frames == 0)) return;
    fig::MeasuredFault f;
    f.fault = fault;
    f.quantity = quantity;
    f.unit = rule->unit;
    f.value = std::isfinite(value) ? value : std::numeric_limits<double>::quiet_NaN();
    f.uncertainty = uncertainty;
    if (!rule->steps.empty()) f.threshold = rule->steps.front().first;
    f.smaller_is_worse = rule->smaller_is_worse;
    f.frame = f.Measured() ? frame : -1;
    f.time_s = f.frame >= 0 && f.frame < m_.num_frames() ? m_.time_s[f.frame]
                                                         : std::numeric_limits<double>::quiet_NaN();
    f.reported = f.Measured() && rule->Exceeds(value, uncertainty);
    f.deduction = f.reported ? rule->DeductionFor(value) : 0.0;
    f.frames = frames;
    f.frames_seen = frames_seen;
    out_.push_back(std::move(f));
  }

  // The worst of `value` over `over` where every one of `points` was seen: not measured (NaN) when
  // they were seen in fewer than kMinSeenFrames of those frames (or, in a shorter span, in all).
  template <typename Value>
  void AddWorstSeen(const char* fault,
                    const char* quantity,
                    const std::vector<int>& over,
                    std::initializer_list<const char*> points,
                    double uncertainty,
                    const Value& value,
                    const std::function<bool()>& seen_by_the_camera = {}) {
    std::vector<int> ids;
    for (const char* p : points) ids.push_back(model_.FindPoint(p));
    std::vector<int> where;
    const bool one_camera = seen_by_the_camera && options_.single_camera_centre_W;
    for (int f : over) {
      if (!seen_.everything_seen() || one_camera) Pose(f);
      if (std::all_of(ids.begin(), ids.end(), [&](int p) { return seen_.Seen(p, f, ws_); }) &&
          (!one_camera || seen_by_the_camera()))
        where.push_back(f);
    }
    std::pair<double, int> worst{std::numeric_limits<double>::quiet_NaN(), -1};
    if (!over.empty() &&
        static_cast<int>(where.size()) >= std::min<int>(kMinSeenFrames, int(over.size()))) {
      worst = Worst(where, value);
      if (worst.second < 0) return;  // the quantity does not exist in this model
    }
    Add(fault,
        quantity,
        worst.first,
        uncertainty,
        worst.second,
        static_cast<int>(over.size()),
        static_cast<int>(where.size()));
  }

  // Mean of the two sides of a joint angle (deg, anatomical: `sign` makes flexion positive).
  std::function<double(int)> Both(const char* name, double sign) const {
    const int r = Column(m_, std::string("r_") + name), l = Column(m_, std::string("l_") + name);
    return [this, r, l, sign](int f) {
      if (r < 0 || l < 0) return std::numeric_limits<double>::quiet_NaN();
      return sign * 0.5 * (m_.q(r, f) + m_.q(l, f)) / kDeg;
    };
  }

  // A model point in W at the configuration last given to Pose (NaN-free: the point exists).
  Eigen::Vector3d At(int point) const {
    const auto& p = model_.point(point);
    const auto& X = ws_.X_WB[static_cast<size_t>(p.segment)];
    return Eigen::Vector3d(X.rotation() * p.p_BoP_B + X.translation());
  }
  void Pose(int frame) {
    const Eigen::VectorXd q = m_.q.col(frame);
    dynamics::CalcForwardKinematics(model_, ws_, q);
  }

  // One camera (ExecutionOptions::single_camera_centre_W), the model posed: the unit ray to `at`.
  Eigen::Vector3d Ray(const Eigen::Vector3d& at) const {
    return (at - *options_.single_camera_centre_W).normalized();
  }
  // Whether the angle between u and v shows in the picture: their plane faces the camera (its
  // normal within 60° of the ray), or they are nearly in line (within 10°: no plane to see).
  bool PlaneFacesCamera(const Eigen::Vector3d& u,
                        const Eigen::Vector3d& v,
                        const Eigen::Vector3d& at) const {
    const Eigen::Vector3d n = u.normalized().cross(v.normalized());
    if (n.norm() < std::sin(10.0 * kDeg)) return true;
    return std::abs(n.normalized().dot(Ray(at))) >= 0.5;
  }
  // The joint angle at b of a–b–c, for each of the named triplets, shows in the picture.
  std::function<bool()> AnglesFaceCamera(std::vector<std::array<const char*, 3>> triplets) const {
    return [this, triplets = std::move(triplets)] {
      for (const auto& t : triplets) {
        const int a = model_.FindPoint(t[0]), b = model_.FindPoint(t[1]),
                  c = model_.FindPoint(t[2]);
        if (a < 0 || b < 0 || c < 0) continue;
        if (!PlaneFacesCamera(At(a) - At(b), At(c) - At(b), At(b))) return false;
      }
      return true;
    };
  }

  // Legs and arms: bent knees (not a tuck's — unless the tuck is a close call with a pike, whose
  // bent knees a judge would see), bent elbows, arms lifted sideways.
  void LimbsAndArms() {
    const double ua = options_.angle_uncertainty_deg;
    if (skill().shape != fig::SkillShape::kTuck || j_.rotation.shape_alternative == "pike")
      AddWorstSeen("knees_bent",
                   "knee flexion",
                   frames_,
                   {"r_hip_jc", "r_knee_jc", "r_ankle_jc", "l_hip_jc", "l_knee_jc", "l_ankle_jc"},
                   ua,
                   Both("knee_flexion", 1.0),
                   AnglesFaceCamera({{"r_hip_jc", "r_knee_jc", "r_ankle_jc"},
                                     {"l_hip_jc", "l_knee_jc", "l_ankle_jc"}}));
    if (skill().shape != fig::SkillShape::kTuck)  // a tuck's hands hold the shins: elbows bent
      AddWorstSeen("arms_bent",
                   "elbow flexion",
                   frames_,
                   {"r_shoulder_jc",
                    "r_elbow_jc",
                    "r_wrist_jc",
                    "l_shoulder_jc",
                    "l_elbow_jc",
                    "l_wrist_jc"},
                   options_.elbow_uncertainty_deg,
                   Both("elbow_flexion", -1.0),
                   AnglesFaceCamera({{"r_shoulder_jc", "r_elbow_jc", "r_wrist_jc"},
                                     {"l_shoulder_jc", "l_elbow_jc", "l_wrist_jc"}}));
    ArmsOut();
  }

  // The arms away from a held position, in a straight somersault's middle half (a tuck's and a
  // pike's hands hold the legs; jumps swing the arms — the sample's in-bounce reaches 53°; the
  // take-off's arm swing and the landing's are not the element's): the angle between the upper
  // arm and the trunk, from the nearer of "by the sides" (0°) and "overhead" (180°) — arms out
  // sideways or forward at 45° read 45°, overhead 0°.
  void ArmsOut() {
    const int sh[2] = {model_.FindPoint("r_shoulder_jc"), model_.FindPoint("l_shoulder_jc")};
    const int el[2] = {model_.FindPoint("r_elbow_jc"), model_.FindPoint("l_elbow_jc")};
    const int neck = model_.FindPoint("neck_jc"), lumbar = model_.FindPoint("lumbar_jc");
    if (skill().shape != fig::SkillShape::kStraight || skill().quarter_somersaults <= 0 ||
        sh[0] < 0 || sh[1] < 0 || el[0] < 0 || el[1] < 0 || neck < 0 || lumbar < 0)
      return;
    std::vector<int> middle;
    for (int f : frames_)
      if (std::abs(m_.time_s[f] - 0.5 * (j_.flight.takeoff_s + j_.flight.landing_s)) <=
          0.25 * j_.time_of_flight_s())
        middle.push_back(f);
    AddWorstSeen(
        "arms_out",
        "arms away from the sides or overhead (middle half)",
        middle,
        {"r_shoulder_jc", "r_elbow_jc", "l_shoulder_jc", "l_elbow_jc", "neck_jc", "lumbar_jc"},
        options_.angle_uncertainty_deg,
        [&](int k) {
          Pose(k);
          const Eigen::Vector3d down = (At(lumbar) - At(neck)).normalized();
          double sum = 0;
          for (int s = 0; s < 2; ++s) {
            const double angle =
                std::acos(std::clamp((At(el[s]) - At(sh[s])).normalized().dot(down), -1.0, 1.0)) /
                kDeg;
            sum += std::min(angle, 180.0 - angle);
          }
          return 0.5 * sum;
        },
        [&] {
          const Eigen::Vector3d down = At(lumbar) - At(neck);
          return PlaneFacesCamera(At(el[0]) - At(sh[0]), down, At(sh[0])) &&
                 PlaneFacesCamera(At(el[1]) - At(sh[1]), down, At(sh[1]));
        });
  }

  // The legs' spread: the ankles' distance beyond the hips' (legs hanging parallel give 0), where
  // both ankles were seen — a leg the cameras lost in a tuck is the fit's guess, not a spread.
  void LegsApart() {
    const int ra = model_.FindPoint("r_ankle_jc"), la = model_.FindPoint("l_ankle_jc");
    const int rh = model_.FindPoint("r_hip_jc"), lh = model_.FindPoint("l_hip_jc");
    if (ra < 0 || la < 0 || rh < 0 || lh < 0) return;
    AddWorstSeen(
        "legs_apart",
        options_.single_camera_centre_W ? "ankles apart beyond the hips, across the camera's view"
                                        : "ankles apart beyond the hips",
        frames_,
        {"r_ankle_jc", "l_ankle_jc", "r_hip_jc", "l_hip_jc"},
        options_.position_uncertainty_m,
        [&](int k) {
          Pose(k);
          Eigen::Vector3d ankles = At(ra) - At(la), hips = At(rh) - At(lh);
          if (options_.single_camera_centre_W) {  // across the view only
            const Eigen::Vector3d ray = Ray(0.5 * (At(rh) + At(lh)));
            ankles -= ankles.dot(ray) * ray;
            hips -= hips.dot(ray) * ray;
          }
          return ankles.norm() - hips.norm();
        },
        [&] {  // the hips' axis, along which legs part, within 30° of the picture
          const Eigen::Vector3d hips = (At(rh) - At(lh)).normalized();
          return std::abs(hips.dot(Ray(0.5 * (At(rh) + At(lh))))) <= 0.5;
        });
  }

  // The shape: a straight body bent at the hips; a pike's or a tuck's trunk–thigh angle over its
  // hold (the angle the shape was counted from).
  void Shape() {
    const double ua = options_.angle_uncertainty_deg;
    if (skill().shape == fig::SkillShape::kStraight && skill().quarter_somersaults > 0)
      AddWorstSeen("body_bent",
                   "hip flexion",
                   frames_,
                   {"neck_jc", "r_hip_jc", "l_hip_jc", "r_knee_jc", "l_knee_jc"},
                   ua,
                   Both("hip_flexion", -1.0),
                   AnglesFaceCamera({{"neck_jc", "r_hip_jc", "r_knee_jc"},
                                     {"neck_jc", "l_hip_jc", "l_knee_jc"}}));
    if (skill().shape == fig::SkillShape::kStraight || j_.rotation.shape_hold_fraction <= 0) return;
    // Where the hold is most open: the frame whose trunk–thigh angle is largest below the closed
    // limit, for the studio to jump to.
    const auto hip = Both("hip_flexion", -1.0);
    int frame = -1;
    double widest = -1;
    for (int f : frames_) {
      const double angle = 180.0 - hip(f);
      if (angle <= 135.0 && angle > widest) {
        widest = angle;
        frame = f;
      }
    }
    Add(skill().shape == fig::SkillShape::kPike ? "pike_open" : "tuck_open",
        "trunk-thigh angle (median of the hold)",
        j_.rotation.shape_hip_angle_deg,
        ua,
        frame);
  }

  // The opening before landing: a somersault in a tuck or pike opens (trunk–thigh past 135°) at
  // the end of its longest closed hold, this long before the feet touch. Not the last closed
  // frame: athletes meet the bed with the hips bent again (the s2mLab athlete lands at 120–135°).
  void Opening() {
    if (skill().shape == fig::SkillShape::kStraight || skill().quarter_somersaults < 4) return;
    const auto hip = Both("hip_flexion", -1.0);
    int best_end = -1, best_length = 0, run = 0;
    for (int f = std::max(0, j_.flight.takeoff_frame);
         f <= std::min(m_.num_frames() - 1, j_.flight.landing_frame);
         ++f) {
      const bool closed = m_.time_s[f] < j_.flight.landing_s && 180.0 - hip(f) <= 135.0;
      run = closed ? run + 1 : 0;
      if (closed && run > best_length) {
        best_length = run;
        best_end = f;
      }
    }
    if (best_end < 0) return;
    const int opened = std::min(best_end + 1, m_.num_frames() - 1);
    Add("late_opening",
        "opening before landing",
        j_.flight.landing_s - m_.time_s[opened],
        options_.time_uncertainty_s,
        opened);
  }

  // Travel on the bed, and height lost against the element before.
  void TravelAndHeight() {
    Add("travel",
        "landing from take-off",
        j_.displacement_from_takeoff_m,
        options_.position_uncertainty_m,
        j_.flight.landing_frame);
    const size_t jump = static_cast<size_t>(&j_ - a_.jumps.data());
    for (size_t k = jump; k-- > 0;) {
      if (a_.jumps[k].partial()) continue;
      Add("height_loss",
          "apex below the element before",
          a_.jumps[k].apex_m() - j_.apex_m(),
          options_.position_uncertainty_m,
          frames_[frames_.size() / 2]);
      break;
    }
  }

  const TrialAnalysis& a_;
  const JumpMetrics& j_;
  const Motion& m_;
  const dynamics::Model<double>& model_;
  const fig::ExecutionRules& rules_;
  const ExecutionOptions& options_;
  const SeenPoints seen_;
  dynamics::Workspace<double> ws_;
  std::vector<int> frames_;
  std::vector<fig::MeasuredFault> out_;
};

}  // namespace

std::vector<fig::MeasuredFault> MeasureExecution(const TrialAnalysis& a,
                                                 size_t jump,
                                                 const fig::ExecutionRules& rules,
                                                 const ExecutionOptions& options) {
  if (jump >= a.jumps.size() || a.jumps[jump].partial()) return {};
  return ElementMeasures(a, jump, rules, options).Run();
}

}  // namespace acro::analysis
