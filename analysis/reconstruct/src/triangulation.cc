#include "acro/reconstruct/triangulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "acro/base/input_error.h"

namespace acro::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// At most this many views per point enter the consensus (2¹² subsets at worst).
constexpr int kMaxConsensusViews = 12;

// A camera as the triangulation uses it: the pose world → camera and the pixel scale, detections
// being turned into undistorted normalised coordinates once.
struct ViewGeometry {
  const vision::Camera* camera = nullptr;
  Eigen::Matrix<double, 3, 4> P;  // [R | t]
  double focal_px = 1.0;          // mean focal length: normalised error × this ≈ pixels
};

ViewGeometry GeometryOf(const vision::Camera& camera) {
  ViewGeometry g;
  g.camera = &camera;
  g.P.leftCols<3>() = camera.R_KW;
  g.P.col(3) = camera.t_KW;
  g.focal_px = 0.5 * (camera.K(0, 0) + camera.K(1, 1));
  return g;
}

Eigen::Vector2d Normalised(const vision::Camera& camera,
                           const Eigen::Vector2d& uv_px,
                           bool model_distortion = true) {
  const Eigen::Vector2d u = model_distortion ? camera.Undistort(uv_px) : uv_px;
  const double y = (u.y() - camera.K(1, 2)) / camera.K(1, 1);
  const double x = (u.x() - camera.K(0, 2) - camera.K(0, 1) * y) / camera.K(0, 0);
  return {x, y};
}

// One observation of a point: a view, its normalised coordinates and its weight (confidence).
struct Observation {
  const ViewGeometry* view = nullptr;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double weight = 1.0;
};

// Reprojection error (undistorted pixels) of X in one observation; infinity behind the camera.
double ErrorPx(const Observation& o, const Eigen::Vector3d& X) {
  const Eigen::Vector3d p = o.view->P.leftCols<3>() * X + o.view->P.col(3);
  if (!(p.z() > 1e-6)) return std::numeric_limits<double>::infinity();
  return o.view->focal_px * (p.head<2>() / p.z() - o.xy).norm();
}

// Weighted DLT: the null vector of the stacked rows w·f·(x P₃ − P₁), w·f·(y P₃ − P₂).
Eigen::Vector3d LinearTriangulation(const std::vector<const Observation*>& obs) {
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  for (const Observation* o : obs) {
    const auto& P = o->view->P;
    const double w = o->weight * o->view->focal_px;
    const Eigen::RowVector4d r1 = w * (o->xy.x() * P.row(2) - P.row(0));
    const Eigen::RowVector4d r2 = w * (o->xy.y() * P.row(2) - P.row(1));
    AtA += r1.transpose() * r1 + r2.transpose() * r2;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(AtA);
  const Eigen::Vector4d h = eig.eigenvectors().col(0);
  if (!(std::abs(h(3)) > 1e-12)) return Eigen::Vector3d::Constant(kNaN);
  return h.head<3>() / h(3);
}

// Gauss–Newton on Σ w (f (p_xy / p_z − x))², from X; a few steps suffice from the DLT.
// One observation's reprojection residual r (px, undistorted) at X and its Jacobian J = ∂r/∂X;
// false when X is not in front of the camera.
bool Linearize(const Observation& o,
               const Eigen::Vector3d& X,
               Eigen::Vector2d* r,
               Eigen::Matrix<double, 2, 3>* J) {
  const Eigen::Matrix3d R = o.view->P.leftCols<3>();
  const Eigen::Vector3d p = R * X + o.view->P.col(3);
  if (!(p.z() > 1e-6)) return false;
  const double f = o.view->focal_px;
  *r = f * (p.head<2>() / p.z() - o.xy);
  J->row(0) = f * (R.row(0) - (p.x() / p.z()) * R.row(2)) / p.z();
  J->row(1) = f * (R.row(1) - (p.y() / p.z()) * R.row(2)) / p.z();
  return true;
}

Eigen::Vector3d Refine(const std::vector<const Observation*>& obs, Eigen::Vector3d X) {
  Eigen::Vector2d r;
  Eigen::Matrix<double, 2, 3> J;
  for (int iteration = 0; iteration < 8; ++iteration) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const Observation* o : obs) {
      if (!Linearize(*o, X, &r, &J)) return Eigen::Vector3d::Constant(kNaN);
      H += o->weight * J.transpose() * J;
      g += o->weight * J.transpose() * r;
    }
    const Eigen::Vector3d step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    X += step;
    if (step.norm() < 1e-7) break;
  }
  return X;
}

