#include "acro/report/body_report.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/input_error.h"

namespace acro::ui {

// The analysis types this report presents.
using namespace acro::analysis;  // NOLINT(build/namespaces)

namespace {

using Json = nlohmann::ordered_json;  // keys in the order written

Json VectorJson(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

Json MatrixJson(const Eigen::Matrix3d& m) {
  Json rows = Json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return rows;
}

}  // namespace

std::string FormatBodyReportText(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec) {
  std::string out;
  out += "model: " + posed.model + fmt::format(", height {:.3f} m\n", posed.height_m);
  out += "pose: " +
         (pose_spec.empty() ? std::string("reference (standing, arms down)")
                            : std::string(pose_spec)) +
         "\n";
  out +=
      "frame: origin at the hip-joint midpoint, x anterior, y left, z up (metres, kg, kg·m²)\n\n";
  out +=
      "segment        mass_kg   com_x   com_y   com_z     I_xx     I_yy     I_zz  (about the "
      "segment COM)\n";
  for (const BodySegment& s : posed.segments) {
    // Explicit right alignment: fmt would left-align "nan" in a width, printf does not.
    out += fmt::format("{:<13} {:>8.3f} {:>7.3f} {:>7.3f} {:>7.3f} {:>8.4f} {:>8.4f} {:>8.4f}\n",
                       s.name,
                       s.in_H.mass_kg,
                       s.in_H.p_HoCm_H.x(),
                       s.in_H.p_HoCm_H.y(),
                       s.in_H.p_HoCm_H.z(),
                       s.in_H.I_Cm_H(0, 0),
                       s.in_H.I_Cm_H(1, 1),
                       s.in_H.I_Cm_H(2, 2));
  }
  const InertialProperties& t = posed.total;
  out += fmt::format("\nwhole body: mass {:.3f} kg, centre of mass ({:.4f}, {:.4f}, {:.4f}) m\n",
                     t.mass_kg,
                     t.p_HoCm_H.x(),
                     t.p_HoCm_H.y(),
                     t.p_HoCm_H.z());
  out += "inertia about the centre of mass (kg·m²):\n";
  for (int r = 0; r < 3; ++r)
    out += fmt::format(
        "  {:>9.4f} {:>9.4f} {:>9.4f}\n", t.I_Cm_H(r, 0), t.I_Cm_H(r, 1), t.I_Cm_H(r, 2));
  out += "\nsomersault-axis inertia (left-right axis through the centre of mass):\n";
  out += fmt::format(
      "  straight {:.2f} kg·m², pike {:.2f} kg·m² (straight/pike {:.2f}), tuck {:.2f} kg·m² "
      "(straight/tuck {:.2f})\n",
      shapes.straight_kgm2,
      shapes.pike_kgm2,
      shapes.straight_kgm2 / shapes.pike_kgm2,
      shapes.tuck_kgm2,
      shapes.straight_kgm2 / shapes.tuck_kgm2);
  const double ratio = shapes.straight_kgm2 / shapes.pose_kgm2;
  out += fmt::format(
      "  this pose: {:.2f} kg·m²; with the same take-off angular momentum it somersaults {:.2f} "
      "times as fast as straight\n",
      shapes.pose_kgm2,
      ratio);
  return out;
}

std::string FormatBodyReportJson(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec) {
  // The whole body.
  Json j;
  j["model"] = posed.model;
  j["height_m"] = posed.height_m;
  j["frame"] = "origin at the hip-joint midpoint, x anterior, y left, z up";
  j["pose"] = pose_spec;
  Json total;
  total["mass_kg"] = posed.total.mass_kg;
  total["com_m"] = VectorJson(posed.total.p_HoCm_H);
  total["inertia_com_kgm2"] = MatrixJson(posed.total.I_Cm_H);
  j["total"] = std::move(total);
  // Every segment.
  j["segments"] = Json::array();
  for (const BodySegment& s : posed.segments) {
    Json segment;
    segment["name"] = s.name;
    segment["mass_kg"] = s.in_H.mass_kg;
    segment["com_m"] = VectorJson(s.in_H.p_HoCm_H);
    segment["inertia_com_kgm2"] = MatrixJson(s.in_H.I_Cm_H);
    segment["joint_m"] = VectorJson(s.p_HoJ_H);
    segment["end_m"] = VectorJson(s.p_HoE_H);
    j["segments"].push_back(std::move(segment));
  }
  // The somersault-axis inertia of the shapes.
  j["somersault_inertia_kgm2"] = {{"straight", shapes.straight_kgm2},
                                  {"pike", shapes.pike_kgm2},
                                  {"tuck", shapes.tuck_kgm2},
                                  {"pose", shapes.pose_kgm2}};
  j["somersault_ratio_straight_to_pose"] = shapes.straight_kgm2 / shapes.pose_kgm2;
  // Names come from the athlete file: bytes that are not UTF-8 become U+FFFD.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace acro::ui
