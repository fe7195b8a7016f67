#include "acro/report/analysis_report.h"

#include <algorithm>

#include <fmt/format.h>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "acro/assess/jump_rotation.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/text_format.h"
#include "acro/dynamics/configuration.h"
#include "html_page.h"

namespace acro::ui {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr Rgb kBlue{0.12, 0.47, 0.71};
constexpr Rgb kOrange{1.0, 0.5, 0.05};
constexpr Rgb kGreen{0.17, 0.63, 0.17};
constexpr Rgb kRed{0.84, 0.15, 0.16};
constexpr Rgb kGrey{0.4, 0.4, 0.4};
constexpr Rgb kFlightBand{0.3, 0.6, 1.0};

std::vector<double> ToVector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// A chart over the trial's time axis with the flights shaded.
Chart TimeChart(const analysis::TrialAnalysis& a, std::string title, std::string y_label) {
  Chart c;
  c.title = std::move(title);
  c.x_label = "time (s)";
  c.y_label = std::move(y_label);
  for (const analysis::Flight& f : a.phases.flights) {
    ShadedInterval band;
    band.x0 = f.takeoff_s;
    band.x1 = f.landing_s;
    band.color = kFlightBand;
    band.alpha = f.partial ? 0.08 : 0.18;
    band.label = "flight";
    c.bands.push_back(band);
  }
  return c;
}

LineSeries Series(std::string name, std::vector<double> x, std::vector<double> y, Rgb color) {
  LineSeries s;
  s.name = std::move(name);
  s.x = std::move(x);
  s.y = std::move(y);
  s.color = color;
  return s;
}

// The values of a per-frame row only in the judged flight frames (NaN elsewhere), so a plot of
// flight residuals is not dominated by the bed's reaction.
std::vector<double> InFlights(const analysis::TrialAnalysis& a, const Eigen::VectorXd& row) {
  std::vector<double> out(static_cast<size_t>(row.size()),
                          std::numeric_limits<double>::quiet_NaN());
  for (const analysis::FlightCheck& f : a.check.flights)
    for (int i = f.first_frame; i <= f.last_frame && i < row.size(); ++i)
      out[static_cast<size_t>(i)] = row[i];
  return out;
}

// "0.20 s" for the residual's averaging window.
std::string Window(const analysis::TrialAnalysis& a) {
  return FormatFixed(a.check_options.residual_window_s, 2) + " s";
}

// A residual over time: single frames (thin), the judged window means (bold) and the limit.
Chart ResidualChart(const analysis::TrialAnalysis& a,
                    std::string title,
                    std::string y_label,
                    const std::string& symbol,
                    std::vector<double> per_frame,
                    const Eigen::VectorXd& window_mean,
                    double limit) {
  Chart c = TimeChart(a, std::move(title), std::move(y_label));
  LineSeries frames = Series(symbol + " per frame",
                             ToVector(a.reconstruction.motion.time_s),
                             std::move(per_frame),
                             {0.95, 0.6, 0.6});
  frames.width_px = 1.0;
  c.series.push_back(frames);
  c.series.push_back(Series(symbol + ", " + Window(a) + " mean (judged)",
                            ToVector(a.reconstruction.motion.time_s),
                            ToVector(window_mean),
                            kRed));
  ReferenceLine line;
  line.y = limit;
  line.label = "limit";
  c.reference_lines.push_back(line);
  return c;
}

// Fixed-point, "–" for a missing value, and no "-0" for a value that rounds to zero.
std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "–";
  std::string text = FormatFixed(v, digits);
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

// The flight's twist as a coach reads it: "362 left" (degrees, the way she turned), or the signed
// degrees alone when no half twist was counted.
std::string TwistCell(const analysis::JumpRotation& rotation) {
  const fig::TwistDirection d = analysis::TwistDirectionOf(rotation);
  if (d == fig::TwistDirection::kNone) return Fixed(rotation.measured_twist_rad * kRadToDeg, 0);
  return Fixed(std::abs(rotation.measured_twist_rad) * kRadToDeg, 0) + "\u00a0" +  // no break
         analysis::TwistDirectionName(d);
}

// "com_height.svg" for "com_height.png".
std::string SvgName(const std::string& png) {
  return std::filesystem::path(png).replace_extension(".svg").string();
}

std::string Html(const std::string& s) {
  return HtmlEscape(s);
}

}  // namespace