// The standard error per coordinate (m) of X fitted to `obs`: σ² (JᵀWJ)⁻¹, σ² the weighted
// squared residual per degree of freedom (2n − 3: one with two views, a rough estimate that the
// median over a take evens out).
double Uncertainty(const std::vector<const Observation*>& obs, const Eigen::Vector3d& X) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double ssr = 0, weights = 0;
  Eigen::Vector2d r;
  Eigen::Matrix<double, 2, 3> J;
  for (const Observation* o : obs) {
    if (!Linearize(*o, X, &r, &J)) return kNaN;
    H += o->weight * J.transpose() * J;
    ssr += o->weight * r.squaredNorm();
    weights += o->weight;
  }
  const int dof = 2 * static_cast<int>(obs.size()) - 3;
  if (dof < 1 || !(weights > 0)) return kNaN;
  const Eigen::Matrix3d cov = (ssr / dof) * H.inverse();
  return std::sqrt(std::max(0.0, cov.trace()) / 3.0);
}

// Triangulates one point from its observations with a consensus over views, as Pose2Sim's
// triangulation decides it (its triangulation.py, triangulation_from_best_cameras): all views when
// their mean reprojection error is within the threshold, else the subset of one view fewer with the
// least mean error, and so on down to min_views views; here also no view of the subset beyond
// `max_view_error_factor` thresholds, so that one wild view does not hide in a mean. The subset's
// point is then refined on the weighted reprojection error. Fills `agreed` (per observation) and
// returns NaN when no subset agrees.
Eigen::Vector3d ConsensusPoint(const std::vector<Observation>& obs,
                               const TriangulationOptions& options,
                               std::vector<char>* agreed) {
  const int n = static_cast<int>(obs.size());
  agreed->assign(n, 0);
  if (n < options.min_views) return Eigen::Vector3d::Constant(kNaN);
  const double threshold = options.max_reprojection_px;
  const double view_limit = options.max_view_error_factor * threshold;
  const bool refine = options.refine;

  std::vector<int> subset(n);
  std::vector<const Observation*> chosen;
  for (int m = n; m >= options.min_views; --m) {
    // Every subset of m views (a bit mask with m bits), the least mean error kept.
    double best_mean = std::numeric_limits<double>::infinity();
    unsigned best_mask = 0;
    Eigen::Vector3d best_X = Eigen::Vector3d::Constant(kNaN);
    for (unsigned mask = 0; mask < (1u << n); ++mask) {
      if (__builtin_popcount(mask) != m) continue;
      chosen.clear();
      for (int i = 0; i < n; ++i)
        if (mask & (1u << i)) chosen.push_back(&obs[i]);
      const Eigen::Vector3d X = LinearTriangulation(chosen);
      if (!X.allFinite()) continue;
      double sum = 0, worst = 0;
      for (const Observation* o : chosen) {
        const double e = ErrorPx(*o, X);
        sum += e;
        worst = std::max(worst, e);
      }
      const double mean = sum / m;
      if (worst <= view_limit && mean < best_mean) {
        best_mean = mean;
        best_mask = mask;
        best_X = X;
      }
    }
    if (!(best_mean <= threshold)) continue;
    chosen.clear();
    for (int i = 0; i < n; ++i)
      if (best_mask & (1u << i)) chosen.push_back(&obs[i]);
    Eigen::Vector3d X = refine ? Refine(chosen, best_X) : best_X;
    if (!X.allFinite()) X = best_X;
    for (int i = 0; i < n; ++i) (*agreed)[i] = (best_mask >> i) & 1u;
    return X;
  }
  return Eigen::Vector3d::Constant(kNaN);
}

