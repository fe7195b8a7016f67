// Force platforms: BTK's asserted geometry and channels, closed-form synthetic plates (TYPE 2 and
// 3, ZERO baseline), a moment-transfer identity, physics on real trials (COP on the plate under
// load; flight phase of a jump), and TYPE-2 vs TYPE-4 of the same trial (c3d.org sample 10).

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "acro/capture/c3d.h"
#include "acro/capture/force_plate.h"
#include "refdata.h"

namespace acro::capture {
namespace {

using acro::testing::RefdataFile;

// The plate frame as documented in force_plate.h: x = c1 − c2, y from c1 − c4, z = x × y.
Eigen::Matrix3d PlateRotation(const ForcePlate& p) {
  Eigen::Vector3d x = (p.corners_W_m.col(0) - p.corners_W_m.col(1)).normalized();
  Eigen::Vector3d z = x.cross(p.corners_W_m.col(0) - p.corners_W_m.col(3)).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return R;
}

// ---------------------------------------------------------------------------------------------
// BTK ForcePlatformsExtractor values.
TEST(ForcePlate, Eb015piGeometryAsBtk) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pi.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.force_plates.size(), 2u);
  const char* labels[2][6] = {{"FX1", "FY1", "FZ1", "MX1", "MY1", "MZ1"},
                              {"FX2", "FY2", "FZ2", "MX2", "MY2", "MZ2"}};
  const double origins[2][3] = {{-4.4, 1.9, -21.6}, {-4.06, 3.81, -20.06}};
  const double corners[2][4][3] = {{{520.0451, 1242.1694, 0.6219},
                                    {57.0463, 1243.1996, 0.6211},
                                    {58.1765, 1751.1963, 2.0812},
                                    {521.1754, 1750.1661, 2.0820}},
                                   {{53.6555, 1139.9977, 1.9204},
                                    {516.6432, 1143.3159, 1.2880},
                                    {520.2825, 635.3301, 0.1814},
                                    {57.2948, 632.0118, 0.8138}}};
  for (int i = 0; i < 2; ++i) {
    const ForcePlate& p = t.force_plates[i];
    EXPECT_EQ(p.type, 2);
    ASSERT_EQ(p.channels.size(), 6u);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(t.analog_channels[p.channels[k]].label, labels[i][k]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.origin_F_m(k) * 1000, origins[i][k], 1e-5);
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.corners_W_m(k, c) * 1000, corners[i][c][k], 5e-5);
    }
    EXPECT_EQ(p.force_W_N.cols(), t.num_analog_samples());
  }
}

TEST(ForcePlate, Type2AsBtk) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_10/TYPE-2.C3D");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.force_plates.size(), 1u);
  const ForcePlate& p = t.force_plates[0];
  EXPECT_EQ(p.type, 2);
  ASSERT_EQ(p.channels.size(), 6u);
  const char* labels[6] = {"FX1", "FY1", "FZ1", "MX1", "MY1", "MZ1"};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(t.analog_channels[p.channels[k]].label, labels[k]);
  EXPECT_NEAR(p.origin_F_m(0) * 1000, -1.6, 1e-5);
  EXPECT_NEAR(p.origin_F_m(1) * 1000, 0.7, 1e-5);
  EXPECT_NEAR(p.origin_F_m(2) * 1000, 37.5, 1e-5);
  const int fx = p.channels[0], fy = p.channels[1], mx = p.channels[3];
  EXPECT_NEAR(t.analog(fx, 1), 0.08843, 1e-5);
  EXPECT_NEAR(t.analog(fx, 3), -0.08843, 1e-5);
  EXPECT_NEAR(t.analog(fx, 1020), -69.59441, 1e-5);
  EXPECT_NEAR(t.analog(fx, 1021), -72.24731, 1e-5);
  EXPECT_NEAR(t.analog(fy, 0), 0.17762, 1e-5);
  EXPECT_NEAR(t.analog(mx, 2), 36.83129, 1e-5);
  EXPECT_NEAR(t.analog(mx, 560), 73.66259, 1e-5);
  EXPECT_NEAR(t.analog(mx, 561), 0.0, 1e-5);
  // ORIGIN z > 0 contradicts the manual: reported.
  bool warned = false;
  for (const std::string& w : t.warnings) warned = warned || w.find("ORIGIN") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(ForcePlate, Type4CalMatrixAsBtk) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_10/TYPE-4.C3D");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.force_plates.size(), 1u);
  const ForcePlate& p = t.force_plates[0];
  EXPECT_EQ(p.type, 4);
  ASSERT_EQ(p.channels.size(), 6u);
  const char* labels[6] = {"FX1", "FY1", "FZ1", "MX1", "MY1", "MZ1"};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(t.analog_channels[p.channels[k]].label, labels[k]);
  EXPECT_EQ(t.num_analog_samples(), 3980);
  EXPECT_NEAR(p.origin_F_m(0) * 1000, -1.6, 1e-5);
  EXPECT_NEAR(p.origin_F_m(1) * 1000, 0.7, 1e-5);
  EXPECT_NEAR(p.origin_F_m(2) * 1000, 37.5, 1e-5);
  // BTK: CAL_MATRIX == (this matrix, written row by row)ᵀ.
  Eigen::Matrix<double, 6, 6> btk;
  btk << 1.5270, 0.0140, 0.0460, -4.2840, -5.4940, 2.8560,  //
      -0.0050, 1.5390, -0.0190, 17.1600, 5.6680, -9.6390,   //
      0.0000, -0.0090, 5.9880, 13.2330, 13.2500, 4.6090,    //
      0.0000, 0.0020, 0.0000, 741.8710, -0.5390, -0.5970,   //
      0.0020, -0.0010, 0.000, -1.6820, 739.6310, 2.0420,    //
      -0.0020, -0.0050, -0.0020, -3.2500, -0.5940, 391.8790;
  ASSERT_EQ(p.cal_matrix.rows(), 6);
  ASSERT_EQ(p.cal_matrix.cols(), 6);
  EXPECT_LE((p.cal_matrix - btk.transpose()).cwiseAbs().maxCoeff(), 5e-5);
}

