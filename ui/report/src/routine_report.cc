#include "acro/report/routine_report.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/motion.h"
#include "acro/athlete/orientation.h"
#include "acro/base/file_io.h"
#include "acro/base/text_format.h"
#include "acro/capture/c3d.h"
#include "acro/design/skill_file.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/reconstruct/markerset.h"
#include "html_page.h"

namespace acro::ui {

using namespace acro::analysis;  // NOLINT(build/namespaces)
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// Box–Muller on a 32-bit Mersenne Twister: the same numbers on every platform and library.
class Gaussian {
 public:
  explicit Gaussian(unsigned seed) : rng_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (double(rng_()) + 0.5) / 4294967296.0;
    const double u2 = (double(rng_()) + 0.5) / 4294967296.0;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2 * std::numbers::pi * u2);
    has_spare_ = true;
    return r * std::cos(2 * std::numbers::pi * u2);
  }

 private:
  std::mt19937 rng_;
  bool has_spare_ = false;
  double spare_ = 0;
};

// The skill files' names in skills/: 01.yaml, 02.yaml, …
std::string SkillFileName(size_t index) {
  return fmt::format("skills/{:02d}.yaml", index + 1);
}

}  // namespace

capture::Trial MakeRoutineMarkerTrial(const SimulatedRoutine& routine,
                                      const AthleteProfile& athlete,
                                      const RoutineMarkerOptions& options) {
  const dynamics::Model<double>& model = routine.model;
  dynamics::Workspace<double> ws(model);
  const MarkerSet set = BuiltinMarkerSet("trampoline");
  const std::vector<ModelMarker> markers = PlaceMarkers(set, model, athlete.height_m);
  const int num_frames = routine.num_frames();
  // The trial's description and points.
  capture::Trial trial;
  trial.source.point_units = "mm";
  trial.point_rate_hz = routine.options.point_rate_hz;
  trial.first_frame = 1;
  trial.num_frames = num_frames;
  trial.subject_name = athlete.name;
  for (const ModelMarker& m : markers)
    trial.points.push_back({m.name, "trampoline set, " + m.name, capture::PointType::kMarker, "m"});
  const RoutineSimulationOptions& bed = routine.options;
  const Eigen::Vector3d half(bed.bed_length_m / 2, bed.bed_width_m / 2, 0);
  const Eigen::Vector3d corners[4] = {bed.bed_centre_m + Eigen::Vector3d(half.x(), half.y(), 0),
                                      bed.bed_centre_m + Eigen::Vector3d(-half.x(), half.y(), 0),
                                      bed.bed_centre_m + Eigen::Vector3d(-half.x(), -half.y(), 0),
                                      bed.bed_centre_m + Eigen::Vector3d(half.x(), -half.y(), 0)};
  for (int k = 0; k < 4; ++k)
    trial.points.push_back({"BED_C" + std::to_string(k + 1),
                            "corner of the woven bed at rest",
                            capture::PointType::kMarker,
                            "m"});
  // The positions with noise.
  const int P = trial.num_points();
  trial.positions.resize(3, std::int64_t(num_frames) * P);
  trial.residuals.setConstant(P, num_frames, 1.0f);
  trial.camera_masks.setConstant(P, num_frames, 0x3F);
  Gaussian noise(options.noise_seed);
  const double sd = options.noise_sd_m;
  for (int fr = 0; fr < num_frames; ++fr) {
    dynamics::CalcForwardKinematics(model, ws, routine.q.col(fr));
    for (int m = 0; m < int(markers.size()); ++m) {
      const auto& X = ws.X_WB[size_t(markers[size_t(m)].segment)];
      Eigen::Vector3d p = X * markers[size_t(m)].p_BoM_B;
      for (int a = 0; a < 3; ++a) p[a] += sd * noise();
      trial.position(fr, m) = p;
    }
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d p = corners[k];
      for (int a = 0; a < 3; ++a) p[a] += sd * noise();
      trial.position(fr, int(markers.size()) + k) = p;
    }
  }
  return trial;
}

