#include "acro/athlete/athlete_profile.h"

#include <fstream>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::filesystem::path Write(const std::string& name, const std::string& text) {
  const auto path = acro::testing::TempDir() / name;
  std::ofstream(path) << text;
  return path;
}

std::string ErrorReading(const std::filesystem::path& path) {
  try {
    ReadAthleteProfile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AthleteProfile, TheSampleProfileGivesADeLevaBody) {
  const auto path = acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
  const AthleteProfile profile = ReadAthleteProfile(path);
  EXPECT_EQ(profile.sex, Sex::kFemale);
  EXPECT_EQ(profile.height_m, 1.75);
  EXPECT_EQ(profile.mass_kg, 65.0);
  EXPECT_FALSE(profile.yeadon_measurements.has_value());
  const AthleteBody body = MakeAthleteBody(profile);
  EXPECT_NE(body.model.find("de Leva"), std::string::npos);
  // Its measured thigh length is used.
  const BodySegment& thigh = body.segments[static_cast<size_t>(body.Find("l_thigh"))];
  EXPECT_NEAR(
      (thigh.p_HoE_H - thigh.p_HoJ_H).norm(), profile.segment_lengths_m.at("thigh"), 8 * kEps);
}

TEST(AthleteProfile, TheInlineYeadonSampleGivesAYeadonBody) {
  const auto path = acro::testing::SourceDir() / "samples/athletes/sample_athlete_yeadon.yaml";
  const AthleteProfile profile = ReadAthleteProfile(path);
  ASSERT_TRUE(profile.yeadon_measurements.has_value());
  const YeadonHuman human = YeadonHuman::Make(*profile.yeadon_measurements, profile.yeadon_options);
  EXPECT_TRUE(human.warnings().empty());  // every stadium's perimeter/width ratio is in (2, π)
  const AthleteBody body = MakeAthleteBody(profile);
  EXPECT_NE(body.model.find("Yeadon"), std::string::npos);
  EXPECT_NEAR(body.total.mass_kg, profile.mass_kg, 64 * kEps * profile.mass_kg);
  EXPECT_NEAR(
      body.height_m, profile.height_m, 0.02);  // the made-up measurements fit the stated height
}

TEST(AthleteProfile, YeadonMeasurementsByPathAreScaledToTheProfilesMass) {
  const auto meas = acro::testing::RefdataFile("yeadon/male1.txt");
  ACRO_REQUIRE_REFDATA_FILE(meas);
  const auto path = Write(
      "yeadon_profile.yaml",
      "name: M1\nsex: m\nheight_m: 1.80\nmass_kg: 70\nyeadon:\n  measurements: " + meas.string() +
          "\n  density: clauser\n");
  const AthleteProfile profile = ReadAthleteProfile(path);
  ASSERT_TRUE(profile.yeadon_measurements.has_value());
  EXPECT_EQ(profile.yeadon_options.density, DensitySet::kClauser);
  const AthleteBody body = MakeAthleteBody(profile);
  EXPECT_NEAR(body.total.mass_kg, 70.0, 64 * kEps * 70.0);
  EXPECT_NE(body.model.find("clauser"), std::string::npos);
}

TEST(AthleteProfile, InlineMeasurementsAreValidatedLikeAFile) {
  std::string text =
      "name: X\nsex: f\nheight_m: 1.6\nmass_kg: 50\nyeadon:\n  measurements:\n"
      "    measurementconversionfactor: 0.01\n";
  for (std::string_view name : kYeadonMeasurementNames) {
    if (name != "Lk6d") text += "    " + std::string(name) + ": 10\n";
  }
  const std::string error = ErrorReading(Write("inline.yaml", text));
  EXPECT_NE(error.find("measurement 'Lk6d' is missing"), std::string::npos) << error;
}

TEST(AthleteProfile, ErrorsNameTheFileLineAndKey) {
  const auto typo = Write("typo.yaml", "name: A\nsex: f\nhieght_m: 1.7\nmass_kg: 60\n");
  EXPECT_NE(ErrorReading(typo).find(typo.string() + ": line 3: unknown key 'hieght_m'"),
            std::string::npos);
  const auto sex = Write("sex.yaml", "name: A\nsex: x\nheight_m: 1.7\nmass_kg: 60\n");
  EXPECT_EQ(ErrorReading(sex), sex.string() + ": line 2: sex: 'x' is not f or m");
  const auto mass = Write("mass.yaml", "name: A\nsex: m\nheight_m: 1.7\nmass_kg: 6000\n");
  EXPECT_NE(ErrorReading(mass).find(": line 4: mass_kg: '6000' is not a body mass"),
            std::string::npos);
  const auto missing = Write("missing.yaml", "name: A\nsex: m\nmass_kg: 60\n");
  EXPECT_NE(ErrorReading(missing).find("the required key 'height_m' is missing"),
            std::string::npos);
  const auto length =
      Write("length.yaml",
            "name: A\nsex: m\nheight_m: 1.7\nmass_kg: 60\nsegment_lengths_m:\n  tibia: 0.4\n");
  EXPECT_NE(ErrorReading(length).find(": line 6: unknown key 'tibia'"), std::string::npos);
  const auto nofile =
      Write("nofile.yaml",
            "name: A\nsex: m\nheight_m: 1.7\nmass_kg: 60\nyeadon:\n  measurements: nowhere.txt\n");
  EXPECT_NE(ErrorReading(nofile).find(": line 6: measurements: no such file"), std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