TEST(ForcePlate, Type4aWrenchAtAnalogRate) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_10/TYPE-4a.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.force_plates.size(), 2u);
  EXPECT_EQ(t.force_plates[0].cop_W_m.cols(), 5760);  // 360 frames × 16
  EXPECT_EQ(t.force_plates[0].force_W_N.cols(), 5760);
}

TEST(ForcePlate, Sample09TwoPlatforms) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_09/PolygonC3D.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  EXPECT_EQ(ReadC3d(path).force_plates.size(), 2u);
}

TEST(ForcePlate, OutputsOnlyWhenAsked) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  C3dReadOptions options;
  options.compute_force_plates = false;
  const Trial t = ReadC3d(path, options);
  ASSERT_EQ(t.force_plates.size(), 2u);
  EXPECT_EQ(t.force_plates[0].force_W_N.cols(), 0);
  EXPECT_EQ(t.force_plates[0].channels.size(), 6u);  // geometry still read
  // Computing afterwards gives what the reader gives.
  ForcePlate plate = t.force_plates[0];
  CalcForcePlateOutputs(t, &plate, nullptr);
  EXPECT_TRUE(plate.force_W_N == ReadC3d(path).force_plates[0].force_W_N);
}

// ---------------------------------------------------------------------------------------------
// Synthetic plates with a known wrench: closed-form expectations from the documented convention.
Trial SyntheticTrial(int channels, int frames, int per_frame) {
  Trial t;
  t.source.path = "synthetic";
  t.source.point_units_to_m = 1e-3;
  t.num_frames = frames;
  t.point_rate_hz = 100;
  t.analog_rate_hz = 100.0 * per_frame;
  t.analog_channels.resize(channels);
  t.analog = Eigen::MatrixXd::Zero(channels, std::int64_t(frames) * per_frame);
  return t;
}

ForcePlate SyntheticPlate(int type, const Eigen::Vector3d& origin_F_m) {
  // 0.6 m × 0.4 m plate centred at (1, 2, 0): x_F = +X, y_F = −Y, z_F = −Z (down).
  ForcePlate p;
  p.type = type;
  const Eigen::Vector3d c(1, 2, 0);
  p.corners_W_m.col(0) = c + Eigen::Vector3d(0.3, -0.2, 0);
  p.corners_W_m.col(1) = c + Eigen::Vector3d(-0.3, -0.2, 0);
  p.corners_W_m.col(2) = c + Eigen::Vector3d(-0.3, 0.2, 0);
  p.corners_W_m.col(3) = c + Eigen::Vector3d(0.3, 0.2, 0);
  p.origin_F_m = origin_F_m;
  for (int k = 0; k < (type == 3 ? 8 : 6); ++k) p.channels.push_back(k);
  return p;
}

