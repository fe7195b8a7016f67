// `acrolab info --json`: the JSON object of a small trial built in memory, parsed and compared
// value by value (keys, their order, integers as integers, a missing number as null).
#include "acro/capture/trial_info.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "json_keys.h"

namespace acro::capture {
namespace {

// Parsed with the keys in file order. The parsed values are not const: [] on a missing key then
// gives null rather than undefined behaviour.
using Json = nlohmann::ordered_json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Two markers (B missing in frames 1 and 2), one model output, one analog channel at 2 samples per
// frame, a plate without outputs and one with, two events and a warning with characters JSON
// escapes.
Trial MakeTrial() {
  Trial t;
  t.source.path = "lab/jump \"1\".c3d";
  t.source.format = "C3D";
  t.source.processor = "Intel";
  t.source.point_storage = "float";
  t.source.point_units = "mm";
  t.point_rate_hz = 100.0;
  t.first_frame = 5;
  t.num_frames = 4;
  t.subject_name = "Ann";
  t.points = {{"A", "", PointType::kMarker, "m"},
              {"B", "", PointType::kMarker, "m"},
              {"LKneeAngles", "", PointType::kAngle, "deg"}};
  t.positions = Eigen::Matrix3Xd::Ones(3, 12);
  t.position(1, 1).setConstant(kNaN);
  t.position(2, 1).setConstant(kNaN);
  t.analog_rate_hz = 200.0;
  t.analog_channels = {{"Fz", "vertical force", "N"}};
  t.analog = Eigen::MatrixXd::Zero(1, 8);
  ForcePlate idle;
  idle.type = 2;
  idle.channels = {0, 1, 2, 3, 4, 5};
  idle.corners_W_m.row(0) << 0.5, -0.5, -0.5, 0.5;
  idle.origin_F_m = Eigen::Vector3d(0.0, 0.0, -0.04);
  ForcePlate loaded = idle;
  loaded.force_W_N = Eigen::Matrix3Xd::Zero(3, 8);
  loaded.force_W_N(2, 3) = -750.5;
  t.force_plates = {idle, loaded};
  t.events = {{"Take-off", "General", "feet leave the bed", "Ann", 0.015},
              {"Landing", "General", "", "Ann", 0.035}};
  t.warnings = {"POINT:UNITS: \"mm\"\tassumed\nfrom the data"};
  return t;
}

TEST(TrialInfo, JsonParsesWithEveryDocumentedKeyInOrder) {
  Json j = Json::parse(FormatTrialInfoJson(MakeTrial()));
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(acro::testing::JsonKeys(j),
            (std::vector<std::string>{"file",
                                      "format",
                                      "processor",
                                      "point_storage",
                                      "frames",
                                      "first_frame",
                                      "point_rate_hz",
                                      "duration_s",
                                      "point_units",
                                      "subject",
                                      "markers",
                                      "marker_labels",
                                      "points",
                                      "missing_marker_frames_total",
                                      "gaps",
                                      "analog_rate_hz",
                                      "analog_samples_per_frame",
                                      "analog_channels",
                                      "force_plates",
                                      "events",
                                      "warnings"}));
}

TEST(TrialInfo, JsonHoldsTheTrialsValues) {
  Json j = Json::parse(FormatTrialInfoJson(MakeTrial()));
  // Texts, escaped quotes included.
  EXPECT_EQ(j["file"], "lab/jump \"1\".c3d");
  EXPECT_EQ(j["format"], "C3D");
  EXPECT_EQ(j["processor"], "Intel");
  EXPECT_EQ(j["point_storage"], "float");
  EXPECT_EQ(j["point_units"], "mm");
  EXPECT_EQ(j["subject"], "Ann");
  // Counts are integers, not 4.0.
  for (const char* key : {"frames",
                          "first_frame",
                          "markers",
                          "points",
                          "missing_marker_frames_total",
                          "analog_samples_per_frame"})
    EXPECT_TRUE(j[key].is_number_integer()) << key;
  EXPECT_EQ(j["frames"], 4);
  EXPECT_EQ(j["first_frame"], 5);
  EXPECT_EQ(j["markers"], 2);
  EXPECT_EQ(j["points"], 3);
  EXPECT_EQ(j["missing_marker_frames_total"], 2);
  EXPECT_EQ(j["analog_samples_per_frame"], 2);
  // Rates and duration: the doubles themselves (JSON numbers are written to round-trip).
  EXPECT_EQ(j["point_rate_hz"].get<double>(), 100.0);
  EXPECT_EQ(j["duration_s"].get<double>(), 0.04);
  EXPECT_EQ(j["analog_rate_hz"].get<double>(), 200.0);
  EXPECT_EQ(j["marker_labels"], Json::parse(R"(["A", "B"])"));
  EXPECT_EQ(j["gaps"], Json::parse(R"([
              {"label": "A", "missing_frames": 0, "longest_gap_frames": 0, "gap_count": 0},
              {"label": "B", "missing_frames": 2, "longest_gap_frames": 2, "gap_count": 1}])"));
  EXPECT_EQ(j["analog_channels"],
            Json::parse(R"([{"label": "Fz", "unit": "N", "description": "vertical force"}])"));
  EXPECT_EQ(j["warnings"], Json::parse(R"(["POINT:UNITS: \"mm\"\tassumed\nfrom the data"])"));
}

TEST(TrialInfo, JsonForcePlatesAndEvents) {
  Json j = Json::parse(FormatTrialInfoJson(MakeTrial()));
  ASSERT_EQ(j["force_plates"].size(), 2u);
  Json& idle = j["force_plates"][0];
  EXPECT_EQ(idle["type"], 2);
  EXPECT_TRUE(idle["type"].is_number_integer());
  EXPECT_EQ(idle["channels"], Json::parse("[0, 1, 2, 3, 4, 5]"));
  EXPECT_EQ(idle["corners_W_m"],
            Json::parse("[[0.5, 0, 0], [-0.5, 0, 0], [-0.5, 0, 0], [0.5, 0, 0]]"));
  EXPECT_EQ(idle["origin_F_m"], Json::parse("[0, 0, -0.04]"));
  // No outputs: the peak is NaN in the library and null in JSON (JSON has no NaN).
  EXPECT_TRUE(idle["peak_vertical_force_N"].is_null());
  EXPECT_EQ(j["force_plates"][1]["peak_vertical_force_N"].get<double>(), 750.5);
  // The description only when there is one.
  EXPECT_EQ(j["events"], Json::parse(R"([
              {"label": "Take-off", "context": "General", "time_s": 0.015,
               "description": "feet leave the bed"},
              {"label": "Landing", "context": "General", "time_s": 0.035}])"));
}

// Labels come from files that need not be UTF-8: the output is still JSON, the bad byte replaced.
TEST(TrialInfo, JsonStaysValidWithLabelsThatAreNotUtf8) {
  Trial t = MakeTrial();
  t.points[0].label = "Kn\xE9";  // "Kné" in Latin-1
  Json j = Json::parse(FormatTrialInfoJson(t));
  EXPECT_EQ(j["marker_labels"][0], "Kn\xEF\xBF\xBD");  // U+FFFD
}

}  // namespace
}  // namespace acro::capture
