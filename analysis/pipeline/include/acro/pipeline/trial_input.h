#pragma once

/// \file
/// The input every door starts from (docs/design.md, "One pipeline"): a trial read once — its bytes
/// hashed and parsed, so that the provenance is of the bytes analysed —, turned Z up, with the
/// athlete it is analysed for: a profile, or the one default body every door uses. `analyze`,
/// `overlay`, `compare`, `library add`, the studio and the video doors of milestone 3 call
/// OpenTrial and nothing else to get here.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/capture/trial.h"
#include "acro/reconstruct/up_axis.h"

namespace acro::pipeline {

/// The body used when no athlete profile is given — the same in every door: de Leva's (1996) body
/// of a 1.75 m, 65 kg woman (a trampolinist of the senior women's field; segment masses and
/// inertias are then generic, and the doors say so).
inline constexpr double kDefaultHeightM = 1.75;
inline constexpr double kDefaultMassKg = 65.0;
inline constexpr analysis::Sex kDefaultSex = analysis::Sex::kFemale;

/// Who the trial is analysed for: a profile (docs/formats/athlete.md), or de Leva's body of the
/// numbers given (the defaults above when none are).
struct AthleteChoice {
  std::filesystem::path profile;
  double height_m = kDefaultHeightM;
  double mass_kg = kDefaultMassKg;
  analysis::Sex sex = kDefaultSex;

  bool IsValid(std::string* why) const;
};

/// The athlete's body and how to name it.
struct Athlete {
  analysis::AthleteBody body;
  std::optional<analysis::AthleteProfile> profile;  ///< when a profile was read
  /// "Name, model" from a profile; "default de Leva athlete (no athlete file)" otherwise.
  std::string name;
  /// A line for the user when the default body is used (empty with a profile).
  std::string warning;
};

/// Reads the profile, or makes the default body. Throws acro::InputError for a bad profile.
Athlete MakeAthlete(const AthleteChoice& choice);

struct TrialRequest {
  std::filesystem::path trial;
  /// A static trial recorded in the same lab (optional): turned up as the trial is.
  std::filesystem::path static_trial;
  /// The file's up axis: "auto" (found from the head and the feet), or "x", "-y", … (up_axis.h).
  std::string up = "auto";
  AthleteChoice athlete;
  /// What the door needs of the trial, checked once when it is opened
  /// (capture::DemandUsableContent): at least this many frames holding a marker position, and a
  /// marker with one. Two for what measures motion (a velocity needs two); `reconstruct` takes one.
  int min_frames = 2;
  std::string use = "the analysis";
};

struct TrialInput {
  std::filesystem::path path;  ///< as given
  capture::Trial trial;        ///< Z up
  std::optional<capture::Trial> static_trial;
  /// SHA-256 of the bytes parsed (read once: a file changed afterwards does not change it); for
  /// an input made from videos or detections, of `inputs`' hashes.
  std::string sha256;
  /// An input made from other files (videos, detections, a calibration): each file read, its
  /// role ("video", "video side", "detections", "calibration", "intrinsics") and its SHA-256 —
  /// what analysis.json lists, so that `library add FILE --analysis DIR` knows the analysis is
  /// of FILE. Empty for a trial read from its own file.
  struct HashedFile {
    std::string role;
    std::filesystem::path path;
    std::string sha256;
  };
  std::vector<HashedFile> inputs;
  std::int64_t size_bytes = 0;
  analysis::UpAxis up;  ///< what OrientTrialUp found
  Athlete athlete;
  /// What the user should know, one line each: the import's warnings, the turn (the default
  /// body's line is athlete.warning, for the doors that use the body).
  std::vector<std::string> warnings;
};

/// Reads the trial's bytes once, hashes them, parses them by the file's extension (.c3d, .trc,
/// .csv), checks its usable content (request.min_frames), turns the trial (and the static trial) Z
/// up as `request.up` says, and makes the athlete. Throws acro::InputError naming the file for what
/// cannot be read or used, with the counts.
TrialInput OpenTrial(const TrialRequest& request);

}  // namespace acro::pipeline
