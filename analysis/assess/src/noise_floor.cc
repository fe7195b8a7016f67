#include "acro/assess/noise_floor.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include <Eigen/Dense>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/reconstruct/butterworth.h"
#include "acro/reconstruct/inverse_kinematics.h"

namespace acro::analysis {
namespace {

// The frames [first, first + count) of a motion.
Motion Slice(const Motion& motion, int first, int count) {
  Motion out;
  out.coordinate_names = motion.coordinate_names;
  out.marker_names = motion.marker_names;
  out.rate_hz = motion.rate_hz;
  out.time_s = motion.time_s.segment(first, count);
  out.q = motion.q.middleCols(first, count);
  return out;
}

// The motion made smooth, so that the floor measures the noise and not the motion's own glitches
// (a fit that jumps for a frame or two, a swap): per coordinate a running median of 7 frames, then
// the trial's low-pass; the root quaternion renormalised.
void Smooth(Motion& motion, const ReconstructionSummary& summary) {
  const int F = motion.num_frames();
  const int h = 3;
  if (F < 2 * h + 1) return;
  const double dt = (motion.time_s[F - 1] - motion.time_s[0]) / (F - 1);
  std::optional<ButterworthFilter> filter;
  if (summary.filtered && summary.cutoff_hz > 0)
    filter.emplace(summary.filter_order, summary.cutoff_hz, 1.0 / dt);
  std::vector<double> window(2 * h + 1);
  for (int c = 0; c < motion.nq(); ++c) {
    Eigen::VectorXd x = motion.q.row(c).transpose();
    Eigen::VectorXd y = x;
    for (int f = 0; f < F; ++f) {
      const int a = std::clamp(f - h, 0, F - 2 * h - 1);
      for (int k = 0; k <= 2 * h; ++k) window[size_t(k)] = x[a + k];
      std::nth_element(window.begin(), window.begin() + h, window.end());
      y[f] = window[size_t(h)];
    }
    if (filter) filter->FilterZeroLag(y);
    motion.q.row(c) = y.transpose();
  }
  for (int f = 0; f < F; ++f) motion.q.col(f).segment<4>(3).normalize();
}

// One flight's frames: the fitted span [first, first + count) and, inside it, the judged frames
// [judged_first, judged_first + judged_count) (offsets into the span).
struct FlightSpan {
  int first = 0, count = 0, judged_first = 0, judged_count = 0;
  Motion motion;         // the motion over the span, smoothed
  Eigen::Matrix3Xd p_M;  // its model markers, 3 × count·M, frame-major
  FrameDynamics clean;   // the refit of those markers without noise and without the filter
};

// The span's model markers + white noise of `noise_rms_m` (recorded samples only; 0: none), the
// trial's filter (unless `filtered` is false), the same inverse kinematics warm-started frame by
// frame, the same inverse dynamics. `max_marker_error_m` (when given) gets the fit's largest
// marker error over the judged frames.
FrameDynamics Refit(const ReconstructionResult& rec,
                    const FlightSpan& span,
                    double noise_rms_m,
                    bool filtered,
                    double height_m,
                    unsigned seed,
                    double* max_marker_error_m) {
  const int M = static_cast<int>(rec.markers.size());
  const int F = span.count;
  const double dt = (span.motion.time_s[F - 1] - span.motion.time_s[0]) / (F - 1);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_rms_m > 0 ? noise_rms_m : 1.0);
  // One column per marker coordinate, one row per frame.
  Eigen::MatrixXd signals(F, 3 * M);
  const bool masked = rec.recorded.size() == Eigen::Index(rec.motion.num_frames()) * M;
  for (int f = 0; f < F; ++f)
    for (int m = 0; m < M; ++m) {
      const bool present = !masked || rec.recorded[Eigen::Index(span.first + f) * M + m];
      for (int d = 0; d < 3; ++d)
        signals(f, 3 * m + d) =
            present ? span.p_M(d, Eigen::Index(f) * M + m) + (noise_rms_m > 0 ? noise(rng) : 0.0)
                    : std::numeric_limits<double>::quiet_NaN();
    }
  if (filtered && rec.summary.filtered && rec.summary.cutoff_hz > 0)
    FilterColumnsWithGaps(
        ButterworthFilter(rec.summary.filter_order, rec.summary.cutoff_hz, 1.0 / dt), signals);
  InverseKinematics ik(rec.model, rec.markers, rec.joint_limits, rec.ik_options);
  Motion refit = span.motion;
  Eigen::Matrix3Xd observed(3, M);
  double max_error = 0.0;
  for (int f = 0; f < F; ++f) {
    for (int m = 0; m < M; ++m)
      for (int d = 0; d < 3; ++d) observed(d, m) = signals(f, 3 * m + d);
    // Warm-started from the previous frame's fit, as the reconstruction fits (the first frame
    // from the motion's own pose).
    Eigen::VectorXd q =
        f == 0 ? Eigen::VectorXd(span.motion.q.col(0)) : Eigen::VectorXd(refit.q.col(f - 1));
    const IkFrameResult fit = ik.Solve(observed, q);
    refit.q.col(f) = q;
    if (f >= span.judged_first && f < span.judged_first + span.judged_count)
      max_error = std::max(max_error, fit.max_m);
  }
  if (max_marker_error_m) *max_marker_error_m = max_error;
  return CalcFrameDynamics(rec.model, refit, height_m);
}

// What a noisy refit changes in the judged measures against the span's clean refit (the same
// markers fitted without noise and without the filter). The filter is in the difference: its
// cutoff is where the trial's noise put it, and what it removes of a fast motion (a tuck's entry,
// a kick-out) the inverse dynamics sees as residuals and momentum change — on the sample as COCO-17
// keypoints more than the noise that gets through it (docs/physical-check.md).
FlightNoiseFloor MeasureNoisyCopy(const ReconstructionResult& rec,
                                  const FlightSpan& span,
                                  double noise_rms_m,
                                  double window_s,
                                  double height_m,
                                  double L_floor,
                                  unsigned seed) {
  FlightNoiseFloor out;
  double marker_error = 0.0;
  const FrameDynamics d = Refit(rec, span, noise_rms_m, true, height_m, seed, &marker_error);
  const FrameDynamics& clean = span.clean;
  out.max_marker_error_m = marker_error;
  const int j0 = span.judged_first, m = span.judged_count;
  const double dt = (span.motion.time_s[span.count - 1] - span.motion.time_s[0]) / (span.count - 1);
  const int w = static_cast<int>(std::lround(window_s / dt));
  out.window_force_bw =
      WindowedMeanNorms(d.force_bw.middleCols(j0, m) - clean.force_bw.middleCols(j0, m), w)
          .maxCoeff();
  out.window_moment_bwh =
      WindowedMeanNorms(d.moment_bwh.middleCols(j0, m) - clean.moment_bwh.middleCols(j0, m), w)
          .maxCoeff();
  // A body whose momentum is exactly the clean refit's mean, plus the change the noise makes.
  const Eigen::Matrix3Xd L_clean = clean.angular_momentum.middleCols(j0, m);
  const Eigen::Matrix3Xd L =
      (d.angular_momentum.middleCols(j0, m) - L_clean).colwise() + L_clean.rowwise().mean();
  out.momentum_variation = CalcMomentumVariation(L, L_floor);
  // The gravity a parabola fitted to the change of the COM height adds.
  out.gravity_error_m_per_s2 = std::abs(FitFallingGravity(
      span.motion.time_s.segment(j0, m),
      (d.com_W.row(2).segment(j0, m) - clean.com_W.row(2).segment(j0, m)).transpose()));
  return out;
}

// Runs job(0 … count − 1) on up to `threads` workers; stops taking jobs once `stop` is set.
void RunInParallel(int count,
                   int threads,
                   std::atomic<bool>& stop,
                   const std::function<bool()>& cancelled,
                   const std::function<void(int)>& job) {
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i; !stop && (i = next++) < count;) {
      if (cancelled && cancelled()) {
        stop = true;
        break;
      }
      job(i);
    }
  };
  const int workers = std::clamp(threads, 1, std::max(1, count));
  std::vector<std::thread> pool;
  for (int i = 1; i < workers; ++i) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

}  // namespace

