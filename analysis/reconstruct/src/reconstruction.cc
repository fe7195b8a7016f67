#include "acro/reconstruct/reconstruction.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <thread>

#include <fmt/format.h>

#include "acro/athlete/orientation.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/reconstruct/phases.h"

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
  for (Eigen::Index i = dynamics::kRootNq; i < q.size(); ++i)
    q[i] = UnwrapAngle(reference[i], q[i]);
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
  if (!view_fit.IsValid(&sub)) return fail("view_fit: " + sub);
  if (!flight_physics.IsValid(&sub)) return fail("flight_physics: " + sub);
  for (const auto& [a, b] : ballistic_flights_s)
    if (std::isfinite(a) && std::isfinite(b) && !(a < b))
      return fail("ballistic_flights_s: a flight must end after it starts");
  if (filter_order < 1 || filter_order > 8) return fail("filter_order must be 1–8");
  if (!(cutoff_hz >= 0)) return fail("cutoff_hz must be >= 0 (0: residual analysis)");
  if (scaling_window_frames < 1) return fail("scaling_window_frames must be >= 1");
  if (!(keypoint_temporal_prior_m_per_rad >= 0 && std::isfinite(keypoint_temporal_prior_m_per_rad)))
    return fail("keypoint_temporal_prior_m_per_rad must be finite and >= 0");
  if (!(keypoint_limb_rotation_prior_m_per_rad >= 0 &&
        std::isfinite(keypoint_limb_rotation_prior_m_per_rad)))
    return fail("keypoint_limb_rotation_prior_m_per_rad must be finite and >= 0");
  if (num_threads < 0 || min_chunk_frames < 1)
    return fail("num_threads >= 0, min_chunk_frames >= 1");
  return true;
}

