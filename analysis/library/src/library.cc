#include "acro/library/library.h"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <system_error>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "json_text.h"

namespace acro::library {

namespace {

// The lock notice and the wait, process-wide (Library::SetLockNotice).
std::function<void(const std::string&)>& LockNotice() {
  static std::function<void(const std::string&)> notice;
  return notice;
}

struct BusyWait {
  std::string file;
  int timeout_ms = 30000;
};

// SQLite's busy handler: the first call says that it waits and for how long; then 50 ms steps
// until the wait is over (returning 0 makes the statement fail with SQLITE_BUSY).
int WaitWhileLocked(void* data, int count) {
  const BusyWait* wait = static_cast<const BusyWait*>(data);
  if (count == 0 && LockNotice())
    LockNotice()(
        fmt::format("{}: locked by another process (a batch, a window or another add "
                    "writing to it); waiting up to {:g} s",
                    wait->file,
                    wait->timeout_ms / 1000.0));
  if (count * 50 >= wait->timeout_ms) return 0;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return 1;
}

int WaitFromEnvironment() {
  const char* text = std::getenv("ACROLAB_LIBRARY_WAIT_S");
  if (text == nullptr) return 30000;
  char* end = nullptr;
  const double s = std::strtod(text, &end);
  if (end == text || !(s >= 0 && s <= 3600)) return 30000;
  return static_cast<int>(s * 1000);
}

// The wait of the library last opened on this thread (a Statement's failure names it).
thread_local int last_wait_ms = 30000;

// SQLite's message, or what a lock still held after the wait means.
std::string SqliteMessage(sqlite3* db, const char* error, int timeout_ms = last_wait_ms) {
  if ((sqlite3_extended_errcode(db) & 0xff) == SQLITE_BUSY)
    return fmt::format(
        "is locked by another process, still after {:g} s (ACROLAB_LIBRARY_WAIT_S "
        "sets the wait)",
        timeout_ms / 1000.0);
  return error ? error : sqlite3_errmsg(db);
}

using Json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// The schema, as the steps that made it: step k takes a library of version k − 1 to version k.
// Never edit a step that has shipped; add one (docs/library.md, "Schema").

// Version 1: athletes and their profiles, sessions, trials, jumps.
constexpr const char* kSchemaStep1 = R"sql(
CREATE TABLE acrolab_library(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE athletes(
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL UNIQUE);
CREATE TABLE athlete_profiles(
  id INTEGER PRIMARY KEY,
  athlete_id INTEGER NOT NULL REFERENCES athletes(id) ON DELETE CASCADE,
  first_seen TEXT NOT NULL,
  sha256 TEXT NOT NULL,
  stature_m REAL NOT NULL,
  mass_kg REAL NOT NULL,
  profile TEXT NOT NULL,
  UNIQUE(athlete_id, sha256));
CREATE TABLE sessions(
  id INTEGER PRIMARY KEY,
  athlete_id INTEGER NOT NULL REFERENCES athletes(id) ON DELETE CASCADE,
  date TEXT NOT NULL,
  place TEXT NOT NULL DEFAULT '',
  notes TEXT NOT NULL DEFAULT '',
  UNIQUE(athlete_id, date));
CREATE TABLE trials(
  id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  profile_id INTEGER NOT NULL REFERENCES athlete_profiles(id),
  path TEXT NOT NULL UNIQUE,
  sha256 TEXT NOT NULL,
  size_bytes INTEGER NOT NULL,
  video_path TEXT NOT NULL DEFAULT '',
  calibration_path TEXT NOT NULL DEFAULT '',
  analysis_version TEXT NOT NULL,
  analysis_source TEXT NOT NULL,
  analysed_at TEXT NOT NULL,
  verdict TEXT NOT NULL,
  jumps_json TEXT NOT NULL);
CREATE INDEX trials_session ON trials(session_id);
CREATE TABLE jumps(
  id INTEGER PRIMARY KEY,
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  jump_index INTEGER NOT NULL,
  partial INTEGER NOT NULL,
  fig_code TEXT NOT NULL,
  skill_name TEXT NOT NULL,
  time_of_flight_s REAL NOT NULL,
  displacement_m REAL NOT NULL,
  apex_above_bed_m REAL NOT NULL,
  difficulty REAL NOT NULL,
  verdict TEXT NOT NULL,
  verdict_class TEXT NOT NULL,
  UNIQUE(trial_id, jump_index));
)sql";

// Version 2: each jump's failure cause, take-off time and landing on the bed (for the season's
// landing charts), the athlete profile's path of each trial (the studio opens a stored trial with
// it), designed skills and routines, and the indices of `query`. The new jump columns
// are filled from each trial's stored jumps.json.
constexpr const char* kSchemaStep2 = R"sql(
ALTER TABLE jumps ADD COLUMN cause TEXT NOT NULL DEFAULT '';
ALTER TABLE jumps ADD COLUMN takeoff_s REAL NOT NULL DEFAULT 0;
ALTER TABLE jumps ADD COLUMN landing_x_m REAL;
ALTER TABLE jumps ADD COLUMN landing_y_m REAL;
ALTER TABLE jumps ADD COLUMN landing_in_zone_a INTEGER;
ALTER TABLE trials ADD COLUMN athlete_profile_path TEXT NOT NULL DEFAULT '';
CREATE TABLE designs(
  id INTEGER PRIMARY KEY,
  athlete_id INTEGER NOT NULL REFERENCES athletes(id) ON DELETE CASCADE,
  kind TEXT NOT NULL CHECK(kind IN ('skill', 'routine')),
  name TEXT NOT NULL,
  codes TEXT NOT NULL,
  difficulty REAL NOT NULL,
  content TEXT NOT NULL,
  created_at TEXT NOT NULL,
  UNIQUE(athlete_id, kind, name));
CREATE INDEX jumps_code ON jumps(fig_code, trial_id);
CREATE INDEX jumps_trial ON jumps(trial_id);
CREATE INDEX sessions_date ON sessions(date, athlete_id);
)sql";

// Version 3: each jump's place on the score sheet (element number, HD deduction, reported execution
// faults, space-separated), filled from each trial's stored jumps.json.
constexpr const char* kSchemaStep3 = R"sql(
ALTER TABLE jumps ADD COLUMN element INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jumps ADD COLUMN hd_deduction REAL;
ALTER TABLE jumps ADD COLUMN faults TEXT NOT NULL DEFAULT '';
)sql";

