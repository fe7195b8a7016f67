// Issue "a season of training", its acceptance: a season of 3 athletes × 40 sessions × 5 routines
// made by the sample-routine generator (heights rising over the season, landings moving on the
// bed, each routine its own noise), added by `acrolab batch -j 2`, killed once half-way by
// SIGTERM and started again. Every trial must then be in the library exactly once with all its
// jumps, nothing half-written; the stored analysis is `acrolab analyze`'s; `query` finds what the
// season holds; `progress` draws the season and sees the heights rise.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/capture/c3d.h"
#include "acro/library/library.h"
#include "acro/library/progress.h"
#include "long_tests.h"
#include "refdata.h"
#include "sample_routine.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using acro::library::Library;

// The full season (3 × 40 × 5 = 600 routines, about 11 minutes on two cores) is a soak test, run
// with ACRO_LONG_TESTS=1 (docs/testing.md); the default run keeps its shape on 3 × 12 × 2 = 72.
constexpr int kAthletes = 3, kSkills = 3;
const int kSessions = acro::testing::LongTests() ? 40 : 12,
          kRoutines = acro::testing::LongTests() ? 5 : 2;
const int kTrials = kAthletes * kSessions * kRoutines;

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string Date(int session) {
  // Every other day from 1 September.
  const int day = 2 * session;  // 0 … 78
  static const int kMonthDays[] = {30, 31, 30, 31};
  int month = 9, d = day;
  for (int m = 0; d >= kMonthDays[m]; ++m, ++month) d -= kMonthDays[m];
  return fmt::format("2026-{:02d}-{:02d}", month, d + 1);
}

struct Season {
  fs::path root;
  std::vector<std::string> athletes;  // names
  std::vector<fs::path> trials;       // absolute paths
  std::map<std::string, std::string> athlete_of, date_of;
};

