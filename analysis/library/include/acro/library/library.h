#pragma once

// The season library: one SQLite file holding athletes (with the history of their profiles),
// training sessions, trials (the source files by path and content hash — never copied, never
// modified — with their videos and calibrations, and which Acrolab analysed them), every jump of
// every trial (the fields of jumps.json, the verdict and its cause), and designed skills and
// routines. docs/library.md has the schema, the migrations and how several processes share one
// file.
//
// Concurrency: the file is in WAL mode, so one writer and any number of readers (a batch storing
// trials while the studio or `library query` reads) work at the same time; writers take turns (a
// write waits up to `busy_timeout_ms` for another's transaction). Every store is one transaction:
// a process killed in the middle leaves the library as it was before it.
//
// SQLite stays private to this target's sources: no SQLite type appears here.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace acro::library {

/// The schema this Acrolab writes. A library file of an older schema is migrated when it is
/// opened for writing (each step in one transaction); a newer one is refused.
inline constexpr int kSchemaVersion = 3;

/// ~/.local/share/acrolab/library.sqlite ($XDG_DATA_HOME/acrolab/library.sqlite when set).
std::filesystem::path DefaultLibraryPath();

/// True for a session date as the library stores it: YYYY-MM-DD, month 1–12, day 1–31.
bool IsSessionDate(const std::string& text);

/// One jump of a stored trial: the columns the library filters on, taken from jumps.json.
struct JumpRecord {
  int index = 0;  ///< 1-based, as in jumps.json
  bool partial = false;
  std::string fig_code;
  std::string skill_name;
  double takeoff_s = 0.0;
  double time_of_flight_s = 0.0;
  /// Horizontal displacement of the feet from take-off to landing (m).
  double displacement_m = 0.0;
  double apex_above_bed_m = 0.0;
  double difficulty = 0.0;
  /// The physical check's verdict as jumps.json words it ("pass", "pass within its noise",
  /// "fail: …", "not judged…"), its class ("pass", "fail" or "not judged") and, for a failure,
  /// its cause (the text after "fail: ").
  std::string verdict;
  std::string verdict_class;
  std::string cause;
  /// Landing point on the bed (m, the bed's frame: x along its length), and whether it lies in the
  /// FIG zone A; absent when the trial has no bed.
  std::optional<double> landing_x_m;
  std::optional<double> landing_y_m;
  std::optional<bool> landing_in_zone_a;
  /// On the score sheet (jumps.json's `score`, when it has one): the element's number in the
  /// routine (0: not an element — an in-bounce, or after the routine ended), its landing's HD
  /// deduction when the bed is known, and the execution faults reported on it (the rule keys).
  int element = 0;
  std::optional<double> hd_deduction;
  std::vector<std::string> faults;
};

/// The jumps of a jumps.json (as `acrolab analyze` writes it). Throws acro::InputError naming
/// `source` and the field at fault.
std::vector<JumpRecord> ParseJumpsJson(const std::string& json, const std::string& source);

/// The verdict of a whole trial from its jumps' verdicts: "fail" when any jump fails, "pass" when
/// every judged jump passes, "not judged" when none was judged.
std::string TrialVerdict(const std::vector<JumpRecord>& jumps);

/// What one store writes: the trial, its athlete and session, and its analysis.
struct TrialToStore {
  std::string athlete;               ///< the profile's name
  std::string athlete_profile;       ///< the profile file's text (kept once per distinct content)
  std::string athlete_profile_path;  ///< absolute (for opening the trial again), may be empty
  double stature_m = 0.0;
  double mass_kg = 0.0;
  std::string session_date;  ///< YYYY-MM-DD
  std::string session_place;
  std::string session_notes;
  std::string path;  ///< absolute, as the library names the trial
  std::string sha256;
  std::int64_t size_bytes = 0;
  std::string video_path;  ///< attached files (absolute), empty when none
  std::string calibration_path;
  std::string analysis_version;  ///< the Acrolab that made the analysis
  std::string analysis_source;   ///< "analysed" or the imported analysis directory
  std::string jumps_json;
};

/// A stored trial as `list` and `show` give it.
struct TrialSummary {
  std::int64_t id = 0;
  std::string athlete;
  std::string session_date;
  std::string session_place;
  std::string path;
  std::string sha256;
  std::int64_t size_bytes = 0;
  std::string video_path;
  std::string calibration_path;
  std::string athlete_profile_path;  ///< the profile the trial was stored with
  std::string analysis_version;
  std::string analysis_source;
  std::string analysed_at;  ///< UTC, ISO 8601
  std::string verdict;
  int num_jumps = 0;
  double difficulty = 0.0;  ///< sum over the complete jumps
  double time_of_flight_s = 0.0;
};

