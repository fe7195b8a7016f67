// The season library (analysis/library): storing and replacing trials, queries checked against a
// brute-force filter of what was stored, the migration from schema 1, files that are not a
// library (refused with one line, their bytes unchanged), two processes writing at once, and the
// progress series against hand-computed medians and an exact trend.
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/library/library.h"
#include "acro/library/progress.h"

namespace {

namespace fs = std::filesystem;
using acro::library::JumpQuery;
using acro::library::JumpRow;
using acro::library::Library;

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("acro_library_test_" + std::to_string(getpid()) + "_" + std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

struct SyntheticJump {
  std::string code;
  double tof;
  double hd;
  std::string verdict;
  double landing_x, landing_y;
};

std::string JumpsJson(const std::vector<SyntheticJump>& jumps) {
  nlohmann::json a = nlohmann::json::array();
  int index = 1;
  for (const SyntheticJump& j : jumps) {
    a.push_back(
        {{"index", index},
         {"partial", false},
         {"takeoff_s", 1.5 * index},
         {"time_of_flight_s", j.tof},
         {"apex_above_bed_m", 9.81 * j.tof * j.tof / 8},
         {"displacement_from_takeoff_m", j.hd},
         {"landing_in_bed_m", {j.landing_x, j.landing_y}},
         {"landing_in_zone_a", std::abs(j.landing_x) <= 1.075 && std::abs(j.landing_y) <= 0.54},
         {"fig_code", j.code},
         {"skill_name", "skill " + j.code},
         {"difficulty", j.code == "800o" ? 1.0 : 0.5},
         {"verdict", j.verdict}});
    ++index;
  }
  return a.dump();
}

acro::library::TrialToStore MakeTrial(const std::string& athlete,
                                      const std::string& date,
                                      const std::string& path,
                                      const std::vector<SyntheticJump>& jumps) {
  acro::library::TrialToStore t;
  t.athlete = athlete;
  t.athlete_profile = "name: " + athlete + "\nheight_m: 1.7\nmass_kg: 60\n";
  t.stature_m = 1.7;
  t.mass_kg = 60;
  t.session_date = date;
  t.path = path;
  t.sha256 = acro::Sha256Hex(path);
  t.size_bytes = 1000;
  t.analysis_version = "0.1.0";
  t.analysis_source = "analysed";
  t.jumps_json = JumpsJson(jumps);
  return t;
}

std::string FileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every jump stored by the Season fixture, as the brute force checks the queries against.
struct Stored {
  std::string athlete, date, path;
  SyntheticJump jump;
};

// A small season: 3 athletes × 10 sessions × 3 trials × 4 jumps, values from a fixed seed.
std::vector<Stored> FillSeason(Library& lib) {
  std::vector<Stored> all;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const char* codes[] = {"40o", "41/", "800o", "821o"};
  for (const char* athlete : {"Ann", "Bea", "Cleo"})
    for (int s = 0; s < 10; ++s) {
      const std::string date =
          "2026-" + std::string(s < 5 ? "09-0" : "10-1") + std::to_string(s % 5 + 1);
      for (int t = 0; t < 3; ++t) {
        std::vector<SyntheticJump> jumps;
        for (int k = 0; k < 4; ++k)
          jumps.push_back({codes[(t + k) % 4],
                           1.2 + 0.5 * u(rng),
                           0.8 * u(rng),
                           u(rng) < 0.2 ? "fail: residual force 0.4 BW" : "pass",
                           2 * u(rng) - 1,
                           u(rng) - 0.5});
        const std::string path =
            "/season/" + std::string(athlete) + "/" + date + "/r" + std::to_string(t) + ".c3d";
        lib.StoreTrial(MakeTrial(athlete, date, path, jumps));
        for (const SyntheticJump& j : jumps) all.push_back({athlete, date, path, j});
      }
    }
  return all;
}

TEST(Library, StoresReplacesAndFindsTrials) {
  TempDir dir;
  const fs::path file = dir.path() / "sub" / "library.sqlite";
  {
    Library lib(file, Library::Mode::kReadWrite);
    EXPECT_EQ(lib.schema_version_found(), 0);
    EXPECT_EQ(lib.schema_version(), acro::library::kSchemaVersion);
    lib.StoreTrial(MakeTrial("Ann", "2026-09-01", "/t/a.c3d", {{"40o", 1.3, 0.2, "pass", 0, 0}}));
    // The same path again (a re-analysis): replaced, not added.
    lib.StoreTrial(MakeTrial("Ann",
                             "2026-09-01",
                             "/t/a.c3d",
                             {{"40o", 1.4, 0.2, "pass", 0, 0}, {"41/", 1.5, 0.3, "pass", 0, 0}}));
    EXPECT_EQ(lib.ListTrials().size(), 1u);
    const auto rows = lib.QueryJumps(JumpQuery{});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_NEAR(rows[0].jump.time_of_flight_s, 1.4, 1e-12);
    EXPECT_TRUE(lib.FindTrial("/t/a.c3d").stored);
    EXPECT_FALSE(lib.FindTrial("/t/b.c3d").stored);
    EXPECT_TRUE(lib.RemoveTrial("/t/a.c3d"));
    EXPECT_FALSE(lib.RemoveTrial("/t/a.c3d"));
    EXPECT_TRUE(lib.QueryJumps(JumpQuery{}).empty());
  }
  // Read-only reopening sees what was written; a read-only library refuses writes.
  Library reader(file, Library::Mode::kReadOnly);
  EXPECT_EQ(reader.schema_version_found(), acro::library::kSchemaVersion);
  EXPECT_THROW(reader.RemoveTrial("/t/a.c3d"), acro::InputError);
}

TEST(Library, QueriesMatchABruteForceFilter) {
  TempDir dir;
  Library lib(dir.path() / "library.sqlite", Library::Mode::kReadWrite);
  const std::vector<Stored> all = FillSeason(lib);
  ASSERT_EQ(all.size(), 3u * 10 * 3 * 4);
  std::vector<JumpQuery> queries(6);
  queries[0].athlete = "Bea";
  queries[1].athlete = "Ann";
  queries[1].fig_code = "821o";
  queries[1].date_from = "2026-09-03";
  queries[1].date_to = "2026-10-12";
  queries[2].verdict_class = "fail";
  queries[3].min_time_of_flight_s = 1.4;
  queries[3].max_time_of_flight_s = 1.6;
  queries[4].min_displacement_m = 0.5;
  queries[4].fig_code = "40o";
  queries[5].athlete = "Nobody";
  for (size_t k = 0; k < queries.size(); ++k) {
    const JumpQuery& q = queries[k];
    size_t expected = 0;
    for (const Stored& s : all) {
      const bool fail = s.jump.verdict.rfind("fail", 0) == 0;
      if ((q.athlete.empty() || s.athlete == q.athlete) &&
          (q.fig_code.empty() || s.jump.code == q.fig_code) &&
          (q.date_from.empty() || s.date >= q.date_from) &&
          (q.date_to.empty() || s.date <= q.date_to) &&
          (q.verdict_class.empty() || (q.verdict_class == "fail") == fail) &&
          (!q.min_time_of_flight_s || s.jump.tof >= *q.min_time_of_flight_s) &&
          (!q.max_time_of_flight_s || s.jump.tof <= *q.max_time_of_flight_s) &&
          (!q.min_displacement_m || s.jump.hd >= *q.min_displacement_m))
        ++expected;
    }
    const std::vector<JumpRow> rows = lib.QueryJumps(q);
    EXPECT_EQ(rows.size(), expected) << "query " << k;
    for (const JumpRow& r : rows) {
      if (!q.athlete.empty()) {
        EXPECT_EQ(r.athlete, q.athlete);
      }
      if (!q.fig_code.empty()) {
        EXPECT_EQ(r.jump.fig_code, q.fig_code);
      }
    }
  }
  EXPECT_GT(lib.QueryJumps(queries[1]).size(), 0u);
  // A failure keeps its cause; the CSV has a header and one line per row.
  const auto failed = lib.QueryJumps(queries[2]);
  ASSERT_FALSE(failed.empty());
  EXPECT_EQ(failed[0].jump.cause, "residual force 0.4 BW");
  const std::string csv = acro::library::FormatJumpRowsCsv(failed);
  EXPECT_EQ(size_t(std::count(csv.begin(), csv.end(), '\n')), failed.size() + 1);
  // A query that cannot hold is refused with its reason.
  JumpQuery bad;
  bad.date_from = "2026-10-01";
  bad.date_to = "2026-09-01";
  try {
    lib.QueryJumps(bad);
    ADD_FAILURE() << "an empty date range was accepted";
  } catch (const acro::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("before --from"), std::string::npos) << e.what();
  }
}

TEST(Library, MigratesASchemaOneLibrary) {
  TempDir dir;
  const fs::path file = dir.path() / "old.sqlite";
  Library::CreateWithSchemaVersion(file, 1);
  // A trial as schema 1 stored it (no landing, cause or take-off columns), by hand.
  const std::string json = JumpsJson(
      {{"40o", 1.3, 0.2, "fail: timing", 0.3, -0.2}, {"41/", 1.4, 0.1, "pass", -1.5, 0.1}});
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    const std::string sql =
        "INSERT INTO athletes(id, name) VALUES (1, 'Ann');"
        "INSERT INTO athlete_profiles(id, athlete_id, first_seen, sha256, stature_m, mass_kg, "
        "profile) VALUES (1, 1, '2026-01-01', 'x', 1.7, 60, 'name: Ann');"
        "INSERT INTO sessions(id, athlete_id, date) VALUES (1, 1, '2026-01-01');"
        "INSERT INTO trials(id, session_id, profile_id, path, sha256, size_bytes, "
        "analysis_version, analysis_source, analysed_at, verdict, jumps_json) VALUES (1, 1, 1, "
        "'/old/a.c3d', 'abc', 10, '0.0.9', 'analysed', '2026-01-01T00:00:00Z', 'fail', '" +
        json +
        "');"
        "INSERT INTO jumps(trial_id, jump_index, partial, fig_code, skill_name, time_of_flight_s, "
        "displacement_m, apex_above_bed_m, difficulty, verdict, verdict_class) VALUES "
        "(1, 1, 0, '40o', 's', 1.3, 0.2, 2, 0.5, 'fail: timing', 'fail'),"
        "(1, 2, 0, '41/', 's', 1.4, 0.1, 2, 0.5, 'pass', 'pass');";
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
  }
  // Read-only: an older schema is not migrated behind the user's back, and said so.
  EXPECT_THROW(Library(file, Library::Mode::kReadOnly), acro::InputError);
  Library lib(file, Library::Mode::kReadWrite);
  EXPECT_EQ(lib.schema_version_found(), 1);
  EXPECT_EQ(lib.schema_version(), acro::library::kSchemaVersion);
  const std::vector<JumpRow> rows = lib.QueryJumps(JumpQuery{});
  ASSERT_EQ(rows.size(), 2u);
  // The new columns, filled from the stored jumps.json.
  EXPECT_EQ(rows[0].jump.cause, "timing");
  ASSERT_TRUE(rows[0].jump.landing_x_m.has_value());
  EXPECT_NEAR(*rows[0].jump.landing_x_m, 0.3, 1e-12);
  EXPECT_TRUE(*rows[0].jump.landing_in_zone_a);
  EXPECT_FALSE(*rows[1].jump.landing_in_zone_a);
  EXPECT_NEAR(rows[1].jump.takeoff_s, 3.0, 1e-12);
  // And schema 2's table works: a design stored, replaced by name, listed.
  EXPECT_GT(lib.StoreDesign("Ann", "routine", "final", "40o 41/", 1.0, "{}"), 0);
  const std::int64_t id = lib.StoreDesign("Ann", "routine", "final", "40o 42/", 1.2, "{\"v\": 2}");
  const auto designs = lib.ListDesigns("Ann");
  ASSERT_EQ(designs.size(), 1u);
  EXPECT_EQ(designs[0].codes, "40o 42/");
  EXPECT_EQ(lib.DesignContent(id), "{\"v\": 2}");
  EXPECT_THROW(lib.StoreDesign("Ann", "ballet", "x", "", 0, "{}"), acro::InputError);
}