// The mirror name of `name` ("" when it has none).
std::string MirrorName(const std::string& name) {
  auto swap_prefix = [&](const std::string& from, const std::string& to, bool need_upper) {
    if (name.size() <= from.size() || name.compare(0, from.size(), from) != 0) return std::string();
    const char next = name[from.size()];
    if (need_upper &&
        !(std::isupper(static_cast<unsigned char>(next)) || next == ' ' || next == '_'))
      return std::string();
    return to + name.substr(from.size());
  };
  for (const auto& [from, to, upper] :
       std::vector<std::tuple<std::string, std::string, bool>>{{"left_", "right_", false},
                                                               {"right_", "left_", false},
                                                               {"Left", "Right", true},
                                                               {"Right", "Left", true},
                                                               {"L", "R", true},
                                                               {"R", "L", true}}) {
    const std::string m = swap_prefix(from, to, upper);
    if (!m.empty()) return m;
  }
  return {};
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  const size_t k =
      std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

}  // namespace

bool TriangulationOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(min_confidence >= 0 && min_confidence <= 1))
    return fail(fmt::format("minimum confidence {:g} is outside 0 … 1", min_confidence));
  if (!(max_reprojection_px > 0 && max_reprojection_px <= 1000))
    return fail(
        fmt::format("reprojection threshold {:g} px is outside (0, 1000]", max_reprojection_px));
  if (min_views < 2) return fail(fmt::format("{} views: a point needs at least 2", min_views));
  return true;
}

std::vector<std::pair<int, int>> LeftRightPairsOfNames(const std::vector<std::string>& names) {
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < static_cast<int>(names.size()); ++i) {
    const std::string& name = names[i];
    const bool left =
        name.rfind("left_", 0) == 0 || name.rfind("Left", 0) == 0 ||
        (name.size() > 1 && name[0] == 'L' &&
         (std::isupper(static_cast<unsigned char>(name[1])) || name[1] == ' ' || name[1] == '_'));
    if (!left) continue;
    const std::string mirror = MirrorName(name);
    for (int j = 0; j < static_cast<int>(names.size()); ++j)
      if (names[j] == mirror) pairs.emplace_back(i, j);
  }
  return pairs;
}

Eigen::Vector3d TriangulatePoint(const std::vector<const vision::Camera*>& cameras,
                                 const std::vector<Eigen::Vector2d>& pixels,
                                 const std::vector<double>& weights) {
  if (cameras.size() < 2 || pixels.size() != cameras.size() || weights.size() != cameras.size())
    return Eigen::Vector3d::Constant(kNaN);
  std::vector<ViewGeometry> geometry;
  geometry.reserve(cameras.size());
  for (const vision::Camera* c : cameras) geometry.push_back(GeometryOf(*c));
  std::vector<Observation> obs(cameras.size());
  std::vector<const Observation*> all;
  for (size_t i = 0; i < cameras.size(); ++i) {
    obs[i] = {&geometry[i], Normalised(*cameras[i], pixels[i]), weights[i]};
    all.push_back(&obs[i]);
  }
  const Eigen::Vector3d X = Refine(all, LinearTriangulation(all));
  for (const Observation& o : obs)
    if (!std::isfinite(ErrorPx(o, X))) return Eigen::Vector3d::Constant(kNaN);
  return X;
}

namespace {

// The detections of the chosen person of one camera in one frame, normalised; confidence 0 where
// absent or below the threshold.
struct ViewFrame {
  Eigen::Matrix2Xd xy;
  Eigen::VectorXd confidence;
  Eigen::Matrix2Xd pixels;  // as detected, for the reported error
};

ViewFrame PrepareView(const vision::Camera& camera,
                      const capture::DetectedPerson& person,
                      const TriangulationOptions& options) {
  const double min_confidence = options.min_confidence;
  const int n = static_cast<int>(person.cols());
  ViewFrame vf;
  vf.xy.setZero(2, n);
  vf.confidence.setZero(n);
  vf.pixels = person.topRows<2>();
  for (int j = 0; j < n; ++j) {
    const double c = person(2, j);
    if (!(c >= min_confidence) || !std::isfinite(person(0, j)) || !std::isfinite(person(1, j)) ||
        (person(0, j) == 0 && person(1, j) == 0))
      continue;
    vf.xy.col(j) = Normalised(camera, person.col(j).head<2>(), options.model_distortion);
    vf.confidence(j) = std::max(c, 1e-3);
  }
  return vf;
}

// Median pixel distance between a person's confident keypoints and the projection of 3D points
// (infinity when they share fewer than three).
double PersonDistance(const vision::Camera& camera,
                      const capture::DetectedPerson& person,
                      const std::vector<Eigen::Vector3d>& points,
                      double min_confidence) {
  std::vector<double> d;
  for (int j = 0; j < static_cast<int>(points.size()) && j < person.cols(); ++j) {
    if (!points[j].allFinite() || !(person(2, j) >= min_confidence)) continue;
    const auto uv = camera.Project(points[j]);
    if (uv) d.push_back((*uv - person.col(j).head<2>()).norm());
  }
  if (d.size() < 3) return std::numeric_limits<double>::infinity();
  return Percentile(d, 0.5);
}

}  // namespace

