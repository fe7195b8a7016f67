#include "acro/assess/trial_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/demand.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/capture/storage.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/reconstruct/motion_export.h"
#include "acro/reconstruct/view_fit.h"
#include "score_json.h"

namespace acro::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = std::numbers::pi / 180.0;

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Sole centre of each foot in its segment frame: the midpoint of the toe tip and the point below
// the ankle at toe height (the foot frame is parallel to H in the reference pose).
struct Soles {
  int segment[2] = {-1, -1};
  Eigen::Vector3d p_FoS_F[2];
};

Soles FindSoles(const dynamics::Model<double>& model) {
  Soles soles;
  const char* sides[2] = {"r", "l"};
  for (int s = 0; s < 2; ++s) {
    const int toe = model.FindPoint(std::string(sides[s]) + "_toe");
    ACRO_DEMAND(toe >= 0);
    const auto& p = model.point(toe);
    soles.segment[s] = p.segment;
    const Eigen::Vector3d toe_F = p.p_BoP_B;
    soles.p_FoS_F[s] = 0.5 * (toe_F + Eigen::Vector3d(0.0, 0.0, toe_F.z()));
  }
  return soles;
}

// Whole-body COM and the two sole centres on every frame.
void CalcComAndSoles(const dynamics::Model<double>& model,
                     const Motion& motion,
                     Eigen::Matrix3Xd& com,
                     Eigen::Matrix3Xd& soles_r,
                     Eigen::Matrix3Xd& soles_l) {
  const Soles soles = FindSoles(model);
  const int n = motion.num_frames();
  com.resize(3, n);
  soles_r.resize(3, n);
  soles_l.resize(3, n);
  dynamics::Workspace<double> ws(model);
  Eigen::VectorXd q(model.nq());
  for (int i = 0; i < n; ++i) {
    q = motion.q.col(i);
    dynamics::CalcForwardKinematics(model, ws, q);
    com.col(i) = dynamics::CalcCenterOfMassPosition(model, ws);
    for (int s = 0; s < 2; ++s) {
      const auto& X = ws.X_WB[static_cast<size_t>(soles.segment[s])];
      (s == 0 ? soles_r : soles_l).col(i) = X.rotation() * soles.p_FoS_F[s] + X.translation();
    }
  }
}

// Linear interpolation of the columns of x (sampled at `time_s`) at time t.
Eigen::Vector3d At(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& time_s, double t) {
  const int n = static_cast<int>(time_s.size());
  if (t <= time_s[0]) return x.col(0);
  if (t >= time_s[n - 1]) return x.col(n - 1);
  const int i =
      static_cast<int>(std::upper_bound(time_s.data(), time_s.data() + n, t) - time_s.data()) - 1;
  const double u = (t - time_s[i]) / (time_s[i + 1] - time_s[i]);
  return (1.0 - u) * x.col(i) + u * x.col(i + 1);
}

// What touches the bed at a landing at time t, in W: for the feet, the four corners of each sole
// (toe and heel, each ± half the sole's width across the foot); for the front or back, the two hip
// joint centres. The heel lies a quarter of the ankle-to-toe length behind the ankle and the sole
// is 38 % of the foot's length wide (de Leva 1996's foot: heel 20 % of the foot's length behind the
// lateral malleolus; breadth/length of adult feet about 0.38). Interpolated between the frames
// around t.
std::vector<Eigen::Vector3d> LandingContactsW(const dynamics::Model<double>& model,
                                              const Motion& motion,
                                              double t,
                                              fig::BodyPosition position) {
  std::vector<std::pair<int, Eigen::Vector3d>> local;  // segment, point in its frame
  if (position == fig::BodyPosition::kFeet) {
    for (const char* side : {"r", "l"}) {
      const int toe = model.FindPoint(std::string(side) + "_toe");
      ACRO_DEMAND(toe >= 0);
      const auto& p = model.point(toe);
      const Eigen::Vector3d toe_F = p.p_BoP_B;
      const double length = 1.25 * std::max(toe_F.x(), 0.0);
      const Eigen::Vector3d heel_F(toe_F.x() - length, toe_F.y(), toe_F.z());
      const Eigen::Vector3d half_width(0.0, 0.19 * length, 0.0);
      for (const Eigen::Vector3d& c : {Eigen::Vector3d(toe_F + half_width),
                                       Eigen::Vector3d(toe_F - half_width),
                                       Eigen::Vector3d(heel_F + half_width),
                                       Eigen::Vector3d(heel_F - half_width)})
        local.emplace_back(p.segment, c);
    }
  } else {
    for (const char* name : {"r_hip_jc", "l_hip_jc"}) {
      const int hip = model.FindPoint(name);
      ACRO_DEMAND(hip >= 0);
      local.emplace_back(model.point(hip).segment, model.point(hip).p_BoP_B);
    }
  }
  const int n = motion.num_frames();
  int i = static_cast<int>(std::upper_bound(motion.time_s.data(), motion.time_s.data() + n, t) -
                           motion.time_s.data()) -
          1;
  i = std::clamp(i, 0, std::max(0, n - 2));
  const int i1 = std::min(i + 1, n - 1);
  const double u =
      i1 == i
          ? 0.0
          : std::clamp((t - motion.time_s[i]) / (motion.time_s[i1] - motion.time_s[i]), 0.0, 1.0);
  dynamics::Workspace<double> ws(model);
  std::vector<Eigen::Vector3d> out(local.size(), Eigen::Vector3d::Zero());
  for (const auto& [frame, weight] :
       {std::pair<int, double>(i, 1.0 - u), std::pair<int, double>(i1, u)}) {
    const Eigen::VectorXd q = motion.q.col(frame);
    dynamics::CalcForwardKinematics(model, ws, q);
    for (size_t k = 0; k < local.size(); ++k) {
      const auto& X = ws.X_WB[static_cast<size_t>(local[k].first)];
      out[k] += weight * (X.rotation() * local[k].second + X.translation());
    }
  }
  return out;
}

