#include "acro/report/skill_report.h"

#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/motion.h"
#include "acro/athlete/orientation.h"
#include "acro/base/file_io.h"
#include "acro/base/text_format.h"
#include "acro/capture/c3d.h"
#include "acro/dynamics/kinematics.h"
#include "acro/report/chart.h"
#include "html_page.h"

namespace acro::ui {

// The analysis types this report presents.
using namespace acro::analysis;  // NOLINT(build/namespaces)
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

std::vector<double> ToStd(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// Samples of [0, T] at `rate_hz`, the last one at T.
std::vector<double> SampleTimes(double T, double rate_hz) {
  std::vector<double> t;
  const int n = static_cast<int>(std::floor(T * rate_hz + 1e-9));
  for (int k = 0; k <= n; ++k) t.push_back(k / rate_hz);
  if (T - t.back() > 1e-9) t.push_back(T);
  return t;
}

// Somersault, tilt and twist of an orientation (acro/athlete/orientation.h).
Eigen::Vector3d SomersaultTiltTwist(const Eigen::Quaterniond& q) {
  const analysis::SomersaultTiltTwist a = CalcSomersaultTiltTwist(q.toRotationMatrix());
  return Eigen::Vector3d(a.somersault_rad, a.tilt_rad, a.twist_rad);
}

std::string Html(const std::string& s) {
  return HtmlEscape(s);
}

}  // namespace

std::string MakeSkillFromCodeJson(const SkillFromCodeResult& r) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  Json j;
  j["fig_code"] = r.skill.fig_code;
  j["skill"] = r.skill.name;
  j["athlete"] = r.skill.athlete.name;
  j["difficulty"] = r.difficulty.total();
  j["difficulty_explained"] = r.difficulty.Explain();
  j["flight_time_s"] = r.flight_time_s;
  j["takeoff_vertical_velocity_m_per_s"] = r.takeoff_vertical_velocity_mps;
  j["angular_momentum_N_m_s"] = {r.H_Scm_W.x(), r.H_Scm_W.y(), r.H_Scm_W.z()};
  j["somersault_momentum_N_m_s"] = r.somersault_momentum;
  j["twist_momentum_N_m_s"] = r.twist_momentum;
  j["normalized_somersault_momentum_per_s"] = r.normalized_somersault_momentum;
  j["aerial_twist_actions_deg"] = Json::array();
  for (double a : r.aerial_twist_actions_rad)
    j["aerial_twist_actions_deg"].push_back(a * kRadToDeg);
  j["air_somersaults"] = r.air_somersault_rad / (2 * std::numbers::pi);
  j["air_twists"] = r.air_twist_rad / (2 * std::numbers::pi);
  j["twist_direction"] = analysis::TwistDirectionName(r.twist_direction);
  j["half_twists_per_somersault"] = r.half_twists_per_somersault;
  j["max_tilt_deg"] = r.max_tilt_rad * kRadToDeg;
  j["landing_tilt_deg"] = r.landing_tilt_rad * kRadToDeg;
  j["time_to_prepare_landing_s"] = r.time_to_prepare_landing_s;
  j["shooting_residual_deg"] = r.shooting_residual_rad * kRadToDeg;
  j["shooting_simulations"] = r.shooting_simulations;
  j["keyframes"] = r.skill.keyframes.size();
  j["feasible"] = r.feasible();
  j["not_feasible"] = r.not_feasible;
  return j.dump(2) + "\n";
}