namespace {

// The views' checks: at least two, each camera valid and named once, one keypoint set.
void DemandTriangulableViews(const std::vector<CameraView>& views) {
  if (views.size() < 2)
    throw InputError("",
                     "detections",
                     fmt::format("{} camera{} with detections: triangulation needs at least 2",
                                 views.size(),
                                 views.size() == 1 ? "" : "s"));
  std::set<std::string> seen;
  for (const CameraView& v : views) {
    std::string why;
    if (!v.camera.IsValid(&why)) throw InputError("", "camera " + v.camera.name, why);
    if (!seen.insert(v.camera.name).second)
      throw InputError("", "detections", "two cameras named '" + v.camera.name + "'");
    if (v.detections.names != views[0].detections.names)
      throw InputError(v.detections.source,
                       "keypoints",
                       fmt::format("camera {} has {} keypoints ({}…), camera {} {}: the views must "
                                   "use one keypoint set",
                                   v.camera.name,
                                   v.detections.names.size(),
                                   v.detections.names.empty() ? "" : v.detections.names[0],
                                   views[0].camera.name,
                                   views[0].detections.names.size()));
  }
}

// TriangulateKeypoints frame by frame: the athlete chosen in each camera, each keypoint's
// consensus point, the left/right repairs, and what each camera contributed.
class Triangulator {
 public:
  Triangulator(const std::vector<CameraView>& views, const TriangulationOptions& options)
      : views_(views),
        options_(options),
        num_views_(static_cast<int>(views.size())),
        num_points_(static_cast<int>(views[0].detections.names.size())) {
    int num_frames = 0;
    for (const CameraView& v : views) num_frames = std::max(num_frames, v.detections.num_frames());
    result_.names = views[0].detections.names;
    result_.num_frames = num_frames;
    result_.positions.setConstant(3, static_cast<Eigen::Index>(num_frames) * num_points_, kNaN);
    result_.reprojection_px.setConstant(num_points_, num_frames, kNaN);
    result_.views.setZero(num_points_, num_frames);
    result_.uncertainty_m.setConstant(num_points_, num_frames, kNaN);
    result_.cameras.resize(num_views_);
    result_.observed.resize(num_views_);
    for (int v = 0; v < num_views_; ++v) {
      result_.cameras[v].name = views[v].camera.name;
      ViewKeypoints& seen_by = result_.observed[v];
      seen_by.camera = views[v].camera;
      seen_by.xy.setConstant(2, static_cast<Eigen::Index>(num_frames) * num_points_, kNaN);
      seen_by.confidence.setZero(num_points_, num_frames);
      seen_by.agreed.setConstant(num_points_, num_frames, false);
      if (views[v].detections.num_frames() < num_frames)
        result_.warnings.push_back(fmt::format(
            "camera {}: detections for {} frames, the longest view has {}: its last {} frame(s) "
            "are triangulated from the other cameras",
            views[v].camera.name,
            views[v].detections.num_frames(),
            num_frames,
            num_frames - views[v].detections.num_frames()));
    }
    for (const CameraView& v : views) geometry_.push_back(GeometryOf(v.camera));
    pairs_ = LeftRightPairsOfNames(result_.names);
    errors_.resize(num_views_);
    previous_.assign(num_points_, Eigen::Vector3d::Constant(kNaN));
  }

  int num_frames() const { return result_.num_frames; }