namespace {

// Root residuals in flight against their thresholds, and the angular momentum.
void AddFlightFigures(const analysis::TrialAnalysis& a,
                      const std::vector<double>& t,
                      std::vector<ReportFigure>& out) {
  const analysis::FrameDynamics& f = a.check.frames;
  const Eigen::VectorXd force = f.force_bw.colwise().norm().transpose();
  const Eigen::VectorXd moment = f.moment_bwh.colwise().norm().transpose();
  const bool judged = !a.check.flights.empty();
  if (judged)
    out.push_back({"residual_force.png",
                   "Residual force at the COM over the judged flight frames, in body weights: per "
                   "frame and averaged over the window the verdict judges. Gravity is the only "
                   "external force in flight, so it should be zero.",
                   ResidualChart(a,
                                 "Root residual force in flight",
                                 "|F| / body weight",
                                 "|F|",
                                 InFlights(a, force),
                                 a.check.window_force_bw,
                                 a.check_options.max_force_bw)});
  if (judged)
    out.push_back({"residual_moment.png",
                   "Residual moment about the COM over the judged flight frames, in body weight × "
                   "stature, per frame and averaged as judged.",
                   ResidualChart(a,
                                 "Root residual moment in flight",
                                 "|M| / (body weight × height)",
                                 "|M|",
                                 InFlights(a, moment),
                                 a.check.window_moment_bwh,
                                 a.check_options.max_moment_bwh)});
  if (judged) {
    Chart c = TimeChart(a, "Angular momentum about the centre of mass", "kg·m²/s");
    const Eigen::Matrix3Xd& L = f.angular_momentum;
    c.series.push_back(Series("|L|", t, InFlights(a, L.colwise().norm().transpose()), kBlue));
    c.series.push_back(Series("L_x", t, InFlights(a, L.row(0).transpose()), kOrange));
    c.series.push_back(Series("L_y", t, InFlights(a, L.row(1).transpose()), kGreen));
    c.series.push_back(Series("L_z", t, InFlights(a, L.row(2).transpose()), kGrey));
    out.push_back({"angular_momentum.png",
                   "Angular momentum about the COM in the lab frame over the judged flight frames: "
                   "constant in each flight for a physically consistent capture.",
                   c});
  }
}

// The chosen joint: angle and torque over the whole trial.
void AddJointFigures(const analysis::TrialAnalysis& a,
                     const AnalysisReportOptions& options,
                     const std::vector<double>& t,
                     std::vector<ReportFigure>& out) {
  const analysis::Motion& m = a.reconstruction.motion;
  const analysis::FrameDynamics& f = a.check.frames;
  const auto it = std::find(m.coordinate_names.begin(), m.coordinate_names.end(), options.joint);
  const int row =
      it == m.coordinate_names.end() ? -1 : static_cast<int>(it - m.coordinate_names.begin());
  if (row < 7) {
    std::string names;
    for (size_t k = 7; k < m.coordinate_names.size() && k < 12; ++k)
      names += (k > 7 ? ", " : "") + m.coordinate_names[k];
    throw InputError("",
                     "--joint",
                     "'" + options.joint + "' is not a joint coordinate (e.g. " + names +
                         ", …; docs/reconstruction.md)");
  }
  {
    Chart c = TimeChart(a, "Joint angle: " + options.joint, "degrees");
    std::vector<double> y(t.size());
    for (size_t i = 0; i < t.size(); ++i) y[i] = m.q(row, static_cast<Eigen::Index>(i)) * kRadToDeg;
    c.series.push_back(Series(options.joint, t, y, kBlue));
    out.push_back(
        {"joint_angle.png", "Angle of " + options.joint + " (model sign convention).", c});
  }
  {
    Chart c = TimeChart(a, "Joint torque: " + options.joint, "N·m");
    c.series.push_back(Series(options.joint + " torque",
                              t,
                              ToVector(f.joint_torque_Nm.row(row - dynamics::kRootNq).transpose()),
                              kOrange));
    out.push_back({"joint_torque.png",
                   "Net torque about the " + options.joint + " axis from inverse dynamics.",
                   c});
  }
}

// The silhouettes' IoU over the video, and each flight's somersault and twist.
void AddVideoAndRotationFigures(const analysis::TrialAnalysis& a,
                                const AnalysisReportOptions& options,
                                const std::vector<double>& t,
                                std::vector<ReportFigure>& out) {
  if (!options.silhouette_iou.empty()) {
    Chart c = TimeChart(a, "Silhouettes: video against reconstruction", "IoU");
    LineSeries s =
        Series("IoU per video frame", options.silhouette_time_s, options.silhouette_iou, kBlue);
    s.line = false;
    s.markers = true;
    c.series.push_back(s);
    c.y_range = ValueRange{0.0, 1.0};
    c.reference_lines.push_back({0.85, "0.85", kGrey, true});
    out.push_back({"silhouette_iou.png",
                   "Intersection over union of the athlete cut out of the video and the "
                   "reconstructed athlete projected by the camera, per video frame in flight: a "
                   "drop shows a wrong sync, calibration or reconstruction (docs/overlay.md).",
                   c});
  }
  // Somersault and twist of every flight from its take-off (what the FIG code counts).
  if (!a.jumps.empty()) {
    Chart c = TimeChart(a, "Somersault (solid) and twist (dashed) from each take-off", "degrees");
    std::vector<double> somersault(t.size(), std::numeric_limits<double>::quiet_NaN());
    std::vector<double> twist = somersault;
    for (const analysis::JumpMetrics& j : a.jumps) {
      const analysis::FlightRotation r = analysis::CalcFlightRotation(a, j.index);
      for (size_t k = 0; k < r.frames.size(); ++k) {
        somersault[size_t(r.frames[k])] = r.somersault_deg[k];
        twist[size_t(r.frames[k])] = r.twist_deg[k];
      }
    }
    c.series.push_back(Series("somersault", t, somersault, kBlue));
    LineSeries tw = Series("twist", t, twist, kOrange);
    tw.dashed = true;
    c.series.push_back(tw);
    out.push_back({"rotation.png",
                   "Somersault (about the pelvis's lateral axis at take-off) and twist of every "
                   "flight, from 0 at its take-off: a back somersault is −360°, a full twist "
                   "360°.",
                   c});
  }
}

}  // namespace

