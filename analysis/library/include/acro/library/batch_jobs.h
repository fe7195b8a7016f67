#pragma once

/// \file
/// `acrolab batch`'s jobs (docs/library.md): a folder's trials, or a job list — one trial per line
/// with its own `library add` options, quoted as a shell would (a subset: blanks, '…', "…", \) —,
/// each made a `library add` request with the batch's defaults.

#include <filesystem>
#include <string>
#include <vector>

#include "acro/library/add_trial.h"

namespace acro::library {

/// One job: a trial and the `library add` options of its line.
struct BatchJob {
  int number = 0;                  ///< 1-based, in the list's order
  std::string where;               ///< "LIST: line N" (or the trial's path) for messages
  std::vector<std::string> words;  ///< TRIAL then options (paths made absolute)
  AddRequest request;
};

/// What the batch gives every job that does not say otherwise: the athlete profile and session
/// date, and the folder of earlier analyses (`--analyses`: job-N/ per job).
struct BatchDefaults {
  std::string athlete, session, analyses;
};

/// The jobs of `source`: every C3D and TRC under a folder, in name order, or the lines of a job
/// list (relative paths are relative to the list's folder; an option other than --athlete,
/// --session, --place, --notes, --video, --calib, or one without its value, is an error naming
/// the line). Throws acro::InputError naming the list and line, or a job with no athlete.
std::vector<BatchJob> ReadBatchJobs(const std::filesystem::path& source, const BatchDefaults& defaults);

/// A line's words: blanks separate, '…' and "…" quote, \ escapes, # starts a comment. Throws
/// acro::InputError naming `where` for a quote left open.
std::vector<std::string> SplitJobWords(const std::string& line, const std::string& where);

/// `word` as a shell reads it back (quoted only when it needs to be).
std::string ShellQuote(const std::string& word);

/// The value after `option` in a job's words (after the trial), or empty.
std::string OptionValue(const std::vector<std::string>& words, const std::string& option);

}  // namespace acro::library