std::string JoinFaults(const std::vector<std::string>& faults) {
  std::string out;
  for (const std::string& f : faults) out += (out.empty() ? "" : " ") + f;
  return out;
}

std::vector<std::string> SplitFaults(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find(' ', start), text.size());
    if (end > start) out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

bool IsDate(const std::string& s) {
  if (s.size() != 10 || s[4] != '-' || s[7] != '-') return false;
  for (int i : {0, 1, 2, 3, 5, 6, 8, 9})
    if (s[size_t(i)] < '0' || s[size_t(i)] > '9') return false;
  const int month = std::stoi(s.substr(5, 2)), day = std::stoi(s.substr(8, 2));
  return month >= 1 && month <= 12 && day >= 1 && day <= 31;
}

// One prepared statement, finalised on scope exit; Bind* by 1-based index.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const std::string& file) : db_(db), file_(file) {
    if (sqlite3_prepare_v2(db, sql.c_str(), int(sql.size()), &stmt_, nullptr) != SQLITE_OK)
      Fail("prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& Bind(int i, const std::string& v) {
    Check(sqlite3_bind_text(stmt_, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& Bind(int i, double v) {
    Check(sqlite3_bind_double(stmt_, i, v));
    return *this;
  }
  Statement& Bind(int i, std::int64_t v) {
    Check(sqlite3_bind_int64(stmt_, i, v));
    return *this;
  }
  Statement& Bind(int i, int v) { return Bind(i, std::int64_t(v)); }
  template <typename T>
  Statement& Bind(int i, const std::optional<T>& v) {
    if (v) return Bind(i, *v);
    Check(sqlite3_bind_null(stmt_, i));
    return *this;
  }
  Statement& Bind(int i, const std::optional<bool>& v) {
    if (v) return Bind(i, int(*v));
    Check(sqlite3_bind_null(stmt_, i));
    return *this;
  }
  /// True while there is a row.
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    Fail("step");
    return false;
  }
  void Run() {
    while (Step()) {
    }
  }
  void Reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  std::string Text(int c) const {
    const unsigned char* t = sqlite3_column_text(stmt_, c);
    return t ? std::string(reinterpret_cast<const char*>(t), size_t(sqlite3_column_bytes(stmt_, c)))
             : std::string();
  }
  double Double(int c) const { return sqlite3_column_double(stmt_, c); }
  std::int64_t Int(int c) const { return sqlite3_column_int64(stmt_, c); }
  bool IsNull(int c) const { return sqlite3_column_type(stmt_, c) == SQLITE_NULL; }
  std::optional<double> OptionalDouble(int c) const {
    return IsNull(c) ? std::nullopt : std::optional<double>(Double(c));
  }

 private:
  void Check(int rc) {
    if (rc != SQLITE_OK) Fail("bind");
  }
  [[noreturn]] void Fail(const char* what) {
    throw InputError(file_, what, SqliteMessage(db_, nullptr));
  }
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string file_;
};

}  // namespace

bool IsSessionDate(const std::string& text) {
  return IsDate(text);
}

void Library::SetLockNotice(std::function<void(const std::string&)> notice) {
  LockNotice() = std::move(notice);
}

struct Library::Impl {
  std::filesystem::path path;
  sqlite3* db = nullptr;
  Mode mode = Mode::kReadOnly;
  int found_version = 0;
  int version = 0;
  BusyWait wait;

  ~Impl() {
    if (db) sqlite3_close_v2(db);
  }

  std::string File() const { return path.string(); }