// The execution assistant's measurements per element (docs/scoring.md): each fault's worst value as
// a multiple of its rule's first threshold (1 = where the first deduction begins; for the opening,
// whose smaller values are worse, the threshold over the value), so that faults of degrees, metres
// and seconds share one axis; the uncertainty band shows as the dashed line above 1.
void AddExecutionFigure(const analysis::TrialAnalysis& a, std::vector<ReportFigure>& out) {
  const fig::RoutineScore& s = a.score;
  if (s.elements.empty()) return;
  std::vector<std::string> faults;  // in the order first measured
  for (const fig::ScoredElement& e : s.elements)
    for (const fig::MeasuredFault& f : e.faults)
      if (!std::isnan(f.ThresholdRatio()) &&
          std::find(faults.begin(), faults.end(), f.fault) == faults.end())
        faults.push_back(f.fault);
  if (faults.empty()) return;
  static const Rgb kColors[] = {kBlue,
                                kOrange,
                                kGreen,
                                kRed,
                                {0.58, 0.4, 0.74},
                                {0.55, 0.34, 0.29},
                                {0.89, 0.47, 0.76},
                                kGrey,
                                {0.74, 0.74, 0.13},
                                {0.09, 0.75, 0.81}};
  Chart c;
  c.title = "Execution: each fault measured, per element";
  c.x_label = "element";
  c.y_label = "worst value / first threshold";
  double top = 1.5;
  for (size_t k = 0; k < faults.size(); ++k) {
    LineSeries series;
    series.markers = true;
    series.line = false;
    series.color = kColors[k % std::size(kColors)];
    for (const fig::ScoredElement& e : s.elements)
      for (const fig::MeasuredFault& f : e.faults) {
        const double ratio = f.ThresholdRatio();
        if (f.fault != faults[k] || std::isnan(ratio)) continue;
        series.x.push_back(e.element + 0.06 * (double(k) - 0.5 * double(faults.size() - 1)));
        series.y.push_back(std::clamp(ratio, -0.5, 10.0));
        top = std::max(top, std::min(ratio, 10.0) + 0.2);
        if (series.name.empty())
          series.name = fmt::format("{} (1 = {:g} {})", f.fault, f.threshold, f.unit);
      }
    c.series.push_back(std::move(series));
  }
  ReferenceLine first;
  first.y = 1.0;
  first.label = "first deduction (0.1)";
  first.color = kRed;
  c.reference_lines.push_back(first);
  c.x_range = ValueRange{0.5, double(s.elements.size()) + 0.5};
  c.y_range = ValueRange{0.0, top};
  c.height_px = 420;
  out.push_back(
      {"execution.png",
       "The execution assistant's measurements: for every element, each fault's worst value "
       "over the element as a multiple of the rule file's first threshold (1: where its first "
       "deduction begins; the opening's time before landing inverted, smaller being worse). A "
       "fault is reported only past 1 by more than the measurement's uncertainty; the values "
       "are in the score sheet above and in score.json.",
       c});
}