// Total vertical ground reaction of all plates with outputs, per analog sample (empty if none).
Eigen::VectorXd TotalVerticalForce(const capture::Trial& trial) {
  Eigen::VectorXd fz;
  for (const capture::ForcePlate& p : trial.force_plates) {
    if (p.force_W_N.cols() == 0) continue;
    if (fz.size() == 0) fz = Eigen::VectorXd::Zero(p.force_W_N.cols());
    if (p.force_W_N.cols() != fz.size()) continue;
    fz += p.force_W_N.row(2).transpose();
  }
  return fz;
}

const char* DirectionName(fig::SomersaultDirection d) {
  switch (d) {
    case fig::SomersaultDirection::kForward:
      return "forward";
    case fig::SomersaultDirection::kBackward:
      return "backward";
    default:
      return "none";
  }
}

const char* ShapeName(fig::SkillShape s) {
  switch (s) {
    case fig::SkillShape::kTuck:
      return "tuck";
    case fig::SkillShape::kPike:
      return "pike";
    default:
      return "straight";
  }
}

}  // namespace

bool TrialAnalysisOptions::IsValid(std::string* why) const {
  if (!reconstruction.IsValid(why)) return false;
  if (!phases.IsValid(why)) return false;
  if (!check.IsValid(why)) return false;
  if (!noise_floor.IsValid(why)) return false;
  if (!rotation.IsValid(why)) return false;
  if (surface_height_m && !std::isfinite(*surface_height_m)) {
    if (why) *why = "surface_height_m must be a number";
    return false;
  }
  if (bed && !(bed->length_m > 0 && bed->width_m > 0 && bed->long_axis_W.norm() > 0.5)) {
    if (why) *why = "bed: length and width must be positive and the long axis a unit vector";
    return false;
  }
  if (!rules.IsValid(why)) return false;
  if (!execution.IsValid(why)) return false;
  if (!(std::isfinite(landing_uncertainty_m) && landing_uncertainty_m >= 0 &&
        landing_uncertainty_m <= 1)) {
    if (why) *why = "landing_uncertainty_m must be between 0 and 1 m";
    return false;
  }
  return true;
}