std::string MakeSkillResultJson(const SkillDesign& design,
                                const SkillOptimizationResult& r,
                                const SkillSimulationResult* sim) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  // The skill and the timing before and after.
  Json j;
  j["skill"] = design.skill().name;
  j["fig_code"] = design.skill().fig_code;
  j["athlete"] = design.skill().athlete.name;
  j["model"] = SkillModelNumber(r.model);
  j["flight_time_s"] = design.flight_time_s();
  j["keyframe_names"] = Json::array();
  for (const SkillKeyframe& k : design.skill().keyframes) j["keyframe_names"].push_back(k.name);
  j["keyframe_times_initial_s"] = ToStd(r.times_initial_s);
  j["keyframe_times_s"] = ToStd(r.optimized.times_s);
  j["objective_initial"] = r.objective_initial;
  j["objective"] = r.objective;
  j["objective_ratio"] = r.objective_initial / r.objective;
  j["angular_momentum_variation_initial"] = r.angular_momentum_variation_initial;
  j["angular_momentum_variation"] = r.angular_momentum_variation;
  j["max_joint_deviation_deg"] = r.max_joint_deviation_rad * kRadToDeg;
  j["max_orientation_deviation_deg"] = r.max_orientation_deviation_rad * kRadToDeg;
  // Every keyframe's joint angles and orientation within its e₂ (rounding: 1e-9 rad).
  bool within = true;
  for (int i = 0; i < design.num_keyframes(); ++i) {
    const double e2 = design.skill().keyframes[static_cast<size_t>(i)].tolerance_angle_rad + 1e-9;
    within = within &&
             (r.optimized.joint_angles_rad.col(i) - design.keyframe_joint_angles_rad().col(i))
                     .cwiseAbs()
                     .maxCoeff() <= e2 &&
             r.optimized.keyframe_orientations[static_cast<size_t>(i)].angularDistance(
                 design.keyframe_orientations()[static_cast<size_t>(i)]) <= e2;
  }
  j["keyframes_within_tolerance"] = within;
  // The solver's stages.
  j["solver"] = Json::array();
  for (size_t i = 0; i < r.stages.size(); ++i) {
    const SkillOptimizationSummary& s = r.stages[i];
    j["solver"].push_back({{"stage", i == 0 ? "model 2" : "model 1"},
                           {"success", s.success},
                           {"iterations", s.iterations},
                           {"initial_cost", s.initial_cost},
                           {"final_cost", s.final_cost},
                           {"time_s", s.time_s},
                           {"message", s.message}});
  }
  // The flight simulation, when there is one.
  if (sim != nullptr) {
    const Eigen::Vector3d stt = SomersaultTiltTwist(sim->final_orientation) * kRadToDeg;
    Json simulation;
    simulation["H_Scm_W_kgm2ps"] = {sim->H_Scm_W.x(), sim->H_Scm_W.y(), sim->H_Scm_W.z()};
    simulation["H_mean_W_kgm2ps"] = {sim->H_mean_W.x(), sim->H_mean_W.y(), sim->H_mean_W.z()};
    simulation["final_orientation_error_deg"] = sim->final_orientation_error_rad * kRadToDeg;
    simulation["rms_orientation_error_deg"] = sim->rms_orientation_error_rad * kRadToDeg;
    simulation["somersault_turns"] = sim->somersault_turns;
    simulation["intended_somersault_turns"] = sim->intended_somersault_turns;
    simulation["twist_turns"] = sim->twist_turns;
    simulation["intended_twist_turns"] = sim->intended_twist_turns;
    simulation["warnings"] = sim->warnings;
    simulation["final_somersault_tilt_twist_deg"] = {stt.x(), stt.y(), stt.z()};
    simulation["status"] = sim->flight.summary.BriefReport();
    j["simulation"] = std::move(simulation);
  }
  // Names come from the skill file: bytes that are not UTF-8 become U+FFFD.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

capture::Trial MakeSkillMarkerTrial(const SkillDesign& design,
                                    const SkillTrajectory& trajectory,
                                    double rate_hz) {
  const dynamics::Model<double>& m = design.model();
  dynamics::Workspace<double> ws(m);
  const std::vector<double> times = SampleTimes(design.flight_time_s(), rate_hz);
  capture::Trial t;
  t.source.format = "generated";
  t.point_rate_hz = rate_hz;
  t.num_frames = static_cast<int>(times.size());
  t.subject_name = design.skill().athlete.name;
  for (const dynamics::Point<double>& p : m.points())
    t.points.push_back({p.name, "virtual marker", capture::PointType::kMarker, "m"});
  t.positions.resize(3, std::int64_t(t.num_frames) * m.num_points());
  for (int f = 0; f < t.num_frames; ++f) {
    const SkillMotionState s = CalcSkillMotion(design, trajectory, times[static_cast<size_t>(f)]);
    dynamics::CalcForwardKinematics(m, ws, s.q);
    for (int p = 0; p < m.num_points(); ++p)
      t.position(f, p) = dynamics::CalcPointPosition(m, ws, p);
  }
  t.events.push_back({"Take-off", "General", "designed skill", t.subject_name, 0.0});
  t.events.push_back(
      {"Landing", "General", "designed skill", t.subject_name, design.flight_time_s()});
  return t;
}