  void Exec(const std::string& sql, const char* what) {
    char* error = nullptr;
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
      const std::string message = SqliteMessage(db, error, wait.timeout_ms);
      sqlite3_free(error);
      throw InputError(File(), what, message);
    }
  }

  int UserVersion() {
    Statement s(db, "PRAGMA user_version", File());
    return s.Step() ? int(s.Int(0)) : 0;
  }

  // What an existing file is, before anything is written to it: a file that is not an SQLite
  // database, a damaged one, or another program's database is refused (and left as it is); a
  // schema newer than this Acrolab's too. Sets found_version.
  void CheckExisting() {
    const std::string file = File();
    // (reading the catalogue is the first read: a file that is not a database fails here)
    char* error = nullptr;
    struct Found {
      int tables = 0;
      bool ours = false;
    } found;
    const int rc = sqlite3_exec(
        db,
        "SELECT name FROM sqlite_master WHERE type = 'table'",
        [](void* out, int, char** values, char**) {
          auto* f = static_cast<Found*>(out);
          ++f->tables;
          if (values[0] && std::string(values[0]) == "acrolab_library") f->ours = true;
          return 0;
        },
        &found,
        &error);
    if (rc != SQLITE_OK) {
      const bool locked = (sqlite3_extended_errcode(db) & 0xff) == SQLITE_BUSY;
      const std::string message = SqliteMessage(db, error, wait.timeout_ms);
      sqlite3_free(error);
      if (locked) throw InputError(file, "", message);
      throw InputError(file, "", "not an Acrolab library: " + message + "; left as it is");
    }
    const int tables = found.tables;
    bool ours = found.ours;
    QuickCheck();
    // A database with nothing in it is what opening a new file makes: another process creating
    // the library, or one that stopped before its first step; made here (when writing).
    if (tables == 0 && mode == Mode::kReadWrite) {
      ours = true;
    } else if (!ours) {
      throw InputError(file,
                       "",
                       tables == 0 ? "an empty SQLite database, not an Acrolab library"
                                   : "an SQLite database but not an Acrolab library (no table "
                                     "acrolab_library)");
    }
    found_version = UserVersion();
    if (found_version > kSchemaVersion)
      throw InputError(file,
                       "schema",
                       fmt::format("version {} is newer than this Acrolab's {} (Acrolab {} or "
                                   "later wrote it)",
                                   found_version,
                                   kSchemaVersion,
                                   "a newer"));
    if (found_version < 1 && tables > 0)
      throw InputError(file, "schema", fmt::format("version {} is not valid", found_version));
  }

  // SQLite's own check of the file: a damaged library is refused, with its first problem.
  void QuickCheck() {
    Statement check(db, "PRAGMA quick_check", File());
    std::string problems;
    int count = 0;
    while (check.Step()) {
      const std::string line = check.Text(0);
      if (line == "ok") continue;
      if (count++ < 1) problems = line;
    }
    if (count > 0)
      throw InputError(File(),
                       "",
                       fmt::format("damaged library ({} problem{}, first: {}); left as it is",
                                   count,
                                   count > 1 ? "s" : "",
                                   problems));
  }

  // Writing: a new file or an older schema brought to this Acrolab's (WAL first: it persists in
  // the file, then each step). Reading: an older schema is refused.
  void Migrate() {
    if (mode == Mode::kReadWrite) {
      if (version < kSchemaVersion) {
        Exec("PRAGMA journal_mode = WAL", "WAL mode");
        for (int v = version + 1; v <= kSchemaVersion; ++v) ApplyStep(v);
        version = kSchemaVersion;
      }
      Exec("PRAGMA synchronous = NORMAL", "synchronous");
    } else if (version < kSchemaVersion) {
      throw InputError(File(),
                       "schema",
                       fmt::format("version {} is older than this Acrolab's {}: open it for "
                                   "writing once (acrolab library add or migrate) to migrate it",
                                   version,
                                   kSchemaVersion));
    }
  }

  // Runs `work` in one write transaction (BEGIN IMMEDIATE: the write lock is taken first, so two
  // writers take turns instead of failing on upgrade), rolled back when it throws.
  void Write(const std::function<void()>& work) {
    if (mode != Mode::kReadWrite) throw InputError(File(), "", "opened read-only");
    Exec("BEGIN IMMEDIATE", "begin");
    try {
      work();
      Exec("COMMIT", "commit");
    } catch (...) {
      sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }

  void ApplyStep(int version_to);
  void FillJumpColumnsFromJson();
  void FillScoreColumnsFromJson();
  std::int64_t IdOf(const std::string& sql, const std::function<void(Statement&)>& bind);
};

void Library::Impl::ApplyStep(int version_to) {
  Write([&] {
    // Another process may have made this step while this one waited for the lock.
    if (UserVersion() >= version_to) return;
    if (version_to == 1) {
      Exec(kSchemaStep1, "create the schema");
      Statement marker(db,
                       "INSERT INTO acrolab_library(key, value) VALUES ('created_at', ?1), "
                       "('created_by', 'Acrolab')",
                       File());
      marker.Bind(1, UtcNow()).Run();
    } else if (version_to == 2) {
      Exec(kSchemaStep2, "migrate to schema 2");
      FillJumpColumnsFromJson();
    } else if (version_to == 3) {
      Exec(kSchemaStep3, "migrate to schema 3");
      FillScoreColumnsFromJson();
    }
    Exec(fmt::format("PRAGMA user_version = {}", version_to), "set the schema version");
  });
}

void Library::Impl::FillJumpColumnsFromJson() {
  Statement trials(db, "SELECT id, path, jumps_json FROM trials", File());
  Statement update(db,
                   "UPDATE jumps SET cause = ?3, takeoff_s = ?4, landing_x_m = ?5, landing_y_m = "
                   "?6, landing_in_zone_a = ?7 WHERE trial_id = ?1 AND jump_index = ?2",
                   File());
  while (trials.Step()) {
    for (const JumpRecord& j : ParseJumpsJson(trials.Text(2), trials.Text(1) + " (stored)")) {
      update.Bind(1, trials.Int(0))
          .Bind(2, j.index)
          .Bind(3, j.cause)
          .Bind(4, j.takeoff_s)
          .Bind(5, j.landing_x_m)
          .Bind(6, j.landing_y_m)
          .Bind(7, j.landing_in_zone_a)
          .Run();
      update.Reset();
    }
  }
}

void Library::Impl::FillScoreColumnsFromJson() {
  Statement trials(db, "SELECT id, path, jumps_json FROM trials", File());
  Statement update(db,
                   "UPDATE jumps SET element = ?3, hd_deduction = ?4, faults = ?5 WHERE trial_id = "
                   "?1 AND jump_index = ?2",
                   File());
  while (trials.Step()) {
    for (const JumpRecord& j : ParseJumpsJson(trials.Text(2), trials.Text(1) + " (stored)")) {
      update.Bind(1, trials.Int(0))
          .Bind(2, j.index)
          .Bind(3, j.element)
          .Bind(4, j.hd_deduction)
          .Bind(5, JoinFaults(j.faults))
          .Run();
      update.Reset();
    }
  }
}

std::int64_t Library::Impl::IdOf(const std::string& sql,
                                 const std::function<void(Statement&)>& bind) {
  Statement s(db, sql, File());
  bind(s);
  if (!s.Step()) throw InputError(File(), "lookup", "no row for " + sql);
  return s.Int(0);
}

