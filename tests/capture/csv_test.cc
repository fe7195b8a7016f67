#include "acro/capture/csv.h"

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

}  // namespace
}  // namespace acro::capture