capture::Storage MakeSkillMotionTable(const SkillDesign& design,
                                      const SkillTrajectory& trajectory,
                                      double rate_hz) {
  const std::vector<double> times = SampleTimes(design.flight_time_s(), rate_hz);
  capture::Storage s;
  s.name = design.skill().name;
  s.in_degrees = true;
  s.labels = {"pelvis_tx", "pelvis_ty", "pelvis_tz", "somersault", "tilt", "twist"};
  // Joint angles by the names of every other output file (MakeCoordinateNames: r_knee_flexion, …).
  const std::vector<std::string> names = MakeCoordinateNames(design.model());
  s.labels.insert(s.labels.end(), names.begin() + dynamics::kRootNq, names.end());
  s.time_s =
      Eigen::Map<const Eigen::VectorXd>(times.data(), static_cast<Eigen::Index>(times.size()));
  s.data.resize(static_cast<Eigen::Index>(times.size()),
                static_cast<Eigen::Index>(s.labels.size()));
  Eigen::Vector3d unwrapped = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < times.size(); ++k) {
    const SkillMotionState st = CalcSkillMotion(design, trajectory, times[k]);
    const Eigen::Vector3d a = SomersaultTiltTwist(dynamics::GetRootQuaternion(st.q));
    // Unwrap somersault and twist so that several turns read as such.
    for (int c = 0; c < 3; ++c) unwrapped[c] = k == 0 ? a[c] : UnwrapAngle(unwrapped[c], a[c]);
    const Eigen::Index row = static_cast<Eigen::Index>(k);
    s.data.block<1, 3>(row, 0) = st.q.head<3>().transpose();
    s.data.block<1, 3>(row, 3) = unwrapped.transpose() * kRadToDeg;
    const int joints = static_cast<int>(st.q.size()) - dynamics::kRootNq;
    s.data.row(row).tail(joints) = st.q.tail(joints).transpose() * kRadToDeg;
  }
  return s;
}

Chart MakeSkillTimingChart(const SkillDesign& design, const SkillOptimizationResult& r) {
  const int n = design.num_keyframes();
  constexpr Rgb kInitialGrey{0.5, 0.5, 0.5};
  constexpr Rgb kOptimisedRed{0.84, 0.15, 0.16};
  Chart timing;
  timing.title = "Keyframe timing: " + design.skill().name;
  timing.x_label = "keyframe";
  timing.y_label = "time (s)";
  const std::string optimised =
      "optimised (model " + std::to_string(SkillModelNumber(r.model)) + ")";
  LineSeries even{.name = "initial (even)",
                  .x = {},
                  .y = ToStd(r.times_initial_s),
                  .color = kInitialGrey,
                  .dashed = true,
                  .markers = true};
  LineSeries opt{.name = optimised,
                 .x = {},
                 .y = ToStd(r.optimized.times_s),
                 .color = kOptimisedRed,
                 .markers = true};
  for (int i = 0; i < n; ++i) {
    even.x.push_back(i + 1);
    opt.x.push_back(i + 1);
  }
  timing.series = {even, opt};
  return timing;
}

