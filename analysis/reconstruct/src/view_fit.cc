#include "acro/reconstruct/view_fit.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/base/parallel.h"
#include "acro/dynamics/configuration.h"
#include "acro/reconstruct/butterworth.h"

#include "view_residuals.h"

namespace acro::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using view_residuals::FocalPx;
using view_residuals::Median;

// One camera's detections of one point in one frame, ready for the fit.
struct Seen {
  int view = 0;
  int marker = 0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();   // as fitted (filtered)
  Eigen::Vector2d raw = Eigen::Vector2d::Zero();  // as detected, for the reported error
  double confidence = 0.0;
  bool agreed = false;
};

// Reprojection error (px, normalised coordinates × focal) of p_W in view v; NaN behind it.
double ErrorPx(const vision::Camera& c, const Eigen::Vector3d& p_W, const Eigen::Vector2d& xy) {
  const Eigen::Vector3d p = c.R_KW * p_W + c.t_KW;
  if (!(p.z() > 1e-6)) return kNaN;
  return FocalPx(c) * (p.head<2>() / p.z() - xy).norm();
}

}  // namespace

ViewsToFit MakeViewsToFit(const Triangulation& triangulation,
                          const Eigen::Matrix3d& R_trial_world) {
  ViewsToFit out;
  out.names = triangulation.names;
  out.num_frames = triangulation.num_frames;
  out.views = triangulation.observed;
  for (ViewKeypoints& v : out.views) v.camera.R_KW = v.camera.R_KW * R_trial_world.transpose();
  return out;
}

bool ViewFitOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (!(gate_px > 0 && std::isfinite(gate_px))) return fail("gate_px must be finite and > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (num_threads < 0) return fail("num_threads must be >= 0");
  return true;
}

std::string ViewFitSummary::Report() const {
  std::string s = fmt::format(
      "fit to the views: {} frames, {} detections ({} that no triangulated point had, {} beyond "
      "the gate left out), reprojection median {:.1f} px from the triangulated fit → {:.1f} px\n",
      frames,
      detections_used,
      detections_added,
      detections_gated,
      median_before_px,
      median_after_px);
  for (const ViewFitCamera& c : cameras)
    s += fmt::format("  {}: {} detections, {} left out, median {:.1f} → {:.1f} px\n",
                     c.name,
                     c.used,
                     c.gated,
                     c.median_before_px,
                     c.median_after_px);
  return s;
}