TEST(ForcePlate, Type2SyntheticWrenchAndBaseline) {
  const int frames = 20, per_frame = 2;
  Trial t = SyntheticTrial(6, frames, per_frame);
  const char* units[6] = {"N", "N", "N", "Nmm", "Nmm", "Nmm"};
  for (int k = 0; k < 6; ++k) t.analog_channels[k].unit = units[k];
  const Eigen::Vector3d r(0.002, -0.001, -0.04);  // surface centre from the transducer, in F
  ForcePlate p = SyntheticPlate(2, r);
  p.zero = {1, 5};
  // Reaction on the body, in F (z down): 700 N up, some shear; COP at (0.1, −0.05) in F; free
  // moment 2 N·m.
  const Eigen::Vector3d f(10, -20, -700);
  const Eigen::Vector3d cop_F(0.1, -0.05, 0);
  const double tz = 2.0;
  const Eigen::Vector3d m_C = cop_F.cross(f) + Eigen::Vector3d(0, 0, tz);
  const Eigen::Vector3d m_O = m_C - f.cross(r);  // M_O = M_C + (C − O) × f … with C − O = r
  const Eigen::Matrix<double, 6, 1> offset =
      (Eigen::Matrix<double, 6, 1>() << 3, -2, 15, 400, -300, 50).finished();
  for (int s = 0; s < frames * per_frame; ++s) {
    const bool loaded = s >= 5 * per_frame;  // frames 1–5 unloaded: the ZERO baseline
    for (int k = 0; k < 3; ++k) t.analog(k, s) = (loaded ? f(k) : 0) + offset(k);
    for (int k = 0; k < 3; ++k) t.analog(3 + k, s) = (loaded ? m_O(k) * 1000 : 0) + offset(3 + k);
  }
  std::vector<std::string> warnings;
  CalcForcePlateOutputs(t, &p, &warnings);
  EXPECT_TRUE(warnings.empty());
  const Eigen::Matrix3d R = PlateRotation(p);
  const Eigen::Vector3d centre(1, 2, 0);
  const int s = 30;
  const double eps = 1e-9;
  EXPECT_LE((p.force_W_N.col(s) - Eigen::Vector3d(10, 20, 700)).norm(), eps);
  EXPECT_LE((p.cop_W_m.col(s) - (centre + Eigen::Vector3d(0.1, 0.05, 0))).norm(), eps);
  EXPECT_LE((p.free_moment_W_Nm.col(s) - Eigen::Vector3d(0, 0, -tz)).norm(), eps);
  EXPECT_LE((p.moment_at_origin_W_Nm.col(s) - R * m_O).norm(), 1e-6);
  // Unloaded samples: zero force after the baseline, no COP.
  EXPECT_LE(p.force_W_N.col(0).norm(), eps);
  EXPECT_TRUE(std::isnan(p.cop_W_m(0, 0)));
}

TEST(ForcePlate, Type3SyntheticVerticalLoad) {
  Trial t = SyntheticTrial(8, 1, 1);
  const double a = 0.12, b = 0.2;
  ForcePlate p = SyntheticPlate(3, Eigen::Vector3d(a, b, -0.05));
  // 800 N at (x, y) in F spread bilinearly over sensors at (+a,+b), (−a,+b), (−a,−b), (+a,−b)
  // (the sensor layout behind the Kistler formulas: Mx = b(fz1+fz2−fz3−fz4), My =
  // a(−fz1+fz2+fz3−fz4)).
  const double x = 0.05, y = -0.08, load = -800;  // reaction along −z_F (up)
  const double wx = (x + a) / (2 * a), wy = (y + b) / (2 * b);
  t.analog(4, 0) = load * wx * wy;              // (+a, +b)
  t.analog(5, 0) = load * (1 - wx) * wy;        // (−a, +b)
  t.analog(6, 0) = load * (1 - wx) * (1 - wy);  // (−a, −b)
  t.analog(7, 0) = load * wx * (1 - wy);        // (+a, −b)
  CalcForcePlateOutputs(t, &p, nullptr);
  EXPECT_LE((p.force_W_N.col(0) - Eigen::Vector3d(0, 0, 800)).norm(), 1e-9);
  // COP_W = centre + R (x, y, 0) with R = diag(1, −1, −1).
  EXPECT_LE((p.cop_W_m.col(0) - Eigen::Vector3d(1 + x, 2 - y, 0)).norm(), 1e-12);
  EXPECT_LE(p.free_moment_W_Nm.col(0).norm(), 1e-9);
}

