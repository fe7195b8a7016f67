#include "acro/athlete/athlete_profile.h"

#include <cmath>

#include <fmt/format.h>

#include "acro/base/demand.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::analysis {

AthleteProfile AthleteProfileFromYaml(const YamlNode& root, const std::filesystem::path& base_dir) {
  AthleteProfile profile;
  profile.source = root.file();
  if (!root.IsMap()) root.Fail("an athlete profile is a map of 'key: value' lines");
  root.RequireKnownKeys(
      {"name", "sex", "height_m", "mass_kg", "yeadon", "segment_lengths_m", "segment_masses_kg"});

  // Identity, sex, height and mass (all required).
  profile.name = root.At("name").AsString();
  const YamlNode& sex = root.At("sex");
  const std::string sex_text = sex.AsString();
  if (sex_text == "f" || sex_text == "female") {
    profile.sex = Sex::kFemale;
  } else if (sex_text == "m" || sex_text == "male") {
    profile.sex = Sex::kMale;
  } else {
    sex.Fail("'" + sex_text + "' is not f or m");
  }
  const YamlNode& height = root.At("height_m");
  profile.height_m = height.AsDouble();
  if (!(profile.height_m > 0.5 && profile.height_m < 2.8))
    height.Fail("'" + height.text() + "' is not a height in metres (0.5–2.8)");
  const YamlNode& mass = root.At("mass_kg");
  profile.mass_kg = mass.AsDouble();
  if (!(profile.mass_kg > 10.0 && profile.mass_kg < 300.0))
    mass.Fail("'" + mass.text() + "' is not a body mass in kg (10–300)");

  // Optional Yeadon measurements: a path to a yeadon measurement file, or the map inline.
  if (const YamlNode* yeadon = root.Find("yeadon"); yeadon != nullptr) {
    yeadon->RequireKnownKeys({"measurements", "density", "symmetric"});
    if (!yeadon->IsMap()) yeadon->Fail("expected 'measurements:' and optionally 'density:'");
    const YamlNode& meas = yeadon->At("measurements");
    if (meas.IsScalar()) {
      std::filesystem::path path = meas.AsString();
      if (path.is_relative()) path = base_dir / path;
      if (!PathExists(path)) meas.Fail("no such file '" + path.string() + "'");
      profile.yeadon_measurements = ReadYeadonMeasurements(path);
    } else if (meas.IsMap()) {
      profile.yeadon_measurements = YeadonMeasurementsFromYaml(meas);
    } else {
      meas.Fail("expected a file path or a map of the 95 measurements");
    }
    if (const YamlNode* density = yeadon->Find("density"); density != nullptr) {
      if (!ParseDensitySet(density->AsString(), &profile.yeadon_options.density))
        density->Fail("'" + density->text() + "' is not dempster, chandler or clauser");
    }
    if (const YamlNode* symmetric = yeadon->Find("symmetric"); symmetric != nullptr)
      profile.yeadon_options.symmetric = symmetric->AsBool();
    // The measurements' own stature against the profile's: a file in centimetres read as metres
    // (measurementconversionfactor 1) would otherwise give a 175 m athlete (docs/limits.md).
    YeadonMeasurements m = *profile.yeadon_measurements;
    m.total_mass_kg = profile.mass_kg;
    const double h =
        MakeAthleteBodyFromYeadon(YeadonHuman::Make(m, profile.yeadon_options)).height_m;
    if (!(std::abs(h - profile.height_m) <= 0.15 * profile.height_m))
      meas.Fail(
          fmt::format("the measurements give an athlete of {:.3g} m, the profile's height_m "
                      "is {:.2f} m: check measurementconversionfactor (0.01 for "
                      "centimetres, 0.001 for millimetres)",
                      h,
                      profile.height_m));
  }

  // Optional measured segment lengths (de Leva route).
  if (const YamlNode* lengths = root.Find("segment_lengths_m"); lengths != nullptr) {
    if (!lengths->IsMap()) lengths->Fail("expected 'segment: length' lines");
    lengths->RequireKnownKeys(
        {"pelvis", "thorax", "head", "upper_arm", "forearm", "hand", "thigh", "shank", "foot"});
    for (const auto& [key, node] : lengths->entries()) {
      const double v = node.AsDouble();
      if (!(v > 0.0 && v < 1.5))
        node.Fail("'" + node.text() + "' is not a segment length in metres");
      profile.segment_lengths_m[key] = v;
    }
  }
  // Optional segment masses (either route).
  if (const YamlNode* masses = root.Find("segment_masses_kg"); masses != nullptr) {
    if (!masses->IsMap()) masses->Fail("expected 'segment: mass' lines");
    const std::vector<std::string_view> names(kStandardSegmentNames.begin(),
                                              kStandardSegmentNames.end());
    masses->RequireKnownKeys(names);
    for (const auto& [key, node] : masses->entries()) {
      const double v = node.AsDouble();
      if (!(v > 0.0 && v < 0.8 * profile.mass_kg))
        node.Fail("'" + node.text() + "' is not a segment mass in kg (0 < m < 0.8 × mass_kg)");
      profile.segment_masses_kg[key] = v;
    }
  }
  return profile;
}

AthleteProfile ReadAthleteProfile(const std::filesystem::path& path) {
  return AthleteProfileFromYaml(ReadYamlFile(path), path.parent_path());
}

AthleteBody MakeAthleteBody(const AthleteProfile& profile) {
  AthleteBody body;
  if (profile.yeadon_measurements) {
    YeadonMeasurements meas = *profile.yeadon_measurements;
    meas.total_mass_kg = profile.mass_kg;
    body = MakeAthleteBodyFromYeadon(YeadonHuman::Make(meas, profile.yeadon_options));
  } else {
    body =
        MakeDeLevaBody(profile.height_m, profile.mass_kg, profile.sex, profile.segment_lengths_m);
  }
  if (profile.segment_masses_kg.empty()) return body;
  // Replaced segment masses: same centre of mass, inertia in proportion; then the whole body.
  for (const auto& [name, mass_kg] : profile.segment_masses_kg) {
    const int s = body.Find(name);
    ACRO_DEMAND(s >= 0);
    InertialProperties& in = body.segments[static_cast<size_t>(s)].in_H;
    in.I_Cm_H *= mass_kg / in.mass_kg;
    in.mass_kg = mass_kg;
  }
  std::vector<InertialProperties> all;
  for (const BodySegment& s : body.segments) all.push_back(s.in_H);
  body.total = CombineInertia(all);
  return body;
}

}  // namespace acro::analysis