namespace {

// What every step of the fit to the views reads.
struct ViewFitInputs {
  const ViewsToFit& views;
  const std::vector<int>& marker_of_point;
  const dynamics::Model<double>& model;
  const std::vector<ModelMarker>& markers;
  const std::vector<JointLimit>& limits;
  InverseKinematicsOptions fit_options;
  int P = 0, V = 0, F = 0;
  std::vector<Eigen::Vector3d> centre;  // per camera, in W
};

// Each view's detections within the gate of each frame's warm start (a wrong one is left out
// before the filter could spread it over its neighbours), counted per camera in `summary`.
std::vector<Eigen::Matrix2Xd> GatedTracks(const ViewFitInputs& in,
                                          const InverseKinematicsOptions& ik_options,
                                          const Motion& motion,
                                          double gate_px,
                                          ViewFitSummary* summary) {
  std::vector<Eigen::Matrix2Xd> xy(static_cast<size_t>(in.V));
  for (int v = 0; v < in.V; ++v) xy[size_t(v)] = in.views.views[size_t(v)].xy;
  InverseKinematics ik(in.model, in.markers, in.limits, ik_options);
  Eigen::Matrix3Xd p_WM;
  for (int k = 0; k < in.F; ++k) {
    ik.CalcMarkerPositions(motion.q.col(k), p_WM);
    for (int j = 0; j < in.P; ++j) {
      const int m = in.marker_of_point[size_t(j)];
      for (int v = 0; v < in.V; ++v) {
        auto s = xy[size_t(v)].col(Eigen::Index(k) * in.P + j);
        if (!s.allFinite()) continue;
        if (m < 0 || !motion.fit[size_t(k)].valid ||
            !(ErrorPx(in.views.views[size_t(v)].camera, p_WM.col(m), s) <= gate_px)) {
          if (m >= 0 && motion.fit[size_t(k)].valid) ++summary->cameras[size_t(v)].gated;
          s.setConstant(kNaN);
        }
      }
    }
  }
  return xy;
}

// Each view's tracks low-passed as the triangulated points were.
void FilterTracks(const ButterworthFilter& filter,
                  int P,
                  int F,
                  std::vector<Eigen::Matrix2Xd>* xy) {
  Eigen::VectorXd track(F);
  for (Eigen::Matrix2Xd& view : *xy)
    for (int j = 0; j < P; ++j)
      for (int r = 0; r < 2; ++r) {
        for (int k = 0; k < F; ++k) track[k] = view(r, Eigen::Index(k) * P + j);
        FilterWithGaps(filter, track);
        for (int k = 0; k < F; ++k) view(r, Eigen::Index(k) * P + j) = track[k];
      }
}

// The rays of a frame's detections (grouped by marker). Weights: per view as pixels (the ray
// distance × f/z, relative to the point's views' mean), by the confidence, and by √(3 / 2n) so
// that n rays weigh as one 3D point.
void WeightedRays(const ViewFitInputs& in,
                  const std::vector<Seen>& seen,
                  const Eigen::Matrix3Xd& p_WM,
                  std::vector<MarkerRay>* rays) {
  rays->clear();
  for (size_t a = 0; a < seen.size();) {
    size_t b = a;
    while (b < seen.size() && seen[b].marker == seen[a].marker) ++b;
    const int n = static_cast<int>(b - a);
    double mean_scale = 0, mean_conf = 0;
    std::vector<double> scale(static_cast<size_t>(n));
    for (size_t i = a; i < b; ++i) {
      const vision::Camera& cam = in.views.views[size_t(seen[i].view)].camera;
      const double z = (cam.R_KW * p_WM.col(seen[i].marker) + cam.t_KW).z();
      scale[i - a] = FocalPx(cam) / z;
      mean_scale += scale[i - a] / n;
      mean_conf += seen[i].confidence / n;
    }
    for (size_t i = a; i < b; ++i) {
      const vision::Camera& cam = in.views.views[size_t(seen[i].view)].camera;
      MarkerRay ray;
      ray.marker = seen[i].marker;
      ray.origin_W = in.centre[size_t(seen[i].view)];
      ray.direction_W = cam.R_KW.transpose() * Eigen::Vector3d(seen[i].xy.x(), seen[i].xy.y(), 1.0);
      ray.weight = in.markers[size_t(ray.marker)].weight * std::sqrt(1.5 / n) *
                   std::sqrt(seen[i].confidence / mean_conf) * scale[i - a] / mean_scale;
      rays->push_back(ray);
    }
    a = b;
  }
}

// What one chunk of frames gave.
struct ChunkFit {
  std::vector<std::vector<double>> before;  // per camera, the warm start's errors (px)
  std::vector<int> used;                    // per camera, detections fitted
  int added = 0, frames = 0;
};

// Frames first..last−1 fitted to the views, each from its frame-by-frame pose: `fitted`'s column
// and the detections used per frame (untouched where not fitted), the iterations into `motion`.
ChunkFit FitChunk(const ViewFitInputs& in,
                  const std::vector<Eigen::Matrix2Xd>& xy,
                  int first,
                  int last,
                  Motion* motion,
                  Eigen::MatrixXd* fitted,
                  std::vector<std::vector<Seen>>* used_by_frame) {
  InverseKinematics ik(in.model, in.markers, in.limits, in.fit_options);
  ChunkFit out;
  out.before.resize(size_t(in.V));
  out.used.assign(size_t(in.V), 0);
  Eigen::Matrix3Xd p_WM;
  std::vector<Seen> seen;
  std::vector<MarkerRay> rays;
  for (int k = first; k < last; ++k) {
    if (!motion->fit[size_t(k)].valid) continue;
    Eigen::VectorXd q = motion->q.col(k);
    ik.CalcMarkerPositions(q, p_WM);
    seen.clear();
    for (int j = 0; j < in.P; ++j) {
      const int m = in.marker_of_point[size_t(j)];
      if (m < 0) continue;
      for (int v = 0; v < in.V; ++v) {
        const ViewKeypoints& view = in.views.views[size_t(v)];
        const double conf = view.confidence(j, k);
        const Eigen::Vector2d s = xy[size_t(v)].col(Eigen::Index(k) * in.P + j);
        if (!(conf > 0) || !s.allFinite()) continue;
        seen.push_back({v, m, s, view.xy.col(Eigen::Index(k) * in.P + j), conf, view.agreed(j, k)});
      }
    }
    if (seen.size() < 3) continue;
    WeightedRays(in, seen, p_WM, &rays);
    const IkFrameResult r = ik.SolveRays(rays, q);
    if (r.num_markers < 3 || !q.allFinite()) continue;  // not fitted: the frame as it was
    for (const Seen& s : seen) {
      const vision::Camera& cam = in.views.views[size_t(s.view)].camera;
      const double e = ErrorPx(cam, p_WM.col(s.marker), s.raw);
      if (std::isfinite(e)) out.before[size_t(s.view)].push_back(e);
      ++out.used[size_t(s.view)];
      out.added += s.agreed ? 0 : 1;
    }
    fitted->col(k) = q;
    (*used_by_frame)[size_t(k)] = seen;
    motion->fit[size_t(k)].iterations += r.iterations;
    ++out.frames;
  }
  return out;
}

// The corrections to the fit to the points, per frame the root's displacement, its rotation
// vector and the joint angles' changes (NaN where not fitted).
Eigen::MatrixXd Corrections(const Motion& motion, const Eigen::MatrixXd& fitted, int n, int F) {
  Eigen::MatrixXd corrections = Eigen::MatrixXd::Constant(F, 6 + n, kNaN);
  for (int k = 0; k < F; ++k) {
    if (!std::isfinite(fitted(0, k))) continue;
    const Eigen::VectorXd q0 = motion.q.col(k), q1 = fitted.col(k);
    corrections.block(k, 0, 1, 3) = (q1.head<3>() - q0.head<3>()).transpose();
    const Eigen::AngleAxisd turn(dynamics::GetRootQuaternion(q0).normalized().conjugate() *
                                 dynamics::GetRootQuaternion(q1).normalized());
    corrections.block(k, 3, 1, 3) = (turn.angle() * turn.axis()).transpose();
    corrections.block(k, 6, 1, n) = (q1.tail(n) - q0.tail(n)).transpose();
  }
  return corrections;
}

// Frame k's fit residual: per marker the RMS distance from the rays it was fitted to, into the
// motion; each detection's reprojection error (px) into `after`.
void RecordResidual(const ViewFitInputs& in,
                    const std::vector<Seen>& used,
                    const Eigen::Matrix3Xd& p_WM,
                    int k,
                    Motion* motion,
                    std::vector<std::vector<double>>* after) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(Eigen::Index(in.markers.size()));
  Eigen::VectorXi count = Eigen::VectorXi::Zero(Eigen::Index(in.markers.size()));
  for (const Seen& s : used) {
    const vision::Camera& cam = in.views.views[size_t(s.view)].camera;
    const double e = ErrorPx(cam, p_WM.col(s.marker), s.raw);
    if (std::isfinite(e)) (*after)[size_t(s.view)].push_back(e);
    const Eigen::Vector3d d =
        (cam.R_KW.transpose() * Eigen::Vector3d(s.xy.x(), s.xy.y(), 1.0)).normalized();
    const Eigen::Vector3d r = p_WM.col(s.marker) - in.centre[size_t(s.view)];
    sum[s.marker] += (r - d * d.dot(r)).squaredNorm();
    ++count[s.marker];
  }
  FrameFit& fit = motion->fit[size_t(k)];
  double total = 0;
  int markers_seen = 0;
  fit.max_m = 0;
  for (Eigen::Index m = 0; m < sum.size(); ++m) {
    const double e = count[m] > 0 ? std::sqrt(sum[m] / count[m]) : kNaN;
    motion->marker_error_m(m, k) = e;
    if (count[m] == 0) continue;
    total += e * e;
    ++markers_seen;
    fit.max_m = std::max(fit.max_m, e);
  }
  fit.rms_m = std::sqrt(total / std::max(1, markers_seen));
}

}  // namespace