capture::Storage MakeRoutineMotionTable(const SimulatedRoutine& routine, const std::string& name) {
  const int n = routine.num_frames();
  capture::Storage s;
  s.name = name;
  s.in_degrees = true;
  s.labels = {"pelvis_tx", "pelvis_ty", "pelvis_tz", "somersault", "tilt", "twist"};
  const std::vector<std::string> names = MakeCoordinateNames(routine.model);
  s.labels.insert(s.labels.end(), names.begin() + dynamics::kRootNq, names.end());
  s.time_s = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / routine.options.point_rate_hz);
  s.data.resize(n, static_cast<Eigen::Index>(s.labels.size()));
  Eigen::Vector3d unwrapped = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const auto q = routine.q.col(k);
    const SomersaultTiltTwist a =
        CalcSomersaultTiltTwist(dynamics::GetRootQuaternion(q).normalized().toRotationMatrix());
    const Eigen::Vector3d angles(a.somersault_rad, a.tilt_rad, a.twist_rad);
    for (int c = 0; c < 3; ++c)
      unwrapped[c] = k == 0 ? angles[c] : UnwrapAngle(unwrapped[c], angles[c]);
    s.data.block<1, 3>(k, 0) = q.head<3>().transpose();
    s.data.block<1, 3>(k, 3) = unwrapped.transpose() * kRadToDeg;
    const int joints = static_cast<int>(q.size()) - dynamics::kRootNq;
    s.data.row(k).tail(joints) = q.tail(joints).transpose() * kRadToDeg;
  }
  return s;
}

Chart MakeRoutineHeightChart(const RoutineDesignResult& result) {
  const SimulatedRoutine& r = result.simulation;
  dynamics::Workspace<double> ws(r.model);
  Chart chart;
  chart.title = "Centre of mass over the routine (flights shaded, the table's order)";
  chart.x_label = "time (s)";
  chart.y_label = "height above the bed (m)";
  LineSeries com;
  com.name = "centre of mass";
  const double bed = r.options.bed_centre_m.z();
  for (int k = 0; k < r.num_frames(); ++k) {
    dynamics::CalcForwardKinematics(r.model, ws, r.q.col(k));
    com.x.push_back(k / r.options.point_rate_hz);
    com.y.push_back(dynamics::CalcCenterOfMassPosition(r.model, ws).z() - bed);
  }
  chart.series.push_back(std::move(com));
  for (size_t i = 0; i < r.flights.size(); ++i)
    chart.bands.push_back({r.flights[i].takeoff_s,
                           r.flights[i].landing_s,
                           {0.6, 0.6, 0.6},
                           i % 2 == 0 ? 0.15 : 0.25,
                           ""});
  chart.reference_lines.push_back({0.0, "bed at rest"});
  chart.width_px = 1100;
  return chart;
}