std::filesystem::path DefaultLibraryPath() {
  const char* data = std::getenv("XDG_DATA_HOME");
  if (data && *data) return std::filesystem::path(data) / "acrolab" / "library.sqlite";
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home && *home ? home : ".") / ".local" / "share" / "acrolab" /
         "library.sqlite";
}

Library::Library(const std::filesystem::path& path, Mode mode, int busy_timeout_ms)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.mode = mode;
  const std::string file = path.string();
  std::error_code ec;
  const bool exists = std::filesystem::exists(path, ec);
  if (!exists && mode == Mode::kReadOnly)
    throw InputError(file, "", "no library here (acrolab library add creates one)");
  if (exists && !std::filesystem::is_regular_file(path, ec))
    throw InputError(file, "", "not a file");
  const bool empty = exists && std::filesystem::file_size(path, ec) == 0;
  if (!exists && !path.parent_path().empty()) {
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) throw InputError(file, "", "cannot create its directory: " + ec.message());
  }
  int flags = mode == Mode::kReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  if (!exists) flags |= SQLITE_OPEN_CREATE;
  flags |= SQLITE_OPEN_NOMUTEX;
  if (sqlite3_open_v2(file.c_str(), &m.db, flags, nullptr) != SQLITE_OK)
    throw InputError(file, "", std::string("cannot open: ") + sqlite3_errmsg(m.db));
  m.wait = {file, busy_timeout_ms >= 0 ? busy_timeout_ms : WaitFromEnvironment()};
  sqlite3_busy_handler(m.db, WaitWhileLocked, &m.wait);
  last_wait_ms = m.wait.timeout_ms;
  sqlite3_extended_result_codes(m.db, 1);

  // SQLite makes FILE-wal and FILE-shm beside a WAL library when it opens it; for a file it
  // refuses, those it made are removed again, so that the folder is left as it was.
  const std::filesystem::path wal = file + "-wal", shm = file + "-shm";
  const bool had_wal = std::filesystem::exists(wal, ec), had_shm = std::filesystem::exists(shm, ec);
  try {
    if (exists && !empty) m.CheckExisting();
  } catch (const InputError&) {
    sqlite3_close_v2(m.db);
    m.db = nullptr;
    if (!had_wal && std::filesystem::exists(wal, ec) && std::filesystem::file_size(wal, ec) == 0)
      std::filesystem::remove(wal, ec);
    if (!had_shm) std::filesystem::remove(shm, ec);
    throw;
  }
  m.Exec("PRAGMA foreign_keys = ON", "foreign keys");
  m.version = m.found_version;
  m.Migrate();
}

Library::~Library() = default;

const std::filesystem::path& Library::path() const {
  return impl_->path;
}
int Library::schema_version_found() const {
  return impl_->found_version;
}
int Library::schema_version() const {
  return impl_->version;
}

