#include "acro/reconstruct/reconstruction.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <thread>

#include <fmt/format.h>

#include "acro/athlete/standard_human.h"
#include "acro/athlete/orientation.h"
#include "acro/reconstruct/phases.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/configuration.h"

namespace acro::analysis {

namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Matrix3Xd FrameObservations(const Eigen::Matrix3Xd& P, int frame, int M) {
  return P.middleCols(Eigen::Index(frame) * M, M);
}

/// Largest joint-angle difference (rad) and root orientation difference (rad) between two q.
std::pair<double, double> ConfigurationDistance(const Eigen::VectorXd& a,
                                                const Eigen::VectorXd& b) {
  const auto n = a.size() - dynamics::kRootNq;
  const double joints = (a.tail(n) - b.tail(n)).cwiseAbs().maxCoeff();
  const double dot = std::min(1.0, std::abs(a.segment<4>(3).dot(b.segment<4>(3))));
  return {joints, 2.0 * std::acos(dot)};
}

/// Adds multiples of 2π to q's joint angles so that each is nearest to the reference's.
void UnwrapJoints(const Eigen::VectorXd& reference, Eigen::VectorXd& q) {
  for (Eigen::Index i = dynamics::kRootNq; i < q.size(); ++i) q[i] = UnwrapAngle(reference[i], q[i]);
}

}  // namespace

bool ReconstructionOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  std::string sub;
  if (!gaps.IsValid(&sub)) return fail("gaps: " + sub);
  if (!ik.IsValid(&sub)) return fail("ik: " + sub);
  if (!scaling.IsValid(&sub)) return fail("scaling: " + sub);
  if (filter_order < 1 || filter_order > 8) return fail("filter_order must be 1–8");
  if (!(cutoff_hz >= 0)) return fail("cutoff_hz must be >= 0 (0: residual analysis)");
  if (scaling_window_frames < 1) return fail("scaling_window_frames must be >= 1");
  if (num_threads < 0 || min_chunk_frames < 1)
    return fail("num_threads >= 0, min_chunk_frames >= 1");
  return true;
}

std::string ReconstructionSummary::BriefReport() const {
  std::string out = "marker set " + markerset_report + "\n";
  out += "gaps: " + gaps.BriefReport() + "\n";
  if (filtered) {
    out += fmt::format("filter: zero-lag Butterworth, order {}, cutoff {:.1f} Hz{}\n",
                       filter_order,
                       cutoff_hz,
                       cutoff_from_residual_analysis ? " (Winter's residual analysis)" : "");
  } else {
    out += "filter: none\n";
  }
  out += "scaling: " + (scaling_report.empty() ? std::string("none") : scaling_report) + "\n";
  out += fmt::format(
      "inverse kinematics: {} of {} frames fitted in {} chunk(s) ({} re-solved), {} left/right "
      "swaps repaired\n"
      "marker RMS per frame: median {:.1f} mm, 95th percentile {:.1f} mm; largest marker error "
      "{:.1f} mm\n",
      frames_fitted,
      frames,
      chunks,
      chunks_resolved,
      swaps_repaired,
      median_rms_m * 1e3,
      p95_rms_m * 1e3,
      max_m * 1e3);
  for (size_t i = 0; i < flights.size(); ++i) {
    const FlightFit& f = flights[i];
    out += fmt::format(
        "flight {} (frames {}–{}): RMS median {:.1f} mm, 95th percentile {:.1f} mm, max {:.1f} "
        "mm\n",
        i + 1,
        f.first_frame,
        f.last_frame,
        f.median_rms_m * 1e3,
        f.p95_rms_m * 1e3,
        f.max_m * 1e3);
  }
  for (const std::string& w : warnings) out += "warning: " + w + "\n";
  return out;
}

