#pragma once

// The 95 anthropometric measurements of Yeadon's (1990) inertia model, read from the yeadon
// package's measurement file ("key: value" lines, '#' comments, `measurementconversionfactor`
// converting the values into metres, optional `totalmass` in kg with −1 meaning "not measured"),
// or from an inline YAML map in an athlete profile (docs/formats/athlete.md).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "acro/base/yaml.h"

namespace acro::analysis {

/// The measurement names in the yeadon package's order: torso (Ls…), left arm (La…), right arm
/// (Lb…), left leg (Lj…), right leg (Lk…). L = length from the segment's base level, p = perimeter,
/// w = width, d = depth (Yeadon 1990, Fig. 2 and the package's measurement template).
inline constexpr std::array<std::string_view, 95> kYeadonMeasurementNames = {
    "Ls1L", "Ls2L", "Ls3L", "Ls4L", "Ls5L", "Ls6L", "Ls7L", "Ls8L", "Ls0p", "Ls1p", "Ls2p",
    "Ls3p", "Ls5p", "Ls6p", "Ls7p", "Ls0w", "Ls1w", "Ls2w", "Ls3w", "Ls4w", "Ls4d",  // torso: 21
    "La2L", "La3L", "La4L", "La5L", "La6L", "La7L", "La0p", "La1p", "La2p", "La3p", "La4p",
    "La5p", "La6p", "La7p", "La4w", "La5w", "La6w", "La7w",  // left arm: 18
    "Lb2L", "Lb3L", "Lb4L", "Lb5L", "Lb6L", "Lb7L", "Lb0p", "Lb1p", "Lb2p", "Lb3p", "Lb4p",
    "Lb5p", "Lb6p", "Lb7p", "Lb4w", "Lb5w", "Lb6w", "Lb7w",  // right arm: 18
    "Lj1L", "Lj3L", "Lj4L", "Lj5L", "Lj6L", "Lj8L", "Lj9L", "Lj1p", "Lj2p", "Lj3p", "Lj4p",
    "Lj5p", "Lj6p", "Lj7p", "Lj8p", "Lj9p", "Lj8w", "Lj9w", "Lj6d",  // left leg: 19
    "Lk1L", "Lk3L", "Lk4L", "Lk5L", "Lk6L", "Lk8L", "Lk9L", "Lk1p", "Lk2p", "Lk3p", "Lk4p",
    "Lk5p", "Lk6p", "Lk7p", "Lk8p", "Lk9p", "Lk8w", "Lk9w", "Lk6d"};  // right leg: 19

/// Index of a measurement name in kYeadonMeasurementNames, or −1.
int YeadonMeasurementIndex(std::string_view name);

struct YeadonMeasurements {
  /// Values in metres, in kYeadonMeasurementNames order.
  std::array<double, 95> values_m{};
  /// Measured body mass (the file's `totalmass`), when given: the model's densities are then
  /// scaled so that its mass equals it (as the yeadon package does).
  std::optional<double> total_mass_kg;
  /// Where the values came from (a file name), for messages.
  std::string source;

  /// The value of a named measurement in metres (ACRO_DEMAND on an unknown name).
  double Get(std::string_view name) const;
  void Set(std::string_view name, double value_m);
};

/// Reads a yeadon measurement file. Throws acro::InputError naming the file, the line and the key
/// for an unknown key, a missing key (the line after which it was expected), a value that is not
/// a number, is missing, or is not positive, and for a missing or non-positive
/// measurementconversionfactor.
YeadonMeasurements ReadYeadonMeasurements(const std::filesystem::path& path);

/// The same from a parsed YAML map (a measurement file or an athlete profile's inline map).
YeadonMeasurements YeadonMeasurementsFromYaml(const YamlNode& map);

}  // namespace acro::analysis
