#include "acro/capture/force_plate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace acro::capture {
namespace {

// N·m per unit of a moment channel ("Nmm", "N.mm", "Nm", "N.m"); 0 if the unit says nothing.
double MomentUnitToNm(std::string unit) {
  std::string u;
  for (char c : unit) {
    if (c != ' ' && c != '.' && c != '*' && c != '\0')
      u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (u.empty()) return 0.0;
  if (u.size() >= 3 && u.compare(u.size() - 2, 2, "mm") == 0) return 1e-3;
  if (u == "nm") return 1.0;
  if (u == "ncm") return 1e-2;
  return 0.0;
}

// Fraction of the samples loaded above 20 % of the peak force whose COP lies on the plate (its
// rectangle in F, 10 % margin); 1 when the plate is never loaded.
double FractionCopOnPlate(const ForcePlate& plate,
                          const Eigen::Matrix3d& R_WF,
                          const Eigen::Vector3d& centre_W) {
  const Eigen::Index n = plate.force_W_N.cols();
  if (n == 0) return 1.0;
  const double peak = plate.force_W_N.colwise().norm().maxCoeff();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  for (int c = 0; c < 4; ++c)
    half = half.cwiseMax((R_WF.transpose() * (plate.corners_W_m.col(c) - centre_W)).cwiseAbs());
  int loaded = 0;
  int on = 0;
  for (Eigen::Index s = 0; s < n; ++s) {
    if (plate.force_W_N.col(s).norm() < 0.2 * peak || std::isnan(plate.cop_W_m(0, s))) continue;
    ++loaded;
    const Eigen::Vector3d d = (R_WF.transpose() * (plate.cop_W_m.col(s) - centre_W)).cwiseAbs();
    if (d.x() <= 1.1 * half.x() && d.y() <= 1.1 * half.y()) ++on;
  }
  return loaded == 0 ? 1.0 : double(on) / loaded;
}

// Warnings about one plate, "file: plate: problem"; the plate named by its number in the trial
// when it is one of the trial's plates.
class PlateWarner {
 public:
  PlateWarner(const Trial& trial, const ForcePlate& plate, std::vector<std::string>* warnings)
      : file_(trial.source.path), warnings_(warnings) {
    which_ = "FORCE_PLATFORM TYPE " + std::to_string(plate.type) + " plate";
    for (std::size_t i = 0; i < trial.force_plates.size(); ++i) {
      if (&trial.force_plates[i] == &plate) {
        which_ = "FORCE_PLATFORM plate " + std::to_string(i + 1) + " (TYPE " +
                 std::to_string(plate.type) + ")";
      }
    }
  }
  void operator()(const std::string& problem) const {
    if (warnings_ != nullptr) warnings_->push_back(file_ + ": " + which_ + ": " + problem);
  }

 private:
  std::string file_;
  std::string which_;
  std::vector<std::string>* warnings_;
};

// What turns one plate's channels into its outputs: the type and number of channels used, their
// baseline, the COP length unit (TYPE 1), the plate frame F in W and its surface centre, the
// surface centre relative to the transducer origin in F, and the calibration matrix (TYPE 4).
struct PlateSetup {
  int type = 0;
  int needed = 0;
  Eigen::Matrix<double, 8, 1> baseline = Eigen::Matrix<double, 8, 1>::Zero();
  double length_to_m = 0.0;
  Eigen::Matrix3d R_WF;
  Eigen::Vector3d centre_W;
  Eigen::Vector3d r;
  Eigen::Matrix<double, 6, 6> cal = Eigen::Matrix<double, 6, 6>::Identity();
};

// Whether the plate's first `needed` channels exist among the trial's analog channels.
bool HasChannels(const Trial& trial, const ForcePlate& plate, int needed) {
  if (static_cast<int>(plate.channels.size()) < needed) return false;
  for (int k = 0; k < needed; ++k) {
    if (plate.channels[k] < 0 || plate.channels[k] >= trial.num_analog_channels()) return false;
  }
  return true;
}

// Baseline per channel over the ZERO frame range (1-based frames of the data), if valid; else 0.
Eigen::Matrix<double, 8, 1> CalcBaseline(const Trial& trial, const ForcePlate& plate, int needed) {
  const std::int64_t samples = trial.num_analog_samples();
  const int per_frame = trial.analog_samples_per_frame();
  Eigen::Matrix<double, 8, 1> baseline = Eigen::Matrix<double, 8, 1>::Zero();
  if (plate.zero.size() >= 2 && plate.zero[0] >= 1 && plate.zero[1] >= plate.zero[0] &&
      per_frame > 0 && plate.zero[0] <= trial.num_frames) {
    const std::int64_t s0 = std::int64_t(plate.zero[0] - 1) * per_frame;
    const std::int64_t s1 =
        std::min<std::int64_t>(std::int64_t(plate.zero[1]) * per_frame, samples);
    for (int k = 0; k < needed; ++k) {
      baseline(k) = trial.analog.row(plate.channels[k]).segment(s0, s1 - s0).mean();
    }
  }
  return baseline;
}

// N·m per unit of the moment channels as labelled (the point unit when the label says nothing).
double LabelledMomentUnitToNm(const Trial& trial, const ForcePlate& plate) {
  const int type = plate.type;
  double labelled_moment_to_Nm = 0;
  if (type == 2 || type == 4 || type == 1) {
    labelled_moment_to_Nm =
        MomentUnitToNm(trial.analog_channels[plate.channels[type == 1 ? 5 : 3]].unit);
  }
  if (labelled_moment_to_Nm == 0) labelled_moment_to_Nm = trial.source.point_units_to_m;
  return labelled_moment_to_Nm;
}

// Metres per unit of the TYPE 1 COP channels: their unit, else the point unit.
double CopLengthUnitToM(const Trial& trial, const ForcePlate& plate) {
  double length_to_m = trial.source.point_units_to_m;
  if (plate.type == 1) {
    const double u = MomentUnitToNm("N" + trial.analog_channels[plate.channels[3]].unit);
    if (u != 0) length_to_m = u;
  }
  return length_to_m;
}

// Plate frame F in W from the corners (C3D manual, "FORCE_PLATFORM:CORNERS"), and the surface
// centre; false when the corners do not span a plane.
bool CalcPlateFrame(const Eigen::Matrix<double, 3, 4>& c,
                    Eigen::Matrix3d* R_WF,
                    Eigen::Vector3d* centre_W) {
  Eigen::Vector3d x = c.col(0) - c.col(1);
  Eigen::Vector3d y = c.col(0) - c.col(3);
  Eigen::Vector3d z = x.cross(y);
  if (x.norm() == 0 || z.norm() == 0) return false;
  x.normalize();
  z.normalize();
  y = z.cross(x);
  *R_WF << x, y, z;
  *centre_W = c.rowwise().mean();
  return true;
}

// r = surface centre relative to the transducer origin, in F (ORIGIN, z ≤ 0; a positive z is
// negated, with a warning).
Eigen::Vector3d SurfaceCentreOffset(const ForcePlate& plate, const PlateWarner& warn) {
  Eigen::Vector3d r = plate.origin_F_m;
  if (plate.type == 1) r.head<2>().setZero();
  if (r.z() > 0) {
    warn("ORIGIN z = " + std::to_string(r.z()) +
         " m is positive (the manual has it negative); negated");
    if (plate.type == 3) {
      r.z() = -r.z();
    } else {
      r = -r;
    }
  }
  return r;
}

// The TYPE 4 calibration matrix (identity, with a warning, when missing or not 6×6; identity for
// other types).
Eigen::Matrix<double, 6, 6> CalibrationMatrix(const ForcePlate& plate, const PlateWarner& warn) {
  Eigen::Matrix<double, 6, 6> cal = Eigen::Matrix<double, 6, 6>::Identity();
  if (plate.type == 4) {
    if (plate.cal_matrix.rows() == 6 && plate.cal_matrix.cols() == 6) {
      cal = plate.cal_matrix;
    } else {
      warn("CAL_MATRIX missing or not 6×6; identity used");
    }
  }
  return cal;
}

// The plate's outputs on every analog sample, with moment channels in units of `moment_to_Nm`.
void CalcOutputs(const Trial& trial,
                 const PlateSetup& setup,
                 double moment_to_Nm,
                 ForcePlate* plate) {
  const int type = setup.type;
  const Eigen::Vector3d& r = setup.r;
  const double length_to_m = setup.length_to_m;
  const std::int64_t samples = trial.num_analog_samples();
  plate->force_W_N.resize(3, samples);
  plate->cop_W_m.resize(3, samples);
  plate->free_moment_W_Nm.resize(3, samples);
  plate->moment_at_origin_W_Nm.resize(3, samples);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix<double, 8, 1> v;
  for (std::int64_t s = 0; s < samples; ++s) {
    for (int k = 0; k < setup.needed; ++k)
      v(k) = trial.analog(plate->channels[k], s) - setup.baseline(k);
    // Force f and moment m_O about the transducer origin, exerted by the plate on the body, in F.
    Eigen::Vector3d f;
    Eigen::Vector3d m_O;
    Eigen::Vector3d m_C;  // about the surface centre
    if (type == 1) {
      // Fx, Fy, Fz, COPx, COPy, Tz: the moment about the centre follows from the COP.
      f = v.head<3>();
      const Eigen::Vector3d cop(v(3) * length_to_m, v(4) * length_to_m, 0.0);
      m_C = cop.cross(f) + Eigen::Vector3d(0, 0, v(5) * moment_to_Nm);
      m_O = m_C - f.cross(r);
    } else if (type == 3) {
      // Kistler: fx12, fx34, fy14, fy23, fz1..fz4; sensors at (±a, ±b) (Kistler manual formulas,
      // as in the C3D manual "TYPE-3").
      const double a = std::abs(r.x());
      const double b = std::abs(r.y());
      f << v(0) + v(1), v(2) + v(3), v(4) + v(5) + v(6) + v(7);
      m_O << b * (v(4) + v(5) - v(6) - v(7)), a * (-v(4) + v(5) + v(6) - v(7)),
          b * (-v(0) + v(1)) + a * (v(2) - v(3));
      m_C = m_O + f.cross(Eigen::Vector3d(0, 0, r.z()));
    } else {
      Eigen::Matrix<double, 6, 1> w = setup.cal * v.head<6>();
      f = w.head<3>();
      m_O = w.tail<3>() * moment_to_Nm;
      // Transfer to the surface centre: M_C = M_O + (O − C) × f = M_O + f × r.
      m_C = m_O + f.cross(r);
    }
    plate->force_W_N.col(s) = setup.R_WF * f;
    plate->moment_at_origin_W_Nm.col(s) = setup.R_WF * m_O;
    // Centre of pressure on the surface (z = 0 in F about the centre): M_C,x = y·Fz, M_C,y =
    // −x·Fz.
    if (std::abs(f.z()) >= kMinCopForce_N) {
      const Eigen::Vector3d cop(-m_C.y() / f.z(), m_C.x() / f.z(), 0.0);
      const double free_z = m_C.z() - (cop.x() * f.y() - cop.y() * f.x());
      plate->cop_W_m.col(s) = setup.R_WF * cop + setup.centre_W;
      plate->free_moment_W_Nm.col(s) = setup.R_WF * Eigen::Vector3d(0, 0, free_z);
    } else {
      plate->cop_W_m.col(s).setConstant(nan);
      plate->free_moment_W_Nm.col(s).setConstant(nan);
    }
  }
}

// Unit check by physics: under load the COP lies on the plate. Vicon 370 files (c3d.org sample
// 3) label moment channels "Nm" while holding N·mm, which puts the COP hundreds of metres away;
// when the other factor brings it onto the plate, that factor is used, with a warning; else the
// outputs are computed again with the labelled one.
void CheckMomentUnitByCop(const Trial& trial,
                          const PlateSetup& setup,
                          double labelled_moment_to_Nm,
                          const PlateWarner& warn,
                          ForcePlate* plate) {
  const double inside = FractionCopOnPlate(*plate, setup.R_WF, setup.centre_W);
  if (inside >= 0.5) return;
  const double other =
      labelled_moment_to_Nm == 1.0 ? 1e-3 : (labelled_moment_to_Nm == 1e-3 ? 1.0 : 0.0);
  if (other == 0) return;
  CalcOutputs(trial, setup, other, plate);
  if (FractionCopOnPlate(*plate, setup.R_WF, setup.centre_W) >= 0.9) {
    warn("moment channels in '" + trial.analog_channels[plate->channels[3]].unit +
         "' put the COP off the plate under load; their values are taken as " +
         (other == 1e-3 ? "N·mm" : "N·m"));
  } else {
    CalcOutputs(trial, setup, labelled_moment_to_Nm, plate);
  }
}

}  // namespace

void CalcForcePlateOutputs(const Trial& trial,
                           ForcePlate* plate,
                           std::vector<std::string>* warnings) {
  const PlateWarner warn(trial, *plate, warnings);
  // No outputs until they are computed.
  plate->force_W_N.resize(3, 0);
  plate->cop_W_m.resize(3, 0);
  plate->free_moment_W_Nm.resize(3, 0);
  plate->moment_at_origin_W_Nm.resize(3, 0);

  // A supported type with its channels.
  PlateSetup setup;
  setup.type = plate->type;
  if (setup.type < 1 || setup.type > 4) {
    warn("type not supported (only 1-4); no ground reaction computed");
    return;
  }
  setup.needed = setup.type == 3 ? 8 : 6;
  if (!HasChannels(trial, *plate, setup.needed)) return;  // reported by the reader

  // Baseline; units: forces in N, moments converted from the moment channels' unit, lengths
  // (TYPE 1 COP) in the point unit.
  setup.baseline = CalcBaseline(trial, *plate, setup.needed);
  const double labelled_moment_to_Nm = LabelledMomentUnitToNm(trial, *plate);
  setup.length_to_m = CopLengthUnitToM(trial, *plate);

  // Geometry and calibration.
  if (!CalcPlateFrame(plate->corners_W_m, &setup.R_WF, &setup.centre_W)) {
    warn("CORNERS do not span a plane; no ground reaction computed");
    return;
  }
  setup.r = SurfaceCentreOffset(*plate, warn);
  setup.cal = CalibrationMatrix(*plate, warn);

  // Outputs with the labelled moment unit, checked against the plate for TYPE 2 and 4.
  CalcOutputs(trial, setup, labelled_moment_to_Nm, plate);
  if (setup.type == 2 || setup.type == 4)
    CheckMomentUnitByCop(trial, setup, labelled_moment_to_Nm, warn, plate);
}

}  // namespace acro::capture