std::optional<BedGeometry> FindBed(const capture::Trial& trial) {
  // Static markers named BED…: their median positions.
  std::vector<Eigen::Vector3d> corners;
  std::vector<std::string> names;
  for (int p = 0; p < trial.num_points(); ++p) {
    const std::string& label = trial.points[static_cast<size_t>(p)].label;
    if (label.size() < 3) continue;
    std::string head = label.substr(0, 3);
    std::transform(head.begin(), head.end(), head.begin(), [](unsigned char c) {
      return static_cast<char>(std::toupper(c));
    });
    if (head != "BED" || trial.points[static_cast<size_t>(p)].type != capture::PointType::kMarker)
      continue;
    std::vector<double> xyz[3];
    for (int f = 0; f < trial.num_frames; ++f) {
      const auto c = trial.positions.col(static_cast<Eigen::Index>(f) * trial.num_points() + p);
      if (!std::isfinite(c[0])) continue;
      for (int k = 0; k < 3; ++k) xyz[k].push_back(c[k]);
    }
    if (2 * static_cast<int>(xyz[0].size()) < trial.num_frames) continue;
    Eigen::Vector3d median;
    for (int k = 0; k < 3; ++k) {
      auto mid = xyz[k].begin() + static_cast<long>(xyz[k].size() / 2);
      std::nth_element(xyz[k].begin(), mid, xyz[k].end());
      median[k] = *mid;
    }
    corners.push_back(median);
    names.push_back(label);
  }
  if (corners.size() != 4) return std::nullopt;
  BedGeometry bed;
  for (const Eigen::Vector3d& c : corners) bed.centre_W += 0.25 * c;
  // Order the corners by angle about the centre, so that 0–1–2–3 go round the rectangle.
  std::vector<int> order = {0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Eigen::Vector3d da = corners[static_cast<size_t>(a)] - bed.centre_W;
    const Eigen::Vector3d db = corners[static_cast<size_t>(b)] - bed.centre_W;
    return std::atan2(da.y(), da.x()) < std::atan2(db.y(), db.x());
  });
  auto corner = [&](int k) { return corners[static_cast<size_t>(order[static_cast<size_t>(k)])]; };
  // Opposite sides averaged: side a from corner 0 to 1 (and 3 to 2), side b from 1 to 2 (0 to 3).
  Eigen::Vector3d a = 0.5 * ((corner(1) - corner(0)) + (corner(2) - corner(3)));
  Eigen::Vector3d b = 0.5 * ((corner(2) - corner(1)) + (corner(3) - corner(0)));
  a.z() = 0.0;
  b.z() = 0.0;
  if (a.norm() < b.norm()) std::swap(a, b);
  if (b.norm() < 0.3) return std::nullopt;  // not a bed: the markers are not spread out
  bed.length_m = a.norm();
  bed.width_m = b.norm();
  bed.long_axis_W = a / a.norm();
  std::sort(names.begin(), names.end());
  bed.source = "markers " + names.front() + "–" + names.back();
  return bed;
}

