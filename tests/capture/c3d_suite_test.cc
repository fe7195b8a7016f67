// The remaining values that BTK, ezc3d, py-c3d and c3dio assert for the c3d.org and BTK suites
// (../shared/refdata/{c3dio-c3d_org_samples,BTKData}/expected.md), table by table. Samples 01/02
// and the odd BTK files are in c3d_reader_test, force platforms in force_plate_test, round trips in
// c3d_writer_test, broken files in c3d_bad_input_test.
//
// Decisions for files that c3dio expects to be rejected (we follow BTK and load them, with
// warnings, because their data are recoverable):
//   sample_06/MACsample.c3d   loads (non-standard names; BTK reads it)
//   sample_11/evart.c3d       loads; warnings: TYPE-3 plates with 6 channels (no ground reaction
//                             for those two), ANALOG:RATE inconsistent with the layout, SCALE short
//   sample_13/*.c3d           loads; warning: POINT:FRAMES one more than the header range (header
//   used, as BTK) sample_15/FP1, FP2        load (BTK reads them) sample_16/*.c3d           load;
//   warnings: every residual -1 with real coordinates (kept), units
//                             assumed metres from the data's magnitude
//   sample_24/MotionMonitor   loads; warning: header analog words disagree with ANALOG:USED (the
//                             parameter fits the file and is used)
//   sample_28/dynamic, standing  load; warnings: POINT:RATE and ANALOG:RATE missing (header rate
//   used),
//                             duplicate labels, units assumed
// Files that fail: Empty.c3d, sample_18/bad_parameter_section.c3d (c3d_reader_test).

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/capture/c3d.h"
#include "refdata.h"