std::vector<std::pair<int, int>> FindFlights(const Eigen::Matrix3Xd& positions,
                                             int M,
                                             const Eigen::VectorXd& time_s,
                                             double clearance_m,
                                             double min_duration_s) {
  // The lowest marker of each frame, and the level it rests at (2nd percentile).
  const int F = static_cast<int>(positions.cols() / M);
  Eigen::VectorXd low = Eigen::VectorXd::Constant(F, std::nan(""));
  std::vector<double> finite;
  for (int f = 0; f < F; ++f) {
    double z = std::numeric_limits<double>::infinity();
    for (int m = 0; m < M; ++m) {
      const double v = positions(2, Eigen::Index(f) * M + m);
      if (!std::isnan(v)) z = std::min(z, v);
    }
    if (std::isfinite(z)) {
      low[f] = z;
      finite.push_back(z);
    }
  }
  std::vector<std::pair<int, int>> flights;
  if (finite.empty() || time_s.size() != F) return flights;
  std::sort(finite.begin(), finite.end());
  const double ground = Percentile(finite, 2.0);
  // The phase detector's feet route on that height (complete flights only).
  PhaseOptions options;
  options.feet_clearance_m = clearance_m;
  options.min_flight_s = min_duration_s;
  for (const Flight& flight :
       DetectFlightsFromFeet(time_s, low, ground, Eigen::VectorXd(), options).flights) {
    if (!flight.partial) flights.push_back({flight.takeoff_frame, flight.landing_frame - 1});
  }
  return flights;
}