namespace {

using Say = std::function<void(const std::string&)>;

// The soles' and the COM's paths over the motion (W).
struct BodyPaths {
  Eigen::Matrix3Xd com_W, sole_r, sole_l;
};

// 2. Phases: force plates when the trial has them, else the soles against the bed when the bed
// is known, else the whole-body COM.
BodyPaths FindPhases(const capture::Trial& trial,
                     const TrialAnalysisOptions& options,
                     const Say& progress,
                     TrialAnalysis* analysis) {
  TrialAnalysis& out = *analysis;
  const Motion& motion = out.reconstruction.motion;
  const dynamics::Model<double>& model = out.reconstruction.model;
  out.bed = options.bed ? options.bed : FindBed(trial);
  if (!out.bed) out.surface_height_m = options.surface_height_m;
  BodyPaths paths;
  CalcComAndSoles(model, motion, paths.com_W, paths.sole_r, paths.sole_l);
  out.feet_z_m = paths.sole_r.row(2).cwiseMin(paths.sole_l.row(2)).transpose();
  const Eigen::VectorXd com_z = paths.com_W.row(2).transpose();
  PhaseOptions phase_options = options.phases;
  phase_options.gravity_m_per_s2 = model.gravity_W().norm();
  const Eigen::VectorXd fz =
      options.use_force_plates ? TotalVerticalForce(trial) : Eigen::VectorXd();
  if (!options.given_flights_s.empty()) {
    out.phases = DetectFlightsFromIntervals(
        options.given_flights_s, motion.time_s, com_z, options.given_flights_source, phase_options);
  } else if (fz.size() > 0 && trial.analog_rate_hz > 0) {
    Eigen::VectorXd t(fz.size());
    for (Eigen::Index i = 0; i < fz.size(); ++i)
      t[i] = static_cast<double>(i) / trial.analog_rate_hz;
    out.phases = DetectFlightsFromForce(t, fz, motion.time_s, com_z, phase_options);
  } else if (const std::optional<double> surface = out.SurfaceHeight()) {  // bed or given
    out.phases = DetectFlightsFromFeet(motion.time_s, out.feet_z_m, *surface, com_z, phase_options);
  } else {
    // No surface known: the flights from the COM first, then the surface from the soles over the
    // contacts between them. A bed: the flights from the soles against it (the COM alone misses
    // the soft start and end of a bed's push by several frames). A floor: the COM's flights stay
    // (a rigid floor's push starts and ends sharply, and the model's sole point, the middle of
    // the foot, rises with the heel before the toes leave the floor).
    out.phases = DetectFlightsFromCom(motion.time_s, com_z, phase_options);
    out.surface =
        EstimateContactSurface(motion.time_s, out.feet_z_m, com_z, out.phases, phase_options);
    if (out.surface) {
      progress("phases: " + out.surface->Describe() + ", estimated from the soles and the COM");
      if (out.surface->gives_way) {
        out.phases = DetectFlightsFromFeet(
            motion.time_s, out.feet_z_m, out.surface->z_m, com_z, phase_options);
        out.phases.method = "feet, bed estimated";
      }
    }
  }
  return paths;
}

// 3. The physical check, judged against the trial's noise, localised when it fails.
void CheckTrialPhysics(const TrialAnalysisOptions& options,
                       const Say& progress,
                       const std::function<void()>& stop_if_cancelled,
                       TrialAnalysis* analysis) {
  TrialAnalysis& out = *analysis;
  const ReconstructionResult& rec = out.reconstruction;
  const Motion& motion = rec.motion;
  const dynamics::Model<double>& model = rec.model;
  out.check_options = options.check;
  out.check = CheckPhysics(
      model, motion, out.phases.flights, out.stature_m, rec.summary.cutoff_hz, options.check);
  const double noise = rec.summary.noise_rms_m;
  if (options.judge_against_noise && noise > 0 && !out.check.flights.empty()) {
    progress(fmt::format(
        "check: what {:.1f} mm of noise alone gives the {} flights (up to {} noisy copies each)",
        1e3 * noise,
        out.check.flights.size(),
        options.noise_floor.repetitions));
    NoiseFloorOptions noise_floor = options.noise_floor;
    if (!noise_floor.cancelled) noise_floor.cancelled = options.cancelled;
    const std::vector<FlightNoiseFloor> floors =
        CalcNoiseFloor(rec, out.check, noise, options.check, noise_floor);
    stop_if_cancelled();
    JudgeAgainstNoise(out.check,
                      floors,
                      noise,
                      rec.markerset.keypoints ? "video keypoints" : "markers",
                      options.check);
  }
  if (!out.check.pass && options.localise && rec.marker_positions.cols() > 0)
    LocalisePhysicsFailure(
        model, motion, rec.marker_positions, rec.markers, options.check, out.check);
  progress("check: " + out.check.verdict);
}

// The body's orientation and its mean hip and knee flexion per frame (for the shape).
struct PostureSeries {
  std::vector<Eigen::Quaterniond> q_WB;
  Eigen::VectorXd hip, knee;
};

PostureSeries MakePostureSeries(const Motion& motion) {
  const int n = motion.num_frames();
  PostureSeries out;
  out.q_WB.resize(static_cast<size_t>(n));
  out.hip.resize(n);
  out.knee.resize(n);
  const std::vector<std::string>& names = motion.coordinate_names;
  auto column = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  const int rh = column("r_hip_flexion"), lh = column("l_hip_flexion");
  const int rk = column("r_knee_flexion"), lk = column("l_knee_flexion");
  for (int i = 0; i < n; ++i) {
    out.q_WB[static_cast<size_t>(i)] =
        Eigen::Quaterniond(motion.q(3, i), motion.q(4, i), motion.q(5, i), motion.q(6, i))
            .normalized();
    // Anatomical flexion, mean of both sides: the model's hip flexion is a negative angle about y,
    // its knee flexion positive (docs/reconstruction.md).
    out.hip[i] = rh >= 0 && lh >= 0 ? -0.5 * (motion.q(rh, i) + motion.q(lh, i)) : 0.0;
    out.knee[i] = rk >= 0 && lk >= 0 ? 0.5 * (motion.q(rk, i) + motion.q(lk, i)) : 0.0;
  }
  return out;
}

// 4. One flight's metrics: feet at take-off and landing, displacement, landing in the bed,
// rotation, FIG code and difficulty, the flight's check and verdict.
JumpMetrics MeasureJump(const TrialAnalysis& out,
                        size_t k,
                        const BodyPaths& paths,
                        const PostureSeries& posture,
                        const TrialAnalysisOptions& options) {
  const Motion& motion = out.reconstruction.motion;
  const int n = motion.num_frames();
  const Eigen::Matrix3Xd& sole_r = paths.sole_r;
  const Eigen::Matrix3Xd& sole_l = paths.sole_l;
  const Flight& f = out.phases.flights[k];
  JumpMetrics j;
  j.index = static_cast<int>(k) + 1;
  j.flight = f;
  j.takeoff_feet_W =
      0.5 * (At(sole_r, motion.time_s, f.takeoff_s) + At(sole_l, motion.time_s, f.takeoff_s));
  j.landing_feet_W =
      0.5 * (At(sole_r, motion.time_s, f.landing_s) + At(sole_l, motion.time_s, f.landing_s));
  j.displacement_from_takeoff_m = (j.landing_feet_W - j.takeoff_feet_W).head<2>().norm();
  j.apex_above_bed_m = kNaN;
  j.displacement_from_centre_m = kNaN;
  j.landing_in_bed_m.setConstant(kNaN);
  if (const std::optional<double> surface = out.SurfaceHeight()) {
    j.apex_above_bed_m = f.apex_z_m - *surface;
  }
  if (out.bed) {
    const BedGeometry& bed = *out.bed;
    const Eigen::Vector3d d = j.landing_feet_W - bed.centre_W;
    const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(bed.long_axis_W);
    j.landing_in_bed_m = Eigen::Vector2d(d.dot(bed.long_axis_W), d.dot(across));
    j.displacement_from_centre_m = j.landing_in_bed_m.norm();
    j.landing_in_zone_a = std::abs(j.landing_in_bed_m.x()) <= 0.5 * fig::kZoneALength_m &&
                          std::abs(j.landing_in_bed_m.y()) <= 0.5 * fig::kZoneAWidth_m;
  }
  // Rotation over the frames that enclose the flight.
  const int first = std::clamp(f.takeoff_frame - 1, 0, n - 2);
  const int last = std::clamp(f.landing_frame, first + 1, n - 1);
  j.rotation =
      CountJumpRotation(posture.q_WB, first, last, posture.hip, posture.knee, options.rotation);
  // What touched the bed, in the bed's axes, by the landing position the rotation found.
  if (out.bed && !f.partial) {
    const BedGeometry& bed = *out.bed;
    const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(bed.long_axis_W);
    for (const Eigen::Vector3d& p : LandingContactsW(
             out.reconstruction.model, motion, f.landing_s, j.rotation.landing_position)) {
      const Eigen::Vector3d d = p - bed.centre_W;
      j.landing_contacts_in_bed_m.emplace_back(d.dot(bed.long_axis_W), d.dot(across));
    }
  }
  j.fig_code = fig::FormatFigCode(j.rotation.skill);
  j.skill_name = fig::FigSkillName(j.rotation.skill);
  j.difficulty = fig::CalcFigDifficulty(j.rotation.skill);
  // The check of this flight.
  for (const FlightCheck& fc : out.check.flights)
    if (fc.flight == static_cast<int>(k)) j.check = fc;
  if (j.partial()) {
    j.verdict = "not judged: partial flight";
  } else if (!j.check) {
    j.verdict = "not judged";
  } else if (j.check->pass) {
    j.verdict = j.check->judged_against_noise ? "pass within its noise" : "pass";
  } else {
    j.verdict = "fail: " + j.check->FailureText();
  }
  return j;
}

}  // namespace

