#include "acro/athlete/yeadon_measurements.h"

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

// The InputError message of reading `path` ("" when it reads).
std::string ErrorReading(const std::filesystem::path& path) {
  try {
    ReadYeadonMeasurements(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(YeadonMeasurements, ReadsTheSampleFileInMetres) {
  const auto path = acro::testing::RefdataFile("yeadon/male1.txt");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const YeadonMeasurements m = ReadYeadonMeasurements(path);
  // The file holds centimetres with measurementconversionfactor .01 ("Ls1L: 4.9", "Lk6d: 11.1").
  EXPECT_DOUBLE_EQ(m.Get("Ls1L"), 4.9 * 0.01);
  EXPECT_DOUBLE_EQ(m.Get("Lk6d"), 11.1 * 0.01);
  EXPECT_FALSE(m.total_mass_kg.has_value());
  for (double v : m.values_m) EXPECT_GT(v, 0.0);
}

TEST(YeadonMeasurements, TotalMassMinusOneMeansNotMeasured) {
  const auto path = acro::testing::RefdataFile("yeadon/female1.txt");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const YeadonMeasurements m = ReadYeadonMeasurements(path);
  EXPECT_FALSE(m.total_mass_kg.has_value());
}

TEST(YeadonMeasurements, BadKeyNamesTheKeyAndLine) {
  const auto path = acro::testing::RefdataFile("yeadon/male1_badkey.txt");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const std::string error = ErrorReading(path);
  EXPECT_NE(error.find(path.string() + ": line 29: LsLL: unknown measurement name"),
            std::string::npos)
      << error;
}

TEST(YeadonMeasurements, BadValueNamesTheKeyAndLine) {
  const auto path = acro::testing::RefdataFile("yeadon/male1_badval.txt");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const std::string error = ErrorReading(path);
  EXPECT_NE(error.find(path.string() + ": line 29: Ls1L: no value"), std::string::npos) << error;
}

TEST(YeadonMeasurements, MissingKeyNamesTheKeyAndWhereItWasExpected) {
  const auto path = acro::testing::RefdataFile("yeadon/male1_missingkey.txt");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const std::string error = ErrorReading(path);
  // Lk8w is absent; its predecessor in yeadon's order, Lk9p, is on line 187 of the file.
  EXPECT_NE(error.find(path.string() + ": line 188: measurement 'Lk8w' is missing (expected after "
                                       "'Lk9p' on line 187)"),
            std::string::npos)
      << error;
}

// Writes `text` to a temporary file and returns the error of reading it.
std::string ErrorOfText(const std::string& name, const std::string& text) {
  const auto path = acro::testing::TempDir() / name;
  std::ofstream(path) << text;
  return ErrorReading(path);
}

// A complete, valid measurement text (every value 10 cm) with `extra` appended.
std::string Complete(const std::string& extra) {
  std::string text = "measurementconversionfactor: 0.01\n";
  for (std::string_view name : kYeadonMeasurementNames) text += std::string(name) + ": 10\n";
  return text + extra;
}

TEST(YeadonMeasurements, NegativeOrNonNumericValuesAreRefused) {
  std::string text = Complete("");
  text.replace(text.find("Ls2L: 10"), 8, "Ls2L: -3");
  EXPECT_NE(ErrorOfText("neg.txt", text).find("line 3: Ls2L: must be positive, found '-3'"),
            std::string::npos);
  text = Complete("");
  text.replace(text.find("Ls3L: 10"), 8, "Ls3L: 1O");
  EXPECT_NE(ErrorOfText("alpha.txt", text).find("line 4: Ls3L: '1O' is not a number"),
            std::string::npos);
  EXPECT_NE(ErrorOfText("dup.txt", Complete("Ls1L: 3\n")).find("duplicate key 'Ls1L'"),
            std::string::npos);
  EXPECT_NE(
      ErrorOfText("mass.txt", Complete("totalmass: -5\n")).find("totalmass: must be a positive"),
      std::string::npos);
  std::string no_factor = Complete("");
  no_factor.erase(0, no_factor.find('\n') + 1);
  EXPECT_NE(ErrorOfText("nofactor.txt", no_factor).find("'measurementconversionfactor' is missing"),
            std::string::npos);
  EXPECT_EQ(ErrorOfText("ok.txt", Complete("totalmass: 61.5\n")), "");
}

}  // namespace
}  // namespace acro::analysis