bool NoiseFloorOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (!(repetitions >= 1 && repetitions <= 100)) return fail("repetitions must be 1–100");
  if (!(padding_s >= 0 && padding_s <= 10)) return fail("padding_s must be 0–10 s");
  if (num_threads < 0) return fail("num_threads must be non-negative");
  return true;
}

std::vector<FlightNoiseFloor> CalcNoiseFloor(const ReconstructionResult& rec,
                                             const PhysicalCheck& check,
                                             double noise_rms_m,
                                             const PhysicalCheckOptions& check_options,
                                             const NoiseFloorOptions& options) {
  DemandValidOptions(options, "noise floor options");
  DemandValidOptions(check_options, "physical check options");
  ACRO_DEMAND(noise_rms_m >= 0);
  std::vector<FlightNoiseFloor> floors(check.flights.size());
  const Motion& motion = rec.motion;
  const int n = motion.num_frames();
  if (noise_rms_m == 0 || n < 3) return floors;
  const double dt = (motion.time_s[n - 1] - motion.time_s[0]) / (n - 1);
  const int pad = static_cast<int>(std::lround(options.padding_s / dt));
  const double height_m = check.height_m;
  const double L_floor =
      check_options.momentum_floor_mh2_per_s * rec.model.total_mass() * height_m * height_m;
  const int threads = options.num_threads > 0
                          ? options.num_threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::atomic<bool> stop{false};

  // Each judged flight's span: its smoothed motion, model markers and clean refit.
  std::vector<FlightSpan> spans(check.flights.size());
  std::vector<int> judged;
  {
    InverseKinematics ik(rec.model, rec.markers, rec.joint_limits, rec.ik_options);
    const int M = static_cast<int>(rec.markers.size());
    Eigen::Matrix3Xd p_M;
    for (size_t k = 0; k < check.flights.size(); ++k) {
      const FlightCheck& fc = check.flights[k];
      if (fc.last_frame - fc.first_frame < 4) continue;  // not judged
      FlightSpan& s = spans[k];
      s.first = std::max(0, fc.first_frame - pad);
      s.count = std::min(n - 1, fc.last_frame + pad) - s.first + 1;
      s.judged_first = fc.first_frame - s.first;
      s.judged_count = fc.last_frame - fc.first_frame + 1;
      s.motion = Slice(motion, s.first, s.count);
      Smooth(s.motion, rec.summary);
      s.p_M.resize(3, Eigen::Index(s.count) * M);
      for (int f = 0; f < s.count; ++f) {
        ik.CalcMarkerPositions(s.motion.q.col(f), p_M);
        s.p_M.middleCols(Eigen::Index(f) * M, M) = p_M;
      }
      judged.push_back(static_cast<int>(k));
    }
  }
  RunInParallel(static_cast<int>(judged.size()), threads, stop, options.cancelled, [&](int i) {
    FlightSpan& s = spans[size_t(judged[size_t(i)])];
    s.clean = Refit(rec, s, 0.0, false, height_m, 0, nullptr);
  });

  // The noisy copies; each flight's floor is the largest of its copies'. The first copy of every
  // flight, then the others only where the first reaches half a threshold (times the factor): a
  // flight far below (markers' millimetre of noise) cannot have a limit raised unless its other
  // copies gave more than twice its first.
  auto copy = [&](int k, int r) {
    return MeasureNoisyCopy(
        rec,
        spans[size_t(k)],
        noise_rms_m,
        check_options.residual_window_s,
        height_m,
        L_floor,
        options.seed + 7919u * static_cast<unsigned>(k) + static_cast<unsigned>(r));
  };
  auto take = [](FlightNoiseFloor& f, const FlightNoiseFloor& c) {
    f.window_force_bw = std::max(f.window_force_bw, c.window_force_bw);
    f.window_moment_bwh = std::max(f.window_moment_bwh, c.window_moment_bwh);
    f.momentum_variation = std::max(f.momentum_variation, c.momentum_variation);
    f.gravity_error_m_per_s2 = std::max(f.gravity_error_m_per_s2, c.gravity_error_m_per_s2);
    f.max_marker_error_m = std::max(f.max_marker_error_m, c.max_marker_error_m);
  };
  std::vector<FlightNoiseFloor> first(judged.size());
  RunInParallel(static_cast<int>(judged.size()), threads, stop, options.cancelled, [&](int i) {
    first[size_t(i)] = copy(judged[size_t(i)], 0);
  });
  const double reach = 0.5 / check_options.noise_factor;
  const double g = check.gravity_m_per_s2;
  std::vector<std::pair<int, int>> more;  // (index into judged, copy)
  for (size_t i = 0; i < judged.size(); ++i) {
    take(floors[size_t(judged[i])], first[i]);
    const FlightNoiseFloor& f = first[i];
    const bool in_reach = f.window_force_bw >= reach * check_options.max_force_bw ||
                          f.window_moment_bwh >= reach * check_options.max_moment_bwh ||
                          f.momentum_variation >= reach * check_options.max_momentum_variation ||
                          f.gravity_error_m_per_s2 >= reach * check_options.max_gravity_error * g ||
                          f.max_marker_error_m >= reach * check_options.max_marker_error_m;
    if (in_reach)
      for (int r = 1; r < options.repetitions; ++r) more.emplace_back(int(i), r);
  }
  std::vector<FlightNoiseFloor> copies(more.size());
  RunInParallel(static_cast<int>(more.size()), threads, stop, options.cancelled, [&](int t) {
    copies[size_t(t)] = copy(judged[size_t(more[size_t(t)].first)], more[size_t(t)].second);
  });
  if (stop) return std::vector<FlightNoiseFloor>(check.flights.size());
  for (size_t t = 0; t < more.size(); ++t)
    take(floors[size_t(judged[size_t(more[t].first)])], copies[t]);
  return floors;
}

}  // namespace acro::analysis
