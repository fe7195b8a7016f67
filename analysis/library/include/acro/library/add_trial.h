#pragma once

// Adding a trial to the library: `acrolab library add` and each job of `acrolab batch`. The trial
// is known by its absolute path and its content's SHA-256: an unchanged file already analysed by
// this Acrolab is a no-op; a changed file, or one analysed by another Acrolab, is analysed again
// (`acrolab analyze`'s analysis, the same function) and its stored jumps replaced, in one
// transaction. An existing analysis directory (`acrolab analyze -o DIR`, made on another machine
// say) can be stored instead of analysing: its analysis.json names the trial's hash, which must be
// the file's.

#include <filesystem>
#include <functional>
#include <string>

#include "acro/assess/trial_analysis.h"
#include "acro/library/library.h"

namespace acro::library {

struct AddRequest {
  std::filesystem::path trial;
  std::filesystem::path athlete_profile;  ///< the athlete's YAML profile (required)
  /// YYYY-MM-DD; empty: the trial file's modification date (local time).
  std::string session_date;
  std::string session_place;
  std::string session_notes;
  std::filesystem::path video;
  std::filesystem::path calibration;
  /// An analysis directory of this trial to store instead of analysing (empty: analyse).
  std::filesystem::path analysis_dir;
  /// Analyse and store even when the library holds this content from this Acrolab.
  bool force = false;
};

enum class AddOutcome {
  kAdded,       ///< new in the library
  kReanalysed,  ///< stored before with another content or another Acrolab; replaced
  kUnchanged,   ///< stored with this content by this Acrolab: nothing done
};

struct AddResult {
  AddOutcome outcome = AddOutcome::kAdded;
  std::string path;  ///< the trial's absolute path, as the library names it
  std::string sha256;
  std::string why;  ///< for kReanalysed: what changed
  std::int64_t trial_id = 0;
  std::string verdict;
  int num_jumps = 0;
};

struct AddOptions {
  /// The analysis (its reconstruction options, the bed…): as `acrolab analyze` without a video.
  analysis::TrialAnalysisOptions analysis;
  /// Import warnings and other remarks, one line each.
  std::function<void(const std::string&)> warn;
};

/// What the library would do with `request.trial` now, without doing it: kUnchanged, kAdded or
/// kReanalysed (with `why`). Throws acro::InputError when the file cannot be read.
AddResult PlanAdd(const Library& library, const AddRequest& request);

/// Adds (or re-analyses) one trial. Throws acro::InputError for a trial, profile or analysis
/// directory at fault; the library is then unchanged.
AddResult AddTrial(Library& library, const AddRequest& request, const AddOptions& options = {});

/// A file's modification date as YYYY-MM-DD in local time.
std::string FileDate(const std::filesystem::path& path);

}  // namespace acro::library