std::string MakeRoutineJson(const RoutineDesignResult& result) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  const SimulatedRoutine& r = result.simulation;
  auto vec = [](const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); };
  Json j;
  j["name"] = result.spec.name;
  j["athlete"] = result.skills.empty() ? "" : result.skills.front().skill.athlete.name;
  j["codes"] = Json::array();
  for (const SkillFromCodeResult& s : result.skills) j["codes"].push_back(s.skill.fig_code);
  j["difficulty"] = result.difficulty;
  j["time_of_flight_s"] = result.time_of_flight_s;
  j["notes"] = result.notes;
  j["point_rate_hz"] = r.options.point_rate_hz;
  j["num_frames"] = r.num_frames();
  j["skills"] = Json::array();
  const double bed = r.options.bed_centre_m.z();
  for (size_t i = 0; i < result.skills.size(); ++i) {
    const SkillFromCodeResult& s = result.skills[i];
    const RoutineFlightTruth& f = r.flights[i];
    Json k;
    k["fig_code"] = s.skill.fig_code;
    k["name"] = s.skill.name;
    k["skill_file"] = SkillFileName(i);
    k["difficulty"] = s.difficulty.total();
    k["design_flight_time_s"] = s.flight_time_s;
    k["takeoff_s"] = f.takeoff_s;
    k["landing_s"] = f.landing_s;
    k["time_of_flight_s"] = f.landing_s - f.takeoff_s;
    k["takeoff_vertical_velocity_m_per_s"] = f.takeoff_vertical_velocity_m_per_s;
    k["apex_above_bed_m"] = f.apex_com_z_m - bed;
    k["angular_momentum_N_m_s"] = vec(f.H_Scm_W);
    k["normalized_somersault_momentum_per_s"] = s.normalized_somersault_momentum;
    k["air_somersault_deg"] = f.air_somersault_rad * kRadToDeg;
    k["air_twist_deg"] = f.air_twist_rad * kRadToDeg;
    k["twist_direction"] = TwistDirectionName(s.twist_direction);
    k["landing_feet_from_bed_centre_m"] =
        Json::array({f.landing_feet_m.x() - r.options.bed_centre_m.x(),
                     f.landing_feet_m.y() - r.options.bed_centre_m.y()});
    k["time_to_prepare_landing_s"] = s.time_to_prepare_landing_s;
    j["skills"].push_back(std::move(k));
  }
  j["contacts"] = Json::array();
  for (const RoutineContactTruth& c : r.contacts)
    j["contacts"].push_back({{"start_s", c.start_s},
                             {"end_s", c.end_s},
                             {"push_deg", c.push_rad * kRadToDeg},
                             {"peak_bed_force_body_weights", c.peak_force_body_weights},
                             {"max_depression_m", c.max_depression_m}});
  j["max_boundary_jumps"] = {
      {"com_position_m", r.max_boundary_position_jump_m},
      {"com_velocity_m_per_s", r.max_boundary_velocity_jump_m_per_s},
      {"orientation_rad", r.max_boundary_orientation_jump_rad},
      {"angular_velocity_rad_per_s", r.max_boundary_angular_velocity_jump_rad_per_s},
      {"joint_angle_rad", r.max_boundary_joint_jump_rad},
      {"joint_rate_rad_per_s", r.max_boundary_joint_rate_jump_rad_per_s}};
  return j.dump(2) + "\n";
}

