#include "acro/reconstruct/motion_export.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/capture/c3d.h"

namespace acro::analysis {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// Vicon-style angle points: label and the coordinates in (X sagittal, Y frontal, Z transverse).
struct AnglePoint {
  const char* label;
  const char* x;
  const char* y;
  const char* z;
};

constexpr AnglePoint kAnglePoints[] = {
    {"LumbarAngles", "lumbar_flexion", "lumbar_bending", "lumbar_rotation"},
    {"NeckAngles", "neck_flexion", "neck_bending", "neck_rotation"},
    {"LShoulderAngles", "l_shoulder_flexion", "l_shoulder_abduction", "l_shoulder_rotation"},
    {"RShoulderAngles", "r_shoulder_flexion", "r_shoulder_abduction", "r_shoulder_rotation"},
    {"LElbowAngles", "l_elbow_flexion", "", "l_elbow_pronation"},
    {"RElbowAngles", "r_elbow_flexion", "", "r_elbow_pronation"},
    {"LWristAngles", "l_wrist_flexion", "l_wrist_deviation", ""},
    {"RWristAngles", "r_wrist_flexion", "r_wrist_deviation", ""},
    {"LHipAngles", "l_hip_flexion", "l_hip_abduction", "l_hip_rotation"},
    {"RHipAngles", "r_hip_flexion", "r_hip_abduction", "r_hip_rotation"},
    {"LKneeAngles", "l_knee_flexion", "", ""},
    {"RKneeAngles", "r_knee_flexion", "", ""},
    {"LAnkleAngles", "l_ankle_flexion", "l_ankle_inversion", ""},
    {"RAnkleAngles", "r_ankle_flexion", "r_ankle_inversion", ""},
};

int FindName(const Motion& motion, const char* name) {
  if (name[0] == '\0') return -1;
  for (size_t i = 0; i < motion.coordinate_names.size(); ++i)
    if (motion.coordinate_names[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

capture::Storage MakeMotionStorage(const Motion& motion) {
  capture::Storage table;
  table.name = "acrolab reconstruct";
  table.in_degrees = true;
  table.labels = motion.coordinate_names;
  table.time_s = motion.time_s;
  table.data = motion.q.transpose();
  for (int c = 7; c < motion.nq(); ++c) table.data.col(c) *= kRadToDeg;
  return table;
}

void WriteMotionMot(const Motion& motion, const std::filesystem::path& path) {
  capture::WriteStorage(MakeMotionStorage(motion), path, capture::StorageFlavor::kMot);
}

std::string FormatMotionCsv(const Motion& motion) {
  std::string out = "time_s";
  for (int c = 0; c < motion.nq(); ++c) {
    const std::string& n = motion.coordinate_names[size_t(c)];
    out += "," + n + (c < 3 ? "_m" : c < 7 ? "" : "_deg");
  }
  out += ",rms_m,max_m,num_markers\n";
  for (int f = 0; f < motion.num_frames(); ++f) {
    out += fmt::format("{:.6f}", motion.time_s[f]);
    for (int c = 0; c < motion.nq(); ++c)
      out += fmt::format(",{:.9g}", c < 7 ? motion.q(c, f) : motion.q(c, f) * kRadToDeg);
    const FrameFit& fit = motion.fit[size_t(f)];
    if (fit.valid)
      out += fmt::format(",{:.6g},{:.6g},{}\n", fit.rms_m, fit.max_m, fit.num_markers);
    else
      out += fmt::format(",,,{}\n", fit.num_markers);
  }
  return out;
}

void WriteMotionCsv(const Motion& motion, const std::filesystem::path& path) {
  WriteFileAtomically(path, FormatMotionCsv(motion));
}

std::string FormatMarkerResidualsCsv(const Motion& motion) {
  std::string out = "marker,frames,mean_m,rms_m,max_m\n";
  for (int m = 0; m < static_cast<int>(motion.marker_names.size()); ++m) {
    double sum = 0, sum2 = 0, mx = 0;
    int n = 0;
    for (int f = 0; f < motion.num_frames(); ++f) {
      const double d = motion.marker_error_m(m, f);
      if (std::isnan(d)) continue;
      sum += d;
      sum2 += d * d;
      mx = std::max(mx, d);
      ++n;
    }
    if (n > 0)
      out += fmt::format("{},{},{:.6g},{:.6g},{:.6g}\n",
                         motion.marker_names[size_t(m)],
                         n,
                         sum / n,
                         std::sqrt(sum2 / n),
                         mx);
    else
      out += fmt::format("{},0,,,\n", motion.marker_names[size_t(m)]);
  }
  return out;
}

capture::Trial MakeModelOutputTrial(const ReconstructionResult& result,
                                    const capture::Trial& source) {
  const Motion& motion = result.motion;
  const int M = static_cast<int>(result.markers.size());
  const int F = motion.num_frames();
  capture::Trial t;
  t.source.format = "C3D";
  t.source.point_units = "mm";
  t.source.point_units_to_m = 1e-3;
  t.point_rate_hz = source.point_rate_hz;
  t.first_frame = source.first_frame;
  t.num_frames = F;
  t.subject_name = source.subject_name;
  t.events = source.events;
  for (const ModelMarker& m : result.markers)
    t.points.push_back({m.name, "processed marker", capture::PointType::kMarker, "m"});
  std::vector<const AnglePoint*> angles;
  for (const AnglePoint& a : kAnglePoints) {
    if (FindName(motion, a.x) < 0) continue;
    angles.push_back(&a);
    t.points.push_back({a.label,
                        "joint angles (deg): X sagittal, Y frontal, Z transverse",
                        capture::PointType::kAngle,
                        "deg"});
  }
  const int P = t.num_points();
  t.positions.setConstant(3, Eigen::Index(F) * P, std::nan(""));
  t.residuals.setZero(P, F);
  t.camera_masks.setZero(P, F);
  for (int f = 0; f < F; ++f) {
    for (int m = 0; m < M; ++m) {
      t.position(f, m) = result.marker_positions.col(Eigen::Index(f) * M + m);
      if (!t.valid(f, m)) t.residuals(m, f) = -1.0f;
    }
    for (size_t a = 0; a < angles.size(); ++a) {
      const int p = M + static_cast<int>(a);
      const char* names[3] = {angles[a]->x, angles[a]->y, angles[a]->z};
      for (int d = 0; d < 3; ++d) {
        const int c = FindName(motion, names[d]);
        t.position(f, p)[d] = c >= 0 ? motion.q(c, f) * kRadToDeg : 0.0;
      }
    }
  }
  return t;
}

void WriteMotionC3d(const ReconstructionResult& result,
                    const capture::Trial& source,
                    const std::filesystem::path& path) {
  capture::WriteC3d(MakeModelOutputTrial(result, source), path);
}

}  // namespace acro::analysis