Chart MakeSkillMomentumChart(const SkillDesign& design, const SkillOptimizationResult& r) {
  constexpr ui::Rgb kInitialGrey{0.5, 0.5, 0.5};
  constexpr ui::Rgb kOptimisedRed{0.84, 0.15, 0.16};
  const std::string optimised =
      "optimised (model " + std::to_string(SkillModelNumber(r.model)) + ")";
  const SkillMotionProfile p0 = CalcSkillMotionProfile(design, r.initial, 320);
  const SkillMotionProfile p1 = CalcSkillMotionProfile(design, r.optimized, 320);
  ui::Chart h;
  h.title = "Angular momentum about the centre of mass";
  h.x_label = "time (s)";
  h.y_label = "|H| (kg·m²/s)";
  ui::LineSeries h0{
      .name = "initial timing", .x = ToStd(p0.t_s), .y = {}, .color = kInitialGrey, .dashed = true};
  ui::LineSeries h1{.name = optimised, .x = ToStd(p1.t_s), .y = {}, .color = kOptimisedRed};
  for (int k = 0; k < p0.t_s.size(); ++k) {
    h0.y.push_back(p0.H_Scm_W.col(k).norm());
    h1.y.push_back(p1.H_Scm_W.col(k).norm());
  }
  h.series = {h0, h1};
  return h;
}

