// TRC import/export against the values BTK's test suite asserts
// (../shared/refdata/BTKData/expected.md) and against the OpenSim and Pose2Sim files of
// ../shared/refdata.
#include "acro/capture/trc.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::capture {
namespace {

using acro::testing::RefdataFile;

constexpr double kMm = 1e-3;
// BTK asserts coordinates in mm with 1e-6 (MOTEK, Knee) or 1e-5 (Unnamed) tolerance: in metres,
// ×1e-3.
constexpr double kTol6 = 1e-6 * kMm;
constexpr double kTol5 = 1e-5 * kMm;

std::filesystem::path Btk(const std::string& name) {
  return RefdataFile("BTKData/Input/TRCSamples/" + name);
}

TEST(Trc, MotekT) {
  const auto path = Btk("MOTEK/T.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.source.format, "TRC");
  EXPECT_EQ(trial.first_frame, 1);
  EXPECT_EQ(trial.point_rate_hz, 30.0);
  EXPECT_EQ(trial.num_points(), 41);
  EXPECT_EQ(trial.num_frames, 89);
  EXPECT_EQ(trial.source.point_units, "mm");
  EXPECT_EQ(trial.points[1].label, "LBHD");
  EXPECT_NEAR(trial.position(3, 1).x(), -171.03949 * kMm, kTol6);
  EXPECT_TRUE(trial.warnings.empty()) << trial.warnings.front();
}

TEST(Trc, MotekBallet) {
  const auto path = Btk("MOTEK/ballet_reduced.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.first_frame, 1);
  EXPECT_EQ(trial.point_rate_hz, 30.0);
  EXPECT_EQ(trial.num_points(), 41);
  EXPECT_EQ(trial.num_frames, 100);
  EXPECT_NEAR(trial.position(82, 40).z(), -112.24601 * kMm, kTol6);
}

TEST(Trc, KneeWithOcclusion) {
  const auto path = Btk("Knee.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.first_frame, 1);
  EXPECT_EQ(trial.point_rate_hz, 200.0);
  EXPECT_EQ(trial.num_points(), 71);
  EXPECT_EQ(trial.num_frames, 200);
  EXPECT_NEAR(trial.position(83, 1).x(), 301.65476 * kMm, kTol6);
  EXPECT_FALSE(trial.valid(82, 70));
  EXPECT_EQ(trial.residuals(70, 82), -1.0f);
  // Names padded with blanks in the file (" genou1_NewMarker3 ") are trimmed.
  EXPECT_EQ(trial.points[3].label, "genou1_NewMarker3");
}

struct Expected {
  int frame, point;
  double x, y, z;  // mm; NaN triple = occluded
};

void CheckUnnamed(const Trial& trial, const std::vector<Expected>& rows) {
  for (const Expected& e : rows) {
    SCOPED_TRACE("frame " + std::to_string(e.frame) + " point " + std::to_string(e.point));
    if (std::isnan(e.x)) {
      EXPECT_FALSE(trial.valid(e.frame, e.point));
      EXPECT_EQ(trial.residuals(e.point, e.frame), -1.0f);
    } else {
      ASSERT_TRUE(trial.valid(e.frame, e.point));
      EXPECT_EQ(trial.residuals(e.point, e.frame), 0.0f);
      EXPECT_NEAR(trial.position(e.frame, e.point).x(), e.x * kMm, kTol5);
      EXPECT_NEAR(trial.position(e.frame, e.point).y(), e.y * kMm, kTol5);
      EXPECT_NEAR(trial.position(e.frame, e.point).z(), e.z * kMm, kTol5);
    }
  }
}

constexpr double kGap = std::numeric_limits<double>::quiet_NaN();

TEST(Trc, UnnamedMarkersAreCountedFromTheData) {
  const auto path = Btk("10002-20130626160334-Unnamed.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.first_frame, 1);
  EXPECT_EQ(trial.point_rate_hz, 400.0);
  ASSERT_EQ(trial.num_points(), 10);
  EXPECT_EQ(trial.num_frames, 882);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(trial.points[i].label, "Unlabel#" + std::to_string(i + 1));
  std::vector<Expected> rows;
  for (int f = 0; f <= 10; ++f)
    for (int p = 0; p <= 9; ++p) rows.push_back({f, p, kGap, kGap, kGap});
  rows.push_back({11, 0, 19.91857, 1362.18750, -124.33382});
  for (int f = 11; f <= 25; ++f)
    for (int p = 1; p <= 9; ++p) rows.push_back({f, p, kGap, kGap, kGap});
  rows.push_back({356, 0, -37.94589, 909.69788, -160.10370});
  rows.push_back({356, 1, -161.65665, 1223.79883, -198.66595});
  for (int f = 356; f <= 362; ++f)
    for (int p = 2; p <= 9; ++p) rows.push_back({f, p, kGap, kGap, kGap});
  for (int p : {0, 1, 4}) rows.push_back({540, p, kGap, kGap, kGap});
  rows.push_back({540, 2, 832.84674, 1561.89258, -699.47595});
  rows.push_back({540, 3, -1985.56189, 362.87326, -248.83156});
  rows.push_back({540, 9, -26.17541, 526.26477, -348.95346});
  rows.push_back({881, 0, -799.76202, 801.21472, -391.54608});
  for (int p : {1, 2}) rows.push_back({881, p, kGap, kGap, kGap});
  rows.push_back({881, 3, -1837.97595, -1082.82910, -1182.05762});
  for (int p = 4; p <= 9; ++p) rows.push_back({881, p, kGap, kGap, kGap});
  CheckUnnamed(trial, rows);
  // The header said NumMarkers 0: the reader says what it did instead.
  ASSERT_FALSE(trial.warnings.empty());
  EXPECT_NE(trial.warnings[0].find("NumMarkers"), std::string::npos);
}

TEST(Trc, UnnamedSecondFile) {
  const auto path = Btk("10002-20130731010438-Unnamed.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.first_frame, 1);
  EXPECT_EQ(trial.point_rate_hz, 400.0);
  ASSERT_EQ(trial.num_points(), 37);
  EXPECT_EQ(trial.num_frames, 1313);
  std::vector<Expected> rows = {{0, 0, -352.45120, 985.40039, 288.96054},
                                {0, 12, 799.99994, 1593.03601, 427.78055},
                                {893, 0, kGap, kGap, kGap},
                                {893, 1, -133.13820, 1641.26953, 367.13284},
                                {893, 5, -599.99548, 189.93408, 565.01599},
                                {893, 19, -318.83157, 55.89437, 260.76419},
                                {893, 27, -376.94412, 1453.94983, 208.30200},
                                {893, 28, -419.75079, 1230.84387, 1282.72046},
                                {1312, 0, 386.76334, 1372.59546, 745.81812},
                                {1312, 1, kGap, kGap, kGap},
                                {1312, 31, kGap, kGap, kGap},
                                {1312, 32, 950.22644, 1470.34619, 951.17596}};
  for (int p : {2, 3, 4, 6, 7, 8, 20, 21, 22, 23, 24, 25, 29, 30, 31})
    rows.push_back({893, p, kGap, kGap, kGap});
  CheckUnnamed(trial, rows);
}

TEST(Trc, LyingHeaderMarkerCount) {
  // Header says NumMarkers 66; 33 markers are named and hold data (BTK reads 33).
  const auto path = Btk("Gait.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.num_points(), 33);
  EXPECT_EQ(trial.num_frames, 487);
  EXPECT_EQ(trial.point_rate_hz, 100.0);
  bool warned = false;
  for (const auto& w : trial.warnings) warned |= w.find("NumMarkers = 66") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(Trc, TruncatedAndEmptyFilesFailWithTheirName) {
  for (const char* name : {"Truncated.trc", "Empty.trc"}) {
    const auto path = Btk(name);
    ACRO_REQUIRE_REFDATA_FILE(path);
    try {
      ReadTrc(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(name), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      if (std::string(name) == "Truncated.trc") {
        EXPECT_NE(message.find("unexpected end of file"), std::string::npos);
      }
    }
  }
}

TEST(Trc, OpenSimWalkHasItsHeaderCounts) {
  const auto path = RefdataFile("opensim-models/Pipelines/Gait2354_Simbody/subject01_walk1.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.point_rate_hz, 60.0);
  EXPECT_EQ(trial.num_frames, 151);
  EXPECT_EQ(trial.num_points(), 41);
  EXPECT_TRUE(trial.warnings.empty());
  EXPECT_EQ(trial.points[0].label, "R.ASIS");
  EXPECT_NEAR(trial.position(0, 0).x(), 617.247620 * kMm, kTol6);
}

TEST(Trc, Pose2SimTrampolineRoutineInMetres) {
  const auto path =
      RefdataFile("s2mLab-EKF_multicamera-trampoline/inputs/trc/1_partie_0429_002.trc");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial trial = ReadTrc(path);
  EXPECT_EQ(trial.source.point_units, "m");
  EXPECT_EQ(trial.point_rate_hz, 120.0);
  EXPECT_EQ(trial.num_frames, 1261);
  ASSERT_EQ(trial.num_points(), 17);
  EXPECT_EQ(trial.points[0].label, "Nose");
  EXPECT_EQ(trial.points[16].label, "R Ankle");
  EXPECT_EQ(trial.first_frame, 0);  // Pose2Sim numbers its rows from 0
  // The README counts 564 empty cells: 188 occluded keypoint-frames.
  int missing = 0;
  for (int f = 0; f < trial.num_frames; ++f)
    for (int p = 0; p < 17; ++p) missing += !trial.valid(f, p);
  EXPECT_EQ(3 * missing, 564);
  EXPECT_EQ(trial.position(0, 0).x(), 0.4987122328704115);  // metres in the file: no scaling
  // Flights up to 5 m high (README): the highest keypoint lies between 4 and 8 m.
  double top = 0;
  for (int f = 0; f < trial.num_frames; ++f)
    for (int p = 0; p < 17; ++p)
      if (trial.valid(f, p)) top = std::max(top, trial.position(f, p).z());
  EXPECT_GT(top, 4.0);
  EXPECT_LT(top, 8.0);
}

Trial SmallTrial() {
  Trial trial;
  trial.point_rate_hz = 120.0;
  trial.first_frame = 5;
  trial.num_frames = 4;
  trial.points = {{"Left, Toe", "", PointType::kMarker, "m"},
                  {"RHEE", "", PointType::kMarker, "m"}};
  trial.positions.resize(3, 8);
  for (int c = 0; c < 8; ++c)
    trial.positions.col(c) = Eigen::Vector3d(0.1 * c, -0.2 * c + 1e-4, 1.234567 + c);
  trial.positions.col(3).setConstant(std::nan(""));  // frame 1, point 1 occluded
  trial.residuals.setZero(2, 4);
  trial.residuals(1, 1) = -1;
  trial.camera_masks.setZero(2, 4);
  return trial;
}

TEST(Trc, WriteReadRoundTripKeepsValuesGapsAndFrameNumbers) {
  const Trial original = SmallTrial();
  for (const char* units : {"mm", "m"}) {
    const std::string text =
        WriteTrcToString(original, "small.trc", {.units = units, .decimals = 9});
    const Trial back = ReadTrcFromString(text, "small.trc");
    EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
    ASSERT_EQ(back.num_points(), 2);
    ASSERT_EQ(back.num_frames, 4);
    EXPECT_EQ(back.first_frame, 5);
    EXPECT_EQ(back.point_rate_hz, 120.0);
    EXPECT_EQ(back.points[0].label, "Left, Toe");
    for (int f = 0; f < 4; ++f) {
      for (int p = 0; p < 2; ++p) {
        EXPECT_EQ(back.valid(f, p), original.valid(f, p));
        if (original.valid(f, p)) {
          // 9 decimals in the written unit.
          EXPECT_LT((back.position(f, p) - original.position(f, p)).cwiseAbs().maxCoeff(),
                    1e-9 * LengthUnitToMetres(units));
        }
      }
    }
  }
}

TEST(Trc, BadCellsNameLineAndColumn) {
  std::string text = WriteTrcToString(SmallTrial(), "x.trc");
  // Corrupt the last cell of the last row (line 10: 6 header lines + 4 frames; column 8 = z of
  // marker 2).
  text.insert(text.rfind('\t') + 1, "x");
  try {
    ReadTrcFromString(text, "x.trc");
    FAIL() << "accepted a non-numeric cell";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("x.trc: line 10, column 8: 'x"), std::string::npos) << message;
    EXPECT_NE(message.find("is not a number"), std::string::npos) << message;
  }
}

// A row cut short of its markers' columns: the missing marker is a gap, and the line is said.
TEST(Trc, ShortRowsAreGapsAndSaid) {
  std::string text = WriteTrcToString(SmallTrial(), "x.trc");
  ASSERT_EQ(text.back(), '\n');
  // The last row (line 10) without marker 2's three cells.
  size_t end = text.size() - 1;
  for (int k = 0; k < 3; ++k) end = text.rfind('\t', end - 1);
  text.erase(end, text.size() - 1 - end);
  const Trial trial = ReadTrcFromString(text, "x.trc");
  ASSERT_EQ(trial.num_points(), 2);
  EXPECT_TRUE(trial.valid(3, 0));
  EXPECT_FALSE(trial.valid(3, 1));
  EXPECT_TRUE(trial.valid(2, 1));
  bool said = false;
  for (const std::string& w : trial.warnings)
    said = said || w.find(
                       "x.trc: line 10 holds fewer than the 6 coordinate columns of 2 markers; "
                       "the markers past a row's end are read as gaps") != std::string::npos;
  EXPECT_TRUE(said);
  // A whole file of rows is fine: no such warning.
  for (const std::string& w :
       ReadTrcFromString(WriteTrcToString(SmallTrial(), "y.trc"), "y.trc").warnings)
    EXPECT_EQ(w.find("fewer than"), std::string::npos) << w;
}

TEST(Trc, EveryTruncationLoadsOrFailsCleanly) {
  // Cut a valid file at every length: each prefix either loads or throws InputError, never crashes.
  const std::string text = WriteTrcToString(SmallTrial(), "x.trc");
  int loaded = 0, rejected = 0;
  for (std::size_t n = 0; n <= text.size(); ++n) {
    try {
      const Trial t = ReadTrcFromString(std::string_view(text).substr(0, n), "x.trc");
      EXPECT_LE(t.num_frames, 4);
      ++loaded;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace acro::capture
