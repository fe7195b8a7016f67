#pragma once

// The season library as text (docs/library.md): what `acrolab library list`, `show`, `query` and
// `export` print or write — tables for a terminal, JSON for programs — made from the library's
// records. The command prints it; nothing here opens a terminal or decides what to show.

#include <string>
#include <vector>

#include "acro/library/library.h"

namespace acro::ui {

/// `list --athletes`: one row per athlete (stature, mass, profiles, sessions, trials, jumps).
std::string FormatAthleteTable(const std::vector<library::AthleteSummary>& athletes);

/// `list --designs`: one row per stored design, and the count in `library_path`.
std::string FormatDesignTable(const std::vector<library::DesignSummary>& designs, const std::string& library_path);

/// `list`: one row per trial (id, date, athlete, jumps, DD, time of flight, verdict, path), and
/// the count in `library_path`.
std::string FormatTrialTable(const std::vector<library::TrialSummary>& trials, const std::string& library_path);

/// `list --json`: the same trials as a JSON array (id, athlete, date, path, sha256, verdict, jumps,
/// difficulty, time_of_flight_s, analysis_version).
std::string FormatTrialListJson(const std::vector<library::TrialSummary>& trials);

/// `show`: the trial (file, athlete, session, hash, video, analysis) and its jumps, from its stored
/// jumps.json.
std::string FormatTrialDetails(const library::TrialSummary& trial, const std::string& jumps_json);

/// `query`: one row per jump found, and how many in how long.
std::string FormatJumpRowTable(const std::vector<library::JumpRow>& rows, double query_ms);

/// `export X.json`: every trial of `lib` with its analysis and its jumps.json, under the library's
/// path and schema version.
std::string FormatLibraryExportJson(const library::Library& lib, const std::string& library_path);

}  // namespace acro::ui