std::string ReconstructionSummary::BriefReport() const {
  std::string out = "marker set " + markerset_report + "\n";
  out += "gaps: " + gaps.BriefReport() + "\n";
  if (filtered) {
    out +=
        fmt::format("filter: zero-lag Butterworth, order {}, cutoff {:.1f} Hz{}; noise {:.1f} mm\n",
                    filter_order,
                    cutoff_hz,
                    cutoff_from_residual_analysis ? " (Winter's residual analysis)" : "",
                    1e3 * noise_rms_m);
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
  if (view_fit) out += view_fit->Report();
  if (flight_physics) out += flight_physics->Report();
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

namespace {

// ---- Reconstruct's steps, in the order it runs them ----

// The marker set named in the options, or the one detected from the trial's labels; `match` gets
// its match to the trial's points.
MarkerSet ChooseMarkerSet(const capture::Trial& trial,
                          const ReconstructionOptions& options,
                          MarkerSetMatch* match) {
  if (options.markerset.empty()) return DetectMarkerSet(trial, match);
  MarkerSet markerset = LoadMarkerSet(options.markerset);
  *match = MatchMarkerSet(markerset, trial);
  if (match->num_matched < 3)
    throw InputError(
        trial.source.path,
        "POINT:LABELS",
        "marker set " + markerset.name +
            (markerset.source.rfind("builtin:", 0) == 0 ? std::string()
                                                        : " (" + markerset.source + ")") +
            " matches fewer than 3 labels (" + match->Report() + ")");
  return markerset;
}

// The joint angles (indices among the joint dofs) that none of the trial's markers moves by 1 mm
// per radian or more, in the reference pose nor with every joint bent 0.6 rad (a bent knee lets
// the ankle see the thigh's rotation): what this set cannot see on this trial.
std::vector<int> UnseenJointDofs(const dynamics::Model<double>& model,
                                 const std::vector<ModelMarker>& markers,
                                 const MarkerSetMatch& match) {
  dynamics::Workspace<double> ws(model);
  const auto positions = [&](const Eigen::VectorXd& q) {
    dynamics::CalcForwardKinematics(model, ws, q);
    Eigen::Matrix3Xd p(3, Eigen::Index(markers.size()));
    for (size_t k = 0; k < markers.size(); ++k)
      p.col(Eigen::Index(k)) =
          match.trial_point[k] >= 0
              ? Eigen::Vector3d(ws.X_WB[size_t(markers[k].segment)] * markers[k].p_BoM_B)
              : Eigen::Vector3d::Zero();
    return p;
  };
  const Eigen::VectorXd q0 = dynamics::MakeNeutralConfiguration(model);
  Eigen::VectorXd q1 = q0;
  q1.tail(model.num_joint_dofs()).setConstant(0.6);
  std::vector<int> unseen;
  constexpr double kStep = 1e-4;
  const Eigen::VectorXd poses[] = {q0, q1};
  const Eigen::Matrix3Xd at[] = {positions(q0), positions(q1)};
  for (int j = 0; j < model.num_joint_dofs(); ++j) {
    double moved = 0;
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd dq = poses[k];
      dq[dynamics::kRootNq + j] += kStep;
      moved = std::max(moved, (positions(dq) - at[k]).colwise().norm().maxCoeff() / kStep);
    }
    if (moved < 1e-3) unseen.push_back(j);
  }
  return unseen;
}

// The inverse kinematics options; with video keypoints, the angles that 17 keypoints leave
// undetermined (thorax, hands, feet, forearm pronation) and any other the set cannot see
// (`unseen`) rest at the reference pose, the shoulders' and hips' rotations lean weakly towards it
// when the set has no points on the hands and feet (they are then seen only while the elbow or
// knee is bent), and the angles seen in some poses only keep the previous frame's value in the
// others (the temporal prior).
InverseKinematicsOptions MakeIkOptions(const ReconstructionOptions& options,
                                       const MarkerSet& markerset,
                                       const dynamics::Model<double>& model,
                                       const std::vector<int>& unseen_dofs) {
  InverseKinematicsOptions ik_options = options.ik;
  if (markerset.keypoints && ik_options.temporal_prior_m_per_rad == 0.0)
    ik_options.temporal_prior_m_per_rad = options.keypoint_temporal_prior_m_per_rad;
  if (!markerset.keypoints || !ik_options.joint_prior_m_per_rad.empty()) return ik_options;
  ik_options.joint_prior_m_per_rad.assign(size_t(model.num_joint_dofs()), 0.0);
  // A set with two points or more on each hand (each foot) sees the limb's rotation through the
  // hand's (foot's) direction. Only a set that sees neither (COCO-17) gets the rotation prior: on
  // BODY_25B (feet, no hands) the arms' prior moved the bed estimate from 1.123 to 1.085 m
  // (docs/reconstruction.md).
  auto sees = [&](const std::string& group) {
    std::map<std::string, int> on_segment;
    for (const MarkerDefinition& m : markerset.markers)
      if (ScaleGroupOf(m.segment) == group) ++on_segment[m.segment];
    if (on_segment.size() < 2) return false;
    for (const auto& [segment, count] : on_segment)
      if (count < 2) return false;
    return true;
  };
  const bool sees_hands = sees("hand"), sees_feet = sees("foot");
  for (int s = 1; s < model.num_segments(); ++s) {
    const dynamics::Segment<double>& seg = model.segment(s);
    const std::string base = ScaleGroupOf(seg.name);
    for (int k = 0; k < seg.num_axes; ++k) {
      const int dof = seg.q_start - dynamics::kRootNq + k;
      const bool unseen =
          base == "thorax" || base == "hand" || base == "foot" || (base == "forearm" && k == 1) ||
          std::find(unseen_dofs.begin(), unseen_dofs.end(), dof) != unseen_dofs.end();
      const bool limb_rotation =
          k == 1 && !sees_hands && !sees_feet && (base == "upper_arm" || base == "thigh");
      if (unseen)
        ik_options.joint_prior_m_per_rad[size_t(dof)] =
            options.keypoint_unseen_angle_prior_m_per_rad;
      else if (limb_rotation)
        ik_options.joint_prior_m_per_rad[size_t(dof)] =
            options.keypoint_limb_rotation_prior_m_per_rad;
    }
  }
  return ik_options;
}

// The set's M markers over the trial's frames, frame-major, NaN where absent.
Eigen::Matrix3Xd GatherMarkerPositions(const capture::Trial& trial,
                                       const MarkerSetMatch& match,
                                       int M) {
  const int F = trial.num_frames;
  Eigen::Matrix3Xd P = Eigen::Matrix3Xd::Constant(3, Eigen::Index(F) * M, std::nan(""));
  for (int m = 0; m < M; ++m) {
    const int p = match.trial_point[size_t(m)];
    if (p < 0) continue;
    for (int f = 0; f < F; ++f) P.col(Eigen::Index(f) * M + m) = trial.position(f, p);
  }
  return P;
}

// Left/right swaps in the raw data, before filtering smears them: a mirror pair is exchanged
// when the exchange brings both markers far closer to where they were in the last frame that
// had both (within 5 frames; at 100 Hz and more a marker moves a few centimetres per frame,
// left and right markers are 10–40 cm apart). Not for video keypoints: their detection noise of
// centimetres makes frame-to-frame continuity unreliable (on the s2mLab routine this check
// exchanged 311 pairs and raised the 95th percentile of the marker RMS from 71 to 114 mm); they
// keep the model-based check of FrameSolver. Returns the number of exchanges.
int RepairSwapsByContinuity(const std::vector<ModelMarker>& markers,
                            const ReconstructionOptions& options,
                            int F,
                            Eigen::Matrix3Xd& P) {
  const int M = static_cast<int>(markers.size());
  int swaps = 0;
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
          ++swaps;
        }
      }
      last = f;
    }
  }
  return swaps;
}