std::vector<std::string> WriteRoutineOutputs(const std::filesystem::path& dir,
                                             const std::filesystem::path& final_dir,
                                             const RoutineDesignResult& result,
                                             const RoutineMarkerOptions& markers,
                                             const RoutineReportExtras& extras) {
  CreateOutputDirectory(dir / "skills");
  std::vector<std::string> written;
  auto write = [&](const std::string& name, std::string_view bytes) {
    WriteFileAtomically(dir / name, bytes);
    written.push_back(name);
  };
  const SimulatedRoutine& r = result.simulation;
  const std::string name = result.spec.name.empty() ? "routine" : result.spec.name;
  write("routine.json", MakeRoutineJson(result));
  const AthleteProfile& athlete = result.skills.front().skill.athlete;
  const std::vector<std::uint8_t> c3d =
      capture::WriteC3dToMemory(MakeRoutineMarkerTrial(r, athlete, markers));
  write("routine.c3d", std::string_view(reinterpret_cast<const char*>(c3d.data()), c3d.size()));
  write(
      "routine.mot",
      capture::WriteStorageToString(MakeRoutineMotionTable(r, name), capture::StorageFlavor::kMot));
  const Chart height = MakeRoutineHeightChart(result);
  for (const char* ext : {".png", ".svg"}) {
    WriteChart(height, dir / (std::string("height") + ext));
    written.push_back(std::string("height") + ext);
  }
  for (size_t i = 0; i < result.skills.size(); ++i)
    write(SkillFileName(i), FormatSkillYaml(result.skills[i].skill, final_dir / "skills"));

  // The page.
  std::ostringstream html;
  html << internal::HtmlPageStart(name, 1150);
  html << "<h1>" << HtmlEscape(name) << "</h1>\n<p>Athlete: " << HtmlEscape(athlete.name) << ". "
       << result.skills.size() << " skills, DD " << fmt::format("{:.1f}", result.difficulty)
       << ", time of flight " << fmt::format("{:.3f}", result.time_of_flight_s)
       << " s. Every flight is simulated (prescribed joints, free root under gravity), every "
          "contact on a spring-damper bed.</p>\n";
  for (const std::string& note : result.notes)
    html << "<p class=\"warning\">" << HtmlEscape(note) << "</p>\n";
  html << "<table><tr><th>#</th><th>code</th><th>skill</th><th>DD</th><th>take-off (s)</th>"
          "<th>ToF (s)</th><th>take-off v<sub>z</sub> (m/s)</th><th>apex (m)</th>"
          "<th>H<sub>somersault</sub> (kg·m²/s)</th><th>somersault (°)</th><th>twist (°)</th>"
          "<th>push before (°)</th></tr>\n";
  for (size_t i = 0; i < result.skills.size(); ++i) {
    const SkillFromCodeResult& s = result.skills[i];
    const RoutineFlightTruth& f = r.flights[i];
    html << "<tr><td>" << i + 1 << "</td><td>" << HtmlEscape(s.skill.fig_code)
         << "</td><td style=\"text-align:left\"><a href=\"" << SkillFileName(i) << "\">"
         << HtmlEscape(s.skill.name) << "</a></td><td>"
         << fmt::format("{:.1f}", s.difficulty.total()) << "</td><td>"
         << fmt::format("{:.3f}", f.takeoff_s) << "</td><td>"
         << fmt::format("{:.3f}", f.landing_s - f.takeoff_s) << "</td><td>"
         << fmt::format("{:.2f}", f.takeoff_vertical_velocity_m_per_s) << "</td><td>"
         << fmt::format("{:.2f}", f.apex_com_z_m - r.options.bed_centre_m.z()) << "</td><td>"
         << fmt::format("{:.1f}", std::abs(f.H_Scm_W.y())) << "</td><td>"
         << fmt::format("{:.0f}", f.air_somersault_rad * kRadToDeg) << "</td><td>"
         << fmt::format("{:.0f}", f.air_twist_rad * kRadToDeg) << "</td><td>"
         << (i == 0 ? std::string("–") : fmt::format("{:.0f}", r.contacts[i].push_rad * kRadToDeg))
         << "</td></tr>\n";
  }
  html << "</table>\n<h2>Height</h2>\n<img src=\"height.svg\" alt=\"height\">\n";
  if (!extras.filmstrips.empty() || !extras.filmstrip_note.empty()) {
    html << "<h2>Skills</h2>\n";
    if (!extras.filmstrip_note.empty())
      html << "<p class=\"warning\">" << HtmlEscape(extras.filmstrip_note) << "</p>\n";
    for (size_t i = 0; i < extras.filmstrips.size() && i < result.skills.size(); ++i)
      html << "<figure><img src=\"" << HtmlEscape(extras.filmstrips[i])
           << "\" alt=\"filmstrip\" style=\"max-width:100%\"><figcaption>" << i + 1 << ". "
           << HtmlEscape(result.skills[i].skill.name)
           << ", from take-off to landing, seen from the athlete's left.</figcaption></figure>\n";
  }
  if (!extras.video.empty())
    html << "<h2>Video</h2>\n<video src=\"" << HtmlEscape(extras.video)
         << "\" controls style=\"max-width:100%\"></video>\n";
  html << "<p>Files: routine.json, routine.c3d (trampoline marker set and the bed's corners), "
          "routine.mot, skills/NN.yaml (each skill's keyframes, for acrolab optimize).</p>\n"
       << internal::kHtmlPageEnd;
  write("report.html", html.str());
  return written;
}

}  // namespace acro::ui