void Library::CreateWithSchemaVersion(const std::filesystem::path& path, int version) {
  if (version < 1 || version > kSchemaVersion)
    throw InputError(path.string(), "schema", fmt::format("no version {}", version));
  if (std::filesystem::exists(path)) throw InputError(path.string(), "", "exists already");
  Impl m;
  m.path = path;
  m.mode = Mode::kReadWrite;
  if (sqlite3_open_v2(
          path.string().c_str(), &m.db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK)
    throw InputError(path.string(), "", sqlite3_errmsg(m.db));
  m.Exec("PRAGMA journal_mode = WAL", "WAL mode");
  for (int v = 1; v <= version; ++v) m.ApplyStep(v);
}

std::int64_t Library::StoreTrial(const TrialToStore& t) {
  Impl& m = *impl_;
  const std::string file = m.File();
  if (!IsDate(t.session_date))
    throw InputError(file, "session date", "'" + t.session_date + "' is not YYYY-MM-DD");
  if (t.athlete.empty()) throw InputError(file, "athlete", "no name");
  const std::vector<JumpRecord> jumps = ParseJumpsJson(t.jumps_json, t.path + " (its jumps.json)");
  std::int64_t trial_id = 0;
  m.Write([&] {
    Statement(m.db, "INSERT OR IGNORE INTO athletes(name) VALUES (?1)", file)
        .Bind(1, t.athlete)
        .Run();
    const std::int64_t athlete_id = m.IdOf("SELECT id FROM athletes WHERE name = ?1",
                                           [&](Statement& s) { s.Bind(1, t.athlete); });
    const std::string profile_sha = Sha256Hex(t.athlete_profile);
    Statement(m.db,
              "INSERT OR IGNORE INTO athlete_profiles(athlete_id, first_seen, sha256, stature_m, "
              "mass_kg, profile) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
              file)
        .Bind(1, athlete_id)
        .Bind(2, t.session_date)
        .Bind(3, profile_sha)
        .Bind(4, t.stature_m)
        .Bind(5, t.mass_kg)
        .Bind(6, t.athlete_profile)
        .Run();
    // A profile seen first on a later session's trial but stored by an earlier session's: the
    // history keeps the earliest date it was used.
    Statement(m.db,
              "UPDATE athlete_profiles SET first_seen = min(first_seen, ?3) WHERE athlete_id = ?1 "
              "AND sha256 = ?2",
              file)
        .Bind(1, athlete_id)
        .Bind(2, profile_sha)
        .Bind(3, t.session_date)
        .Run();
    const std::int64_t profile_id =
        m.IdOf("SELECT id FROM athlete_profiles WHERE athlete_id = ?1 AND sha256 = ?2",
               [&](Statement& s) { s.Bind(1, athlete_id).Bind(2, profile_sha); });
    Statement(m.db, "INSERT OR IGNORE INTO sessions(athlete_id, date) VALUES (?1, ?2)", file)
        .Bind(1, athlete_id)
        .Bind(2, t.session_date)
        .Run();
    if (!t.session_place.empty() || !t.session_notes.empty())
      Statement(m.db,
                "UPDATE sessions SET place = CASE WHEN ?3 = '' THEN place ELSE ?3 END, notes = "
                "CASE WHEN ?4 = '' THEN notes ELSE ?4 END WHERE athlete_id = ?1 AND date = ?2",
                file)
          .Bind(1, athlete_id)
          .Bind(2, t.session_date)
          .Bind(3, t.session_place)
          .Bind(4, t.session_notes)
          .Run();
    const std::int64_t session_id =
        m.IdOf("SELECT id FROM sessions WHERE athlete_id = ?1 AND date = ?2",
               [&](Statement& s) { s.Bind(1, athlete_id).Bind(2, t.session_date); });
    Statement(m.db, "DELETE FROM trials WHERE path = ?1", file).Bind(1, t.path).Run();
    Statement(m.db,
              "INSERT INTO trials(session_id, profile_id, path, sha256, size_bytes, video_path, "
              "calibration_path, analysis_version, analysis_source, analysed_at, verdict, "
              "jumps_json, athlete_profile_path) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, "
              "?11, ?12, ?13)",
              file)
        .Bind(1, session_id)
        .Bind(2, profile_id)
        .Bind(3, t.path)
        .Bind(4, t.sha256)
        .Bind(5, t.size_bytes)
        .Bind(6, t.video_path)
        .Bind(7, t.calibration_path)
        .Bind(8, t.analysis_version)
        .Bind(9, t.analysis_source)
        .Bind(10, UtcNow())
        .Bind(11, TrialVerdict(jumps))
        .Bind(12, t.jumps_json)
        .Bind(13, t.athlete_profile_path)
        .Run();
    trial_id = sqlite3_last_insert_rowid(m.db);
    Statement insert(m.db,
                     "INSERT INTO jumps(trial_id, jump_index, partial, fig_code, skill_name, "
                     "time_of_flight_s, displacement_m, apex_above_bed_m, difficulty, verdict, "
                     "verdict_class, cause, takeoff_s, landing_x_m, landing_y_m, "
                     "landing_in_zone_a, element, hd_deduction, faults) VALUES (?1, ?2, ?3, ?4, "
                     "?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19)",
                     file);
    for (const JumpRecord& j : jumps) {
      insert.Bind(1, trial_id)
          .Bind(2, j.index)
          .Bind(3, int(j.partial))
          .Bind(4, j.fig_code)
          .Bind(5, j.skill_name)
          .Bind(6, j.time_of_flight_s)
          .Bind(7, j.displacement_m)
          .Bind(8, j.apex_above_bed_m)
          .Bind(9, j.difficulty)
          .Bind(10, j.verdict)
          .Bind(11, j.verdict_class)
          .Bind(12, j.cause)
          .Bind(13, j.takeoff_s)
          .Bind(14, j.landing_x_m)
          .Bind(15, j.landing_y_m)
          .Bind(16, j.landing_in_zone_a)
          .Bind(17, j.element)
          .Bind(18, j.hd_deduction)
          .Bind(19, JoinFaults(j.faults))
          .Run();
      insert.Reset();
    }
  });
  return trial_id;
}

bool Library::RemoveTrial(const std::string& path) {
  Impl& m = *impl_;
  bool removed = false;
  m.Write([&] {
    Statement(m.db, "DELETE FROM trials WHERE path = ?1", m.File()).Bind(1, path).Run();
    removed = sqlite3_changes(m.db) > 0;
  });
  return removed;
}

StoredState Library::FindTrial(const std::string& path) const {
  Statement s(impl_->db,
              "SELECT sha256, analysis_version, analysis_source FROM trials WHERE path = ?1",
              impl_->File());
  s.Bind(1, path);
  StoredState state;
  if (s.Step()) {
    state.stored = true;
    state.sha256 = s.Text(0);
    state.analysis_version = s.Text(1);
    state.analysis_source = s.Text(2);
  }
  return state;
}

namespace {

constexpr const char* kTrialSummarySelect =
    "SELECT t.id, a.name, s.date, s.place, t.path, t.sha256, t.size_bytes, t.video_path, "
    "t.calibration_path, t.analysis_version, t.analysis_source, t.analysed_at, t.verdict, "
    "(SELECT count(*) FROM jumps j WHERE j.trial_id = t.id), "
    "(SELECT coalesce(sum(j.difficulty), 0) FROM jumps j WHERE j.trial_id = t.id AND NOT "
    "j.partial), "
    "(SELECT coalesce(sum(j.time_of_flight_s), 0) FROM jumps j WHERE j.trial_id = t.id AND NOT "
    "j.partial), "
    "t.athlete_profile_path "
    "FROM trials t JOIN sessions s ON s.id = t.session_id JOIN athletes a ON a.id = s.athlete_id ";

TrialSummary ReadTrialSummary(const Statement& s) {
  TrialSummary t;
  t.id = s.Int(0);
  t.athlete = s.Text(1);
  t.session_date = s.Text(2);
  t.session_place = s.Text(3);
  t.path = s.Text(4);
  t.sha256 = s.Text(5);
  t.size_bytes = s.Int(6);
  t.video_path = s.Text(7);
  t.calibration_path = s.Text(8);
  t.analysis_version = s.Text(9);
  t.analysis_source = s.Text(10);
  t.analysed_at = s.Text(11);
  t.verdict = s.Text(12);
  t.num_jumps = int(s.Int(13));
  t.difficulty = s.Double(14);
  t.time_of_flight_s = s.Double(15);
  t.athlete_profile_path = s.Text(16);
  return t;
}

}  // namespace

std::vector<TrialSummary> Library::ListTrials(const std::string& athlete) const {
  Statement s(impl_->db,
              std::string(kTrialSummarySelect) +
                  "WHERE ?1 = '' OR a.name = ?1 ORDER BY s.date DESC, a.name, t.path",
              impl_->File());
  s.Bind(1, athlete);
  std::vector<TrialSummary> out;
  while (s.Step()) out.push_back(ReadTrialSummary(s));
  return out;
}

std::optional<TrialSummary> Library::FindTrialSummary(const std::string& id_or_path) const {
  const bool is_id = !id_or_path.empty() && id_or_path.size() < 18 &&
                     std::all_of(id_or_path.begin(), id_or_path.end(), [](char c) {
                       return c >= '0' && c <= '9';
                     });
  Statement s(impl_->db,
              std::string(kTrialSummarySelect) + (is_id ? "WHERE t.id = ?1" : "WHERE t.path = ?1"),
              impl_->File());
  if (is_id)
    s.Bind(1, std::int64_t(std::stoll(id_or_path)));
  else
    s.Bind(1, id_or_path);
  if (!s.Step()) return std::nullopt;
  return ReadTrialSummary(s);
}

std::string Library::TrialJumpsJson(std::int64_t trial_id) const {
  Statement s(impl_->db, "SELECT jumps_json FROM trials WHERE id = ?1", impl_->File());
  s.Bind(1, trial_id);
  return s.Step() ? s.Text(0) : std::string();
}

std::vector<AthleteSummary> Library::ListAthletes() const {
  Statement s(impl_->db,
              "SELECT a.name, "
              "(SELECT p.stature_m FROM athlete_profiles p WHERE p.athlete_id = a.id ORDER BY "
              "p.first_seen DESC, p.id DESC LIMIT 1), "
              "(SELECT p.mass_kg FROM athlete_profiles p WHERE p.athlete_id = a.id ORDER BY "
              "p.first_seen DESC, p.id DESC LIMIT 1), "
              "(SELECT count(*) FROM athlete_profiles p WHERE p.athlete_id = a.id), "
              "(SELECT count(*) FROM sessions s WHERE s.athlete_id = a.id), "
              "(SELECT count(*) FROM trials t JOIN sessions s ON s.id = t.session_id WHERE "
              "s.athlete_id = a.id), "
              "(SELECT count(*) FROM jumps j JOIN trials t ON t.id = j.trial_id JOIN sessions s "
              "ON s.id = t.session_id WHERE s.athlete_id = a.id) "
              "FROM athletes a ORDER BY a.name",
              impl_->File());
  std::vector<AthleteSummary> out;
  while (s.Step()) {
    AthleteSummary a;
    a.name = s.Text(0);
    a.stature_m = s.Double(1);
    a.mass_kg = s.Double(2);
    a.num_profiles = int(s.Int(3));
    a.num_sessions = int(s.Int(4));
    a.num_trials = int(s.Int(5));
    a.num_jumps = int(s.Int(6));
    out.push_back(a);
  }
  return out;
}

bool JumpQuery::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!date_from.empty() && !IsDate(date_from))
    return fail("--from: '" + date_from + "' is not YYYY-MM-DD");
  if (!date_to.empty() && !IsDate(date_to))
    return fail("--to: '" + date_to + "' is not YYYY-MM-DD");
  if (!date_from.empty() && !date_to.empty() && date_to < date_from)
    return fail("--to " + date_to + " is before --from " + date_from);
  if (!verdict_class.empty() && verdict_class != "pass" && verdict_class != "fail" &&
      verdict_class != "not judged")
    return fail("--verdict: '" + verdict_class + "' is not pass, fail or 'not judged'");
  auto ordered = [](const std::optional<double>& lo, const std::optional<double>& hi) {
    return !lo || !hi || *lo <= *hi;
  };
  for (const auto& v :
       {min_time_of_flight_s, max_time_of_flight_s, min_displacement_m, max_displacement_m})
    if (v && !std::isfinite(*v)) return fail("a range bound is not a finite number");
  if (!ordered(min_time_of_flight_s, max_time_of_flight_s))
    return fail("the time-of-flight range is empty (min > max)");
  if (!ordered(min_displacement_m, max_displacement_m))
    return fail("the displacement range is empty (min > max)");
  return true;
}