std::vector<ReportFigure> MakeAnalysisFigures(const analysis::TrialAnalysis& a,
                                              const AnalysisReportOptions& options) {
  const analysis::Motion& m = a.reconstruction.motion;
  const std::vector<double> t = ToVector(m.time_s);
  std::vector<ReportFigure> out;

  // COM height and the lowest sole with the phases.
  {
    Chart c = TimeChart(a, "Centre of mass and feet", "height (m)");
    c.series.push_back(
        Series("COM height", t, ToVector(a.check.frames.com_W.row(2).transpose()), kBlue));
    c.series.push_back(Series("lowest sole", t, ToVector(a.feet_z_m), kGreen));
    if (const std::optional<double> surface = a.SurfaceHeight()) {
      ReferenceLine bed;
      bed.y = *surface;
      bed.label = a.surface && !a.bed && !a.surface_height_m
                      ? (a.surface->gives_way ? "bed at rest (estimated)" : "floor (estimated)")
                      : "bed at rest";
      c.reference_lines.push_back(bed);
    }
    out.push_back(
        {"com_height.png", "Whole-body centre of mass and the lowest sole; flights shaded.", c});
  }

  AddFlightFigures(a, t, out);
  AddJointFigures(a, options, t, out);
  AddVideoAndRotationFigures(a, options, t, out);
  AddExecutionFigure(a, out);
  return out;
}