TrialAnalysis AnalyzeTrial(const capture::Trial& trial,
                           const capture::Trial* static_trial,
                           const AthleteBody& body,
                           const TrialAnalysisOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError("", "analysis options", why);
  // Velocities need two frames: a trial that cannot give them is the user's line, never an
  // internal check failing further down (every door's pipeline checked this already).
  capture::DemandUsableContent(trial, trial.source.path, 2, "the analysis");
  auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto stop_if_cancelled = [&] {
    if (options.cancelled && options.cancelled())
      throw Cancelled(trial.source.path + ": cancelled");
  };
  TrialAnalysis out;
  out.trial_name = std::filesystem::path(trial.source.path).filename().string();
  out.stature_m = body.height_m;

  // 1. Reconstruction.
  auto start = std::chrono::steady_clock::now();
  progress(fmt::format("reconstruct: {} frames at {:g} Hz", trial.num_frames, trial.point_rate_hz));
  ReconstructionOptions reconstruction = options.reconstruction;
  if (!reconstruction.cancelled) reconstruction.cancelled = options.cancelled;
  out.reconstruction = Reconstruct(trial, static_trial, body, reconstruction);
  stop_if_cancelled();
  const ReconstructionResult& rec = out.reconstruction;
  out.mass_kg = rec.model.total_mass();
  for (const std::string& w : rec.summary.warnings) out.warnings.push_back(w);
  progress(fmt::format("reconstruct: marker RMS median {:.1f} mm, p95 {:.1f} mm ({:.2f} s)",
                       1e3 * rec.summary.median_rms_m,
                       1e3 * rec.summary.p95_rms_m,
                       Seconds(start)));
  // The fits' reports, line by line.
  std::string lines;
  if (rec.summary.view_fit) lines += rec.summary.view_fit->Report();
  if (rec.summary.flight_physics) lines += rec.summary.flight_physics->Report();
  for (size_t at = 0, end; at < lines.size(); at = end + 1) {
    end = lines.find('\n', at);
    if (end != at) progress("reconstruct: " + lines.substr(at, end - at));
    if (end == std::string::npos) break;
  }
  out.reconstruct_s = Seconds(start);

  // 2. Phases.
  start = std::chrono::steady_clock::now();
  const BodyPaths paths = FindPhases(trial, options, progress, &out);
  int complete = 0;
  for (const Flight& f : out.phases.flights) complete += f.partial ? 0 : 1;
  progress("phases: " + std::to_string(out.phases.flights.size()) + " flights (" +
           std::to_string(complete) + " complete) from the " + out.phases.method);
  stop_if_cancelled();

  // 3. Physical check.
  CheckTrialPhysics(options, progress, stop_if_cancelled, &out);
  out.check_s = Seconds(start);
  stop_if_cancelled();

  // 4. Jump metrics per flight.
  start = std::chrono::steady_clock::now();
  const PostureSeries posture = MakePostureSeries(out.reconstruction.motion);
  for (size_t k = 0; k < out.phases.flights.size(); ++k) {
    JumpMetrics j = MeasureJump(out, k, paths, posture, options);
    if (!j.partial()) {
      ++out.num_scored;
      out.total_difficulty += j.difficulty.total();
      out.total_time_of_flight_s += j.time_of_flight_s();
    }
    out.jumps.push_back(std::move(j));
  }
  // The execution assistant's uncertainties for this trial's noise (markers keep theirs).
  out.execution_options = options.execution.scale_with_noise
                              ? options.execution.WithNoise(out.check.noise_rms_m)
                              : options.execution;
  if (const auto& views = options.reconstruction.views; views && views->views.size() == 1)
    out.execution_options.single_camera_centre_W = views->views[0].camera.CentreInWorld();
  for (size_t k = 0; k < out.jumps.size(); ++k)
    out.jumps[k].execution =
        MeasureExecution(out, k, options.rules.execution, out.execution_options);
  out.score = ScoreTrial(out, options.rules, options.landing_uncertainty_m);
  out.metrics_s = Seconds(start);
  progress(fmt::format("metrics: {} skills, DD {:.1f}, time of flight {:.3f} s",
                       out.num_scored,
                       out.total_difficulty,
                       out.total_time_of_flight_s));
  return out;
}