// Fills the markers' gaps (each marker knows its segment).
GapFillingSummary FillMarkerGaps(const std::vector<ModelMarker>& markers,
                                 double rate,
                                 const GapFillingOptions& options,
                                 Eigen::Matrix3Xd& P) {
  const int M = static_cast<int>(markers.size());
  std::vector<int> segment_of(static_cast<size_t>(M));
  for (int m = 0; m < M; ++m) segment_of[size_t(m)] = markers[size_t(m)].segment;
  return FillGaps(P, M, segment_of, rate, options);
}

// Zero-lag low-pass filter of every coordinate of every marker, the cutoff by Winter's residual
// analysis unless given; the filter's settings go to the summary.
void FilterMarkers(const ReconstructionOptions& options,
                   double rate,
                   int M,
                   int F,
                   Eigen::Matrix3Xd& P,
                   ReconstructionSummary& summary) {
  // One column per marker coordinate, one row per frame.
  Eigen::MatrixXd signals(F, 3 * M);
  for (int m = 0; m < M; ++m)
    for (int f = 0; f < F; ++f)
      for (int d = 0; d < 3; ++d) signals(f, 3 * m + d) = P(d, Eigen::Index(f) * M + m);
  // The cutoff.
  double fc = options.cutoff_hz;
  double noise_intercept = 0.0;
  if (fc <= 0) {
    const ResidualAnalysis analysis =
        CalcResidualAnalysis(signals, rate, options.filter_order, options.num_threads);
    fc = analysis.chosen_cutoff_hz;
    noise_intercept = analysis.noise_intercept;
    summary.cutoff_from_residual_analysis = true;
  }
  // Filter each column, across its gaps (the columns are put back below). The measurement
  // noise: Winter's intercept (the RMS of the noise, the residual's noise line at
  // 0 Hz), or with a cutoff given what the filter removes (the noise above the cutoff).
  const ButterworthFilter filter(options.filter_order, fc, rate);
  if (noise_intercept > 0) {
    FilterColumnsWithGaps(filter, signals);
    summary.noise_rms_m = noise_intercept;
  } else {
    const Eigen::MatrixXd raw = signals;
    FilterColumnsWithGaps(filter, signals);
    const Eigen::ArrayXXd removed = (signals - raw).array();
    const Eigen::Index samples = (removed == removed).count();  // not NaN
    summary.noise_rms_m = std::sqrt(removed.isNaN().select(0.0, removed).square().sum() /
                                    double(std::max<Eigen::Index>(1, samples)));
  }
  for (int m = 0; m < M; ++m)
    for (int f = 0; f < F; ++f)
      for (int d = 0; d < 3; ++d) P(d, Eigen::Index(f) * M + m) = signals(f, 3 * m + d);
  summary.filtered = true;
  summary.filter_order = options.filter_order;
  summary.cutoff_hz = fc;
}

// The static trial's mean position of each of the set's M markers, NaN for a marker it never
// recorded.
Eigen::Matrix3Xd CalcStaticMeanFrame(const capture::Trial& static_trial,
                                     const MarkerSet& markerset,
                                     int M) {
  const MarkerSetMatch sm = MatchMarkerSet(markerset, static_trial);
  Eigen::Matrix3Xd mean = Eigen::Matrix3Xd::Constant(3, M, std::nan(""));
  for (int m = 0; m < M; ++m) {
    const int p = sm.trial_point[size_t(m)];
    if (p < 0) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (int f = 0; f < static_trial.num_frames; ++f) {
      if (!static_trial.valid(f, p)) continue;
      sum += static_trial.position(f, p);
      ++count;
    }
    if (count > 0) mean.col(m) = sum / count;
  }
  return mean;
}

// Frames of the scaling window with at least 80 % of the matched markers (and 4), evenly spread,
// at most options.scaling_window_frames of them.
std::vector<int> ChooseScalingFrames(const Eigen::Matrix3Xd& P,
                                     int M,
                                     int F,
                                     int num_matched,
                                     const ReconstructionOptions& options) {
  const int first = options.scaling_first_frame >= 0 ? options.scaling_first_frame : 0;
  const int last =
      options.scaling_last_frame >= 0 ? std::min(options.scaling_last_frame, F - 1) : F - 1;
  // The window's frames with enough markers.
  std::vector<int> candidates;
  for (int f = first; f <= last; ++f) {
    int present = 0;
    for (int m = 0; m < M; ++m) present += !std::isnan(P(0, Eigen::Index(f) * M + m));
    if (present * 5 >= num_matched * 4 && present >= 4) candidates.push_back(f);
  }
  // Evenly spread among them.
  std::vector<int> chosen;
  const int want = std::min<int>(options.scaling_window_frames, int(candidates.size()));
  for (int k = 0; k < want; ++k) {
    const size_t i = size_t((double(k) + 0.5) * double(candidates.size()) / want);
    chosen.push_back(candidates[std::min(i, candidates.size() - 1)]);
  }
  return chosen;
}