// The season's files and its job list (one line per trial with its athlete and session).
Season MakeSeason(const fs::path& root) {
  Season season;
  season.root = root;
  const std::string sample =
      ReadText(acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml");
  struct Who {
    const char* name;
    const char* file;
    double height, mass;
  } who[kAthletes] = {{"Ann Season", "ann", 1.62, 52},
                      {"Bea Season", "bea", 1.70, 60},
                      {"Cleo Season", "cleo", 1.78, 66}};
  std::ofstream jobs(root / "jobs.txt");
  jobs << "# The season: one trial per line with its athlete and session.\n";
  const auto start = std::chrono::steady_clock::now();
  for (int a = 0; a < kAthletes; ++a) {
    std::string profile = sample;
    auto set = [&profile](const std::string& key, const std::string& value) {
      const size_t at = profile.find("\n" + key + ":");
      ASSERT_NE(at, std::string::npos) << key;
      const size_t end = profile.find('\n', at + 1);
      profile.replace(at + 1, end - at - 1, key + ": " + value);
    };
    set("name", who[a].name);
    set("height_m", fmt::format("{}", who[a].height));
    set("mass_kg", fmt::format("{}", who[a].mass));
    const fs::path profile_path = root / (std::string(who[a].file) + ".yaml");
    std::ofstream(profile_path) << profile;
    season.athletes.push_back(who[a].name);
    // Routines from the generator: the season in three parts, each higher and landing further
    // back and to one side than the last (the last part partly outside zone A), and within a
    // session five routines of slightly different heights; each copy gets its own noise and a
    // shift on the bed.
    for (int part = 0; part < 3; ++part) {
      std::vector<acro::samples::SampleRoutine> bases;
      for (int r = 0; r < kRoutines; ++r) {
        acro::samples::SampleRoutineOptions options;
        options.num_skills = kSkills;
        options.flight_time_scale = 0.92 + 0.08 * part + 0.015 * (r - kRoutines / 2);
        options.landing_offset_m = Eigen::Vector2d(-0.45 * part, 0.12 * part);
        options.noise_seed = unsigned(1000 + 100 * a + 10 * part + r);
        // A fault corrected over the season: the pike's knees bent 25° in every routine of the
        // first part, every other one of the second, none of the third.
        if (part == 0 || (part == 1 && r % 2 == 0)) {
          acro::samples::SampleFault bent;
          bent.skill = 2;
          bent.kind = acro::samples::SampleFault::Kind::kKneesBent;
          bent.value = 25.0;
          options.faults.push_back(bent);
        }
        bases.push_back(
            acro::samples::MakeSampleRoutine(profile_path, profile_path.string(), options));
      }
      const int first = part * kSessions / 3, last = (part + 1) * kSessions / 3;
      for (int s = first; s < last; ++s) {
        const std::string date = Date(s);
        const fs::path dir = root / who[a].file / date;
        fs::create_directories(dir);
        for (int r = 0; r < kRoutines; ++r) {
          acro::capture::Trial trial = bases[size_t(r)].trial;
          std::mt19937 rng(unsigned(100000 * a + 100 * s + r));
          std::normal_distribution<double> noise(0.0, 0.001);
          std::uniform_real_distribution<double> shift(-0.15, 0.15);
          const Eigen::Vector3d offset(shift(rng), shift(rng), 0.0);
          for (int p = 0; p < trial.num_points(); ++p) {
            if (trial.points[size_t(p)].label.rfind("BED", 0) == 0) continue;
            for (int f = 0; f < trial.num_frames; ++f)
              if (trial.valid(f, p))
                trial.position(f, p) +=
                    offset + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
          }
          const fs::path file = dir / fmt::format("routine_{}.c3d", r + 1);
          const std::vector<std::uint8_t> c3d = acro::capture::WriteC3dToMemory(trial);
          acro::WriteFileAtomically(file, std::string(c3d.begin(), c3d.end()));
          season.trials.push_back(fs::absolute(file));
          season.athlete_of[fs::absolute(file).string()] = who[a].name;
          season.date_of[fs::absolute(file).string()] = date;
          jobs << fmt::format("{}/{}/routine_{}.c3d --athlete {}.yaml --session {}\n",
                              who[a].file,
                              date,
                              r + 1,
                              who[a].file,
                              date);
        }
      }
    }
  }
  std::printf("season: %zu trials made in %.1f s\n",
              season.trials.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return season;
}

// Starts acrolab with `args`, stdout and stderr to files in `dir`, TMPDIR `tmp`.
pid_t Start(const std::vector<std::string>& args, const fs::path& dir, const fs::path& tmp) {
  std::vector<std::string> words = {ACROLAB_EXE};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(
      &actions, 1, (dir / "stdout.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(
      &actions, 2, (dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> env_text;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("TMPDIR=", 0) != 0) env_text.push_back(*e);
  env_text.push_back("TMPDIR=" + tmp.string());
  std::vector<char*> env;
  for (std::string& e : env_text) env.push_back(e.data());
  env.push_back(nullptr);
  pid_t pid = 0;
  EXPECT_EQ(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data()), 0);
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

int Wait(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

size_t StoredTrials(const fs::path& library) {
  try {
    const Library lib(library, Library::Mode::kReadOnly);
    return lib.ListTrials().size();
  } catch (const std::exception&) {
    return 0;  // not made yet
  }
}

TEST(LibrarySeason, BatchKilledHalfWayAndRestartedStoresEveryTrialOnce) {
  const fs::path root = fs::temp_directory_path() / ("acro_season_" + std::to_string(getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "tmp");
  const Season season = MakeSeason(root);
  ASSERT_EQ(season.trials.size(), size_t(kTrials));
  const fs::path library = root / "library.sqlite";
  const std::vector<std::string> batch = {
      "batch", (root / "jobs.txt").string(), "-j", "2", "--library", library.string()};

  // The first run, stopped by SIGTERM once half the season is stored.
  const auto start = std::chrono::steady_clock::now();
  const pid_t first = Start(batch, root, root / "tmp");
  size_t before_kill = 0;
  while ((before_kill = StoredTrials(library)) < size_t(kTrials / 2)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    int status = 0;
    ASSERT_EQ(waitpid(first, &status, WNOHANG), 0) << "the batch ended early:\n"
                                                   << ReadText(root / "stderr.txt");
  }
  kill(first, SIGTERM);
  EXPECT_EQ(Wait(first), 143) << ReadText(root / "stderr.txt");
  const double first_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Its jobs were stopped with it: the library does not grow any more, and nothing of theirs is
  // left in the temporary folder.
  const size_t after_kill = StoredTrials(library);
  std::this_thread::sleep_for(std::chrono::seconds(3));
  EXPECT_EQ(StoredTrials(library), after_kill);
  EXPECT_GE(after_kill, before_kill);
  EXPECT_LT(after_kill, size_t(kTrials));
  EXPECT_TRUE(fs::is_empty(root / "tmp"));
  std::printf("first run: %zu trials stored in %.1f s, then SIGTERM\n", after_kill, first_s);

  // The second run goes on where the first stopped.
  const auto restart = std::chrono::steady_clock::now();
  const pid_t second = Start(batch, root, root / "tmp");
  EXPECT_EQ(Wait(second), 0) << ReadText(root / "stderr.txt");
  const double second_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - restart).count();
  const std::string summary = ReadText(root / "stdout.txt");
  std::printf("second run (%.1f s): %s", second_s, summary.c_str());
  EXPECT_NE(summary.find(
                fmt::format("{} added, {} unchanged, 0 failed", kTrials - after_kill, after_kill)),
            std::string::npos)
      << summary;

  // Every trial exactly once, with all its jumps, under its athlete and session.
  const Library lib(library, Library::Mode::kReadOnly);  // (its integrity is checked on opening)
  const std::vector<acro::library::TrialSummary> trials = lib.ListTrials();
  EXPECT_EQ(trials.size(), size_t(kTrials));
  std::set<std::string> paths;
  for (const acro::library::TrialSummary& t : trials) {
    EXPECT_TRUE(paths.insert(t.path).second) << t.path << " twice";
    ASSERT_TRUE(season.athlete_of.count(t.path)) << t.path;
    EXPECT_EQ(t.athlete, season.athlete_of.at(t.path));
    EXPECT_EQ(t.session_date, season.date_of.at(t.path));
    EXPECT_EQ(t.num_jumps, kSkills) << t.path;
  }
  EXPECT_EQ(lib.ListAthletes().size(), size_t(kAthletes));

  // Every session's codes, and a query by athlete, code and dates.
  acro::library::JumpQuery q;
  q.athlete = "Bea Season";
  q.fig_code = "40o";
  const int from = kSessions / 4, to = 3 * kSessions / 4 - 1;  // sessions 10–29 of 40
  q.date_from = Date(from);
  q.date_to = Date(to);
  const std::vector<acro::library::JumpRow> rows = lib.QueryJumps(q);
  EXPECT_EQ(rows.size(), size_t((to - from + 1) * kRoutines));
  for (const auto& r : rows)
    EXPECT_EQ(r.jump.verdict_class, "pass") << r.trial_path << " " << r.jump.verdict;

  // The season's progress: the flights were made 8 % and 16 % longer (of the first part's) in its
  // second and third parts, the landings moved out of zone A; the charts and the page are drawn.
  const acro::library::Progress progress =
      acro::library::CalcProgress(lib.QueryJumps([] {
        acro::library::JumpQuery all;
        all.athlete = "Bea Season";
        all.fig_code = "40o";
        return all;
      }()),
                                  acro::library::ProgressMetric::kTimeOfFlight,
                                  "Bea Season",
                                  "40o");
  ASSERT_EQ(progress.sessions.size(), size_t(kSessions));
  const double early = progress.sessions.front().median, late = progress.sessions.back().median;
  EXPECT_NEAR(late / early, 1.08 / 0.92, 0.01);
  auto zone_a_share = [](const acro::library::SessionProgress& s) {
    return double(s.landings_in_zone_a) / double(s.landing_x_m.size());
  };
  double first_part = 0, last_part = 0;
  const int third = kSessions / 3;
  for (int s = 0; s < third; ++s) {
    first_part += zone_a_share(progress.sessions[size_t(s)]) / third;
    last_part += zone_a_share(progress.sessions[size_t(kSessions - 1 - s)]) / third;
  }
  std::printf("Bea's 40o: time of flight %.3f → %.3f s, landings in zone A %.0f %% → %.0f %%\n",
              early,
              late,
              100 * first_part,
              100 * last_part);
  EXPECT_NEAR(first_part, 1.0, 1e-12);
  EXPECT_LT(last_part, 0.9);
  EXPECT_GT(progress.trend_slope_per_day, 0.0);
  // The score sheet's season (the routines are the straight jump, an in-bounce, then the tuck and
  // the pike): T rises with the flights, H falls as the landings leave zone A, and the bent knees
  // are the most frequent fault, corrected by the third part.
  auto routine_progress = [&](acro::library::ProgressMetric metric) {
    acro::library::JumpQuery all;
    all.athlete = "Bea Season";
    return acro::library::CalcProgress(lib.QueryJumps(all), metric, "Bea Season", "");
  };
  const acro::library::Progress t = routine_progress(acro::library::ProgressMetric::kRoutineTime);
  ASSERT_EQ(t.points.size(), size_t(kSessions * kRoutines));  // one per routine
  ASSERT_EQ(t.sessions.size(), size_t(kSessions));
  EXPECT_NEAR(t.sessions.back().median / t.sessions.front().median, 1.08 / 0.92, 0.01);
  for (const acro::library::ProgressPoint& point : t.points)  // truncated to 0.005
    EXPECT_NEAR(std::round(point.value / 0.005) * 0.005, point.value, 1e-9) << point.value;
  const acro::library::Progress h =
      routine_progress(acro::library::ProgressMetric::kRoutineDisplacement);
  ASSERT_EQ(h.points.size(), size_t(kSessions * kRoutines));
  EXPECT_DOUBLE_EQ(h.sessions.front().median, 2.0);  // both elements in zone A
  EXPECT_LT(h.sessions.back().median, 2.0);
  const acro::library::Progress faults = routine_progress(acro::library::ProgressMetric::kFaults);
  ASSERT_FALSE(faults.fault_counts.empty());
  EXPECT_EQ(faults.fault_counts.front().first, "knees_bent");
  const int bent_routines =
      kSessions / 3 * kRoutines + (kSessions * 2 / 3 - kSessions / 3) * ((kRoutines + 1) / 2);
  EXPECT_EQ(faults.fault_counts.front().second, bent_routines);
  EXPECT_EQ(faults.elements, 2 * kSessions * kRoutines);
  EXPECT_EQ(faults.sessions.front().most_frequent_fault, "knees_bent");
  EXPECT_EQ(faults.sessions.front().most_frequent_count, kRoutines);
  EXPECT_EQ(faults.sessions.back().faults_reported, 0);
  std::printf("Bea's routines: T %.3f → %.3f, H %.2f → %.2f, %s on %d of %d elements\n",
              t.sessions.front().median,
              t.sessions.back().median,
              h.sessions.front().median,
              h.sessions.back().median,
              faults.fault_counts.front().first.c_str(),
              faults.fault_counts.front().second,
              faults.elements);
  for (const char* metric : {"T", "H", "faults"}) {
    const pid_t page = Start({"library",
                              "progress",
                              "--athlete",
                              "Bea Season",
                              "--metric",
                              metric,
                              "--library",
                              library.string(),
                              "-o",
                              (root / (std::string("progress_") + metric)).string()},
                             root,
                             root / "tmp");
    ASSERT_EQ(Wait(page), 0) << ReadText(root / "stderr.txt");
    const std::string html = ReadText(root / (std::string("progress_") + metric) / "progress.html");
    EXPECT_NE(html.find("most frequent fault <b>knees_bent</b>"), std::string::npos) << metric;
    EXPECT_TRUE(fs::exists(root / (std::string("progress_") + metric) / "progress_faults.png"))
        << metric;
  }
  const pid_t chart = Start({"library",
                             "progress",
                             "--athlete",
                             "Bea Season",
                             "--code",
                             "40o",
                             "--library",
                             library.string(),
                             "-o",
                             (root / "progress").string()},
                            root,
                            root / "tmp");
  ASSERT_EQ(Wait(chart), 0) << ReadText(root / "stderr.txt");
  for (const char* f : {"progress.html",
                        "progress.csv",
                        "progress_metric.png",
                        "progress_metric.svg",
                        "progress_landings.png",
                        "progress_zone_a.png"})
    EXPECT_TRUE(fs::exists(root / "progress" / f)) << f;
  if (const char* keep = std::getenv("ACRO_KEEP_SEASON"); keep && *keep) {
    std::printf("kept %s\n", root.c_str());
    return;
  }
  fs::remove_all(root);
}

// `library add` stores what `acrolab analyze` finds for the same file: one routine of the
// generator, both through the real binary.
TEST(LibrarySeason, AddStoresTheAnalysisOfAnalyze) {
  const fs::path root = fs::temp_directory_path() / ("acro_season_one_" + std::to_string(getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "tmp");
  const fs::path athlete = acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
  acro::samples::SampleRoutineOptions options;
  options.num_skills = kSkills;
  options.flight_time_scale = 1.06;
  options.landing_offset_m = Eigen::Vector2d(-0.5, 0.2);
  const acro::samples::SampleRoutine routine =
      acro::samples::MakeSampleRoutine(athlete, athlete.string(), options);
  const std::vector<std::uint8_t> c3d = acro::capture::WriteC3dToMemory(routine.trial);
  const fs::path trial = root / "routine.c3d";
  acro::WriteFileAtomically(trial, std::string(c3d.begin(), c3d.end()));
  const fs::path library = root / "library.sqlite";
  ASSERT_EQ(Wait(Start({"library",
                        "add",
                        trial.string(),
                        "--athlete",
                        athlete.string(),
                        "--session",
                        "2026-09-01",
                        "--library",
                        library.string(),
                        "--quiet"},
                       root,
                       root / "tmp")),
            0)
      << ReadText(root / "stderr.txt");
  ASSERT_EQ(Wait(Start({"analyze",
                        trial.string(),
                        "--athlete",
                        athlete.string(),
                        "--no-images",
                        "--quiet",
                        "-o",
                        (root / "analysis").string()},
                       root,
                       root / "tmp")),
            0)
      << ReadText(root / "stderr.txt");
  const Library lib(library, Library::Mode::kReadOnly);
  const auto stored = lib.FindTrialSummary(trial.string());
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(lib.TrialJumpsJson(stored->id), ReadText(root / "analysis" / "jumps.json"));
  EXPECT_EQ(stored->num_jumps, kSkills);
  // The analysis directory, stored instead of analysing, gives the same jumps; it is refused for
  // another file.
  const fs::path copy = root / "copy.c3d";
  fs::copy_file(trial, copy);
  ASSERT_EQ(Wait(Start({"library",
                        "add",
                        copy.string(),
                        "--athlete",
                        athlete.string(),
                        "--analysis",
                        (root / "analysis").string(),
                        "--library",
                        library.string()},
                       root,
                       root / "tmp")),
            0)
      << ReadText(root / "stderr.txt");
  {
    const Library again(library, Library::Mode::kReadOnly);
    const auto imported = again.FindTrialSummary(copy.string());
    ASSERT_TRUE(imported.has_value());
    EXPECT_EQ(again.TrialJumpsJson(imported->id), ReadText(root / "analysis" / "jumps.json"));
  }
  std::ofstream(root / "other.c3d", std::ios::binary) << ReadText(trial) << "x";
  EXPECT_EQ(Wait(Start({"library",
                        "add",
                        (root / "other.c3d").string(),
                        "--athlete",
                        athlete.string(),
                        "--analysis",
                        (root / "analysis").string(),
                        "--library",
                        library.string()},
                       root,
                       root / "tmp")),
            1);
  EXPECT_NE(ReadText(root / "stderr.txt").find("an analysis of another file"), std::string::npos)
      << ReadText(root / "stderr.txt");
  fs::remove_all(root);
}

}  // namespace