std::optional<double> TrialAnalysis::SurfaceHeight() const {
  if (bed) return bed->centre_W.z();
  if (surface_height_m) return surface_height_m;
  if (surface) return surface->z_m;
  return std::nullopt;
}

std::string TrialAnalysis::SurfaceSource() const {
  if (bed) return fmt::format("bed at rest {:.3f} m from {}", bed->centre_W.z(), bed->source);
  if (surface_height_m) return fmt::format("surface at {:.3f} m given", *surface_height_m);
  if (surface) return surface->Describe() + ", estimated from the soles and the COM";
  return "no surface known";
}

std::string TrialAnalysis::BriefReport() const {
  std::ostringstream s;
  s << "surface: " << SurfaceSource() << "\n";
  s << fmt::format("routine: {} skills, DD {:.1f}, time of flight {:.3f} s\n",
                   num_scored,
                   total_difficulty,
                   total_time_of_flight_s);
  s << fmt::format("score ({}): D {:.1f}  T {:.3f}  H {}",
                   score.rules_name,
                   score.difficulty,
                   score.time_of_flight,
                   score.horizontal_displacement
                       ? fmt::format("{:.2f}", *score.horizontal_displacement)
                       : std::string("- (no bed)"));
  if (score.interrupted) s << "  (" << score.interruption << ")";
  s << "\n";
  for (const std::string& m : score.requirements_missing)
    s << "  requirement not performed: " << m << "\n";
  for (const std::string& b : score.rule_breaks) s << "  " << b << "\n";
  s << "physical check: " << check.verdict << "\n";
  for (const Finding& f : check.findings) s << "  cause: " << f.text << "\n";
  for (const JumpMetrics& j : jumps) {
    s << fmt::format("  {:2} ", j.index) << (j.partial() ? "(partial) " : "") << j.fig_code;
    if (!j.skill_name.empty()) s << " " << j.skill_name;
    s << fmt::format("  ToF {:.3f} s  apex {:.2f} m", j.time_of_flight_s(), j.apex_m());
    if (!j.partial()) s << fmt::format("  DD {:.1f}", j.difficulty.total());
    s << "  " << j.verdict << "\n";
  }
  return s.str();
}

FlightRotation CalcFlightRotation(const TrialAnalysis& analysis, int jump) {
  const Motion& m = analysis.reconstruction.motion;
  for (const JumpMetrics& j : analysis.jumps) {
    if (j.index != jump) continue;
    const int first = std::clamp(j.flight.takeoff_frame, 0, m.num_frames() - 1);
    return CalcMotionRotation(
        m, first, std::clamp(j.flight.landing_frame, first, m.num_frames() - 1));
  }
  return {};
}