std::vector<std::string> WriteSkillOutputs(const std::filesystem::path& dir,
                                           const SkillDesign& design,
                                           const SkillOptimizationResult& r,
                                           const SkillSimulationResult* sim,
                                           const SkillReportExtras& extras) {
  CreateOutputDirectory(dir);
  std::vector<std::string> written;
  auto write = [&](const std::string& name, std::string_view bytes) {
    WriteFileAtomically(dir / name, bytes);
    written.push_back(name);
  };
  // A chart as PNG and SVG from the same drawing.
  auto write_plot = [&](const std::string& stem, const ui::Chart& chart) {
    for (const char* ext : {".png", ".svg"}) {
      ui::WriteChart(chart, dir / (stem + ext));
      written.push_back(stem + ext);
    }
  };
  const int n = design.num_keyframes();

  write("result.json", MakeSkillResultJson(design, r, sim));

  // Timing table and plot (keyframe number against time, as the paper's Figure 7).
  std::ostringstream csv;
  csv << "keyframe,name,time_initial_s,time_s,interval_initial_s,interval_s\n";
  for (int i = 0; i < n; ++i) {
    csv << i + 1 << ",\"" << design.skill().keyframes[static_cast<size_t>(i)].name << "\","
        << fmt::format("{:.4f}", r.times_initial_s[i]) << ","
        << fmt::format("{:.4f}", r.optimized.times_s[i]) << ",";
    if (i > 0)
      csv << fmt::format("{:.4f}", r.times_initial_s[i] - r.times_initial_s[i - 1]) << ","
          << fmt::format("{:.4f}", r.optimized.times_s[i] - r.optimized.times_s[i - 1]);
    else
      csv << ",";
    csv << "\n";
  }
  write("timing.csv", csv.str());
  write_plot("timing", MakeSkillTimingChart(design, r));

  write_plot("angular_momentum", MakeSkillMomentumChart(design, r));

  // The motion.
  const std::vector<std::uint8_t> c3d =
      capture::WriteC3dToMemory(MakeSkillMarkerTrial(design, r.optimized));
  write("motion.c3d", std::string_view(reinterpret_cast<const char*>(c3d.data()), c3d.size()));
  write("motion.mot",
        capture::WriteStorageToString(MakeSkillMotionTable(design, r.optimized),
                                      capture::StorageFlavor::kMot));

  // Report page.
  std::ostringstream html;
  html << internal::HtmlPageStart(design.skill().name, 900);
  html << "<h1>" << Html(design.skill().name)
       << "</h1>\n<p>Athlete: " << Html(design.skill().athlete.name) << ". Flight time "
       << fmt::format("{:.3f}", design.flight_time_s()) << " s. Model ("
       << SkillModelNumber(r.model) << ").</p>\n";
  if (!extras.design_lines.empty()) {
    html << "<h2>Designed from its FIG code</h2>\n<ul>\n";
    for (const std::string& line : extras.design_lines)
      html << (line.rfind("not feasible", 0) == 0 ? "<li class=\"warning\">" : "<li>") << Html(line)
           << "</li>\n";
    html << "</ul>\n<p>The keyframes (skill.yaml) are samples of a simulated flight; the "
            "optimisation below only removes what the splines between them add.</p>\n";
  }
  html << "<table><tr><th></th><th>initial timing</th><th>optimised</th></tr>\n"
       << "<tr><td>J = T⁻¹∫|L̇/(m g h)|² dt</td><td>" << r.objective_initial << "</td><td>"
       << r.objective << "</td></tr>\n<tr><td>angular momentum variation</td><td>"
       << fmt::format("{:.2f}", 100 * r.angular_momentum_variation_initial) << " %</td><td>"
       << fmt::format("{:.2f}", 100 * r.angular_momentum_variation) << " %</td></tr></table>\n";
  if (r.model == SkillModel::kTrajectory)
    html << "<p>Largest keyframe deviation: joint angles "
         << fmt::format("{:.2f}", r.max_joint_deviation_rad * kRadToDeg) << "°, root orientation "
         << fmt::format("{:.2f}", r.max_orientation_deviation_rad * kRadToDeg) << "°.</p>\n";
  html << "<h2>Keyframe timing</h2>\n<img src=\"timing.svg\" "
          "alt=\"timing\">\n<table><tr><th>#</th><th>keyframe"
          "</th><th>initial (s)</th><th>optimised (s)</th></tr>\n";
  for (int i = 0; i < n; ++i)
    html << "<tr><td>" << i + 1 << "</td><td style=\"text-align:left\">"
         << Html(design.skill().keyframes[static_cast<size_t>(i)].name) << "</td><td>"
         << fmt::format("{:.3f}", r.times_initial_s[i]) << "</td><td>"
         << fmt::format("{:.3f}", r.optimized.times_s[i]) << "</td></tr>\n";
  html << "</table>\n<h2>Angular momentum</h2>\n<img src=\"angular_momentum.svg\" alt=\"angular "
          "momentum\">\n";
  if (!extras.filmstrip.empty() || !extras.filmstrip_note.empty()) {
    html << "<h2>Filmstrip</h2>\n";
    if (!extras.filmstrip_note.empty())
      html << "<p class=\"warning\">" << Html(extras.filmstrip_note) << "</p>\n";
    if (!extras.filmstrip.empty()) {
      std::string instants;
      for (const double t : extras.filmstrip_times_s)
        instants += (instants.empty() ? "" : ", ") + fmt::format("{:.2f}", t);
      html << "<figure><img src=\"" << Html(extras.filmstrip)
           << "\" alt=\"filmstrip\" style=\"max-width:100%\"><figcaption>The initial timing (top) "
              "and the optimised timing (bottom) at the same instants ("
           << instants
           << " s), seen from the athlete's left at one scale: the same keyframes, reached at "
              "other times.";
      if (!extras.filmstrip_video.empty())
        html << " As a video: <a href=\"" << Html(extras.filmstrip_video) << "\">"
             << Html(extras.filmstrip_video) << "</a>.";
      html << "</figcaption></figure>\n";
    }
  }
  if (sim != nullptr)
    html << "<h2>Flight simulation</h2>\n<p>The joints follow the optimised motion, the root flies "
            "under gravity with the take-off momentum the design needs: "
         << Html(FormatSkillSimulation(*sim)) << ".</p>\n";
  if (sim != nullptr && !sim->warnings.empty()) {
    html << "<p class=\"warning\"><b>The design does not fly as drawn:</b></p>\n<ul>\n";
    for (const std::string& line : sim->warnings) html << "<li>" << Html(line) << "</li>\n";
    html << "</ul>\n";
  }
  html << "<h2>Solver</h2>\n<ul>\n";
  for (const SkillOptimizationSummary& s : r.stages)
    html << "<li>" << Html(s.BriefReport()) << "</li>\n";
  html << "</ul>\n<p>Files: result.json, timing.csv, motion.c3d (virtual markers), "
          "motion.mot.</p>\n"
       << internal::kHtmlPageEnd;
  write("report.html", html.str());
  return written;
}

}  // namespace acro::ui