  void Frame(int k) {
    const bool recent = k - previous_frame_ <= 10;
    ChoosePeople(k, recent);
    X_.assign(num_points_, Eigen::Vector3d::Constant(kNaN));
    agreed_.assign(num_points_, {});
    view_of_.assign(num_points_, {});
    for (int j = 0; j < num_points_; ++j) Triangulate(j);
    if (!recent) ChooseAgainByPoints(k);
    if (options_.repair_left_right) RepairLeftRight();
    if (Record(k)) {
      previous_ = X_;
      previous_frame_ = k;
    }
  }

  Triangulation Finish() {
    for (int v = 0; v < num_views_; ++v) {
      CameraTriangulationStats& stats = result_.cameras[v];
      stats.median_reprojection_px = Percentile(errors_[v], 0.5);
      stats.p90_reprojection_px = Percentile(errors_[v], 0.9);
      if (stats.frames_with_person == 0)
        result_.warnings.push_back(fmt::format(
            "camera {}: nobody detected in any frame; the other cameras were used", stats.name));
      else if (stats.agreed == 0)
        result_.warnings.push_back(
            fmt::format("camera {}: none of its {} detections agrees with the other views (a wrong "
                        "calibration or detections of another video?); the other cameras were used",
                        stats.name,
                        stats.detections));
    }
    return std::move(result_);
  }

 private:
  // The athlete in each camera: the one nearest the last frame's points when a camera sees
  // several, else the most confident.
  void ChoosePeople(int k, bool recent) {
    chosen_.assign(num_views_, -1);
    frame_.assign(num_views_, ViewFrame{});
    for (int v = 0; v < num_views_; ++v) {
      const auto& people = views_[v].detections;
      if (k >= people.num_frames() || people.frames[k].empty()) continue;
      const auto& candidates = people.frames[k];
      int best = 0;
      if (candidates.size() > 1) {
        double best_score = std::numeric_limits<double>::infinity();
        for (int p = 0; p < static_cast<int>(candidates.size()); ++p) {
          double score;
          if (recent) {
            score =
                PersonDistance(views_[v].camera, candidates[p], previous_, options_.min_confidence);
          } else {
            score = 0;
            for (int j = 0; j < candidates[p].cols(); ++j)
              if (candidates[p](2, j) >= options_.min_confidence) score -= candidates[p](2, j);
          }
          if (score < best_score) {
            best_score = score;
            best = p;
          }
        }
      }
      chosen_[v] = best;
      frame_[v] = PrepareView(views_[v].camera, candidates[best], options_);
    }
  }