FlightRotation CalcMotionRotation(const Motion& m, int first, int last) {
  FlightRotation out;
  if (first < 0 || last < first || last >= m.num_frames()) return out;
  std::vector<Eigen::Quaterniond> q_WB;
  for (int f = first; f <= last; ++f) q_WB.push_back(dynamics::GetRootQuaternion(m.q.col(f)));
  // The somersault axis: the pelvis's lateral axis at take-off, as the jump metrics count it.
  const RotationAngles angles = CalcRotationAngles(q_WB, q_WB.front() * Eigen::Vector3d::UnitY());
  constexpr double kDeg = 180.0 / std::numbers::pi;
  for (int f = first; f <= last; ++f) {
    const Eigen::Index k = f - first;
    out.frames.push_back(f);
    out.somersault_deg.push_back((angles.somersault_rad(k) - angles.somersault_rad(0)) * kDeg);
    out.twist_deg.push_back((angles.twist_rad(k) - angles.twist_rad(0)) * kDeg);
  }
  return out;
}

Eigen::Vector3d CalcFeetCentre(const dynamics::Model<double>& model, const Eigen::VectorXd& q) {
  const Soles soles = FindSoles(model);
  dynamics::Workspace<double> ws(model);
  dynamics::CalcForwardKinematics(model, ws, q);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int s = 0; s < 2; ++s) {
    const auto& X = ws.X_WB[static_cast<size_t>(soles.segment[s])];
    sum += X.rotation() * soles.p_FoS_F[s] + X.translation();
  }
  return 0.5 * sum;
}