namespace {

// The physical check: verdict, noise, what drives a failure, the mass suggestion, thresholds.
void WriteCheckSection(const analysis::TrialAnalysis& a, std::ostringstream& h) {
  h << "<h2>Physical check</h2>\n<p class=\"" << (a.check.pass ? "pass" : "fail") << "\"><b>"
    << Html(a.check.verdict) << "</b></p>\n";
  if (a.check.noise_rms_m > 0)
    h << "<p>Measurement noise of this trial: about " << Fixed(1e3 * a.check.noise_rms_m, 1)
      << " mm per coordinate (" << Html(a.check.data_class)
      << "; Winter's residual analysis). Each flight is judged against what that noise alone "
         "gives its residuals after the same filter, fit and differences: a criterion fails only "
         "beyond both its threshold and "
      << Fixed(a.check_options.noise_factor, 1) << " times that (docs/physical-check.md).</p>\n";
  if (!a.check.findings.empty()) {
    h << "<p>What drives it:</p><ul>\n";
    for (const analysis::Finding& f : a.check.findings) h << "<li>" << Html(f.text) << "</li>\n";
    h << "</ul>\n";
  }
  const analysis::MassSuggestion& ms = a.check.mass_suggestion;
  // The suggestion only when the localisation found masses that explain the failure (with noisy
  // keypoints a least-squares fit of 16 masses to glitches gives a 2 kg pelvis).
  const bool masses_found =
      std::any_of(a.check.findings.begin(), a.check.findings.end(), [](const analysis::Finding& f) {
        return f.kind == analysis::Finding::Kind::kSegmentMass;
      });
  if (!a.check.pass && masses_found && ms.segments.size() > 0 && ms.residual_before > 0) {
    h << "<p>Segment masses that best zero the flight residuals (least squares, total mass kept; "
         "reported, not applied): RMS residual "
      << Fixed(ms.residual_before, 4) << " → " << Fixed(ms.residual_after, 4)
      << ".</p>\n<table><tr><th class=\"l\">segment</th><th>model (kg)</th><th>suggested "
         "(kg)</th></tr>\n";
    for (size_t s = 0; s < ms.segments.size(); ++s)
      h << "<tr><td class=\"l\">" << Html(ms.segments[s]) << "</td><td>"
        << Fixed(ms.current_kg[static_cast<Eigen::Index>(s)], 2) << "</td><td>"
        << Fixed(ms.suggested_kg[static_cast<Eigen::Index>(s)], 2) << "</td></tr>\n";
    h << "</table>\n";
  }
  const analysis::PhysicalCheckOptions& co = a.check_options;
  h << "<p>Thresholds per flight (docs/physical-check.md): residual force ≤ "
    << Fixed(co.max_force_bw, 3) << " body weight, moment about the COM ≤ "
    << Fixed(co.max_moment_bwh, 4)
    << " body weight × stature (OpenSim's residual guidelines with gravity as the external "
       "force), angular momentum within "
    << Fixed(100 * co.max_momentum_variation, 0) << " %, fitted gravity within "
    << Fixed(100 * co.max_gravity_error, 0) << " %, marker error ≤ "
    << Fixed(100 * co.max_marker_error_m, 1) << " cm. Frames within "
    << Fixed(1e3 * a.check.edge_margin_s, 0) << " ms of take-off and landing are not judged.</p>\n";
}

// The per-jump table, the shapes, what the columns mean, the contacts' loads.
void WriteJumpsSection(const analysis::TrialAnalysis& a,
                       const AnalysisReportOptions& options,
                       std::ostringstream& h) {
  // Per-jump table.
  h << "<h2>Jumps</h2>\n<table><tr><th>#</th><th>take-off (s)</th><th>landing (s)</th><th>ToF "
       "(s)</th><th>apex (m)</th><th>HD (m)</th><th>from centre (m)</th><th>somersault "
       "(°)</th><th>twist (°)</th><th class=\"l\">code</th><th class=\"l\">skill</th><th>DD</th>"
       "<th>residual |F| (BW, "
    << Window(a) << " mean)</th>"
    << (options.silhouette_iou.empty() ? "" : "<th>silhouette IoU</th>")
    << "<th class=\"l\">verdict</th></tr>\n";
  for (const analysis::JumpMetrics& j : a.jumps) {
    const bool ok = j.verdict == "pass";
    h << "<tr><td>" << j.index << "</td><td>" << Fixed(j.flight.takeoff_s, 3) << "</td><td>"
      << Fixed(j.flight.landing_s, 3) << "</td><td>" << Fixed(j.time_of_flight_s(), 3)
      << "</td><td>"
      << Fixed(std::isfinite(j.apex_above_bed_m) ? j.apex_above_bed_m : j.apex_m(), 2)
      << "</td><td>" << Fixed(j.displacement_from_takeoff_m, 2) << "</td><td>"
      << Fixed(j.displacement_from_centre_m, 2) << "</td><td>"
      << Fixed(j.rotation.measured_somersault_rad * kRadToDeg, 0) << "</td><td>"
      << TwistCell(j.rotation) << "</td><td class=\"l\"><b>" << Html(j.fig_code)
      << "</b></td><td class=\"l\" title=\"" << Html(j.rotation.shape_reason) << "\">"
      << Html(j.skill_name) << "</td><td>" << (j.partial() ? "–" : Fixed(j.difficulty.total(), 1))
      << "</td><td>" << (j.check ? Fixed(j.check->window_force_bw, 3) : "–") << "</td>"
      << (options.silhouette_iou.empty()
              ? std::string()
              : "<td>" + (j.silhouette_iou ? Fixed(*j.silhouette_iou, 2) : "–") + "</td>")
      << "<td class=\"l " << (ok ? "pass" : "fail") << "\">" << Html(j.verdict) << "</td></tr>\n";
  }
  h << "</table>\n";
  // Why each shape (FIG body positions, held): the angles and how long.
  h << "<p>Shapes (FIG: a body angle at or below 135° is closed; held, not at one "
       "instant):</p>\n<ul>\n";
  for (const analysis::JumpMetrics& j : a.jumps)
    h << "<li>" << j.index << " " << Html(j.fig_code) << ": " << Html(j.rotation.shape_reason)
      << "</li>\n";
  h << "</ul>\n<p>Apex: centre of mass above the surface at rest"
    << (a.SurfaceHeight() ? " (" + Html(a.SurfaceSource()) + ")"
                          : " (no surface known: lab height)")
    << ". HD: horizontal distance of the landing feet from the take-off feet. Somersault (positive "
       "forward) and twist: measured in the air; the code counts the nominal rotation between "
       "landing positions. Residual: the largest mean over "
    << Window(a) << " of the flight, as the verdict judges it.</p>\n";
  if (!a.check.contacts.empty()) {
    h << "<p>Peak bed (or floor) reaction in the contacts, body weights:";
    for (const analysis::ContactLoad& c : a.check.contacts)
      h << " " << Fixed(c.peak_force_bw, 2) << " at " << Fixed(c.peak_s, 2) << " s;";
    h << "</p>\n";
  }
}

// The faults an element was measured with, each with its value, when, and what it suggests.
std::string FaultsCell(const fig::ScoredElement& e) {
  std::string cell;
  for (const fig::MeasuredFault& f : e.faults) {
    if (!f.reported) continue;
    const int digits = f.unit == "deg" ? 0 : 2;
    cell += (cell.empty() ? "" : "; ") + f.quantity + " " + Fixed(f.value, digits) +
            (f.unit == "deg" ? "°" : " " + f.unit) + " ±" + Fixed(f.uncertainty, digits) + " at " +
            Fixed(f.time_s, 2) + " s (−" + Fixed(f.deduction, 1) + ")";
  }
  if (cell.empty()) cell = "none beyond the measurement's uncertainty";
  if (const std::string unseen = fig::DescribeUnmeasured(e); !unseen.empty())
    cell += "; not measured: " + unseen;
  return cell;
}

// The score sheet by the analysis's rules (docs/scoring.md): per element its difficulty (struck
// when not counted), flight, landing zone with its margin, requirements; then D, T, H.
void WriteScoreSection(const analysis::TrialAnalysis& a, std::ostringstream& h) {
  const fig::RoutineScore& s = a.score;
  h << "<h2>Score sheet</h2>\n<p>Rules: <b>" << Html(s.rules_name) << "</b>. " << s.elements.size()
    << " of " << s.expected_elements << " elements"
    << (s.interrupted ? "; <span class=\"fail\">interrupted: " + Html(s.interruption) +
                            "</span> (scored to its last element)"
                      : "")
    << ".</p>\n";
  if (s.elements.empty()) return;
  h << "<table><tr><th>element</th><th>flight</th><th class=\"l\">code</th><th "
       "class=\"l\">skill</th><th>DD</th>"
       "<th>ToF (s)</th><th class=\"l\">landing zone</th><th>margin (cm)</th><th>HD deduction</th>"
       "<th class=\"l\">requirements</th><th class=\"l\">execution faults (measured, "
       "suggested)</th></tr>\n";
  for (const fig::ScoredElement& e : s.elements) {
    h << "<tr><td>" << e.element << "</td><td>" << e.flight << "</td><td class=\"l\"><b>"
      << Html(e.code) << "</b></td><td class=\"l\">" << Html(e.name) << "</td><td"
      << (e.note.empty() ? "" : " title=\"" + Html(e.note) + "\"") << ">"
      << (e.difficulty_counted ? Fixed(e.difficulty.total(), 1)
                               : "<s>" + Fixed(e.difficulty.total(), 1) + "</s>")
      << "</td><td>" << Fixed(e.time_of_flight_s, 3) << "</td>";
    if (e.landing_zone) {
      const fig::HdLanding& z = *e.landing_zone;
      h << "<td class=\"l\">" << Html(z.zone) << "</td><td"
        << (z.uncertain ? " class=\"fail\" title=\"within the "
                          "measurement's uncertainty: a close call\""
                        : "")
        << ">" << (std::isfinite(z.margin_m) ? Fixed(100.0 * z.margin_m, 1) : "–")
        << (z.uncertain ? " ?" : "") << "</td><td>" << Fixed(z.deduction, 1) << "</td>";
    } else {
      h << "<td class=\"l\">–</td><td>–</td><td>–</td>";
    }
    std::string reqs;
    for (const std::string& r : e.requirements) reqs += (reqs.empty() ? "" : "; ") + r;
    h << "<td class=\"l\">" << Html(reqs) << "</td><td class=\"l\">" << Html(FaultsCell(e))
      << "</td></tr>\n";
  }
  h << "</table>\n<p><b>D " << Fixed(s.difficulty, 1) << "</b>"
    << (s.difficulty_capped ? " (capped; " + Fixed(s.difficulty_uncapped, 1) + " performed)" : "")
    << " &nbsp; <b>T " << Fixed(s.time_of_flight, 3) << "</b> (flights "
    << Fixed(s.time_of_flight_sum_s, 4) << " s, truncated) &nbsp; <b>H "
    << (s.horizontal_displacement ? Fixed(*s.horizontal_displacement, 2) : std::string("–"))
    << "</b>" << (s.horizontal_displacement ? "" : " (no bed known: no landing zones)");
  if (s.penalty > 0) h << " &nbsp; penalties −" << Fixed(s.penalty, 1);
  h << " &nbsp; D + T + H" << (s.penalty > 0 ? " − penalties" : "") << " = <b>"
    << Fixed(s.total_without_execution, 3)
    << "</b>; E is the judges'. The execution assistant suggests −"
    << Fixed(s.execution_deductions, 1) << " over " << s.elements.size() << " elements ("
    << s.faults_reported
    << " fault(s) past the rule file's thresholds by more than the measurement's uncertainty; "
       "every quantity "
       "measured is in score.json).</p>\n";
  if (s.close_calls > 0)
    h << "<p class=\"fail\">" << s.close_calls
      << " landing(s) within the measurement's uncertainty of a zone line (marked ?): the call "
         "could go either "
         "way.</p>\n";
  for (const std::string& m : s.requirements_missing)
    h << "<p class=\"fail\">Requirement not performed: " << Html(m) << "</p>\n";
  for (const std::string& b : s.rule_breaks) h << "<p class=\"fail\">" << Html(b) << "</p>\n";
  {
    const analysis::ExecutionOptions& u = a.execution_options;
    h << "<p>How sure the execution assistant is: a fault is reported only past its threshold by "
         "more than "
         "the measurement's uncertainty for this input — joint angles ±"
      << Fixed(u.angle_uncertainty_deg, 1) << "°, elbows ±" << Fixed(u.elbow_uncertainty_deg, 1)
      << "°, positions ±" << Fixed(100 * u.position_uncertainty_m, 1) << " cm, times ±"
      << Fixed(u.time_uncertainty_s, 3) << " s"
      << (a.check.noise_rms_m > 0
              ? " (this trial's noise: about " + Fixed(1000 * a.check.noise_rms_m, 1) +
                    " mm per coordinate" +
                    (u.angle_uncertainty_deg > 5.0 + 1e-9
                         ? ", beyond motion capture's: the uncertainties grown with it"
                         : "") +
                    ")"
              : std::string())
      << "; docs/scoring.md.</p>\n";
  }
  h << "<p>Rules from: " << Html(s.rules_source) << ". Zones: " << Html(s.zones_source)
    << ". Landing: any part of a foot (the model's soles), the hips for front and back "
       "landings.</p>\n";
}

// The filmstrips and the overlay video.
void WriteMediaSections(const analysis::TrialAnalysis& a,
                        const AnalysisReportOptions& options,
                        std::ostringstream& h) {
  // Filmstrips.
  if (!options.filmstrips.empty() || !options.filmstrip_note.empty()) {
    h << "<h2>Filmstrips</h2>\n";
    if (!options.filmstrip_note.empty())
      h << "<p class=\"note\">" << Html(options.filmstrip_note) << "</p>\n";
    for (const auto& [index, file] : options.filmstrips) {
      std::string code;
      for (const analysis::JumpMetrics& j : a.jumps)
        if (j.index == index) code = j.fig_code + " " + j.skill_name;
      h << "<figure><img src=\"" << Html(file) << "\" alt=\"jump " << index
        << "\" style=\"max-width:100%\"><figcaption>Jump " << index << " (" << Html(code)
        << "): eight instants from take-off to landing, seen from the athlete's left, one scale "
           "(parallel projection).";
      for (const auto& [video_index, video] : options.filmstrip_videos)
        if (video_index == index)
          h << " As a video: <a href=\"" << Html(video) << "\">" << Html(video) << "</a>.";
      h << "</figcaption></figure>\n";
    }
  }

  // The overlay video.
  if (!options.overlay_video.empty()) {
    h << "<h2>Over the video</h2>\n<video controls preload=\"metadata\" style=\"max-width:100%\" "
         "src=\""
      << Html(options.overlay_video) << "\"></video>\n<p><a href=\"" << Html(options.overlay_video)
      << "\">" << Html(options.overlay_video)
      << "</a>: the reconstructed athlete drawn through the camera's calibration over its "
         "video.</p>\n";
  }
}

// The plots (or why there are none), the reconstruction's summary, the warnings it does not show.
void WritePlotsAndReconstruction(const analysis::TrialAnalysis& a,
                                 const std::vector<ReportFigure>& figures,
                                 const AnalysisReportOutcome& outcome,
                                 std::ostringstream& h) {
  const analysis::ReconstructionSummary& rs = a.reconstruction.summary;
  // Plots.
  h << "<h2>Plots</h2>\n";
  if (a.check.flights.empty())
    h << "<p class=\"note\">No flight in this trial: no residual, angular momentum or rotation "
         "charts (they cover the flights).</p>\n";
  if (outcome.images_rendered) {
    for (const ReportFigure& f : figures)
      h << "<figure><a href=\"" << Html(SvgName(f.file)) << "\"><img src=\"" << Html(f.file)
        << "\" alt=\"" << Html(f.chart.title) << "\"></a><figcaption>" << Html(f.caption)
        << " (<a href=\"" << Html(SvgName(f.file)) << "\">SVG</a>)</figcaption></figure>\n";
  } else {
    h << "<p class=\"note\">No plots in this report: " << Html(outcome.reason)
      << ". The tables residuals.csv, angles.mot and torques.sto hold the same data.</p>\n";
  }

  // How the motion was reconstructed.
  h << "<h2>Reconstruction</h2>\n<pre>" << Html(rs.BriefReport()) << "</pre>\n";
  // Warnings the reconstruction summary above does not already show.
  const std::string reconstruction = rs.BriefReport();
  std::vector<std::string> more;
  for (const std::string& w : a.warnings)
    if (reconstruction.find(w) == std::string::npos) more.push_back(w);
  if (!more.empty()) {
    h << "<h2>Warnings</h2>\n<ul>\n";
    for (const std::string& w : more) h << "<li>" << Html(w) << "</li>\n";
    h << "</ul>\n";
  }
}

}  // namespace

