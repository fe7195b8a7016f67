#include "acro/pipeline/trial_input.h"

#include <cmath>

#include <fmt/format.h>

#include "acro/athlete/de_leva.h"
#include "acro/base/content_hash.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"

namespace acro::pipeline {

bool AthleteChoice::IsValid(std::string* why) const {
  if (!profile.empty()) return true;
  if (!(height_m >= 0.5 && height_m <= 2.5)) {
    if (why) *why = fmt::format("height {} m: expected 0.5–2.5 m", height_m);
    return false;
  }
  if (!(mass_kg >= 10 && mass_kg <= 250)) {
    if (why) *why = fmt::format("mass {} kg: expected 10–250 kg", mass_kg);
    return false;
  }
  return true;
}

Athlete MakeAthlete(const AthleteChoice& choice) {
  DemandValidOptions(choice, "athlete");
  Athlete out;
  if (!choice.profile.empty()) {
    out.profile = analysis::ReadAthleteProfile(choice.profile);
    out.body = analysis::MakeAthleteBody(*out.profile);
    out.name = out.profile->name + ", " + out.body.model;
    return out;
  }
  out.body = analysis::MakeDeLevaBody(choice.height_m, choice.mass_kg, choice.sex);
  out.name = "default de Leva athlete (no athlete file)";
  out.warning = fmt::format(
      "no --athlete file; using a de Leva athlete of {:.2f} m, {:.1f} kg, sex {} (segment masses "
      "and "
      "inertias will be generic)",
      choice.height_m,
      choice.mass_kg,
      choice.sex == analysis::Sex::kFemale ? "f" : "m");
  return out;
}

TrialInput OpenTrial(const TrialRequest& request) {
  TrialInput in;
  in.path = request.trial;
  // The bytes once: what is hashed is what is parsed.
  const std::vector<std::uint8_t> bytes = ReadFileBytes(request.trial);
  in.size_bytes = static_cast<std::int64_t>(bytes.size());
  in.sha256 =
      Sha256Hex(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  in.trial = capture::ReadTrialFromBytes(bytes, request.trial);
  for (const std::string& w : in.trial.warnings) in.warnings.push_back(w);
  capture::DemandUsableContent(in.trial, request.trial.string(), request.min_frames, request.use);
  const std::string turned = analysis::OrientTrialUp(&in.trial, request.up, &in.up);
  if (!turned.empty()) in.warnings.push_back(turned);
  if (!request.static_trial.empty()) {
    in.static_trial = capture::ReadTrial(request.static_trial);
    capture::DemandUsableContent(
        *in.static_trial, request.static_trial.string(), 1, "a static trial");
    // Recorded in the same lab: the trial's up, forced.
    if (in.up.found)
      analysis::OrientTrialUp(&*in.static_trial,
                              (in.up.sign > 0 ? "" : "-") + std::string(1, char('x' + in.up.axis)));
  }
  in.athlete = MakeAthlete(request.athlete);
  return in;
}

}  // namespace acro::pipeline
