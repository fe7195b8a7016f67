#include "acro/athlete/yeadon_measurements.h"

#include <cmath>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"

namespace acro::analysis {

int YeadonMeasurementIndex(std::string_view name) {
  for (size_t i = 0; i < kYeadonMeasurementNames.size(); ++i)
    if (kYeadonMeasurementNames[i] == name) return static_cast<int>(i);
  return -1;
}

double YeadonMeasurements::Get(std::string_view name) const {
  const int i = YeadonMeasurementIndex(name);
  ACRO_DEMAND(i >= 0);
  return values_m[static_cast<size_t>(i)];
}

void YeadonMeasurements::Set(std::string_view name, double value_m) {
  const int i = YeadonMeasurementIndex(name);
  ACRO_DEMAND(i >= 0);
  values_m[static_cast<size_t>(i)] = value_m;
}

YeadonMeasurements YeadonMeasurementsFromYaml(const YamlNode& map) {
  const std::string& file = map.file();
  if (!map.IsMap()) throw InputError(file, map.Where(), "expected 'name: value' measurement lines");
  YeadonMeasurements out;
  out.source = file;
  std::array<int, 95> line_of{};  // 0 = not seen
  std::optional<double> factor;
  // Every entry: a known key with a positive number.
  for (const auto& entry : map.entries()) {
    // (named, not a structured binding: lambdas capture those only from C++20 compilers on)
    const std::string& key = entry.first;
    const YamlNode& node = entry.second;
    auto number = [&](const char* what) {
      if (node.IsNull()) node.Fail(std::string("no value (expected ") + what + ")");
      double value = 0.0;
      if (!node.IsScalar() || node.quoted() || !ParseYamlNumber(node.text(), &value) ||
          !std::isfinite(value))
        node.Fail("'" + node.text() + "' is not a number");
      return value;
    };
    if (key == "measurementconversionfactor") {
      const double v = number("the factor converting the values into metres");
      if (!(v > 0.0))
        node.Fail("must be positive (1 for metres, 0.01 for centimetres), found '" + node.text() +
                  "'");
      factor = v;
      continue;
    }
    if (key == "totalmass") {
      const double v = number("a mass in kg, or -1 when not measured");
      if (v == -1.0) continue;  // the yeadon package's "not measured"
      if (!(v > 0.0))
        node.Fail("must be a positive mass in kg (or -1 when not measured), found '" + node.text() +
                  "'");
      out.total_mass_kg = v;
      continue;
    }
    const int index = YeadonMeasurementIndex(key);
    if (index < 0)
      node.Fail(
          "unknown measurement name (Yeadon's 95 names are listed in docs/formats/athlete.md)");
    const double v = number("a length in the file's unit");
    if (!(v > 0.0)) node.Fail("must be positive, found '" + node.text() + "'");
    out.values_m[static_cast<size_t>(index)] = v;
    line_of[static_cast<size_t>(index)] = node.line();
  }
  // Every measurement present; a missing one is reported after the line of its predecessor.
  for (size_t i = 0; i < kYeadonMeasurementNames.size(); ++i) {
    if (line_of[i] != 0) continue;
    int after = 0;
    std::string after_name;
    for (size_t j = i; j-- > 0;) {
      if (line_of[j] != 0) {
        after = line_of[j];
        after_name = std::string(kYeadonMeasurementNames[j]);
        break;
      }
    }
    const std::string where = after > 0 ? "line " + std::to_string(after + 1) : map.Where();
    throw InputError(file,
                     where,
                     "measurement '" + std::string(kYeadonMeasurementNames[i]) + "' is missing" +
                         (after > 0 ? " (expected after '" + after_name + "' on line " +
                                          std::to_string(after) + ")"
                                    : ""));
  }
  if (!factor)
    throw InputError(file,
                     map.Where(),
                     "'measurementconversionfactor' is missing (1 when the values are in metres)");
  for (double& v : out.values_m) v *= *factor;
  return out;
}

YeadonMeasurements ReadYeadonMeasurements(const std::filesystem::path& path) {
  return YeadonMeasurementsFromYaml(ReadYamlFile(path));
}

}  // namespace acro::analysis