// The chosen frames' observations and their starting poses, from inverse kinematics on the
// unscaled model warm-started through the window from the first chosen frame to the last.
void FitScalingFrames(const dynamics::Model<double>& model0,
                      const std::vector<ModelMarker>& markers,
                      const std::vector<JointLimit>& limits,
                      const InverseKinematicsOptions& ik_options,
                      const Eigen::Matrix3Xd& P,
                      const std::vector<int>& chosen,
                      std::vector<Eigen::Matrix3Xd>* frames,
                      std::vector<Eigen::VectorXd>* initial_q) {
  const int M = static_cast<int>(markers.size());
  InverseKinematics ik(model0, markers, limits, ik_options);
  Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(model0);
  int last_fitted = -1000000;
  size_t next = 0;
  for (int f = chosen.front(); f <= chosen.back(); ++f) {
    const Eigen::Matrix3Xd obs = FrameObservations(P, f, M);
    if (ik.Solve(obs, q, f - last_fitted > 10).num_markers >= 3) last_fitted = f;
    if (f == chosen[next]) {
      frames->push_back(obs);
      initial_q->push_back(q);
      ++next;
    }
  }
}

// Factors held at a bound of their range mean the fit could not tell the segment's size (a
// window of acrobatics and a sparse set: docs/reconstruction.md, limitations). The warning that
// names them, or empty.
std::string ScalingBoundWarning(const ScalingResult& scaled,
                                const ScalingOptions& scaling_options,
                                bool from_static_trial) {
  std::string at_bound;
  for (const auto& [group, factor] : scaled.scale)
    if (factor <= scaling_options.min_scale + 1e-6 || factor >= scaling_options.max_scale - 1e-6)
      at_bound += (at_bound.empty() ? "" : ", ") + group;
  if (at_bound.empty()) return {};
  return "scaling: the " + at_bound + " factor(s) reached the bound of their range (" +
         std::to_string(scaling_options.min_scale).substr(0, 4) + "–" +
         std::to_string(scaling_options.max_scale).substr(0, 4) +
         "); the fit cannot size these segments" +
         (from_static_trial ? "" : ": record a static trial (--static)");
}

// A frame and the pose fitted at it together with the scale factors.
using Seed = std::pair<int, Eigen::VectorXd>;

// Scales result.model and `markers` to the static trial's mean frame, or to frames spread over a
// window of the motion; reports in result.summary. Returns the poses the scaling fitted at frames
// of this trial (none for a static trial): they start the inverse kinematics.
std::vector<Seed> ScaleToTrial(const capture::Trial* static_trial,
                               const dynamics::Model<double>& model0,
                               const std::vector<JointLimit>& limits,
                               const InverseKinematicsOptions& ik_options,
                               const ReconstructionOptions& options,
                               int num_matched,
                               int F,
                               std::vector<ModelMarker>& markers,
                               ReconstructionResult& result) {
  const int M = static_cast<int>(markers.size());
  ReconstructionSummary& summary = result.summary;
  // The frames to scale to, and for a motion window their starting poses.
  std::vector<Eigen::Matrix3Xd> frames;
  std::vector<Eigen::VectorXd> initial_q;
  std::vector<int> chosen;
  if (static_trial != nullptr) {
    frames.push_back(CalcStaticMeanFrame(*static_trial, result.markerset, M));
  } else {
    chosen = ChooseScalingFrames(result.marker_positions, M, F, num_matched, options);
    if (!chosen.empty())
      FitScalingFrames(model0,
                       markers,
                       limits,
                       ik_options,
                       result.marker_positions,
                       chosen,
                       &frames,
                       &initial_q);
  }
  std::vector<Seed> seeds;
  if (frames.empty()) {
    summary.warnings.push_back("no frame with enough markers to scale the model; unscaled");
    return seeds;
  }
  // The scale factors, the scaled model and markers.
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
  for (size_t k = 0; k < chosen.size(); ++k) seeds.push_back({chosen[k], scaled.poses[k]});
  // The report, and a warning for factors at a bound.
  summary.scaling_report =
      (static_trial ? "static trial, " : "motion window, ") + scaled.BriefReport();
  const std::string warning = ScalingBoundWarning(scaled, scaling_options, static_trial != nullptr);
  if (!warning.empty()) summary.warnings.push_back(warning);
  return seeds;
}

// The motion to fill: names, times, and room for F frames of q, fits and marker errors.
Motion MakeEmptyMotion(const dynamics::Model<double>& model,
                       const std::vector<ModelMarker>& markers,
                       double rate,
                       int F) {
  Motion motion;
  motion.coordinate_names = MakeCoordinateNames(model);
  motion.rate_hz = rate;
  motion.time_s.resize(F);
  for (int f = 0; f < F; ++f) motion.time_s[f] = f / rate;
  motion.q.resize(model.nq(), F);
  motion.fit.assign(size_t(F), FrameFit{});
  for (const ModelMarker& mk : markers) motion.marker_names.push_back(mk.name);
  motion.marker_error_m.setConstant(static_cast<int>(markers.size()), F, std::nan(""));
  return motion;
}