std::vector<JumpRow> Library::QueryJumps(const JumpQuery& q) const {
  DemandValidOptions(q, "query");
  std::string sql =
      "SELECT a.name, s.date, t.id, t.path, j.jump_index, j.partial, j.fig_code, j.skill_name, "
      "j.takeoff_s, j.time_of_flight_s, j.displacement_m, j.apex_above_bed_m, j.difficulty, "
      "j.verdict, j.verdict_class, j.cause, j.landing_x_m, j.landing_y_m, j.landing_in_zone_a, "
      "j.element, j.hd_deduction, j.faults FROM jumps j JOIN trials t ON t.id = j.trial_id JOIN "
      "sessions s ON s.id = t.session_id "
      "JOIN athletes a ON a.id = s.athlete_id WHERE 1";
  // Each filter present adds its condition and its parameter, in order.
  std::vector<std::function<void(Statement&, int)>> binds;
  auto add_text = [&](const std::string& value, const char* condition) {
    if (value.empty()) return;
    sql += fmt::format(" AND {} ?{}", condition, binds.size() + 1);
    binds.push_back([value](Statement& s, int i) { s.Bind(i, value); });
  };
  auto add_number = [&](const std::optional<double>& value, const char* condition) {
    if (!value) return;
    sql += fmt::format(" AND {} ?{}", condition, binds.size() + 1);
    binds.push_back([v = *value](Statement& s, int i) { s.Bind(i, v); });
  };
  add_text(q.athlete, "a.name =");
  add_text(q.fig_code, "j.fig_code =");
  add_text(q.date_from, "s.date >=");
  add_text(q.date_to, "s.date <=");
  add_text(q.verdict_class, "j.verdict_class =");
  add_number(q.min_time_of_flight_s, "j.time_of_flight_s >=");
  add_number(q.max_time_of_flight_s, "j.time_of_flight_s <=");
  add_number(q.min_displacement_m, "j.displacement_m >=");
  add_number(q.max_displacement_m, "j.displacement_m <=");
  if (!q.include_partial) sql += " AND NOT j.partial";
  sql += " ORDER BY s.date, a.name, t.path, j.jump_index";
  Statement s(impl_->db, sql, impl_->File());
  for (size_t i = 0; i < binds.size(); ++i) binds[i](s, int(i + 1));
  std::vector<JumpRow> rows;
  while (s.Step()) {
    JumpRow r;
    r.athlete = s.Text(0);
    r.session_date = s.Text(1);
    r.trial_id = s.Int(2);
    r.trial_path = s.Text(3);
    JumpRecord& j = r.jump;
    j.index = int(s.Int(4));
    j.partial = s.Int(5) != 0;
    j.fig_code = s.Text(6);
    j.skill_name = s.Text(7);
    j.takeoff_s = s.Double(8);
    j.time_of_flight_s = s.Double(9);
    j.displacement_m = s.Double(10);
    j.apex_above_bed_m = s.Double(11);
    j.difficulty = s.Double(12);
    j.verdict = s.Text(13);
    j.verdict_class = s.Text(14);
    j.cause = s.Text(15);
    j.landing_x_m = s.OptionalDouble(16);
    j.landing_y_m = s.OptionalDouble(17);
    if (!s.IsNull(18)) j.landing_in_zone_a = s.Int(18) != 0;
    j.element = int(s.Int(19));
    j.hd_deduction = s.OptionalDouble(20);
    j.faults = SplitFaults(s.Text(21));
    rows.push_back(std::move(r));
  }
  return rows;
}