/// What `query` selects; every filter is optional. Dates are YYYY-MM-DD, inclusive.
struct JumpQuery {
  std::string athlete;
  std::string fig_code;
  std::string date_from;
  std::string date_to;
  std::string verdict_class;  ///< "pass", "fail", "not judged"
  std::optional<double> min_time_of_flight_s, max_time_of_flight_s;
  std::optional<double> min_displacement_m, max_displacement_m;
  bool include_partial = false;
  /// Checks the fields (dates, verdict class, ordered ranges); false with the first fault in `why`.
  bool IsValid(std::string* why) const;
};

/// One row of a query: the jump with its trial, session and athlete.
struct JumpRow {
  std::string athlete;
  std::string session_date;
  std::int64_t trial_id = 0;
  std::string trial_path;
  JumpRecord jump;
};

/// An athlete as `list --athletes` gives it, with the latest profile's numbers.
struct AthleteSummary {
  std::string name;
  double stature_m = 0.0;
  double mass_kg = 0.0;
  int num_profiles = 0;
  int num_sessions = 0;
  int num_trials = 0;
  int num_jumps = 0;
};

/// A designed skill or routine as `list --designs` gives it.
struct DesignSummary {
  std::int64_t id = 0;
  std::string athlete;
  std::string kind;  ///< "skill" or "routine"
  std::string name;
  std::string codes;  ///< the FIG code(s), space-separated
  double difficulty = 0.0;
  std::string created_at;
};

/// How the library stands with one source file: absent, stored and current, or stored by an older
/// content or another Acrolab.
struct StoredState {
  bool stored = false;
  std::string sha256;
  std::string analysis_version;
  std::string analysis_source;
};

/// The library file, open. Not copyable; one per thread.
class Library {
 public:
  enum class Mode { kReadOnly, kReadWrite };

  /// Opens `path`. kReadWrite creates the file (and its directory) when it does not exist and
  /// migrates an older schema; kReadOnly never writes. Throws acro::InputError naming the file
  /// when it is not an SQLite database, not an Acrolab library, of a newer schema, or unreadable —
  /// and leaves such a file untouched.
  ///
  /// Another process's write lock is waited for (docs/library.md, "Locks"): `busy_timeout_ms`, or
  /// when it is negative ACROLAB_LIBRARY_WAIT_S seconds from the environment, else 30 s. The
  /// wait is said at once through the lock notice (SetLockNotice), and a lock still held after it
  /// is acro::InputError "is locked by another process … still after N s".
  Library(const std::filesystem::path& path, Mode mode, int busy_timeout_ms = -1);
  /// Where the line "FILE: locked by another process; waiting up to N s" goes, for every library
  /// this process opens (the command line: stderr). None by default.
  static void SetLockNotice(std::function<void(const std::string&)> notice);
  ~Library();
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;

  const std::filesystem::path& path() const;
  /// The schema the file had when it was opened (0 for a new file), and now.
  int schema_version_found() const;
  int schema_version() const;

  /// Stores (or replaces, by path) one trial with its jumps, in one transaction; returns its id.
  std::int64_t StoreTrial(const TrialToStore& trial);
  /// Removes the trial stored under `path` (its jumps with it); false when there is none.
  bool RemoveTrial(const std::string& path);

  StoredState FindTrial(const std::string& path) const;
  /// Trials, newest session first; `athlete` empty for all.
  std::vector<TrialSummary> ListTrials(const std::string& athlete = {}) const;
  /// One trial by id or by path; empty when there is none.
  std::optional<TrialSummary> FindTrialSummary(const std::string& id_or_path) const;
  /// The stored jumps.json of a trial.
  std::string TrialJumpsJson(std::int64_t trial_id) const;
  std::vector<AthleteSummary> ListAthletes() const;
  /// The jumps that match, by session date then trial then jump. Throws acro::InputError when the
  /// query is not valid.
  std::vector<JumpRow> QueryJumps(const JumpQuery& query) const;

  /// A designed skill or routine (kind "skill" or "routine"), stored by athlete and name (replaced
  /// when the name exists). Returns its id.
  std::int64_t StoreDesign(const std::string& athlete,
                           const std::string& kind,
                           const std::string& name,
                           const std::string& codes,
                           double difficulty,
                           const std::string& content);

  /// The stored designs, `athlete` empty for all; by athlete, then newest first.
  std::vector<DesignSummary> ListDesigns(const std::string& athlete = {}) const;
  /// A stored design's content (JSON), empty when there is none.
  std::string DesignContent(std::int64_t id) const;

  /// For the tests of migrations: a new library file made with the schema of version `version`
  /// (1 … kSchemaVersion) and nothing migrated.
  static void CreateWithSchemaVersion(const std::filesystem::path& path, int version);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// The rows as CSV (a header line, then one line per jump) and as a JSON array.
std::string FormatJumpRowsCsv(const std::vector<JumpRow>& rows);
std::string FormatJumpRowsJson(const std::vector<JumpRow>& rows);

}  // namespace acro::library