// Per-frame inverse kinematics into a motion, shared by the chunks' threads: each thread solves
// its own frames and writes only their columns of the motion and of the marker positions. Counts
// the frames solved (for the progress callback) and the swaps it repairs.
class FrameSolver {
 public:
  FrameSolver(const ReconstructionOptions& options,
              const std::vector<ModelMarker>& markers,
              const Eigen::Array<bool, 1, Eigen::Dynamic>& recorded,
              Eigen::Matrix3Xd& P,
              Motion& motion)
      : options_(options),
        markers_(markers),
        M_(static_cast<int>(markers.size())),
        F_(motion.num_frames()),
        recorded_(recorded),
        P_(P),
        motion_(motion) {}

  // Frame f's observations; the filled samples NaN unless options.fit_filled_samples.
  Eigen::Matrix3Xd Observations(int f) const {
    Eigen::Matrix3Xd obs = FrameObservations(P_, f, M_);
    if (!options_.fit_filled_samples)
      for (int m = 0; m < M_; ++m)
        if (!recorded_[Eigen::Index(f) * M_ + m]) obs.col(m).setConstant(std::nan(""));
    return obs;
  }

  // Solves frames begin, begin + step, … up to (not including) end, starting from q (cold unless
  // warm is set), writing into the motion; step −1 runs backwards in time.
  void SolveRange(
      InverseKinematics& ik, int begin, int end, Eigen::VectorXd q, bool warm, int step = 1) {
    int last_fitted = warm ? begin - step : -1000000;
    Eigen::Matrix3Xd predicted;
    Eigen::VectorXd dist;
    for (int f = begin; f != end && !stopped_; f += step) {
      Eigen::Matrix3Xd obs = Observations(f);
      const bool cold = std::abs(f - last_fitted) > 10;
      if (!cold && options_.repair_swaps) RepairSwapsByPrediction(ik, q, f, obs, predicted);
      const IkFrameResult r = ik.Solve(obs, q, cold);
      if (RecordFit(ik, f, r, obs, q, dist)) last_fitted = f;
      ReportProgress();
    }
  }

  // Takes back the progress of `frames` frames about to be solved again.
  void ForgetProgress(int frames) { done_ -= frames; }
  // Whether options.cancelled asked to stop (the frames after are not solved).
  bool stopped() const { return stopped_; }

  int swaps() const { return swaps_; }

 private:
  // Left/right swaps: a mirror pair whose exchange fits the prediction from q far better is
  // exchanged in the observations and in the marker positions.
  void RepairSwapsByPrediction(InverseKinematics& ik,
                               const Eigen::VectorXd& q,
                               int f,
                               Eigen::Matrix3Xd& obs,
                               Eigen::Matrix3Xd& predicted) {
    ik.CalcMarkerPositions(q, predicted);
    for (int m = 0; m < M_; ++m) {
      const int n = markers_[size_t(m)].mirror;
      if (n <= m || std::isnan(obs(0, m)) || std::isnan(obs(0, n))) continue;
      const double keep =
          (obs.col(m) - predicted.col(m)).norm() + (obs.col(n) - predicted.col(n)).norm();
      const double swap =
          (obs.col(m) - predicted.col(n)).norm() + (obs.col(n) - predicted.col(m)).norm();
      if (swap < options_.swap_ratio * keep && keep - swap > options_.swap_min_gain_m) {
        obs.col(m).swap(obs.col(n));
        P_.col(Eigen::Index(f) * M_ + m).swap(P_.col(Eigen::Index(f) * M_ + n));
        ++swaps_;
      }
    }
  }

  // Writes frame f's fit, marker errors (when valid) and pose into the motion; returns whether
  // the fit is valid (3 markers or more).
  bool RecordFit(InverseKinematics& ik,
                 int f,
                 const IkFrameResult& r,
                 const Eigen::Matrix3Xd& obs,
                 const Eigen::VectorXd& q,
                 Eigen::VectorXd& dist) {
    FrameFit& fit = motion_.fit[size_t(f)];
    fit.num_markers = r.num_markers;
    fit.iterations = r.iterations;
    fit.converged = r.converged;
    fit.valid = r.num_markers >= 3;
    fit.rms_m = r.rms_m;
    fit.max_m = r.max_m;
    if (fit.valid) {
      ik.Evaluate(obs, q, &dist);
      motion_.marker_error_m.col(f) = dist;
    }
    motion_.q.col(f) = q;
    return fit.valid;
  }

  // Counts a solved frame; calls options.progress (and asks options.cancelled) every 10 frames
  // and at the last.
  void ReportProgress() {
    const int d = ++done_;
    if ((options_.progress || options_.cancelled) && (d % 10 == 0 || d == F_)) {
      std::lock_guard<std::mutex> lock(progress_mutex_);
      if (options_.progress) options_.progress(d, F_);
      if (options_.cancelled && options_.cancelled()) stopped_ = true;
    }
  }

