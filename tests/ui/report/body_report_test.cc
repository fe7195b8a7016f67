#include "acro/report/body_report.h"

#include <numbers>

#include <gtest/gtest.h>

#include "acro/athlete/de_leva.h"
#include "acro/base/input_error.h"

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
  const std::string json = FormatBodyReportJson(posed, shapes, "pike");
  for (const char* key : {"\"total\"",
                          "\"mass_kg\"",
                          "\"com_m\"",
                          "\"inertia_com_kgm2\"",
                          "\"segments\"",
                          "\"somersault_ratio_straight_to_pose\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  // One "name" per segment.
  size_t names = 0;
  for (size_t at = json.find("\"name\""); at != std::string::npos;
       at = json.find("\"name\"", at + 1))
    ++names;
  EXPECT_EQ(names, 15u);
  const std::string text = FormatBodyReportText(posed, shapes, "pike");
  EXPECT_NE(text.find("l_thigh"), std::string::npos);
  EXPECT_NE(text.find("somersault-axis inertia"), std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