ViewFitSummary FitModelToViews(const ViewsToFit& views,
                               const std::vector<int>& marker_of_point,
                               const dynamics::Model<double>& model,
                               const std::vector<ModelMarker>& markers,
                               const std::vector<JointLimit>& limits,
                               const InverseKinematicsOptions& ik_options,
                               double cutoff_hz,
                               int filter_order,
                               double rate_hz,
                               const ViewFitOptions& options,
                               Motion* motion,
                               const Progress& progress) {
  DemandValidOptions(options, "fit to the views");
  ViewFitInputs in{views, marker_of_point, model, markers, limits, ik_options, 0, 0, 0, {}};
  in.fit_options.max_iterations = options.max_iterations;
  in.P = static_cast<int>(views.names.size());
  in.V = static_cast<int>(views.views.size());
  in.F = std::min(motion->num_frames(), views.num_frames);
  ACRO_DEMAND(static_cast<int>(marker_of_point.size()) == in.P);
  for (int v = 0; v < in.V; ++v) in.centre.push_back(views.views[size_t(v)].camera.CentreInWorld());
  const int V = in.V, F = in.F;

  ViewFitSummary summary;
  summary.cameras.resize(static_cast<size_t>(V));
  for (int v = 0; v < V; ++v) summary.cameras[size_t(v)].name = views.views[size_t(v)].camera.name;
  std::vector<Eigen::Matrix2Xd> xy =
      GatedTracks(in, ik_options, *motion, options.gate_px, &summary);
  const bool filter = options.filter && cutoff_hz > 0 && cutoff_hz < 0.5 * rate_hz;
  if (filter) FilterTracks(ButterworthFilter(filter_order, cutoff_hz, rate_hz), in.P, F, &xy);

  // Frames in chunks, one InverseKinematics per chunk.
  const int chunk_frames = 50;
  const int chunks = (F + chunk_frames - 1) / chunk_frames;
  std::mutex mutex;
  std::vector<std::vector<double>> before(static_cast<size_t>(V)), after(static_cast<size_t>(V));
  // Each frame's fitted configuration (NaN: not fitted) and the detections it used.
  Eigen::MatrixXd fitted = Eigen::MatrixXd::Constant(motion->nq(), F, kNaN);
  std::vector<std::vector<Seen>> used_by_frame(static_cast<size_t>(F));
  std::atomic<int> done{0};
  std::atomic<bool> stop{false};
  ParallelFor(
      chunks,
      WorkerThreads(options.num_threads),
      [&](int c) {
        const int first = c * chunk_frames, last = std::min(F, first + chunk_frames);
        const ChunkFit chunk = FitChunk(in, xy, first, last, motion, &fitted, &used_by_frame);
        std::lock_guard<std::mutex> lock(mutex);
        for (int v = 0; v < V; ++v) {
          before[size_t(v)].insert(before[size_t(v)].end(),
                                   chunk.before[size_t(v)].begin(),
                                   chunk.before[size_t(v)].end());
          summary.cameras[size_t(v)].used += chunk.used[size_t(v)];
        }
        summary.frames += chunk.frames;
        summary.detections_added += chunk.added;
        done += last - first;
        if (!progress.Report("fit to the views", done, F)) stop = true;
      },
      [&] { return !stop; });
  if (stop) throw Cancelled("fit to the views: cancelled");

  // The corrections to the fit to the points, low-passed as the tracks were, into the motion.
  const int n = model.num_joint_dofs();
  Eigen::MatrixXd corrections = Corrections(*motion, fitted, n, F);
  if (filter)
    FilterColumnsWithGaps(ButterworthFilter(filter_order, cutoff_hz, rate_hz), corrections);
  InverseKinematics ik(model, markers, limits, in.fit_options);
  Eigen::Matrix3Xd p_WM;
  for (int k = 0; k < F; ++k) {
    if (!corrections.row(k).allFinite()) continue;
    Eigen::VectorXd q = motion->q.col(k);
    q.head<3>() += corrections.block(k, 0, 1, 3).transpose();
    const Eigen::Vector3d phi = corrections.block(k, 3, 1, 3).transpose();
    dynamics::SetRootQuaternion<double>(
        dynamics::GetRootQuaternion(q).normalized() * dynamics::QuaternionExp<double>(phi), q);
    q.tail(n) += corrections.block(k, 6, 1, n).transpose();
    motion->q.col(k) = q;
    ik.CalcMarkerPositions(q, p_WM);
    RecordResidual(in, used_by_frame[size_t(k)], p_WM, k, motion, &after);
  }
  std::vector<double> all_before, all_after;
  for (int v = 0; v < V; ++v) {
    ViewFitCamera& c = summary.cameras[size_t(v)];
    c.median_before_px = Median(before[size_t(v)]);
    c.median_after_px = Median(after[size_t(v)]);
    summary.detections_used += c.used;
    summary.detections_gated += c.gated;
    all_before.insert(all_before.end(), before[size_t(v)].begin(), before[size_t(v)].end());
    all_after.insert(all_after.end(), after[size_t(v)].begin(), after[size_t(v)].end());
  }
  summary.median_before_px = Median(all_before);
  summary.median_after_px = Median(all_after);
  return summary;
}

}  // namespace acro::analysis