namespace acro::capture {
namespace {

using acro::testing::RefdataFile;

std::string Org(const std::string& relative) {
  return "c3dio-c3d_org_samples/" + relative;
}

bool HasWarning(const Trial& t, const std::string& text) {
  for (const std::string& w : t.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

// gtest's EXPECT_FLOAT_EQ criterion (ezc3d): within 4 float ULPs.
bool FloatEq(double a, double b) {
  return ::testing::internal::FloatingPoint<float>(static_cast<float>(a))
      .AlmostEquals(::testing::internal::FloatingPoint<float>(static_cast<float>(b)));
}

// ---------------------------------------------------------------------------------------------
// ezc3d comparedIdenticalFilesSample1: pr vs pi, vr, vi — same header values, point data equal
// within 4 float ULPs (in the file's millimetres; invalid samples NaN in both), analog equal too.
// c3dio: the six files are equal, parameters included (we allow only POINT:SCALE's sign, which
// encodes the storage, and the data-start block, which the files place differently).
TEST(C3dSuite, Sample01IdenticalAcrossFormats) {
  const auto ref_path = RefdataFile(Org("sample_01/Eb015pr.c3d"));
  ACRO_REQUIRE_REFDATA_FILE(ref_path);
  const Trial pr = ReadC3d(ref_path);
  for (const char* file :
       {"Eb015pi.c3d", "Eb015vr.c3d", "Eb015vi.c3d", "Eb015si.c3d", "Eb015sr.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(Org(std::string("sample_01/") + file)));
    EXPECT_EQ(t.num_frames, pr.num_frames) << file;
    EXPECT_EQ(t.point_rate_hz, pr.point_rate_hz) << file;
    EXPECT_EQ(t.first_frame, pr.first_frame) << file;
    EXPECT_EQ(t.num_points(), pr.num_points()) << file;
    EXPECT_EQ(t.num_analog_channels(), pr.num_analog_channels()) << file;
    EXPECT_EQ(t.analog_samples_per_frame(), pr.analog_samples_per_frame()) << file;
    ASSERT_EQ(t.events.size(), pr.events.size()) << file;
    for (std::size_t i = 0; i < t.events.size(); ++i) {
      EXPECT_EQ(t.events[i].time_s, pr.events[i].time_s) << file;
      EXPECT_EQ(t.events[i].displayed, pr.events[i].displayed) << file;
      EXPECT_EQ(t.events[i].label, pr.events[i].label) << file;
    }
    int compared = 0;
    for (Eigen::Index i = 0; i < pr.positions.cols(); ++i) {
      ASSERT_EQ(std::isnan(t.positions(0, i)), std::isnan(pr.positions(0, i))) << file;
      if (std::isnan(pr.positions(0, i))) continue;
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(FloatEq(t.positions(k, i) * 1000, pr.positions(k, i) * 1000))
            << file << " sample " << i << " axis " << k << ": " << t.positions(k, i) * 1000
            << " vs " << pr.positions(k, i) * 1000;
      }
      ++compared;
    }
    EXPECT_GT(compared, 11000) << file;
    for (Eigen::Index i = 0; i < pr.analog.size(); ++i) {
      ASSERT_TRUE(FloatEq(t.analog.data()[i], pr.analog.data()[i])) << file << " analog " << i;
    }
    // Parameters (c3dio): same groups, same parameters, same values.
    ASSERT_EQ(t.parameters.groups().size(), pr.parameters.groups().size()) << file;
    for (std::size_t g = 0; g < pr.parameters.groups().size(); ++g) {
      const ParameterGroup& a = pr.parameters.groups()[g];
      const ParameterGroup& b = t.parameters.groups()[g];
      EXPECT_EQ(a.name, b.name) << file;
      ASSERT_EQ(a.parameters.size(), b.parameters.size()) << file << " " << a.name;
      for (std::size_t k = 0; k < a.parameters.size(); ++k) {
        const Parameter& p = a.parameters[k];
        const Parameter& q = b.parameters[k];
        EXPECT_EQ(p.name, q.name) << file;
        EXPECT_EQ(p.description, q.description) << file << " " << a.name << ":" << p.name;
        EXPECT_EQ(p.dimensions, q.dimensions) << file << " " << a.name << ":" << p.name;
        if ((a.name == "POINT" && (p.name == "SCALE" || p.name == "DATA_START"))) continue;
        EXPECT_EQ(p.chars, q.chars) << file << " " << a.name << ":" << p.name;
        EXPECT_EQ(p.AsDoubles(), q.AsDoubles()) << file << " " << a.name << ":" << p.name;
      }
    }
  }
}

// ezc3d comparedIdenticalFilesSample2: data equal (4 ULPs) pc_real vs dec_real and vs dec_int;
// c3dio: the six files have the same number of groups and of parameters per group.
TEST(C3dSuite, Sample02EzC3dAndC3dio) {
  const auto ref_path = RefdataFile(Org("sample_02/pc_real.c3d"));
  ACRO_REQUIRE_REFDATA_FILE(ref_path);
  const Trial ref = ReadC3d(ref_path);
  for (const char* file : {"dec_real.c3d", "dec_int.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(Org(std::string("sample_02/") + file)));
    for (Eigen::Index i = 0; i < ref.positions.cols(); ++i) {
      ASSERT_EQ(std::isnan(t.positions(0, i)), std::isnan(ref.positions(0, i))) << file;
      if (std::isnan(ref.positions(0, i))) continue;
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(FloatEq(t.positions(k, i) * 1000, ref.positions(k, i) * 1000))
            << file << " sample " << i;
      }
    }
    for (Eigen::Index i = 0; i < ref.analog.size(); ++i) {
      ASSERT_TRUE(FloatEq(t.analog.data()[i], ref.analog.data()[i])) << file << " analog " << i;
    }
  }
  // Headers: pc_real vs pc_int and dec_real.
  for (const char* file : {"pc_int.c3d", "dec_real.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(Org(std::string("sample_02/") + file)));
    EXPECT_EQ(t.num_frames, ref.num_frames) << file;
    EXPECT_EQ(t.first_frame, ref.first_frame) << file;
    EXPECT_EQ(t.point_rate_hz, ref.point_rate_hz) << file;
    EXPECT_EQ(t.num_points(), ref.num_points()) << file;
    EXPECT_EQ(t.num_analog_channels(), ref.num_analog_channels()) << file;
    EXPECT_EQ(t.num_analog_samples(), ref.num_analog_samples()) << file;
  }
  for (const char* file :
       {"dec_int.c3d", "dec_real.c3d", "pc_int.c3d", "sgi_int.c3d", "sgi_real.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(Org(std::string("sample_02/") + file)));
    ASSERT_EQ(t.parameters.groups().size(), ref.parameters.groups().size()) << file;
    for (std::size_t g = 0; g < ref.parameters.groups().size(); ++g) {
      EXPECT_EQ(t.parameters.groups()[g].parameters.size(),
                ref.parameters.groups()[g].parameters.size())
          << file << " group " << ref.parameters.groups()[g].name;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Header and parameter facts per file (README table, BTK, py-c3d, c3d.org readmes).
struct FileFacts {
  const char* file;
  int points;
  double point_rate;
  int frames;
  int first_frame;
  int channels;
  double analog_rate;
  int force_plates;
};

class C3dFacts : public ::testing::TestWithParam<FileFacts> {};

TEST_P(C3dFacts, Match) {
  const FileFacts& f = GetParam();
  const auto path = RefdataFile(f.file);
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.num_points(), f.points);
  EXPECT_NEAR(t.point_rate_hz, f.point_rate, 0.01);  // BTK's tolerance for the Phoenix rates
  EXPECT_EQ(t.num_frames, f.frames);
  EXPECT_EQ(t.first_frame, f.first_frame);
  EXPECT_EQ(t.num_analog_channels(), f.channels);
  EXPECT_NEAR(t.analog_rate_hz, f.analog_rate, 0.01);
  EXPECT_EQ(static_cast<int>(t.force_plates.size()), f.force_plates);
  if (f.channels > 0) {
    EXPECT_EQ(t.num_analog_samples(),
              std::int64_t(f.frames) * std::llround(f.analog_rate / f.point_rate));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Suites,
    C3dFacts,
    ::testing::Values(
        // sample_08 (c3d.org table; py-c3d point_used 26, point_rate 50; TESTBPI analog 16 at 200
        // Hz).
        FileFacts{"c3dio-c3d_org_samples/sample_08/TESTAPI.c3d", 26, 50, 450, 1, 16, 200, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_08/TESTBPI.c3d", 26, 50, 450, 1, 16, 200, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_08/TESTCPI.c3d", 26, 50, 450, 1, 16, 200, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_08/TESTDPI.c3d", 26, 50, 450, 1, 16, 200, 2},
        FileFacts{
            "BTKData/Input/C3DSamples/c3d.org/sample08/TESTAPI.c3d", 26, 50, 450, 1, 16, 200, 2},
        // sample_10 (c3d.org table: markers, analog channels, last frame, rates).
        FileFacts{"c3dio-c3d_org_samples/sample_10/TYPE-2.C3D", 13, 60, 199, 1, 6, 1200, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_10/TYPE-2a.c3d", 25, 60, 360, 1, 20, 960, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_10/TYPE-4.C3D", 13, 60, 199, 1, 6, 1200, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_10/TYPE-4a.c3d", 25, 60, 360, 1, 20, 960, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_10/TYPE-3.c3d", 21, 60, 515, 1, 28, 60, 4},
        // sample_13 (BTK: frames from the header range, not POINT:FRAMES).
        FileFacts{"c3dio-c3d_org_samples/sample_13/Dance.c3d", 40, 65.05, 499, 1, 8, 65.05, 0},
        FileFacts{
            "c3dio-c3d_org_samples/sample_13/golfswing.c3d", 29, 107.53, 514, 1, 8, 107.53, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_13/Dance1.c3d", 40, 65.04, 498, 2, 8, 65.04, 0},
        FileFacts{
            "c3dio-c3d_org_samples/sample_13/golfswing1.c3d", 29, 107.53, 513, 2, 8, 107.53, 0},
        // sample_20 (BTK: 30 Hz, 40 points, 701 frames, analog 30 Hz, 0 channels).
        FileFacts{
            "c3dio-c3d_org_samples/sample_20/phasespace_sample.c3d", 40, 30, 701, 1, 0, 30, 0},
        // Others from the README table.
        FileFacts{
            "c3dio-c3d_org_samples/sample_03/gait-pig-nz.c3d", 85, 120, 301, 300, 18, 1800, 3},
        FileFacts{"c3dio-c3d_org_samples/sample_14/sample14.c3d", 14, 50, 186, 25, 32, 800, 3},
        FileFacts{"c3dio-c3d_org_samples/sample_26/Walking_Hybrid_1_1.c3d",
                  25,
                  240,
                  672,
                  290,
                  16,
                  240,
                  2},
        FileFacts{"c3dio-c3d_org_samples/sample_27/kyowadengyo.c3d", 11, 60, 152, 33, 24, 60, 3},
        FileFacts{"c3dio-c3d_org_samples/sample_30/admarche2.c3d", 17, 50, 159, 65, 8, 50, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_33/bigparlove.c3d", 205, 200, 323, 1, 30, 1000, 5},
        FileFacts{"c3dio-c3d_org_samples/sample_34/Basketball.c3d", 64, 120, 774, 1, 0, 120, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_35/Mega Electronics Isokinetic EMG Angle Torque "
                  "Sample File.c3d",
                  0,
                  1,
                  29,
                  1,
                  4,
                  1250,
                  0},
        FileFacts{"c3dio-c3d_org_samples/sample_37/ART-Human_real.c3d", 63, 60, 966, 1, 0, 60, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_21/sample21.c3d", 14, 60, 574, 1, 12, 1020, 2},
        FileFacts{
            "c3dio-c3d_org_samples/sample_22/BKINtechnologies.c3d", 2, 1000, 5065, 1, 20, 1000, 0},
        FileFacts{
            "c3dio-c3d_org_samples/sample_24/MotionMonitorC3D.c3d", 8, 140, 840, 1, 16, 980, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_28/dynamic.C3D", 34, 100, 296, 1, 6, 100, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_28/standing.C3D", 38, 100, 200, 1, 6, 100, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_28/type1.C3D", 28, 100, 296, 1, 6, 100, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_06/MACsample.c3d", 33, 60, 180, 1, 16, 1020, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_06/newwalk.c3d", 25, 60, 360, 1, 20, 960, 2},
        FileFacts{"c3dio-c3d_org_samples/sample_11/2198928.c3d", 94, 60, 189, 1, 40, 600, 4},
        FileFacts{"c3dio-c3d_org_samples/sample_15/FP1.C3D", 8, 60, 480, 1, 12, 600, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_15/FP2.C3D", 8, 60, 480, 1, 12, 600, 1},
        FileFacts{"c3dio-c3d_org_samples/sample_16/basketball.c3d", 22, 25, 34, 1, 0, 25, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_16/golf.c3d", 21, 200, 137, 1, 0, 200, 0},
        FileFacts{"c3dio-c3d_org_samples/sample_00/NexGen Ergonomics/test1.c3d",
                  40,
                  128,
                  721,
                  1,
                  0,
                  128,
                  0},
        FileFacts{"c3dio-c3d_org_samples/sample_00/Innovative Sports Training/Gait with EMG.c3d",
                  24,
                  60,
                  134,
                  1,
                  32,
                  1080,
                  2},
        FileFacts{"BTKData/Input/C3DSamples/others/MyCube.c3d", 14, 50, 1, 1, 0, 50, 0},
        FileFacts{"BTKData/Input/C3DSamples/others/Gait.c3d", 33, 100, 487, 1, 28, 1000, 2}));

// ---------------------------------------------------------------------------------------------
TEST(C3dSuite, Sample07UnsignedOffset) {
  const auto path = RefdataFile(Org("sample_07/16bitanalog.c3d"));
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.num_analog_channels(), 40);
  EXPECT_EQ(t.analog_channels[0].offset, 32767);  // c3dio: ANALOG:OFFSET[0] == 32767
}

// c3dio: EB015PI == TESTAPI == TESTBPI == TESTCPI == TESTDPI (header pointers differ only).
TEST(C3dSuite, Sample08SameDataWhateverThePointers) {
  const auto ref_path = RefdataFile(Org("sample_08/EB015PI.c3d"));
  ACRO_REQUIRE_REFDATA_FILE(ref_path);
  const Trial ref = ReadC3d(ref_path);
  for (const char* file : {"TESTAPI.c3d", "TESTBPI.c3d", "TESTCPI.c3d", "TESTDPI.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(Org(std::string("sample_08/") + file)));
    EXPECT_TRUE(t.positions.cwiseEqual(ref.positions).count() +
                    ref.positions.array().isNaN().count() ==
                ref.positions.size())
        << file;
    EXPECT_TRUE(t.analog == ref.analog) << file;
    EXPECT_TRUE((t.residuals == ref.residuals).all()) << file;
    EXPECT_TRUE((t.camera_masks == ref.camera_masks).all()) << file;
    ASSERT_EQ(t.num_points(), ref.num_points());
    for (int i = 0; i < t.num_points(); ++i)
      EXPECT_EQ(t.points[i].label, ref.points[i].label) << file;
  }
  // py-c3d on TESTDPI: 450 frames from frame 1, 26 points and 16 × 4 analog samples per frame.
  const Trial d = ReadC3d(RefdataFile(Org("sample_08/TESTDPI.c3d")));
  EXPECT_EQ(d.num_frames, 450);
  EXPECT_EQ(d.first_frame, 1);
  EXPECT_EQ(d.num_points(), 26);
  EXPECT_EQ(d.num_analog_channels(), 16);
  EXPECT_EQ(d.analog_samples_per_frame(), 4);
  // TESTBPI: POINT:RATE 50, ANALOG:RATE 200 as parameters.
  const Trial b = ReadC3d(RefdataFile(Org("sample_08/TESTBPI.c3d")));
  EXPECT_EQ(b.parameters.FindDouble("POINT", "RATE").value_or(0), 50);
  EXPECT_EQ(b.parameters.FindDouble("ANALOG", "RATE").value_or(0), 200);
  EXPECT_EQ(b.parameters.FindDouble("ANALOG", "USED").value_or(0), 16);
}

// c3d.org sample 10 readme: DEC integer files, scale 0.17 / 0.06 / 0.17 / 0.06.
TEST(C3dSuite, Sample10StorageAndScale) {
  const std::pair<const char*, double> cases[] = {{"sample_10/TYPE-2.C3D", 0.17},
                                                  {"sample_10/TYPE-2a.c3d", 0.06},
                                                  {"sample_10/TYPE-4.C3D", 0.17},
                                                  {"sample_10/TYPE-4a.c3d", 0.06}};
  for (const auto& [file, scale] : cases) {
    const auto path = RefdataFile(Org(file));
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    EXPECT_EQ(t.source.processor, "DEC") << file;
    EXPECT_EQ(t.source.point_storage, "integer") << file;
    EXPECT_NEAR(t.source.point_scale, scale, 0.005) << file;  // the readme gives two decimals
  }
}

// BTK Sample09: point types from POINT:ANGLES/FORCES/MOMENTS/POWERS, gains, frames from TRIAL.
TEST(C3dSuite, Sample09PointTypesGainsAndFrames) {
  for (const char* file : {"sample_09/PolygonC3D.c3d", "sample_09/PlugInC3D.c3d"}) {
    const auto path = RefdataFile(Org(file));
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    ASSERT_EQ(t.num_points(), 86) << file;
    EXPECT_EQ(t.points[0].label, "RKNE") << file;
    EXPECT_EQ(t.points[0].type, PointType::kMarker) << file;
    EXPECT_EQ(t.points[0].unit, "m") << file;
    EXPECT_EQ(t.points[18].label, "LHipAngles") << file;
    EXPECT_EQ(t.points[18].type, PointType::kAngle) << file;
    EXPECT_EQ(t.points[64].label, "LGroundReactionForce") << file;
    EXPECT_EQ(t.points[64].type, PointType::kForce) << file;
    EXPECT_EQ(t.points[72].label, "LGroundReactionMoment") << file;
    EXPECT_EQ(t.points[72].type, PointType::kMoment) << file;
    EXPECT_EQ(t.points[80].label, "LAnklePower") << file;
    EXPECT_EQ(t.points[80].type, PointType::kPower) << file;
    // ANALOG:GAIN codes: 2 (±5 V) for channels 0–11 and 20–35, 1 (±10 V) for 12–19.
    ASSERT_EQ(t.num_analog_channels(), 36) << file;
    for (int c = 0; c < 36; ++c)
      EXPECT_EQ(t.analog_channels[c].gain_code, (c >= 12 && c <= 19) ? 1 : 2) << file;
    // Frames: POINT:FRAMES = 281; TRIAL:ACTUAL_START_FIELD [1, 0] and ACTUAL_END_FIELD [281, 0].
    EXPECT_EQ(t.num_frames, 281) << file;
    EXPECT_EQ(t.first_frame, 1) << file;
    const Parameter* start = t.parameters.Find("TRIAL", "ACTUAL_START_FIELD");
    const Parameter* end = t.parameters.Find("TRIAL", "ACTUAL_END_FIELD");
    ASSERT_NE(start, nullptr);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(start->AsUnsigned()[0] | (start->AsUnsigned()[1] << 16), 1u) << file;
    EXPECT_EQ(end->AsUnsigned()[0] | (end->AsUnsigned()[1] << 16), 281u) << file;
    EXPECT_EQ(t.parameters.Find("POINT", "FRAMES")->AsUnsigned()[0], 281u) << file;
    // Model outputs keep the file's units (not scaled to metres): angles in degrees.
    double largest_angle = 0;
    for (int f = 0; f < t.num_frames; ++f) {
      if (t.valid(f, 18))
        largest_angle = std::max(largest_angle, t.position(f, 18).cwiseAbs().maxCoeff());
    }
    EXPECT_GT(largest_angle, 5.0) << file;  // degrees, not 1000× smaller
  }
}

// BTK sample_22: events from the EVENT group, with descriptions.
TEST(C3dSuite, Sample22Events) {
  const auto path = RefdataFile(Org("sample_22/BKINtechnologies.c3d"));
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_EQ(t.events.size(), 2u);
  EXPECT_EQ(t.events[0].label, "STAY_CENTRE");
  EXPECT_NEAR(t.events[0].time_s, 0.0, 1e-4);
  EXPECT_EQ(t.events[0].description, "subject must wait at centre starting now");
  EXPECT_EQ(t.events[1].label, "TARGET_ON");
  EXPECT_NEAR(t.events[1].time_s, 1.6140, 1e-4);
  EXPECT_EQ(t.events[1].description,
            "Target light ON, start waiting for subject to leave centre target");
}

// Warnings that name the file, the field and the value for the odd files we load.
TEST(C3dSuite, OddFilesLoadWithWarnings) {
  struct Case {
    const char* file;
    const char* warning;
  };
  const Case cases[] = {
      {"sample_13/Dance.c3d", "POINT:FRAMES: is 500 but the header frames 1..499 give 499"},
      {"sample_13/Dance.c3d", "POINT:DATA_START: is 0 but the header says block 8"},
      {"sample_16/basketball.c3d", "every sample has residual -1"},
      {"sample_16/basketball.c3d", "POINT:UNITS: missing; metres assumed"},
      {"sample_16/golf.c3d", "every sample has residual -1"},
      {"sample_20/phasespace_sample.c3d", "POINT:USED: missing"},
      {"sample_20/phasespace_sample.c3d", "POINT:UNITS: missing; millimetres assumed"},
      {"sample_24/MotionMonitorC3D.c3d", "blank point labels"},
      {"sample_24/MotionMonitorC3D.c3d", "ANALOG:USED: is 16 but the header gives 16 analog words"},
      {"sample_27/kyowadengyo.c3d", "POINT:USED: is 12 but the header says 11 points"},
      {"sample_28/dynamic.C3D", "POINT:RATE: missing"},
      {"sample_28/dynamic.C3D", "duplicate point label"},
      {"sample_28/type1.C3D", "ANALOG:RATE: missing"},
      {"sample_11/evart.c3d", "needs 8"},
      {"sample_02/sgi_int.c3d", "has offset 16129 pointing past the parameter section"},
      {"sample_03/gait-pig.c3d", "their values are taken as N·mm"},
  };
  for (const Case& c : cases) {
    const auto path = RefdataFile(Org(c.file));
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    EXPECT_TRUE(HasWarning(t, c.warning)) << c.file << " lacks warning '" << c.warning << "'";
    for (const std::string& w : t.warnings) {
      EXPECT_NE(w.find(path.filename().string()), std::string::npos) << w;  // names the file
      EXPECT_EQ(w.find('\n'), std::string::npos) << w;                      // one line
    }
  }
  // sample_16: coordinates kept (no gaps), residuals stay -1, metres assumed.
  const Trial golf = ReadC3d(RefdataFile(Org("sample_16/golf.c3d")));
  EXPECT_EQ(golf.positions.array().isNaN().count(), 0);
  EXPECT_TRUE((golf.residuals == -1.0f).all());
  EXPECT_EQ(golf.source.point_units_to_m, 1.0);
  // sample_27: the header's 11 points fit the file; USED = 12 does not.
  EXPECT_EQ(ReadC3d(RefdataFile(Org("sample_27/kyowadengyo.c3d"))).num_points(), 11);
}

// py-c3d (sample 00): every point and analog value read lies within ±1e6.
TEST(C3dSuite, Sample00ValuesBounded) {
  for (const char* file : {"sample_00/Codamotion/codamotion_gaitwands_19970212.c3d",
                           "sample_00/Innovative Sports Training/Gait with EMG.c3d",
                           "sample_00/Motion Analysis Corporation/Sample_Jump2.c3d",
                           "sample_00/Motion Analysis Corporation/Walk1.c3d",
                           "sample_00/NexGen Ergonomics/test1.c3d"}) {
    const auto path = RefdataFile(Org(file));
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    // In file units: markers back to the file's length unit.
    double largest = 0;
    for (Eigen::Index i = 0; i < t.positions.cols(); ++i) {
      if (!std::isnan(t.positions(0, i)))
        largest = std::max(largest, t.positions.col(i).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(largest / t.source.point_units_to_m, 1e6) << file;
    EXPECT_LT(t.analog.size() ? t.analog.cwiseAbs().maxCoeff() : 0.0, 1e6) << file;
  }
}

// ---------------------------------------------------------------------------------------------
// ADemo1 (BTK, Open3DMotion reference): three C3D files of the same trial against the reference
// CSVs.
std::vector<std::vector<std::string>> ReadCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(C3dSuite, ADemo1AgainstOpen3DMotionReference) {
  const auto markers_csv = RefdataFile("BTKData/expected_ADemo1_markers.csv");
  const auto emg_csv = RefdataFile("BTKData/expected_ADemo1_EMG.csv");
  ACRO_REQUIRE_REFDATA_FILE(markers_csv);
  ACRO_REQUIRE_REFDATA_FILE(emg_csv);
  const auto markers = ReadCsv(markers_csv);
  const auto emg = ReadCsv(emg_csv);
  ASSERT_EQ(markers.size(), 512u * 24u);
  ASSERT_EQ(emg.size(), 1023u);
  const char* kLabels[24] = {"L.Sac.Wand", "R.Sac.Wand",  "L.PSIS",     "L.ASIS", "L.Post.Fem.",
                             "L.Ant.Fem.", "L.Post.Tib.", "L.Ant.Tib.", "L.Knee", "L.Ankle",
                             "L.Heel",     "L.Toe",       "R.PSIS",     "R.ASIS", "R.Post.Fem.",
                             "R.Ant.Fem.", "R.Post.Tib.", "R.Ant.Tib.", "R.Knee", "R.Ankle",
                             "R.Heel",     "R.Toe",       "L.Hip",      "R.Hip"};
  const char* kEmg[8] = {"R.Quads",
                         "R.Med.Hams",
                         "R.Ant.Tib",
                         "R.Gastroc",
                         "L.Quads",
                         "L.Med.Hams",
                         "L.Ant.Tib",
                         "L.Gastroc"};
  std::vector<Trial> trials;
  for (const char* file :
       {"BTKData/Input/C3DSamples/others/ADemo1_rewrite_c3d_pc_float.c3d",
        "BTKData/Input/C3DSamples/others/ADemo1_rewrite_c3d_pc_integer.c3d",
        "c3dio-c3d_org_samples/sample_00/Codamotion/codamotion_gaitwands_19970212.c3d"}) {
    const auto path = RefdataFile(file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    EXPECT_EQ(t.first_frame, 1) << file;
    ASSERT_EQ(t.num_points(), 24) << file;
    for (int i = 0; i < 24; ++i) EXPECT_EQ(t.points[i].label, kLabels[i]) << file;
    EXPECT_EQ(t.num_frames, 512) << file;
    EXPECT_EQ(t.point_rate_hz, 200.0) << file;
    ASSERT_EQ(t.num_analog_channels(), 16) << file;
    EXPECT_EQ(t.num_analog_samples(), 1024) << file;
    EXPECT_EQ(t.analog_rate_hz, 400.0) << file;
    EXPECT_EQ(t.analog_samples_per_frame(), 2) << file;
    for (int c = 0; c < 8; ++c) EXPECT_EQ(t.analog_channels[c].label, kEmg[c]) << file;
    // Every marker sample to 0.1 mm; validity (residual ≥ 0) identical to the reference flag.
    int visible = 0;
    double worst_mm = 0;
    for (const auto& row : markers) {
      const int frame = std::stoi(row[0]);
      const int point = std::stoi(row[1]);
      ASSERT_EQ(row[2], kLabels[point]);
      const bool valid = row[6] == "1";
      ASSERT_EQ(t.valid(frame, point), valid) << file << " frame " << frame << " point " << point;
      ASSERT_EQ(t.residuals(point, frame) >= 0, valid) << file;
      if (!valid) continue;
      ++visible;
      for (int k = 0; k < 3; ++k) {
        worst_mm = std::max(worst_mm,
                            std::abs(t.position(frame, point)(k) * 1000 - std::stod(row[3 + k])));
      }
    }
    EXPECT_EQ(visible, 12203) << file;
    EXPECT_LE(worst_mm, 0.1) << file;
    // EMG channels 0–7, samples 0–1022, to 1e-4.
    double worst_emg = 0;
    for (const auto& row : emg) {
      const int s = std::stoi(row[0]);
      for (int c = 0; c < 8; ++c)
        worst_emg = std::max(worst_emg, std::abs(t.analog(c, s) - std::stod(row[1 + c])));
    }
    EXPECT_LE(worst_emg, 1e-4) << file;
    trials.push_back(t);
  }
  // BTK: the float and integer rewrites hold the same analog channels within 1e-5 (every 10th
  // sample).
  for (Eigen::Index s = 0; s < trials[0].analog.cols(); s += 10) {
    for (int c = 0; c < 16; ++c) ASSERT_NEAR(trials[0].analog(c, s), trials[1].analog(c, s), 1e-5);
  }
}

}  // namespace
}  // namespace acro::capture