std::int64_t Library::StoreDesign(const std::string& athlete,
                                  const std::string& kind,
                                  const std::string& name,
                                  const std::string& codes,
                                  double difficulty,
                                  const std::string& content) {
  Impl& m = *impl_;
  if (kind != "skill" && kind != "routine")
    throw InputError(m.File(), "design kind", "'" + kind + "' is not skill or routine");
  std::int64_t id = 0;
  m.Write([&] {
    Statement(m.db, "INSERT OR IGNORE INTO athletes(name) VALUES (?1)", m.File())
        .Bind(1, athlete)
        .Run();
    const std::int64_t athlete_id = m.IdOf("SELECT id FROM athletes WHERE name = ?1",
                                           [&](Statement& s) { s.Bind(1, athlete); });
    Statement(m.db,
              "INSERT OR REPLACE INTO designs(athlete_id, kind, name, codes, difficulty, content, "
              "created_at) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
              m.File())
        .Bind(1, athlete_id)
        .Bind(2, kind)
        .Bind(3, name)
        .Bind(4, codes)
        .Bind(5, difficulty)
        .Bind(6, content)
        .Bind(7, UtcNow())
        .Run();
    id = sqlite3_last_insert_rowid(m.db);
  });
  return id;
}

std::vector<DesignSummary> Library::ListDesigns(const std::string& athlete) const {
  Statement s(impl_->db,
              "SELECT d.id, a.name, d.kind, d.name, d.codes, d.difficulty, d.created_at FROM "
              "designs d JOIN athletes a ON a.id = d.athlete_id WHERE ?1 = '' OR a.name = ?1 "
              "ORDER BY a.name, d.created_at DESC, d.id DESC",
              impl_->File());
  s.Bind(1, athlete);
  std::vector<DesignSummary> out;
  while (s.Step()) {
    DesignSummary d;
    d.id = s.Int(0);
    d.athlete = s.Text(1);
    d.kind = s.Text(2);
    d.name = s.Text(3);
    d.codes = s.Text(4);
    d.difficulty = s.Double(5);
    d.created_at = s.Text(6);
    out.push_back(d);
  }
  return out;
}

std::string Library::DesignContent(std::int64_t id) const {
  Statement s(impl_->db, "SELECT content FROM designs WHERE id = ?1", impl_->File());
  s.Bind(1, id);
  return s.Step() ? s.Text(0) : std::string();
}

// ---------------------------------------------------------------------------------------------
// jumps.json