ReconstructionResult Reconstruct(const capture::Trial& trial,
                                 const capture::Trial* static_trial,
                                 const AthleteBody& body,
                                 const ReconstructionOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(trial.source.path, "options", why);
  if (!(trial.point_rate_hz > 0) || trial.num_frames < 1)
    throw InputError(trial.source.path, "POINT:RATE", "a trial with frames and a rate is needed");
  ReconstructionResult result;
  ReconstructionSummary& summary = result.summary;

  // Marker set: given or detected; markers placed on the athlete's standard human.
  MarkerSetMatch match;
  if (options.markerset.empty()) {
    result.markerset = DetectMarkerSet(trial, &match);
  } else {
    result.markerset = LoadMarkerSet(options.markerset);
    match = MatchMarkerSet(result.markerset, trial);
    if (match.num_matched < 3)
      throw InputError(trial.source.path,
                       "POINT:LABELS",
                       "marker set " + result.markerset.name + " matches fewer than 3 labels (" +
                           match.Report() + ")");
  }
  summary.markerset = result.markerset.name;
  summary.markerset_report = match.Report();
  const dynamics::Model<double> model0 = MakeStandardHumanModel(body);
  std::vector<ModelMarker> markers = PlaceMarkers(result.markerset, model0, body.height_m);
  const std::vector<JointLimit> limits = StandardJointLimits(model0);
  InverseKinematicsOptions ik_options = options.ik;
  if (result.markerset.keypoints && ik_options.joint_prior_m_per_rad.empty()) {
    // Angles that 17 keypoints leave undetermined rest at the reference pose.
    ik_options.joint_prior_m_per_rad.assign(size_t(model0.num_joint_dofs()), 0.0);
    for (int s = 1; s < model0.num_segments(); ++s) {
      const dynamics::Segment<double>& seg = model0.segment(s);
      const std::string base = ScaleGroupOf(seg.name);
      for (int k = 0; k < seg.num_axes; ++k) {
        const bool unseen =
            base == "thorax" || base == "hand" || base == "foot" || (base == "forearm" && k == 1);
        if (unseen)
          ik_options.joint_prior_m_per_rad[size_t(seg.q_start - dynamics::kRootNq + k)] =
              options.keypoint_unseen_angle_prior_m_per_rad;
      }
    }
  }
  const int M = static_cast<int>(markers.size());
  const int F = trial.num_frames;
  const double rate = trial.point_rate_hz;

  // The set's markers, frame-major, NaN where absent.
  Eigen::Matrix3Xd& P = result.marker_positions;
  P.setConstant(3, Eigen::Index(F) * M, std::nan(""));
  for (int m = 0; m < M; ++m) {
    const int p = match.trial_point[size_t(m)];
    if (p < 0) continue;
    for (int f = 0; f < F; ++f) P.col(Eigen::Index(f) * M + m) = trial.position(f, p);
  }

  // Left/right swaps in the raw data, before filtering smears them: a mirror pair is exchanged
  // when the exchange brings both markers far closer to where they were in the last frame that
  // had both (within 5 frames; at 100 Hz and more a marker moves a few centimetres per frame,
  // left and right markers are 10–40 cm apart). Not for video keypoints: their detection noise of
  // centimetres makes frame-to-frame continuity unreliable (on the s2mLab routine this check
  // exchanged 311 pairs and raised the 95th percentile of the marker RMS from 71 to 114 mm); they
  // keep the model-based check below.
  int continuity_swaps = 0;
  if (options.repair_swaps && !result.markerset.keypoints) {
    for (int m = 0; m < M; ++m) {
      const int n = markers[size_t(m)].mirror;
      if (n <= m) continue;
      int last = -1;
      for (int f = 0; f < F; ++f) {
        auto a = P.col(Eigen::Index(f) * M + m);
        auto b = P.col(Eigen::Index(f) * M + n);
        if (std::isnan(a[0]) || std::isnan(b[0])) continue;
        if (last >= 0 && f - last <= 5) {
          const Eigen::Vector3d a0 = P.col(Eigen::Index(last) * M + m);
          const Eigen::Vector3d b0 = P.col(Eigen::Index(last) * M + n);
          const double keep = (a - a0).norm() + (b - b0).norm();
          const double swap = (a - b0).norm() + (b - a0).norm();
          if (swap < options.swap_ratio * keep && keep - swap > options.swap_min_gain_m) {
            a.swap(b);
            ++continuity_swaps;
          }
        }
        last = f;
      }
    }
  }

  // Samples absent from the recording (filled below for the filter and the exports).
  const Eigen::Array<bool, 1, Eigen::Dynamic> recorded = !P.row(0).array().isNaN();

  // Gap filling.
  if (options.fill_gaps) {
    std::vector<int> segment_of(static_cast<size_t>(M));
    for (int m = 0; m < M; ++m) segment_of[size_t(m)] = markers[size_t(m)].segment;
    summary.gaps = FillGaps(P, M, segment_of, rate, options.gaps);
  }

  // Zero-lag low-pass filter, the cutoff by Winter's residual analysis unless given.
  if (options.filter && F >= 3 * (options.filter_order + 1) && rate >= 8.0) {
    Eigen::MatrixXd signals(F, 3 * M);
    for (int m = 0; m < M; ++m)
      for (int f = 0; f < F; ++f)
        for (int d = 0; d < 3; ++d) signals(f, 3 * m + d) = P(d, Eigen::Index(f) * M + m);
    double fc = options.cutoff_hz;
    if (fc <= 0) {
      fc = CalcResidualAnalysis(signals, rate, options.filter_order, options.num_threads)
               .chosen_cutoff_hz;
      summary.cutoff_from_residual_analysis = true;
    }
    const ButterworthFilter filter(options.filter_order, fc, rate);
    for (Eigen::Index c = 0; c < signals.cols(); ++c) {
      Eigen::VectorXd x = signals.col(c);
      FilterWithGaps(filter, x);
      signals.col(c) = x;
    }
    for (int m = 0; m < M; ++m)
      for (int f = 0; f < F; ++f)
        for (int d = 0; d < 3; ++d) P(d, Eigen::Index(f) * M + m) = signals(f, 3 * m + d);
    summary.filtered = true;
    summary.filter_order = options.filter_order;
    summary.cutoff_hz = fc;
  }

  // Scaling: to the static trial's mean frame, or to frames spread over a window of the motion.
  result.model = model0;
  std::vector<std::pair<int, Eigen::VectorXd>> seeds;
  if (options.scale) {
    std::vector<Eigen::Matrix3Xd> frames;
    std::vector<Eigen::VectorXd> initial_q;
    std::vector<int> chosen;
    if (static_trial != nullptr) {
      const MarkerSetMatch sm = MatchMarkerSet(result.markerset, *static_trial);
      Eigen::Matrix3Xd mean = Eigen::Matrix3Xd::Constant(3, M, std::nan(""));
      for (int m = 0; m < M; ++m) {
        const int p = sm.trial_point[size_t(m)];
        if (p < 0) continue;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        int count = 0;
        for (int f = 0; f < static_trial->num_frames; ++f) {
          if (!static_trial->valid(f, p)) continue;
          sum += static_trial->position(f, p);
          ++count;
        }
        if (count > 0) mean.col(m) = sum / count;
      }
      frames.push_back(mean);
    } else {
      const int first = options.scaling_first_frame >= 0 ? options.scaling_first_frame : 0;
      const int last =
          options.scaling_last_frame >= 0 ? std::min(options.scaling_last_frame, F - 1) : F - 1;
      // Frames of the window with at least 80 % of the markers, evenly spread; their starting
      // poses from inverse kinematics warm-started through the window.
      std::vector<int> candidates;
      for (int f = first; f <= last; ++f) {
        int present = 0;
        for (int m = 0; m < M; ++m) present += !std::isnan(P(0, Eigen::Index(f) * M + m));
        if (present * 5 >= match.num_matched * 4 && present >= 4) candidates.push_back(f);
      }
      const int want = std::min<int>(options.scaling_window_frames, int(candidates.size()));
      for (int k = 0; k < want; ++k) {
        const size_t i = size_t((double(k) + 0.5) * double(candidates.size()) / want);
        chosen.push_back(candidates[std::min(i, candidates.size() - 1)]);
      }
      if (!chosen.empty()) {
        InverseKinematics ik(model0, markers, limits, ik_options);
        Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(model0);
        int last_fitted = -1000000;
        size_t next = 0;
        for (int f = chosen.front(); f <= chosen.back(); ++f) {
          const Eigen::Matrix3Xd obs = FrameObservations(P, f, M);
          if (ik.Solve(obs, q, f - last_fitted > 10).num_markers >= 3) last_fitted = f;
          if (f == chosen[next]) {
            frames.push_back(obs);
            initial_q.push_back(q);
            ++next;
          }
        }
      }
    }
    if (!frames.empty()) {
      ScalingOptions scaling_options = options.scaling;
      if (result.markerset.keypoints) scaling_options.offset_prior = options.keypoint_offset_prior;
      ScalingResult scaled = ScaleModel(model0,
                                        markers,
                                        limits,
                                        frames,
                                        scaling_options,
                                        initial_q.empty() ? nullptr : &initial_q,
                                        ik_options);
      result.model = scaled.model;
      markers = scaled.markers;
      // The poses fitted with the factors (frames of this trial) start the inverse kinematics.
      if (!chosen.empty())
        for (size_t k = 0; k < chosen.size(); ++k) seeds.push_back({chosen[k], scaled.poses[k]});
      summary.scaling_report =
          (static_trial ? "static trial, " : "motion window, ") + scaled.BriefReport();
      // Factors held at a bound of their range mean the fit could not tell the segment's size (a
      // window of acrobatics and a sparse set: docs/reconstruction.md, limitations).
      std::string at_bound;
      for (const auto& [group, factor] : scaled.scale)
        if (factor <= scaling_options.min_scale + 1e-6 ||
            factor >= scaling_options.max_scale - 1e-6)
          at_bound += (at_bound.empty() ? "" : ", ") + group;
      if (!at_bound.empty())
        summary.warnings.push_back("scaling: the " + at_bound +
                                   " factor(s) reached the bound of their range (" +
                                   std::to_string(scaling_options.min_scale).substr(0, 4) + "–" +
                                   std::to_string(scaling_options.max_scale).substr(0, 4) +
                                   "); the fit cannot size these segments" +
                                   (static_trial ? "" : ": record a static trial (--static)"));
    } else {
      summary.warnings.push_back("no frame with enough markers to scale the model; unscaled");
    }
  }
  result.markers = markers;

  // Inverse kinematics in chunks of frames, each cold-started at its first frame.
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = options.num_threads > 0 ? options.num_threads : hw;
  const int chunks = std::max(1, std::min(threads, F / options.min_chunk_frames));
  summary.chunks = chunks;
  Motion& motion = result.motion;
  motion.coordinate_names = MakeCoordinateNames(result.model);
  motion.rate_hz = rate;
  motion.time_s.resize(F);
  for (int f = 0; f < F; ++f) motion.time_s[f] = f / rate;
  motion.q.resize(result.model.nq(), F);
  motion.fit.assign(size_t(F), FrameFit{});
  for (const ModelMarker& mk : markers) motion.marker_names.push_back(mk.name);
  motion.marker_error_m.setConstant(M, F, std::nan(""));
  std::atomic<int> done{0};
  std::atomic<int> swaps{0};
  std::mutex progress_mutex;
  auto report_progress = [&]() {
    const int d = ++done;
    if (options.progress && (d % 10 == 0 || d == F)) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      options.progress(d, F);
    }
  };
  // Solves frames begin, begin + step, … up to (not including) end, starting from q (cold unless
  // warm is set), writing into motion; step −1 runs backwards in time.
  auto solve_range =
      [&](InverseKinematics& ik, int begin, int end, Eigen::VectorXd q, bool warm, int step = 1) {
        int last_fitted = warm ? begin - step : -1000000;
        Eigen::Matrix3Xd predicted;
        Eigen::VectorXd dist;
        for (int f = begin; f != end; f += step) {
          Eigen::Matrix3Xd obs = FrameObservations(P, f, M);
          if (!options.fit_filled_samples)
            for (int m = 0; m < M; ++m)
              if (!recorded[Eigen::Index(f) * M + m]) obs.col(m).setConstant(std::nan(""));
          const bool cold = std::abs(f - last_fitted) > 10;
          // Left/right swaps: a mirror pair whose exchange fits the prediction far better.
          if (!cold && options.repair_swaps) {
            ik.CalcMarkerPositions(q, predicted);
            for (int m = 0; m < M; ++m) {
              const int n = markers[size_t(m)].mirror;
              if (n <= m || std::isnan(obs(0, m)) || std::isnan(obs(0, n))) continue;
              const double keep =
                  (obs.col(m) - predicted.col(m)).norm() + (obs.col(n) - predicted.col(n)).norm();
              const double swap =
                  (obs.col(m) - predicted.col(n)).norm() + (obs.col(n) - predicted.col(m)).norm();
              if (swap < options.swap_ratio * keep && keep - swap > options.swap_min_gain_m) {
                obs.col(m).swap(obs.col(n));
                P.col(Eigen::Index(f) * M + m).swap(P.col(Eigen::Index(f) * M + n));
                ++swaps;
              }
            }
          }
          const IkFrameResult r = ik.Solve(obs, q, cold);
          FrameFit& fit = motion.fit[size_t(f)];
          fit.num_markers = r.num_markers;
          fit.iterations = r.iterations;
          fit.converged = r.converged;
          fit.valid = r.num_markers >= 3;
          fit.rms_m = r.rms_m;
          fit.max_m = r.max_m;
          if (fit.valid) {
            last_fitted = f;
            ik.Evaluate(obs, q, &dist);
            motion.marker_error_m.col(f) = dist;
          }
          motion.q.col(f) = q;
          report_progress();
        }
      };
  std::vector<int> bounds(size_t(chunks) + 1);
  for (int c = 0; c <= chunks; ++c) bounds[size_t(c)] = int(std::int64_t(F) * c / chunks);
  {
    std::vector<std::thread> workers;
    for (int c = 0; c < chunks; ++c) {
      workers.emplace_back([&, c]() {
        InverseKinematics ik(result.model, markers, limits, ik_options);
        const int b = bounds[size_t(c)], e = bounds[size_t(c) + 1];
        // A pose fitted with the scale factors inside the chunk is the exact start: solve forward
        // from its frame to the chunk's end and backward to its beginning. Otherwise cold-start.
        const std::pair<int, Eigen::VectorXd>* seed = nullptr;
        for (const auto& sd : seeds)
          if (sd.first >= b && sd.first < e && seed == nullptr) seed = &sd;
        if (seed) {
          solve_range(ik, seed->first, e, seed->second, true, 1);
          solve_range(ik, seed->first - 1, b - 1, motion.q.col(seed->first), true, -1);
        } else {
          solve_range(ik, b, e, dynamics::MakeNeutralConfiguration(result.model), false);
        }
      });
    }
    for (std::thread& t : workers) t.join();
  }
  // Chunk joins: warm-solve each chunk's first frame from the previous chunk's last; if the cold
  // start found another branch, re-solve the chunk sequentially from there.
  {
    InverseKinematics ik(result.model, markers, limits, ik_options);
    for (int c = 1; c < chunks; ++c) {
      const int s = bounds[size_t(c)];
      if (!motion.fit[size_t(s - 1)].valid) continue;
      Eigen::VectorXd q = motion.q.col(s - 1);
      Eigen::Matrix3Xd obs = FrameObservations(P, s, M);
      if (!options.fit_filled_samples)
        for (int m = 0; m < M; ++m)
          if (!recorded[Eigen::Index(s) * M + m]) obs.col(m).setConstant(std::nan(""));
      ik.Solve(obs, q, false);
      Eigen::VectorXd cold = motion.q.col(s);
      UnwrapJoints(q, cold);
      const auto [dj, dr] = ConfigurationDistance(q, cold);
      if (dj > 5.0 * kPi / 180.0 || dr > 5.0 * kPi / 180.0) {
        done -= bounds[size_t(c) + 1] - s;
        solve_range(ik, s, bounds[size_t(c) + 1], motion.q.col(s - 1), true);
        ++summary.chunks_resolved;
      } else {
        // Same branch: shift the whole chunk's joint angles by the same multiples of 2π.
        for (int f = s; f < bounds[size_t(c) + 1]; ++f) {
          Eigen::VectorXd qf = motion.q.col(f);
          UnwrapJoints(f == s ? q : Eigen::VectorXd(motion.q.col(f - 1)), qf);
          motion.q.col(f) = qf;
        }
      }
    }
  }
  // Quaternion sign continuity (q and −q are the same orientation).
  for (int f = 1; f < F; ++f)
    if (motion.q.col(f).segment<4>(3).dot(motion.q.col(f - 1).segment<4>(3)) < 0)
      motion.q.col(f).segment<4>(3) *= -1.0;
  summary.swaps_repaired = swaps + continuity_swaps;

  // Fit quality over the trial and per flight.
  summary.frames = F;
  for (const FrameFit& f : motion.fit) {
    summary.frames_fitted += f.valid;
    if (f.valid) summary.max_m = std::max(summary.max_m, f.max_m);
  }
  const std::vector<double> sorted = SortedFrameRms(motion);
  summary.median_rms_m = Percentile(sorted, 50);
  summary.p95_rms_m = Percentile(sorted, 95);
  for (const auto& [a, b] : FindFlights(P, M, motion.time_s)) {
    FlightFit ff;
    ff.first_frame = a;
    ff.last_frame = b;
    std::vector<double> v;
    for (int f = a; f <= b; ++f) {
      if (!motion.fit[size_t(f)].valid) continue;
      v.push_back(motion.fit[size_t(f)].rms_m);
      ff.max_m = std::max(ff.max_m, motion.fit[size_t(f)].max_m);
    }
    std::sort(v.begin(), v.end());
    ff.median_rms_m = Percentile(v, 50);
    ff.p95_rms_m = Percentile(v, 95);
    summary.flights.push_back(ff);
  }
  if (summary.frames_fitted < F)
    summary.warnings.push_back(std::to_string(F - summary.frames_fitted) +
                               " frames had fewer than 3 markers and hold the previous pose");
  return result;
}

}  // namespace acro::analysis
