#include "acro/report/body_report.h"

#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/de_leva.h"
#include "acro/base/input_error.h"
#include "json_keys.h"

namespace acro::analysis {
namespace {

using ui::FormatBodyReportJson;
using ui::FormatBodyReportText;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kEps = std::numeric_limits<double>::epsilon();

TEST(BodyReport, PoseSpecificationsCombineShapesAndAngles) {
  const BodyPose pose = ParseBodyPose("tuck,knee_flexion=120,l_hip_abduction=-5.5");
  BodyPose tuck;
  ASSERT_TRUE(MakeNamedPose("tuck", &tuck));
  EXPECT_EQ(pose.angles_rad.at("hip_flexion"), tuck.angles_rad.at("hip_flexion"));
  EXPECT_NEAR(pose.angles_rad.at("knee_flexion"), 120 * kDeg, 4 * kEps);
  EXPECT_NEAR(pose.angles_rad.at("l_hip_abduction"), -5.5 * kDeg, 4 * kEps);
  // A shape given later replaces what came before.
  EXPECT_TRUE(ParseBodyPose("knee_flexion=30,straight").angles_rad.empty());
  EXPECT_THROW(ParseBodyPose("tuck,,pike"), InputError);
  EXPECT_THROW(ParseBodyPose("crouch"), InputError);
  EXPECT_THROW(ParseBodyPose("knee_flexion=ninety"), InputError);
  EXPECT_THROW(ParseBodyPose("ankle_flexion=10"), InputError);
}

TEST(BodyReport, JsonCarriesTheTotalsAndEverySegment) {
  const AthleteBody rest = MakeDeLevaBody(1.70, 60, Sex::kMale);
  const AthleteBody posed = PoseAthleteBody(rest, ParseBodyPose("pike"));
  const ShapeInertias shapes = CalcShapeInertias(rest, posed);
  EXPECT_EQ(shapes.pose_kgm2, shapes.pike_kgm2);
  EXPECT_GT(shapes.straight_kgm2, shapes.pike_kgm2);
  EXPECT_GT(shapes.pike_kgm2, shapes.tuck_kgm2);
  // Parsed, then compared value by value: JSON numbers are written to round-trip, so exactly. Not
  // const: [] on a missing key then gives null rather than undefined behaviour.
  nlohmann::ordered_json json =
      nlohmann::ordered_json::parse(FormatBodyReportJson(posed, shapes, "pike"));
  EXPECT_EQ(acro::testing::JsonKeys(json),
            (std::vector<std::string>{"model",
                                      "height_m",
                                      "frame",
                                      "pose",
                                      "total",
                                      "segments",
                                      "somersault_inertia_kgm2",
                                      "somersault_ratio_straight_to_pose"}));
  EXPECT_EQ(json["model"], posed.model);
  EXPECT_EQ(json["height_m"].get<double>(), posed.height_m);
  EXPECT_EQ(json["pose"], "pike");
  auto vector = [](const Eigen::Vector3d& v) {
    return nlohmann::ordered_json{v.x(), v.y(), v.z()};
  };
  auto matrix = [&](const Eigen::Matrix3d& m) {
    return nlohmann::ordered_json{
        vector(m.row(0).transpose()), vector(m.row(1).transpose()), vector(m.row(2).transpose())};
  };
  EXPECT_EQ(json["total"]["mass_kg"].get<double>(), posed.total.mass_kg);
  EXPECT_EQ(json["total"]["com_m"], vector(posed.total.p_HoCm_H));
  EXPECT_EQ(json["total"]["inertia_com_kgm2"], matrix(posed.total.I_Cm_H));
  // One entry per segment, in order.
  ASSERT_EQ(json["segments"].size(), 15u);
  ASSERT_EQ(posed.segments.size(), 15u);
  for (size_t i = 0; i < posed.segments.size(); ++i) {
    const BodySegment& s = posed.segments[i];
    nlohmann::ordered_json& js = json["segments"][i];
    EXPECT_EQ(js["name"], s.name);
    EXPECT_EQ(js["mass_kg"].get<double>(), s.in_H.mass_kg) << s.name;
    EXPECT_EQ(js["com_m"], vector(s.in_H.p_HoCm_H)) << s.name;
    EXPECT_EQ(js["inertia_com_kgm2"], matrix(s.in_H.I_Cm_H)) << s.name;
    EXPECT_EQ(js["joint_m"], vector(s.p_HoJ_H)) << s.name;
    EXPECT_EQ(js["end_m"], vector(s.p_HoE_H)) << s.name;
  }
  nlohmann::ordered_json& somersault = json["somersault_inertia_kgm2"];
  EXPECT_EQ(somersault["straight"].get<double>(), shapes.straight_kgm2);
  EXPECT_EQ(somersault["pike"].get<double>(), shapes.pike_kgm2);
  EXPECT_EQ(somersault["tuck"].get<double>(), shapes.tuck_kgm2);
  EXPECT_EQ(somersault["pose"].get<double>(), shapes.pose_kgm2);
  EXPECT_EQ(json["somersault_ratio_straight_to_pose"].get<double>(),
            shapes.straight_kgm2 / shapes.pose_kgm2);
  const std::string text = FormatBodyReportText(posed, shapes, "pike");
  EXPECT_NE(text.find("l_thigh"), std::string::npos);
  EXPECT_NE(text.find("somersault-axis inertia"), std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