std::string FormatJumpsJson(const TrialAnalysis& a) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  Json jumps = Json::array();
  for (const JumpMetrics& j : a.jumps) {
    // Flight, feet and landing place.
    Json o;
    o["index"] = j.index;
    o["partial"] = j.partial();
    o["takeoff_s"] = j.flight.takeoff_s;
    o["landing_s"] = j.flight.landing_s;
    o["takeoff_frame"] = j.flight.takeoff_frame;
    o["landing_frame"] = j.flight.landing_frame;
    o["time_of_flight_s"] = j.time_of_flight_s();
    o["apex_m"] = j.apex_m();
    o["apex_above_bed_m"] = j.apex_above_bed_m;
    o["surface"] = a.SurfaceSource();
    o["takeoff_vertical_velocity_m_per_s"] = j.takeoff_vertical_velocity_m_per_s();
    o["fitted_gravity_m_per_s2"] = j.flight.fitted_gravity_m_per_s2;
    o["takeoff_feet_m"] = {j.takeoff_feet_W.x(), j.takeoff_feet_W.y(), j.takeoff_feet_W.z()};
    o["landing_feet_m"] = {j.landing_feet_W.x(), j.landing_feet_W.y(), j.landing_feet_W.z()};
    o["displacement_from_takeoff_m"] = j.displacement_from_takeoff_m;
    o["displacement_from_centre_m"] = j.displacement_from_centre_m;
    o["landing_in_bed_m"] = {j.landing_in_bed_m.x(), j.landing_in_bed_m.y()};
    o["landing_in_zone_a"] = j.landing_in_zone_a ? Json(*j.landing_in_zone_a) : Json(nullptr);
    // The skill and its difficulty.
    const fig::FigSkill& skill = j.rotation.skill;
    o["somersault_quarters"] = skill.quarter_somersaults;
    o["direction"] = DirectionName(skill.direction);
    o["twist_halves"] = skill.half_twists;
    o["twist_direction"] = TwistDirectionName(TwistDirectionOf(j.rotation));
    o["shape"] = ShapeName(skill.shape);
    o["fig_code"] = j.fig_code;
    o["skill_name"] = j.skill_name;
    o["difficulty"] = j.difficulty.total();
    o["difficulty_explained"] = j.difficulty.Explain();
    o["measured_somersault_deg"] = j.rotation.measured_somersault_rad / kDeg;
    o["measured_twist_deg"] = j.rotation.measured_twist_rad / kDeg;
    o["max_hip_flexion_deg"] = j.rotation.max_hip_flexion_deg;
    o["knee_flexion_at_max_hip_deg"] = j.rotation.knee_flexion_at_max_hip_deg;
    o["shape_hold_fraction"] = j.rotation.shape_hold_fraction;
    o["shape_reason"] = j.rotation.shape_reason;
    o["shape_alternative"] =
        j.rotation.shape_alternative.empty() ? Json(nullptr) : Json(j.rotation.shape_alternative);
    o["verdict"] = j.verdict;
    o["silhouette_iou"] = j.silhouette_iou ? Json(*j.silhouette_iou) : Json(nullptr);
    // Its line on the score sheet, when it is one of the routine's elements.
    o["score"] = nullptr;
    for (const fig::ScoredElement& e : a.score.elements)
      if (e.flight == j.index) o["score"] = ElementScoreJson(e);
    // The physical check of the flight, when it was judged.
    if (j.check) {
      const FlightCheck& c = *j.check;
      o["check"] = {{"peak_force_bw", c.peak_force_bw},
                    {"rms_force_bw", c.rms_force_bw},
                    {"peak_moment_bwh", c.peak_moment_bwh},
                    {"rms_moment_bwh", c.rms_moment_bwh},
                    {"angular_momentum_kg_m2_per_s", c.mean_angular_momentum},
                    {"momentum_variation", c.momentum_variation},
                    {"fitted_gravity_m_per_s2", c.fitted_gravity_m_per_s2},
                    {"max_marker_error_m", c.max_marker_error_m},
                    {"window_force_bw", c.window_force_bw},
                    {"window_moment_bwh", c.window_moment_bwh}};
      // What the trial's noise alone gives these measures (docs/physical-check.md), when judged
      // against it.
      o["check"]["noise_floor"] =
          c.noise ? Json{{"window_force_bw", c.noise->window_force_bw},
                         {"window_moment_bwh", c.noise->window_moment_bwh},
                         {"momentum_variation", c.noise->momentum_variation},
                         {"gravity_error_m_per_s2", c.noise->gravity_error_m_per_s2},
                         {"max_marker_error_m", c.noise->max_marker_error_m},
                         {"judged_against_noise", c.judged_against_noise}}
                  : Json(nullptr);
    }
    jumps.push_back(std::move(o));
  }
  // Names come from files (trial, athlete, skills): bytes that are not UTF-8 become U+FFFD.
  return jumps.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string FormatResidualsCsv(const TrialAnalysis& a) {
  const Motion& m = a.reconstruction.motion;
  const FrameDynamics& f = a.check.frames;
  // Phase label per frame: "flight k" between take-off and landing frames, else "contact".
  std::vector<int> flight_of(static_cast<size_t>(m.num_frames()), 0);
  for (size_t k = 0; k < a.phases.flights.size(); ++k)
    for (int i = std::max(0, a.phases.flights[k].takeoff_frame);
         i < std::min(m.num_frames(), a.phases.flights[k].landing_frame);
         ++i)
      flight_of[static_cast<size_t>(i)] = static_cast<int>(k) + 1;
  std::string out =
      "time_s,phase,force_x_bw,force_y_bw,force_z_bw,force_bw,moment_x_bwh,moment_y_bwh,"
      "moment_z_bwh,moment_bwh,L_x_kg_m2_per_s,L_y_kg_m2_per_s,L_z_kg_m2_per_s,com_x_m,com_y_m,"
      "com_z_m,lowest_sole_z_m\n";
  for (int i = 0; i < m.num_frames(); ++i) {
    const int k = flight_of[static_cast<size_t>(i)];
    const std::string phase = k > 0 ? "flight " + std::to_string(k) : "contact";
    out += fmt::format(
        "{:.6f},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:."
        "6f},"
        "{:.6f},{:.6f},{:.6f}\n",
        m.time_s[i],
        phase,
        f.force_bw(0, i),
        f.force_bw(1, i),
        f.force_bw(2, i),
        f.force_bw.col(i).norm(),
        f.moment_bwh(0, i),
        f.moment_bwh(1, i),
        f.moment_bwh(2, i),
        f.moment_bwh.col(i).norm(),
        f.angular_momentum(0, i),
        f.angular_momentum(1, i),
        f.angular_momentum(2, i),
        f.com_W(0, i),
        f.com_W(1, i),
        f.com_W(2, i),
        a.feet_z_m[i]);
  }
  return out;
}

capture::Storage MakeTorqueStorage(const TrialAnalysis& a) {
  const Motion& m = a.reconstruction.motion;
  capture::Storage s;
  s.name = "joint torques (inverse dynamics, N·m)";
  s.in_degrees = false;
  s.time_s = m.time_s;
  for (size_t c = 7; c < m.coordinate_names.size(); ++c)
    s.labels.push_back(m.coordinate_names[c] + "_moment");
  s.data = a.check.frames.joint_torque_Nm.transpose();
  return s;
}

void WriteAnalysisTables(const TrialAnalysis& a, const std::filesystem::path& dir) {
  WriteFileAtomically(dir / "jumps.json", FormatJumpsJson(a));
  WriteFileAtomically(dir / "score.json", FormatScoreJson(a.score));
  WriteMotionMot(a.reconstruction.motion, dir / "angles.mot");
  capture::WriteStorage(MakeTorqueStorage(a), dir / "torques.sto", capture::StorageFlavor::kSto);
  WriteFileAtomically(dir / "residuals.csv", FormatResidualsCsv(a));
}

}  // namespace acro::analysis