std::string FormatAnalysisReportHtml(const analysis::TrialAnalysis& a,
                                     const std::vector<ReportFigure>& figures,
                                     const AnalysisReportOptions& options,
                                     const AnalysisReportOutcome& outcome) {
  std::ostringstream h;
  h << internal::HtmlPageStart("Acrolab: " + a.trial_name, 1000);
  h << "<h1>" << Html(a.trial_name) << "</h1>\n<p>Trial <code>" << Html(options.trial_path)
    << "</code>; athlete: " << Html(options.athlete) << " (" << Fixed(a.stature_m, 2) << " m, "
    << Fixed(a.mass_kg, 1) << " kg).</p>\n";

  // Routine summary and verdict.
  h << "<h2>Routine</h2>\n<p><b>" << a.num_scored << " skills</b>, difficulty (DD) <b>"
    << Fixed(a.total_difficulty, 1) << "</b>, time of flight <b>"
    << Fixed(a.total_time_of_flight_s, 3) << " s</b> (the sum the judges use).";
  const int partial = static_cast<int>(a.jumps.size()) - a.num_scored;
  if (partial > 0)
    h << " " << partial << " partial flight(s) at the ends are shown but not scored.";
  h << "</p>\n";
  WriteCheckSection(a, h);
  WriteScoreSection(a, h);
  WriteJumpsSection(a, options, h);
  WriteMediaSections(a, options, h);
  WritePlotsAndReconstruction(a, figures, outcome, h);
  h << "<p>Files: jumps.json, score.json, angles.mot (joint angles, degrees), torques.sto (joint "
       "torques, "
       "N·m), residuals.csv (root residuals, angular momentum and COM per frame).</p>\n"
    << internal::kHtmlPageEnd;
  return h.str();
}

AnalysisReportOutcome WriteAnalysisReport(const analysis::TrialAnalysis& a,
                                          const std::filesystem::path& dir,
                                          const AnalysisReportOptions& options) {
  const std::vector<ReportFigure> figures = MakeAnalysisFigures(a, options);
  AnalysisReportOutcome outcome;
  if (!options.render_images) {
    outcome.reason = "plots were not asked for (--no-images)";
  } else {
    // Each figure as PNG (for the page) and SVG (for papers), from the same drawing.
    try {
      for (const ReportFigure& f : figures) {
        const std::filesystem::path png = dir / f.file;
        std::filesystem::path svg = png;
        svg.replace_extension(".svg");
        WriteChart(f.chart, png);
        WriteChart(f.chart, svg);
        outcome.images.push_back(png);
        outcome.images.push_back(svg);
      }
      outcome.images_rendered = true;
    } catch (const std::exception& e) {
      outcome.reason = std::string("rendering failed: ") + e.what();
    }
  }
  WriteFileAtomically(dir / "report.html", FormatAnalysisReportHtml(a, figures, options, outcome));
  return outcome;
}

}  // namespace acro::ui
