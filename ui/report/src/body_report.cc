#include "acro/report/body_report.h"

#include <cmath>
#include <cstdio>

#include "acro/base/input_error.h"
#include "acro/base/json_writer.h"

namespace acro::ui {

// The analysis types this report presents.
using namespace acro::analysis;  // NOLINT(build/namespaces)

namespace {

std::string Format(const char* format, double a, double b = 0, double c = 0) {
  char buffer[128];
  std::snprintf(buffer, sizeof(buffer), format, a, b, c);
  return buffer;
}

void WriteVector(JsonWriter* w, const Eigen::Vector3d& v) {
  w->Array(std::array<double, 3>{v.x(), v.y(), v.z()});
}

void WriteMatrix(JsonWriter* w, const Eigen::Matrix3d& m) {
  w->BeginArray();
  for (int r = 0; r < 3; ++r) w->Array(std::array<double, 3>{m(r, 0), m(r, 1), m(r, 2)});
  w->EndArray();
}

}  // namespace

std::string FormatBodyReportText(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec) {
  std::string out;
  out += "model: " + posed.model + Format(", height %.3f m\n", posed.height_m);
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
    char line[200];
    std::snprintf(line,
                  sizeof(line),
                  "%-13s %8.3f %7.3f %7.3f %7.3f %8.4f %8.4f %8.4f\n",
                  s.name.c_str(),
                  s.in_H.mass_kg,
                  s.in_H.p_HoCm_H.x(),
                  s.in_H.p_HoCm_H.y(),
                  s.in_H.p_HoCm_H.z(),
                  s.in_H.I_Cm_H(0, 0),
                  s.in_H.I_Cm_H(1, 1),
                  s.in_H.I_Cm_H(2, 2));
    out += line;
  }
  const InertialProperties& t = posed.total;
  out += Format("\nwhole body: mass %.3f kg, centre of mass (%.4f, ", t.mass_kg, t.p_HoCm_H.x());
  out += Format("%.4f, %.4f) m\n", t.p_HoCm_H.y(), t.p_HoCm_H.z());
  out += "inertia about the centre of mass (kg·m²):\n";
  for (int r = 0; r < 3; ++r)
    out += Format("  %9.4f %9.4f", t.I_Cm_H(r, 0), t.I_Cm_H(r, 1)) +
           Format(" %9.4f\n", t.I_Cm_H(r, 2));
  out += "\nsomersault-axis inertia (left-right axis through the centre of mass):\n";
  out += Format("  straight %.2f kg·m², pike %.2f kg·m² (straight/pike %.2f), ",
                shapes.straight_kgm2,
                shapes.pike_kgm2,
                shapes.straight_kgm2 / shapes.pike_kgm2);
  out += Format("tuck %.2f kg·m² (straight/tuck %.2f)\n",
                shapes.tuck_kgm2,
                shapes.straight_kgm2 / shapes.tuck_kgm2);
  const double ratio = shapes.straight_kgm2 / shapes.pose_kgm2;
  out += Format(
      "  this pose: %.2f kg·m²; with the same take-off angular momentum it somersaults %.2f times "
      "as fast as "
      "straight\n",
      shapes.pose_kgm2,
      ratio);
  return out;
}

std::string FormatBodyReportJson(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec) {
  JsonWriter w;
  w.BeginObject();
  w.Field("model", posed.model);
  w.Field("height_m", posed.height_m);
  w.Field("frame", "origin at the hip-joint midpoint, x anterior, y left, z up");
  w.Field("pose", std::string(pose_spec));
  w.Key("total");
  w.BeginObject();
  w.Field("mass_kg", posed.total.mass_kg);
  w.Key("com_m");
  WriteVector(&w, posed.total.p_HoCm_H);
  w.Key("inertia_com_kgm2");
  WriteMatrix(&w, posed.total.I_Cm_H);
  w.EndObject();
  w.Key("segments");
  w.BeginArray();
  for (const BodySegment& s : posed.segments) {
    w.BeginObject();
    w.Field("name", s.name);
    w.Field("mass_kg", s.in_H.mass_kg);
    w.Key("com_m");
    WriteVector(&w, s.in_H.p_HoCm_H);
    w.Key("inertia_com_kgm2");
    WriteMatrix(&w, s.in_H.I_Cm_H);
    w.Key("joint_m");
    WriteVector(&w, s.p_HoJ_H);
    w.Key("end_m");
    WriteVector(&w, s.p_HoE_H);
    w.EndObject();
  }
  w.EndArray();
  w.Key("somersault_inertia_kgm2");
  w.BeginObject();
  w.Field("straight", shapes.straight_kgm2);
  w.Field("pike", shapes.pike_kgm2);
  w.Field("tuck", shapes.tuck_kgm2);
  w.Field("pose", shapes.pose_kgm2);
  w.EndObject();
  w.Field("somersault_ratio_straight_to_pose", shapes.straight_kgm2 / shapes.pose_kgm2);
  w.EndObject();
  return w.str() + "\n";
}

}  // namespace acro::ui