std::vector<JumpRecord> ParseJumpsJson(const std::string& json, const std::string& source) {
  Json doc = internal::ParseJsonText(json, source);
  if (!doc.is_array()) throw InputError(source, "", "not a JSON array of jumps");
  std::vector<JumpRecord> out;
  for (size_t k = 0; k < doc.size(); ++k) {
    const Json& o = doc[k];
    const std::string where = fmt::format("jump {}", k + 1);
    if (!o.is_object()) throw InputError(source, where, "not an object");
    auto number = [&](const char* key, double fallback, bool required) {
      const auto it = o.find(key);
      if (it == o.end() || it->is_null()) {
        if (required) throw InputError(source, where + ": " + key, "missing");
        return fallback;
      }
      if (!it->is_number()) throw InputError(source, where + ": " + key, "not a number");
      return it->get<double>();
    };
    auto text = [&](const char* key) {
      const auto it = o.find(key);
      if (it == o.end() || it->is_null()) return std::string();
      if (!it->is_string()) throw InputError(source, where + ": " + key, "not text");
      return it->get<std::string>();
    };
    JumpRecord j;
    j.index = int(number("index", double(k + 1), true));
    j.partial = o.value("partial", false);
    j.fig_code = text("fig_code");
    j.skill_name = text("skill_name");
    j.takeoff_s = number("takeoff_s", 0.0, false);
    j.time_of_flight_s = number("time_of_flight_s", 0.0, !j.partial);
    j.displacement_m = number("displacement_from_takeoff_m", 0.0, false);
    j.apex_above_bed_m = number("apex_above_bed_m", 0.0, false);
    j.difficulty = number("difficulty", 0.0, false);
    j.verdict = text("verdict");
    if (j.verdict.rfind("fail", 0) == 0) {
      j.verdict_class = "fail";
      const size_t colon = j.verdict.find(": ");
      j.cause = colon == std::string::npos ? std::string() : j.verdict.substr(colon + 2);
    } else if (j.verdict.rfind("pass", 0) == 0) {
      j.verdict_class = "pass";
    } else {
      j.verdict_class = "not judged";
    }
    if (const auto it = o.find("landing_in_bed_m"); it != o.end() && it->is_array() &&
                                                    it->size() == 2 && (*it)[0].is_number() &&
                                                    (*it)[1].is_number()) {
      j.landing_x_m = (*it)[0].get<double>();
      j.landing_y_m = (*it)[1].get<double>();
    }
    if (const auto it = o.find("landing_in_zone_a"); it != o.end() && it->is_boolean())
      j.landing_in_zone_a = it->get<bool>();
    // The score sheet's view of this flight (jumps.json of Acrolab 0.3 and later).
    if (const auto sc = o.find("score"); sc != o.end() && sc->is_object()) {
      if (const auto e = sc->find("element"); e != sc->end() && e->is_number_integer() &&
                                              e->get<long long>() >= 0 &&
                                              e->get<long long>() <= 1000)
        j.element = int(e->get<long long>());
      if (const auto l = sc->find("landing"); l != sc->end() && l->is_object())
        if (const auto d = l->find("deduction");
            d != l->end() && d->is_number() && std::isfinite(d->get<double>()))
          j.hd_deduction = d->get<double>();
      if (const auto ex = sc->find("execution"); ex != sc->end() && ex->is_array())
        for (const Json& f : *ex)
          if (f.is_object() && f.value("reported", false) && f.contains("fault") &&
              f["fault"].is_string()) {
            std::string key = f["fault"].get<std::string>();
            if (key.empty() || key.size() > 64 || key.find_first_of(" \t\r\n") != std::string::npos)
              throw InputError(source,
                               where + ": score.execution",
                               "a fault key is 1 to 64 characters, no spaces");
            j.faults.push_back(std::move(key));
          }
    }
    out.push_back(std::move(j));
  }
  return out;
}

std::string TrialVerdict(const std::vector<JumpRecord>& jumps) {
  bool judged = false;
  for (const JumpRecord& j : jumps) {
    if (j.verdict_class == "fail") return "fail";
    if (j.verdict_class == "pass") judged = true;
  }
  return judged ? "pass" : "not judged";
}

std::string FormatJumpRowsCsv(const std::vector<JumpRow>& rows) {
  auto quoted = [](const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  auto optional = [](const std::optional<double>& v) {
    return v ? fmt::format("{:.4f}", *v) : std::string();
  };
  std::string out =
      "athlete,date,trial,jump,fig_code,skill,partial,takeoff_s,time_of_flight_s,"
      "displacement_m,apex_above_bed_m,difficulty,verdict,cause,landing_x_m,landing_y_m,"
      "landing_in_zone_a,element,hd_deduction,faults\n";
  for (const JumpRow& r : rows) {
    const JumpRecord& j = r.jump;
    out += fmt::format(
        "{},{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.1f},{},{},{},{},{},{},{},{}\n",
        quoted(r.athlete),
        r.session_date,
        quoted(r.trial_path),
        j.index,
        quoted(j.fig_code),
        quoted(j.skill_name),
        j.partial ? 1 : 0,
        j.takeoff_s,
        j.time_of_flight_s,
        j.displacement_m,
        j.apex_above_bed_m,
        j.difficulty,
        quoted(j.verdict_class),
        quoted(j.cause),
        optional(j.landing_x_m),
        optional(j.landing_y_m),
        j.landing_in_zone_a ? (*j.landing_in_zone_a ? "1" : "0") : "",
        j.element,
        j.hd_deduction ? fmt::format("{:.1f}", *j.hd_deduction) : std::string(),
        quoted(JoinFaults(j.faults)));
  }
  return out;
}

std::string FormatJumpRowsJson(const std::vector<JumpRow>& rows) {
  Json out = Json::array();
  for (const JumpRow& r : rows) {
    const JumpRecord& j = r.jump;
    Json o;
    o["athlete"] = r.athlete;
    o["date"] = r.session_date;
    o["trial_id"] = r.trial_id;
    o["trial"] = r.trial_path;
    o["jump"] = j.index;
    o["fig_code"] = j.fig_code;
    o["skill_name"] = j.skill_name;
    o["partial"] = j.partial;
    o["takeoff_s"] = j.takeoff_s;
    o["time_of_flight_s"] = j.time_of_flight_s;
    o["displacement_m"] = j.displacement_m;
    o["apex_above_bed_m"] = j.apex_above_bed_m;
    o["difficulty"] = j.difficulty;
    o["verdict"] = j.verdict;
    o["verdict_class"] = j.verdict_class;
    o["cause"] = j.cause;
    o["landing_in_bed_m"] = j.landing_x_m && j.landing_y_m
                                ? Json::array({*j.landing_x_m, *j.landing_y_m})
                                : Json(nullptr);
    o["landing_in_zone_a"] = j.landing_in_zone_a ? Json(*j.landing_in_zone_a) : Json(nullptr);
    o["element"] = j.element;
    o["hd_deduction"] = j.hd_deduction ? Json(*j.hd_deduction) : Json(nullptr);
    o["faults"] = j.faults;
    out.push_back(std::move(o));
  }
  return out.dump(1) + "\n";
}

}  // namespace acro::library
