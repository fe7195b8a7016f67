#pragma once

// An athlete profile file (YAML, docs/formats/athlete.md): name, sex, height, mass, optionally
// Yeadon measurements (inline or a path to a yeadon measurement file) and measured segment lengths.

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/de_leva.h"
#include "acro/athlete/yeadon_human.h"
#include "acro/athlete/yeadon_measurements.h"
#include "acro/base/yaml.h"

namespace acro::analysis {

struct AthleteProfile {
  std::string name;
  Sex sex = Sex::kFemale;
  double height_m = 0.0;
  double mass_kg = 0.0;
  /// Yeadon's 95 measurements when given; the body then follows Yeadon's model with its densities
  /// scaled to `mass_kg`.
  std::optional<YeadonMeasurements> yeadon_measurements;
  YeadonOptions yeadon_options;
  /// Measured segment lengths for the de Leva route (see de_leva.h for the names).
  SegmentLengths segment_lengths_m;
  /// Segment masses that replace the model's (standard segment names, e.g. "r_thigh"): each
  /// segment keeps its centre of mass and its inertia scales with the mass; the body's total
  /// mass becomes the sum of its segments'. For measured or corrected masses, e.g. what the
  /// physical check suggests.
  std::map<std::string, double> segment_masses_kg;
  /// The profile's file name.
  std::string source;
};

/// Reads a profile. A relative `yeadon.measurements` path is taken from the profile's folder.
/// Throws acro::InputError naming the file, the line and the key at fault.
AthleteProfile ReadAthleteProfile(const std::filesystem::path& path);

/// The same from a parsed YAML document; `base_dir` resolves a relative measurement path.
AthleteProfile AthleteProfileFromYaml(const YamlNode& root, const std::filesystem::path& base_dir);

/// The athlete's body in the reference pose: Yeadon's model when measurements are given (its mass
/// scaled to the profile's), otherwise de Leva's regression.
AthleteBody MakeAthleteBody(const AthleteProfile& profile);

}  // namespace acro::analysis