  // Keypoint j's consensus point over the views that hold it.
  void Triangulate(int j) {
    std::vector<Observation> obs;
    view_of_[j].clear();
    for (int v = 0; v < num_views_; ++v) {
      if (chosen_[v] < 0 || j >= frame_[v].confidence.size() || frame_[v].confidence(j) <= 0)
        continue;
      obs.push_back({&geometry_[v], frame_[v].xy.col(j), frame_[v].confidence(j)});
      view_of_[j].push_back(v);
    }
    // The consensus tries every subset of views: past kMaxConsensusViews, the most confident.
    if (static_cast<int>(obs.size()) > kMaxConsensusViews) {
      std::vector<int> order(obs.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
      std::stable_sort(
          order.begin(), order.end(), [&](int a, int b) { return obs[a].weight > obs[b].weight; });
      order.resize(kMaxConsensusViews);
      std::sort(order.begin(), order.end());
      std::vector<Observation> kept;
      std::vector<int> kept_views;
      for (int i : order) {
        kept.push_back(obs[i]);
        kept_views.push_back(view_of_[j][i]);
      }
      obs = std::move(kept);
      view_of_[j] = std::move(kept_views);
    }
    X_[j] = ConsensusPoint(obs, options_, &agreed_[j]);
  }

  // A camera that saw several people and had no earlier frame to go by: choose again by the
  // points the views agree on.
  void ChooseAgainByPoints(int k) {
    for (int v = 0; v < num_views_; ++v) {
      const auto& people = views_[v].detections;
      if (chosen_[v] < 0 || people.frames[k].size() < 2) continue;
      int best = chosen_[v];
      double best_score = std::numeric_limits<double>::infinity();
      for (int p = 0; p < static_cast<int>(people.frames[k].size()); ++p) {
        const double s =
            PersonDistance(views_[v].camera, people.frames[k][p], X_, options_.min_confidence);
        if (s < best_score) {
          best_score = s;
          best = p;
        }
      }
      if (best != chosen_[v]) {
        chosen_[v] = best;
        frame_[v] = PrepareView(views_[v].camera, people.frames[k][best], options_);
        for (int j = 0; j < num_points_; ++j) Triangulate(j);
      }
    }
  }

  // Left and right exchanged in one camera against what the others agree on.
  void RepairLeftRight() {
    for (int v = 0; v < num_views_; ++v) {
      if (chosen_[v] < 0) continue;
      bool changed = false;
      for (const auto& [a, b] : pairs_) {
        if (frame_[v].confidence(a) <= 0 || frame_[v].confidence(b) <= 0) continue;
        if (!X_[a].allFinite() || !X_[b].allFinite()) continue;
        const Observation oa{&geometry_[v], frame_[v].xy.col(a), 1.0};
        const Observation ob{&geometry_[v], frame_[v].xy.col(b), 1.0};
        const double same_a = ErrorPx(oa, X_[a]), same_b = ErrorPx(ob, X_[b]);
        const double swap_a = ErrorPx(oa, X_[b]), swap_b = ErrorPx(ob, X_[a]);
        const double threshold = options_.max_reprojection_px;
        if (std::max(same_a, same_b) > threshold && std::max(swap_a, swap_b) <= threshold &&
            swap_a + swap_b < 0.5 * (same_a + same_b)) {
          for (Eigen::Index r = 0; r < 2; ++r) {
            std::swap(frame_[v].xy(r, a), frame_[v].xy(r, b));
            std::swap(frame_[v].pixels(r, a), frame_[v].pixels(r, b));
          }
          std::swap(frame_[v].confidence(a), frame_[v].confidence(b));
          ++result_.cameras[v].left_right_repairs;
          changed = true;
        }
      }
      if (changed)
        for (const auto& [a, b] : pairs_) {
          Triangulate(a);
          Triangulate(b);
        }
    }
  }

  // The frame's points, what each view saw and whether it agreed, the reprojection errors and
  // uncertainties; whether any point was triangulated.
  bool Record(int k) {
    bool any = false;
    for (int j = 0; j < num_points_; ++j) {
      const int n_obs = static_cast<int>(view_of_[j].size());
      int n_agreed = 0;
      double weighted = 0, weights = 0;
      std::vector<Observation> used;
      for (int i = 0; i < n_obs; ++i) {
        const int v = view_of_[j][i];
        CameraTriangulationStats& stats = result_.cameras[v];
        ++stats.detections;
        ViewKeypoints& seen_by = result_.observed[v];
        seen_by.xy.col(static_cast<Eigen::Index>(k) * num_points_ + j) = frame_[v].xy.col(j);
        seen_by.confidence(j, k) = frame_[v].confidence(j);
        if (!X_[j].allFinite() || !agreed_[j][i]) {
          if (X_[j].allFinite()) ++stats.rejected;
          continue;
        }
        ++stats.agreed;
        ++n_agreed;
        seen_by.agreed(j, k) = true;
        used.push_back({&geometry_[v], frame_[v].xy.col(j), frame_[v].confidence(j)});
        const auto uv = views_[v].camera.Project(X_[j]);
        if (!uv) continue;
        const double e = (*uv - frame_[v].pixels.col(j)).norm();
        errors_[v].push_back(e);
        weighted += frame_[v].confidence(j) * e * e;
        weights += frame_[v].confidence(j);
      }
      if (!X_[j].allFinite()) continue;
      any = true;
      result_.positions.col(static_cast<Eigen::Index>(k) * num_points_ + j) = X_[j];
      result_.views(j, k) = n_agreed;
      result_.reprojection_px(j, k) = weights > 0 ? std::sqrt(weighted / weights) : kNaN;
      std::vector<const Observation*> pointers;
      for (const Observation& o : used) pointers.push_back(&o);
      result_.uncertainty_m(j, k) = Uncertainty(pointers, X_[j]);
    }
    for (int v = 0; v < num_views_; ++v)
      if (chosen_[v] >= 0) {
        ++result_.cameras[v].frames_with_person;
        if (views_[v].detections.frames[k].size() > 1)
          ++result_.cameras[v].frames_chosen_among_several;
      }
    return any;
  }

  const std::vector<CameraView>& views_;
  const TriangulationOptions& options_;
  const int num_views_;
  const int num_points_;
  Triangulation result_;
  std::vector<ViewGeometry> geometry_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::vector<double>> errors_;  // per camera, the agreeing detections' errors (px)
  std::vector<Eigen::Vector3d> previous_;    // the last frame's points with any
  int previous_frame_ = -1000000;
  // The frame's: the person chosen per camera, their detections, the points, who agreed.
  std::vector<int> chosen_;
  std::vector<ViewFrame> frame_;
  std::vector<Eigen::Vector3d> X_;
  std::vector<std::vector<char>> agreed_;
  std::vector<std::vector<int>> view_of_;
};

}  // namespace

Triangulation TriangulateKeypoints(const std::vector<CameraView>& views,
                                   const TriangulationOptions& options,
                                   const Progress& progress) {
  DemandValidOptions(options, "triangulation");
  DemandTriangulableViews(views);
  Triangulator triangulator(views, options);
  const int num_frames = triangulator.num_frames();
  for (int k = 0; k < num_frames; ++k) {
    progress.ReportOrThrow("triangulate", k, num_frames);
    triangulator.Frame(k);
  }
  progress.ReportOrThrow("triangulate", num_frames, num_frames);
  return triangulator.Finish();
}

double Triangulation::NoiseRmsM() const {
  std::vector<double> v;
  for (Eigen::Index i = 0; i < uncertainty_m.size(); ++i)
    if (std::isfinite(uncertainty_m(i))) v.push_back(uncertainty_m(i));
  return v.empty() ? 0.0 : Percentile(v, 0.5);
}

capture::Trial Triangulation::ToTrial(double rate_hz, const std::string& source) const {
  capture::Trial trial;
  trial.source.path = source;
  trial.source.format = "triangulated";
  trial.source.point_units = "m";
  trial.source.point_units_to_m = 1.0;
  trial.point_rate_hz = rate_hz;
  trial.first_frame = 1;
  trial.num_frames = num_frames;
  for (const std::string& name : names) {
    capture::PointInfo info;
    info.label = name;
    info.description = fmt::format("triangulated from {} cameras", cameras.size());
    info.unit = "m";
    trial.points.push_back(info);
  }
  trial.positions = positions;
  trial.residuals.setConstant(num_points(), num_frames, -1.0f);
  trial.camera_masks.setZero(num_points(), num_frames);
  for (int k = 0; k < num_frames; ++k)
    for (int j = 0; j < num_points(); ++j)
      if (views(j, k) > 0) {
        trial.residuals(j, k) = static_cast<float>(reprojection_px(j, k));
        trial.camera_masks(j, k) = static_cast<std::uint8_t>(std::min(views(j, k), 255));
      }
  return trial;
}

std::string Triangulation::BriefReport() const {
  long found = 0;
  for (int k = 0; k < num_frames; ++k)
    for (int j = 0; j < num_points(); ++j) found += views(j, k) > 0;
  const long total = static_cast<long>(num_frames) * num_points();
  std::string out = fmt::format(
      "triangulated {} of {} keypoint samples ({:.1f} %) from {} cameras; standard "
      "error {:.1f} mm per coordinate (median)\n",
      found,
      total,
      total > 0 ? 100.0 * found / total : 0.0,
      cameras.size(),
      1000 * NoiseRmsM());
  for (const CameraTriangulationStats& c : cameras)
    out += fmt::format(
        "  {}: person in {} frames, {} of {} detections agreed ({} outvoted), reprojection "
        "median {:.1f} px, 90th percentile {:.1f} px{}\n",
        c.name,
        c.frames_with_person,
        c.agreed,
        c.detections,
        c.rejected,
        c.median_reprojection_px,
        c.p90_reprojection_px,
        c.left_right_repairs > 0
            ? fmt::format(", {} left/right pairs put right", c.left_right_repairs)
            : "");
  for (const std::string& w : warnings) out += "  warning: " + w + "\n";
  return out;
}

}  // namespace acro::analysis