  const ReconstructionOptions& options_;
  const std::vector<ModelMarker>& markers_;
  const int M_;
  const int F_;
  const Eigen::Array<bool, 1, Eigen::Dynamic>& recorded_;
  Eigen::Matrix3Xd& P_;
  Motion& motion_;
  std::atomic<int> done_{0};
  std::atomic<int> swaps_{0};
  std::atomic<bool> stopped_{false};
  std::mutex progress_mutex_;
};

// The number of chunks: one per thread (options.num_threads, or the hardware's), at least
// options.min_chunk_frames frames each, at least one.
int CountChunks(const ReconstructionOptions& options, int F) {
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = options.num_threads > 0 ? options.num_threads : hw;
  return std::max(1, std::min(threads, F / options.min_chunk_frames));
}

// Solves the chunks [bounds[c], bounds[c + 1]) in parallel, one thread each. A pose fitted with
// the scale factors inside a chunk is the exact start: solve forward from its frame to the
// chunk's end and backward to its beginning. Otherwise the chunk is cold-started at its first
// frame.
void SolveChunksInParallel(const dynamics::Model<double>& model,
                           const std::vector<ModelMarker>& markers,
                           const std::vector<JointLimit>& limits,
                           const InverseKinematicsOptions& ik_options,
                           const std::vector<int>& bounds,
                           const std::vector<Seed>& seeds,
                           const Motion& motion,
                           FrameSolver& solver) {
  const int chunks = static_cast<int>(bounds.size()) - 1;
  std::vector<std::thread> workers;
  for (int c = 0; c < chunks; ++c) {
    workers.emplace_back([&, c]() {
      InverseKinematics ik(model, markers, limits, ik_options);
      const int b = bounds[size_t(c)], e = bounds[size_t(c) + 1];
      const Seed* seed = nullptr;
      for (const auto& sd : seeds)
        if (sd.first >= b && sd.first < e && seed == nullptr) seed = &sd;
      if (seed) {
        solver.SolveRange(ik, seed->first, e, seed->second, true, 1);
        solver.SolveRange(ik, seed->first - 1, b - 1, motion.q.col(seed->first), true, -1);
      } else {
        solver.SolveRange(ik, b, e, dynamics::MakeNeutralConfiguration(model), false);
      }
    });
  }
  for (std::thread& t : workers) t.join();
}

// Chunk joins: warm-solves each chunk's first frame from the previous chunk's last; if the cold
// start found another branch (a joint or the root more than 5° away), re-solves the chunk
// sequentially from there, else shifts the chunk's joint angles by the multiples of 2π that
// make them continuous. Returns the number of chunks re-solved.
int JoinChunks(const dynamics::Model<double>& model,
               const std::vector<ModelMarker>& markers,
               const std::vector<JointLimit>& limits,
               const InverseKinematicsOptions& ik_options,
               const std::vector<int>& bounds,
               FrameSolver& solver,
               Motion& motion) {
  const int chunks = static_cast<int>(bounds.size()) - 1;
  int resolved = 0;
  InverseKinematics ik(model, markers, limits, ik_options);
  for (int c = 1; c < chunks; ++c) {
    const int s = bounds[size_t(c)];
    if (!motion.fit[size_t(s - 1)].valid) continue;
    // The chunk's first frame warm-started from the previous one, against its cold start.
    Eigen::VectorXd q = motion.q.col(s - 1);
    const Eigen::Matrix3Xd obs = solver.Observations(s);
    ik.Solve(obs, q, false);
    Eigen::VectorXd cold = motion.q.col(s);
    UnwrapJoints(q, cold);
    const auto [dj, dr] = ConfigurationDistance(q, cold);
    if (dj > 5.0 * kPi / 180.0 || dr > 5.0 * kPi / 180.0) {
      // Another branch: re-solve the chunk from the previous chunk's last pose.
      solver.ForgetProgress(bounds[size_t(c) + 1] - s);
      solver.SolveRange(ik, s, bounds[size_t(c) + 1], motion.q.col(s - 1), true);
      ++resolved;
    } else {
      // Same branch: shift the whole chunk's joint angles by the same multiples of 2π.
      for (int f = s; f < bounds[size_t(c) + 1]; ++f) {
        Eigen::VectorXd qf = motion.q.col(f);
        UnwrapJoints(f == s ? q : Eigen::VectorXd(motion.q.col(f - 1)), qf);
        motion.q.col(f) = qf;
      }
    }
  }
  return resolved;
}

// Quaternion sign continuity (q and −q are the same orientation).
void MakeQuaternionSignsContinuous(Motion& motion) {
  for (int f = 1; f < motion.num_frames(); ++f)
    if (motion.q.col(f).segment<4>(3).dot(motion.q.col(f - 1).segment<4>(3)) < 0)
      motion.q.col(f).segment<4>(3) *= -1.0;
}