// Real data: while a foot loads a plate of Eb015pr (more than 50 N), the centre of pressure
// computed from its six channels lies on that plate, inside the rectangle of its CORNERS
// parameter (1 cm of margin for the channels' noise at low load). A wrong channel order, scale,
// sign or calibration matrix moves it off the plate: the COP is a ratio of moments to force.
TEST(ForcePlate, LoadedCentreOfPressureLiesOnThePlate) {
  const auto path = RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_FALSE(t.force_plates.empty());
  int checked = 0;
  for (const ForcePlate& p : t.force_plates) {
    const Eigen::Vector3d c0 = p.corners_W_m.col(0);
    const Eigen::Vector3d e1 = p.corners_W_m.col(1) - c0;  // two edges of the plate
    const Eigen::Vector3d e3 = p.corners_W_m.col(3) - c0;
    for (Eigen::Index s = 0; s < p.force_W_N.cols(); ++s) {
      if (std::abs(p.force_W_N(2, s)) < 50.0 || std::isnan(p.cop_W_m(0, s))) continue;
      const Eigen::Vector3d d = p.cop_W_m.col(s) - c0;
      const double u = d.dot(e1) / e1.squaredNorm(), v = d.dot(e3) / e3.squaredNorm();
      EXPECT_GE(u * e1.norm(), -0.01) << "sample " << s;
      EXPECT_LE(u * e1.norm(), e1.norm() + 0.01) << "sample " << s;
      EXPECT_GE(v * e3.norm(), -0.01) << "sample " << s;
      EXPECT_LE(v * e3.norm(), e3.norm() + 0.01) << "sample " << s;
      EXPECT_NEAR(d.dot(e1.cross(e3).normalized()), 0.0, 0.01) << "sample " << s;  // on its surface
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
}

// ---------------------------------------------------------------------------------------------
// Physics on real trials.

// Under load (force above 20 % of the plate's peak) the COP lies on the plate. Left out:
// sample_06/newwalk.c3d (and its copies sample_10/TYPE-2a, TYPE-4a), where 4 of 456 loaded samples
// of plate 1 put the COP up to 6.3 cm beyond the plate edge at a heel strike.
TEST(ForcePlate, CopOnPlateUnderLoad) {
  const char* files[] = {
      "c3dio-c3d_org_samples/sample_01/Eb015pi.c3d",
      "c3dio-c3d_org_samples/sample_02/pc_real.c3d",
      "c3dio-c3d_org_samples/sample_03/gait-pig.c3d",  // moment channels labelled Nm, values N·mm
      "c3dio-c3d_org_samples/sample_04/sub_labels.c3d",
      "c3dio-c3d_org_samples/sample_09/PolygonC3D.c3d",
      "c3dio-c3d_org_samples/sample_10/TYPE-2.C3D",
      "c3dio-c3d_org_samples/sample_10/TYPE-4.C3D",
      "c3dio-c3d_org_samples/sample_10/TYPE-3.c3d",
      "c3dio-c3d_org_samples/sample_14/sample14.c3d",
      "c3dio-c3d_org_samples/sample_26/Walking_Hybrid_1_1.c3d",
      "c3dio-c3d_org_samples/sample_00/Motion Analysis Corporation/Sample_Jump2.c3d",
      "c3dio-c3d_org_samples/sample_00/Motion Analysis Corporation/Walk1.c3d",
      "c3dio-c3d_org_samples/sample_00/Innovative Sports Training/Gait with EMG.c3d",
      "c3dio-c3d_org_samples/sample_00/Codamotion/codamotion_gaitwands_19970212.c3d",
      "BTKData/Input/C3DSamples/others/Gait.c3d",
  };
  for (const char* file : files) {
    const auto path = RefdataFile(file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    for (const ForcePlate& p : t.force_plates) {
      ASSERT_GT(p.force_W_N.cols(), 0) << file;
      const Eigen::Matrix3d R = PlateRotation(p);
      const Eigen::Vector3d centre = p.corners_W_m.rowwise().mean();
      Eigen::Vector3d half = Eigen::Vector3d::Zero();
      for (int c = 0; c < 4; ++c)
        half = half.cwiseMax((R.transpose() * (p.corners_W_m.col(c) - centre)).cwiseAbs());
      const double peak = p.force_W_N.colwise().norm().maxCoeff();
      if (peak < 100) continue;  // plate not stepped on
      int loaded = 0;
      for (Eigen::Index s = 0; s < p.force_W_N.cols(); ++s) {
        if (p.force_W_N.col(s).norm() < 0.2 * peak) continue;
        ++loaded;
        // A person pushes down: the reaction points up (Z-up labs).
        EXPECT_GT(p.force_W_N(2, s), 0) << file << " sample " << s;
        const Eigen::Vector3d d = (R.transpose() * (p.cop_W_m.col(s) - centre)).cwiseAbs();
        ASSERT_LE(d.x(), half.x() + 1e-9) << file << " sample " << s;
        ASSERT_LE(d.y(), half.y() + 1e-9) << file << " sample " << s;
      }
      EXPECT_GT(loaded, 10) << file;
    }
  }
}

// Sample_Jump2 (c3dio README, own inspection): F1Z + F2Z stays within 50 N of zero in flight
// (0.705–1.178 s) and peaks at 1681.8 N at 1.247 s on landing; the events say take-off 0.6917 s and
// landing 1.1833 s.
TEST(ForcePlate, Jump2FlightAndLanding) {
  const auto path =
      RefdataFile("c3dio-c3d_org_samples/sample_00/Motion Analysis Corporation/Sample_Jump2.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.force_plates.size(), 2u);
  EXPECT_EQ(t.force_plates[0].type, 4);
  const int f1 = t.FindAnalog("F1Z"), f2 = t.FindAnalog("F2Z");
  ASSERT_GE(f1, 0);
  ASSERT_GE(f2, 0);
  double flight_raw = 0, flight_W = 0, peak_W = 0, peak_time = 0;
  for (Eigen::Index s = 0; s < t.num_analog_samples(); ++s) {
    const double time = s / t.analog_rate_hz;
    const double raw = t.analog(f1, s) + t.analog(f2, s);
    const double vertical = t.force_plates[0].force_W_N(2, s) + t.force_plates[1].force_W_N(2, s);
    if (time >= 0.705 && time <= 1.178) {
      flight_raw = std::max(flight_raw, std::abs(raw));
      flight_W = std::max(flight_W, std::abs(vertical));
    }
    if (std::abs(vertical) > peak_W) {
      peak_W = std::abs(vertical);
      peak_time = time;
    }
  }
  EXPECT_LT(flight_raw, 50.0);
  EXPECT_LT(flight_W, 50.0);
  EXPECT_NEAR(peak_W, 1681.8, 0.05);  // README value to its 0.1 N precision
  EXPECT_NEAR(peak_time, 1.247, 0.5 / t.analog_rate_hz + 1e-3);
  ASSERT_EQ(t.events.size(), 4u);
  EXPECT_EQ(t.events[1].context, "Take-Off");
  EXPECT_NEAR(t.events[1].time_s, 0.6917, 1e-4);
  EXPECT_EQ(t.events[2].context, "Landing");
  EXPECT_NEAR(t.events[2].time_s, 1.1833, 1e-4);
}

// TYPE-2 and TYPE-4 of the same trial: after CAL_MATRIX the forces agree to the difference of the
// two files' own calibrations (FZ: TYPE-2 scale 0.37012 N/count vs 5.988 × 0.061069 = 0.3657
// N/count, 1.2 %, plus the cross-talk terms only TYPE-4 applies): within 2 % of the peak vertical
// force. The transposed matrix would be off by more than 100 N, so this also fixes CAL_MATRIX's
// orientation.
TEST(ForcePlate, Type2AndType4GiveTheSameForces) {
  const auto p2 = RefdataFile("c3dio-c3d_org_samples/sample_10/TYPE-2.C3D");
  const auto p4 = RefdataFile("c3dio-c3d_org_samples/sample_10/TYPE-4.C3D");
  ACRO_REQUIRE_REFDATA_FILE(p2);
  ACRO_REQUIRE_REFDATA_FILE(p4);
  const Trial t2 = ReadC3d(p2);
  const Trial t4 = ReadC3d(p4);
  const Eigen::Matrix3Xd& f2 = t2.force_plates[0].force_W_N;
  const Eigen::Matrix3Xd& f4 = t4.force_plates[0].force_W_N;
  ASSERT_EQ(f2.cols(), f4.cols());
  const double peak = f2.row(2).cwiseAbs().maxCoeff();
  EXPECT_GT(peak, 350);
  EXPECT_LE((f2 - f4).cwiseAbs().maxCoeff(), 0.02 * peak);
  // Correlation of the vertical force over the trial.
  const Eigen::VectorXd a = f2.row(2).transpose().array() - f2.row(2).mean();
  const Eigen::VectorXd b = f4.row(2).transpose().array() - f4.row(2).mean();
  EXPECT_GT(a.dot(b) / (a.norm() * b.norm()), 0.999);
  ForcePlate transposed = t4.force_plates[0];
  transposed.cal_matrix.transposeInPlace();
  CalcForcePlateOutputs(t4, &transposed, nullptr);
  EXPECT_GT((f2 - transposed.force_W_N).cwiseAbs().maxCoeff(), 100.0);
}

}  // namespace
}  // namespace acro::capture
