#include "acro/capture/csv.h"

#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::capture {
namespace {

TEST(MarkerCsv, RoundTripIsExactWithGapsAndQuotedLabels) {
  Trial trial;
  trial.point_rate_hz = 200.0;
  trial.first_frame = 1;
  trial.num_frames = 3;
  trial.points = {{"A", "", PointType::kMarker, "m"}, {"B,\"odd\"", "", PointType::kMarker, "m"}};
  trial.positions = Eigen::Matrix3Xd::Random(3, 6);
  trial.positions.col(2).setConstant(std::nan(""));
  const std::string text = WriteMarkerCsvToString(trial);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "frame,time_s,A_x_m,A_y_m,A_z_m,\"B,\"\"odd\"\"_x_m\",\"B,\"\"odd\"\"_y_m\",\"B,"
            "\"\"odd\"\"_z_m\"");
  const Trial back = ReadMarkerCsvFromString(text, "t.csv");
  ASSERT_EQ(back.num_points(), 2);
  EXPECT_EQ(back.points[1].label, "B,\"odd\"");
  EXPECT_DOUBLE_EQ(back.point_rate_hz, 200.0);
  EXPECT_FALSE(back.valid(1, 0));
  EXPECT_EQ(back.residuals(0, 1), -1.0f);
  for (int c : {0, 1, 3, 4, 5}) EXPECT_EQ(back.positions.col(c), trial.positions.col(c));
}

TEST(MarkerCsv, ErrorsNameTheLine) {
  try {
    ReadMarkerCsvFromString("frame,time_s,A_x_m,A_y_m,A_z_m\n1,0,1,2,3\n2,0.1,1,2\n", "m.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "m.csv: line 3: 4 fields where the header has 5");
  }
}

// The message of reading `text`, or "" when it reads.
std::string ReadError(const std::string& text) {
  try {
    ReadMarkerCsvFromString(text, "m.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MarkerCsv, ColumnsOutOfOrderAndTimeGoingBackAreErrorsNamingThem) {
  EXPECT_EQ(ReadError("frame,time_s,A_x_m,A_z_m,A_y_m\n1,0,1,2,3\n2,0.1,1,2,3\n"),
            "m.csv: line 1, column 4: expected 'A_y_m', found 'A_z_m'");
  EXPECT_EQ(ReadError("frame,time_s,A_x_m,A_y_m,A_z_m\n1,0,1,2,3\n2,0.1,1,2,3\n3,0.1,1,2,3\n"),
            "m.csv: line 4, column 2: time 0.100000 s is not after the previous row's 0.100000 s");
}

TEST(MarkerCsv, RepeatedLabelsAndAnUnevenTimeColumnAreSaid) {
  const Trial t = ReadMarkerCsvFromString(
      "frame,time_s,A_x_m,A_y_m,A_z_m,A_x_m,A_y_m,A_z_m\n"
      "1,0,1,2,3,4,5,6\n2,0.01,1,2,3,4,5,6\n3,0.03,1,2,3,4,5,6\n4,0.04,1,2,3,4,5,6\n",
      "m.csv");
  ASSERT_EQ(t.num_points(), 2);
  EXPECT_EQ(t.points[1].label, "A_2");
  EXPECT_DOUBLE_EQ(t.position(0, 1).x(), 4.0);
  ASSERT_EQ(t.warnings.size(), 2u);
  EXPECT_EQ(t.warnings[0],
            "m.csv: line 1: marker label 'A' repeats (markers 1 and 2); the second is read as "
            "'A_2'");
  // 4 frames over 0.04 s: 75 Hz; the rows at 0.01 and 0.03 s are off its grid.
  EXPECT_NE(t.warnings[1].find("m.csv: lines 3, 4: time_s off the even grid of 75"),
            std::string::npos)
      << t.warnings[1];
}

}  // namespace
}  // namespace acro::capture