// Fit quality of the valid frames a–b (a flight).
FlightFit CalcFlightFit(const Motion& motion, int a, int b) {
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
  return ff;
}

// The views' keypoints as the marker set's markers (−1: not in the set).
std::vector<int> MarkersOfPoints(const ViewsToFit& views, const ReconstructionResult& result) {
  std::vector<int> marker_of_point;
  for (const std::string& name : views.names)
    marker_of_point.push_back(result.markerset.Find(name));
  return marker_of_point;
}

// The options' progress and cancellation as a step's Progress.
Progress StepProgress(const ReconstructionOptions& options) {
  Progress progress;
  if (options.progress || options.cancelled)
    progress.report = [&options](const std::string&, int done, int total) {
      if (options.progress) options.progress(done, total);
      return !(options.cancelled && options.cancelled());
    };
  return progress;
}

// The motion refitted to the views (view_fit.h).
ViewFitSummary FitToViews(const ViewsToFit& views,
                          const ReconstructionOptions& options,
                          ReconstructionResult& result) {
  const ReconstructionSummary& s = result.summary;
  ViewFitOptions fit = options.view_fit;
  if (fit.num_threads == 0) fit.num_threads = options.num_threads;
  return FitModelToViews(views,
                         MarkersOfPoints(views, result),
                         result.model,
                         result.markers,
                         result.joint_limits,
                         result.ik_options,
                         s.filtered ? s.cutoff_hz : 0.0,
                         s.filter_order,
                         result.motion.rate_hz,
                         fit,
                         &result.motion,
                         StepProgress(options));
}

// The flights known before the reconstruction, as frames (the first and last frame in the air),
// each refitted as one free flight (flight_physics.h).
FlightPhysicsSummary FitToPhysics(const ViewsToFit& views,
                                  const ReconstructionOptions& options,
                                  ReconstructionResult& result) {
  const Eigen::VectorXd& t = result.motion.time_s;
  std::vector<std::pair<int, int>> flights;
  for (const auto& [takeoff, landing] : options.ballistic_flights_s) {
    if (!std::isfinite(takeoff) || !std::isfinite(landing)) continue;  // partial: not a whole arc
    const auto first = std::upper_bound(t.data(), t.data() + t.size(), takeoff) - t.data();
    const auto end = std::lower_bound(t.data(), t.data() + t.size(), landing) - t.data();
    if (end - 1 > first) flights.push_back({int(first), int(end - 1)});
  }
  FlightPhysicsOptions physics = options.flight_physics;
  if (physics.num_threads == 0) physics.num_threads = options.num_threads;
  return FitFlightsToPhysics(views,
                             MarkersOfPoints(views, result),
                             result.model,
                             result.markers,
                             result.joint_limits,
                             result.ik_options,
                             flights,
                             physics,
                             &result.motion,
                             StepProgress(options));
}

void SummarizeFit(const Motion& motion,
                  const Eigen::Matrix3Xd& P,
                  int M,
                  ReconstructionSummary& summary) {
  const int F = motion.num_frames();
  summary.frames = F;
  for (const FrameFit& f : motion.fit) {
    summary.frames_fitted += f.valid;
    if (f.valid) summary.max_m = std::max(summary.max_m, f.max_m);
  }
  const std::vector<double> sorted = SortedFrameRms(motion);
  summary.median_rms_m = Percentile(sorted, 50);
  summary.p95_rms_m = Percentile(sorted, 95);
  for (const auto& [a, b] : FindFlights(P, M, motion.time_s))
    summary.flights.push_back(CalcFlightFit(motion, a, b));
  if (summary.frames_fitted < F)
    summary.warnings.push_back(std::to_string(F - summary.frames_fitted) +
                               " frames had fewer than 3 markers and hold the previous pose");
}

}  // namespace