// Opens `file` both ways and expects one line naming it and `words`, with its bytes unchanged.
void ExpectRefused(const fs::path& file, const std::string& words) {
  const std::string before = FileBytes(file);
  for (const Library::Mode mode : {Library::Mode::kReadOnly, Library::Mode::kReadWrite}) {
    try {
      Library lib(file, mode);
      ADD_FAILURE() << file << " was opened";
    } catch (const acro::InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.rfind(file.string(), 0), 0u) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
    EXPECT_EQ(FileBytes(file), before) << file << " was changed";
    EXPECT_FALSE(fs::exists(file.string() + "-wal"));
  }
}

TEST(Library, RefusesWhatIsNotALibraryAndLeavesItUntouched) {
  TempDir dir;
  // Not a database at all.
  const fs::path text = dir.path() / "notes.sqlite";
  std::ofstream(text) << "these are my notes, not a database\n" << std::string(5000, 'x');
  ExpectRefused(text, "not an Acrolab library");
  // Another program's SQLite database.
  const fs::path other = dir.path() / "other.sqlite";
  {
    sqlite3* db = nullptr;
    sqlite3_open(other.c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE t(x); INSERT INTO t VALUES (1);", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  ExpectRefused(other, "not an Acrolab library");
  // A library damaged in the middle (a page overwritten), and one cut short.
  const fs::path good = dir.path() / "good.sqlite";
  {
    Library lib(good, Library::Mode::kReadWrite);
    FillSeason(lib);
  }
  // (closing the last connection checkpoints the WAL into the file)
  ASSERT_FALSE(fs::exists(good.string() + "-wal"));
  std::string bytes = FileBytes(good);
  ASSERT_GT(bytes.size(), 16384u);
  const fs::path damaged = dir.path() / "damaged.sqlite";
  {
    std::string d = bytes;
    std::mt19937 rng(3);
    for (size_t i = 3 * 4096 + 8; i < 5 * 4096; ++i) d[i] = char(rng());
    std::ofstream(damaged, std::ios::binary) << d;
  }
  ExpectRefused(damaged, "damaged library");
  const fs::path cut = dir.path() / "cut.sqlite";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  ExpectRefused(cut, "library");
  // A newer schema.
  const fs::path newer = dir.path() / "newer.sqlite";
  fs::copy_file(good, newer);
  {
    sqlite3* db = nullptr;
    sqlite3_open(newer.c_str(), &db);
    sqlite3_exec(
        db, "PRAGMA journal_mode = DELETE; PRAGMA user_version = 9;", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  ExpectRefused(newer, "version 9 is newer");
}

TEST(Library, TwoProcessesWritingAtOnceLoseNothing) {
  TempDir dir;
  const fs::path file = dir.path() / "library.sqlite";
  { Library create(file, Library::Mode::kReadWrite); }
  constexpr int kTrials = 150;
  std::vector<pid_t> children;
  for (int p = 0; p < 2; ++p) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      int status = 0;
      try {
        Library lib(file, Library::Mode::kReadWrite);
        for (int t = 0; t < kTrials; ++t)
          lib.StoreTrial(
              MakeTrial(p ? "Bea" : "Ann",
                        "2026-09-01",
                        "/p" + std::to_string(p) + "/t" + std::to_string(t) + ".c3d",
                        {{"40o", 1.3, 0.2, "pass", 0, 0}, {"41/", 1.4, 0.2, "pass", 0, 0}}));
      } catch (const std::exception& e) {
        std::fprintf(stderr, "child %d: %s\n", p, e.what());
        status = 1;
      }
      _exit(status);
    }
    children.push_back(pid);
  }
  for (const pid_t pid : children) {
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  const Library lib(file, Library::Mode::kReadOnly);
  EXPECT_EQ(lib.ListTrials().size(), size_t(2 * kTrials));
  EXPECT_EQ(lib.QueryJumps(JumpQuery{}).size(), size_t(4 * kTrials));
  EXPECT_EQ(lib.ListAthletes().size(), 2u);
}

TEST(Library, ParsesJumpsJsonAndNamesWhatIsWrong) {
  const auto jumps = acro::library::ParseJumpsJson(
      JumpsJson({{"800o", 1.6, 0.7, "pass within its noise", 0.1, 0.1}}), "x.json");
  ASSERT_EQ(jumps.size(), 1u);
  EXPECT_EQ(jumps[0].verdict_class, "pass");
  EXPECT_EQ(acro::library::TrialVerdict(jumps), "pass");
  try {
    acro::library::ParseJumpsJson(R"([{"index": 1, "time_of_flight_s": "long"}])", "x.json");
    ADD_FAILURE();
  } catch (const acro::InputError& e) {
    EXPECT_STREQ(e.what(), "x.json: jump 1: time_of_flight_s: not a number");
  }
  EXPECT_THROW(acro::library::ParseJumpsJson("{", "x.json"), acro::InputError);
}

TEST(Progress, SessionMediansTrendAndLandings) {
  // Time of flight rising by exactly 0.01 s per day: the trend recovers the slope and R² = 1 for
  // the session medians' line; the medians are the middle values.
  std::vector<JumpRow> rows;
  for (int day = 0; day < 20; day += 5) {
    for (int k = 0; k < 3; ++k) {
      JumpRow r;
      r.athlete = "Ann";
      const int d = 1 + day;
      r.session_date = std::string("2026-09-") + (d < 10 ? "0" : "") + std::to_string(d);
      r.jump.time_of_flight_s = 1.3 + 0.01 * day + 0.02 * (k - 1);
      r.jump.fig_code = "40o";
      r.jump.verdict_class = k == 2 ? "fail" : "pass";
      r.jump.landing_x_m = 0.6 * k;
      r.jump.landing_y_m = 0.0;
      r.jump.landing_in_zone_a = 0.6 * k <= 1.075;
      rows.push_back(r);
    }
  }
  const acro::library::Progress p =
      acro::library::CalcProgress(rows, acro::library::ProgressMetric::kTimeOfFlight, "Ann", "40o");
  ASSERT_EQ(p.sessions.size(), 4u);
  EXPECT_EQ(p.first_date, "2026-09-01");
  for (size_t s = 0; s < 4; ++s) {
    EXPECT_NEAR(p.sessions[s].day, 5.0 * double(s), 1e-12);
    EXPECT_NEAR(p.sessions[s].median, 1.3 + 0.05 * double(s), 1e-12);
    EXPECT_EQ(p.sessions[s].landings_in_zone_a, 2);
    EXPECT_EQ(p.sessions[s].landing_x_m.size(), 3u);
  }
  EXPECT_NEAR(p.trend_slope_per_day, 0.01, 1e-12);
  EXPECT_NEAR(p.trend_intercept, 1.3, 1e-12);
  const acro::library::Progress v =
      acro::library::CalcProgress(rows, acro::library::ProgressMetric::kVerdict, "Ann", "40o");
  EXPECT_NEAR(v.sessions[0].median, 2.0 / 3.0, 1e-12);
  EXPECT_EQ(acro::library::DaysBetween("2026-02-27", "2026-03-01"), 2);
  EXPECT_EQ(acro::library::DaysBetween("2024-02-27", "2024-03-01"), 3);  // leap year
  EXPECT_EQ(acro::library::DaysBetween("2026-12-31", "2027-01-01"), 1);
  EXPECT_THROW(acro::library::CalcProgress({}, acro::library::ProgressMetric::kApex, "Ann", ""),
               acro::InputError);
}

TEST(ContentHash, MatchesTheStandardsTestVectors) {
  // FIPS 180-4's examples (NIST CSRC "SHA256.pdf"): "abc" and the empty message.
  EXPECT_EQ(acro::Sha256Hex("abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(acro::Sha256Hex(""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  TempDir dir;
  const fs::path f = dir.path() / "f.bin";
  std::string big(3 << 20, 'a');  // more than one read block
  std::ofstream(f, std::ios::binary) << big;
  EXPECT_EQ(acro::Sha256OfFile(f), acro::Sha256Hex(big));
  EXPECT_THROW(acro::Sha256OfFile(dir.path() / "missing"), acro::InputError);
}

}  // namespace

// Schema 3 adds each jump's place on the score sheet, filled from the stored jumps.json's `score`
// objects when a schema-2 library is opened for writing; a jumps.json without them (older
// analyses) leaves the jumps off the sheet.
TEST(Library, MigratesASchemaTwoLibraryWithItsScoreSheets) {
  TempDir dir;
  const fs::path file = dir.path() / "two.sqlite";
  Library::CreateWithSchemaVersion(file, 2);
  nlohmann::json jumps = nlohmann::json::parse(
      JumpsJson({{"00", 1.2, 0.0, "pass", 0.0, 0.0}, {"40o", 1.3, 0.2, "pass", 1.2, 0.1}}));
  jumps[1]["score"] = {{"element", 1},
                       {"landing", {{"zone", "B"}, {"deduction", 0.1}}},
                       {"execution",
                        {{{"fault", "knees_bent"}, {"reported", true}},
                         {{"fault", "arms_bent"}, {"reported", false}},
                         {{"fault", "late_opening"}, {"reported", true}}}}};
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    const std::string sql =
        "INSERT INTO athletes(id, name) VALUES (1, 'Ann');"
        "INSERT INTO athlete_profiles(id, athlete_id, first_seen, sha256, stature_m, mass_kg, "
        "profile) VALUES (1, 1, '2026-01-01', 'x', 1.7, 60, 'name: Ann');"
        "INSERT INTO sessions(id, athlete_id, date) VALUES (1, 1, '2026-01-01');"
        "INSERT INTO trials(id, session_id, profile_id, path, sha256, size_bytes, "
        "analysis_version, analysis_source, analysed_at, verdict, jumps_json) VALUES (1, 1, 1, "
        "'/old/a.c3d', 'abc', 10, '0.2.0', 'analysed', '2026-01-01T00:00:00Z', 'pass', '" +
        jumps.dump() +
        "');"
        "INSERT INTO jumps(trial_id, jump_index, partial, fig_code, skill_name, time_of_flight_s, "
        "displacement_m, apex_above_bed_m, difficulty, verdict, verdict_class) VALUES "
        "(1, 1, 0, '00', 's', 1.2, 0.0, 2, 0.0, 'pass', 'pass'),"
        "(1, 2, 0, '40o', 's', 1.3, 0.2, 2, 0.5, 'pass', 'pass');";
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
  }
  Library lib(file, Library::Mode::kReadWrite);
  EXPECT_EQ(lib.schema_version_found(), 2);
  const std::vector<JumpRow> rows = lib.QueryJumps(JumpQuery{});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].jump.element, 0);  // the in-bounce
  EXPECT_FALSE(rows[0].jump.hd_deduction.has_value());
  EXPECT_EQ(rows[1].jump.element, 1);
  ASSERT_TRUE(rows[1].jump.hd_deduction.has_value());
  EXPECT_DOUBLE_EQ(*rows[1].jump.hd_deduction, 0.1);
  EXPECT_EQ(rows[1].jump.faults, (std::vector<std::string>{"knees_bent", "late_opening"}));
  // The routine's T and H, and its faults, as the season's progress reads them.
  const auto t =
      acro::library::CalcProgress(rows, acro::library::ProgressMetric::kRoutineTime, "Ann", "");
  ASSERT_EQ(t.points.size(), 1u);
  EXPECT_NEAR(t.points[0].value, 1.3, 1e-12);
  const auto h = acro::library::CalcProgress(
      rows, acro::library::ProgressMetric::kRoutineDisplacement, "Ann", "");
  EXPECT_NEAR(h.points[0].value, 0.9, 1e-12);
  const auto f =
      acro::library::CalcProgress(rows, acro::library::ProgressMetric::kFaults, "Ann", "");
  ASSERT_EQ(f.points.size(), 1u);  // elements only
  EXPECT_EQ(f.points[0].value, 2.0);
  ASSERT_EQ(f.fault_counts.size(), 2u);
  EXPECT_EQ(f.sessions[0].most_frequent_fault, "knees_bent");
  EXPECT_THROW(
      acro::library::CalcProgress(rows, acro::library::ProgressMetric::kRoutineTime, "Ann", "40o"),
      acro::InputError);
}