ReconstructionResult Reconstruct(const capture::Trial& trial,
                                 const capture::Trial* static_trial,
                                 const AthleteBody& body,
                                 const ReconstructionOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(trial.source.path, "options", why);
  if (trial.num_frames < 1)
    throw InputError(trial.source.path, "", "the trial has no frame; the reconstruction needs 1");
  const double rate = trial.point_rate_hz;
  if (!(rate >= kMinReconstructionRateHz && rate <= kMaxReconstructionRateHz))
    throw InputError(
        trial.source.path,
        "rate",
        "a point rate of " + fmt::format("{:g}", rate) + " Hz is outside " +
            fmt::format("{:g}–{:g}", kMinReconstructionRateHz, kMaxReconstructionRateHz) +
            " Hz (docs/limits.md)");
  if (options.filter && options.cutoff_hz >= 0.5 * rate)
    throw InputError(
        trial.source.path,
        "cutoff",
        fmt::format("a cutoff of {:g} Hz is at or above the trial's Nyquist frequency, "
                    "{:g} Hz",
                    options.cutoff_hz,
                    0.5 * rate));
  ReconstructionResult result;
  ReconstructionSummary& summary = result.summary;
  if (rate > kPlausibleReconstructionRateHz)
    summary.warnings.push_back(
        fmt::format("a point rate of {:g} Hz is above what motion capture records ({:g} Hz); "
                    "check the file's rate",
                    rate,
                    kPlausibleReconstructionRateHz));

  // Marker set: given or detected; markers placed on the athlete's standard human.
  MarkerSetMatch match;
  result.markerset = ChooseMarkerSet(trial, options, &match);
  summary.markerset = result.markerset.name;
  summary.markerset_report = match.Report();
  const dynamics::Model<double> model0 = MakeStandardHumanModel(body);
  std::vector<ModelMarker> markers = PlaceMarkers(result.markerset, model0, body.height_m);
  const std::vector<JointLimit> limits = StandardJointLimits(model0);
  // What the set cannot see on this trial: said, and held at the reference pose.
  const std::vector<int> unseen = UnseenJointDofs(model0, markers, match);
  if (!unseen.empty()) {
    const std::vector<std::string> names = MakeCoordinateNames(model0);
    std::string list;
    for (const int j : unseen)
      list += (list.empty() ? "" : ", ") + names[size_t(dynamics::kRootNq + j)];
    summary.warnings.push_back("the " + result.markerset.name + " " +
                               (result.markerset.keypoints ? "keypoints" : "markers") +
                               " on this trial cannot see " + std::to_string(unseen.size()) +
                               " joint angles (" + list + ")" +
                               (result.markerset.keypoints ? ": held at the reference pose" : ""));
  }
  const InverseKinematicsOptions ik_options =
      MakeIkOptions(options, result.markerset, model0, unseen);
  const int M = static_cast<int>(markers.size());
  const int F = trial.num_frames;

  // The set's markers, frame-major, NaN where absent; left/right swaps in the raw data repaired.
  Eigen::Matrix3Xd& P = result.marker_positions;
  P = GatherMarkerPositions(trial, match, M);
  int continuity_swaps = 0;
  if (options.repair_swaps && !result.markerset.keypoints)
    continuity_swaps = RepairSwapsByContinuity(markers, options, F, P);

  // Samples absent from the recording (filled below for the filter and the exports).
  const Eigen::Array<bool, 1, Eigen::Dynamic> recorded = !P.row(0).array().isNaN();

  // Gap filling.
  if (options.fill_gaps) summary.gaps = FillMarkerGaps(markers, rate, options.gaps, P);

  // Zero-lag low-pass filter, the cutoff by Winter's residual analysis unless given.
  if (options.filter && F >= 3 * (options.filter_order + 1) && rate >= 8.0)
    FilterMarkers(options, rate, M, F, P, summary);

  // Scaling: to the static trial's mean frame, or to frames spread over a window of the motion.
  result.model = model0;
  std::vector<Seed> seeds;
  if (options.scale)
    seeds = ScaleToTrial(
        static_trial, model0, limits, ik_options, options, match.num_matched, F, markers, result);
  result.markers = markers;
  result.joint_limits = limits;
  result.ik_options = ik_options;
  result.recorded = recorded;

  // Inverse kinematics in chunks of frames solved in parallel, each from a scaling pose inside
  // it or cold-started at its first frame; then the chunks joined.
  const int chunks = CountChunks(options, F);
  summary.chunks = chunks;
  Motion& motion = result.motion;
  motion = MakeEmptyMotion(result.model, markers, rate, F);
  std::vector<int> bounds(size_t(chunks) + 1);
  for (int c = 0; c <= chunks; ++c) bounds[size_t(c)] = int(std::int64_t(F) * c / chunks);
  FrameSolver solver(options, markers, recorded, P, motion);
  SolveChunksInParallel(result.model, markers, limits, ik_options, bounds, seeds, motion, solver);
  if (solver.stopped()) throw Cancelled(trial.source.path + ": cancelled");
  summary.chunks_resolved =
      JoinChunks(result.model, markers, limits, ik_options, bounds, solver, motion);
  summary.swaps_repaired = solver.swaps() + continuity_swaps;
  if (options.views && options.fit_to_views)
    summary.view_fit = FitToViews(*options.views, options, result);
  if (options.views && options.fit_flight_physics && !options.ballistic_flights_s.empty()) {
    summary.flight_physics = FitToPhysics(*options.views, options, result);
    for (const std::string& w : summary.flight_physics->warnings)
      summary.warnings.push_back("flight physics: " + w);
  }
  MakeQuaternionSignsContinuous(motion);

  // Fit quality over the trial and per flight.
  SummarizeFit(motion, P, M, summary);
  return result;
}

}  // namespace acro::analysis
