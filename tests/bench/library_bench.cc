// The season library's query (issue "a season of training": athlete + code + date range over
// 10 000 stored jumps ≤ 50 ms), and what a coach waits for at the command line: opening the file
// (with its integrity check) and querying. The library is filled with a synthetic season: 5
// athletes × 50 sessions × 4 trials × 10 jumps = 10 000 jumps of 8 codes.
#include <unistd.h>

#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/content_hash.h"
#include "acro/library/library.h"

namespace {

namespace fs = std::filesystem;
using acro::library::Library;

const char* kCodes[] = {"40o", "41/", "42/", "800o", "801<", "811o", "821o", "831<"};

const fs::path& SeasonLibrary() {
  static const fs::path path = [] {
    const fs::path p =
        fs::temp_directory_path() / fmt::format("acro_library_bench_{}.sqlite", getpid());
    fs::remove(p);
    Library lib(p, Library::Mode::kReadWrite);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (int a = 0; a < 5; ++a)
      for (int s = 0; s < 50; ++s) {
        const std::string date = fmt::format("2026-{:02d}-{:02d}", 1 + s / 28, 1 + s % 28);
        for (int t = 0; t < 4; ++t) {
          nlohmann::json jumps = nlohmann::json::array();
          for (int k = 0; k < 10; ++k)
            jumps.push_back({{"index", k + 1},
                             {"partial", false},
                             {"takeoff_s", 2.0 * k},
                             {"time_of_flight_s", 1.3 + 0.4 * u(rng)},
                             {"displacement_from_takeoff_m", 0.6 * u(rng)},
                             {"apex_above_bed_m", 3 + u(rng)},
                             {"landing_in_bed_m", {u(rng) - 0.5, u(rng) - 0.5}},
                             {"landing_in_zone_a", true},
                             {"fig_code", kCodes[(k + t + s) % 8]},
                             {"skill_name", "skill"},
                             {"difficulty", 1.0},
                             {"verdict", u(rng) < 0.1 ? "fail: timing" : "pass"}});
          acro::library::TrialToStore trial;
          trial.athlete = fmt::format("Athlete {}", a);
          trial.athlete_profile = trial.athlete;
          trial.session_date = date;
          trial.path = fmt::format("/season/{}/{}/{}.c3d", a, date, t);
          trial.sha256 = acro::Sha256Hex(trial.path);
          trial.analysis_version = "0.1.0";
          trial.analysis_source = "analysed";
          trial.jumps_json = jumps.dump();
          lib.StoreTrial(trial);
        }
      }
    return p;
  }();
  return path;
}

acro::library::JumpQuery TheQuery() {
  acro::library::JumpQuery q;
  q.athlete = "Athlete 2";
  q.fig_code = "821o";
  q.date_from = "2026-01-10";
  q.date_to = "2026-02-15";
  return q;
}

void BM_QueryAthleteCodeDates(benchmark::State& state) {
  const Library lib(SeasonLibrary(), Library::Mode::kReadOnly);
  size_t rows = 0;
  for (auto _ : state) {
    rows = lib.QueryJumps(TheQuery()).size();
    benchmark::DoNotOptimize(rows);
  }
  state.counters["jumps_stored"] = double(lib.QueryJumps({}).size());
  state.counters["rows"] = double(rows);
}
BENCHMARK(BM_QueryAthleteCodeDates)->Unit(benchmark::kMillisecond);

// What `acrolab library query` does: open (with the integrity check), then query.
void BM_OpenAndQuery(benchmark::State& state) {
  for (auto _ : state) {
    const Library lib(SeasonLibrary(), Library::Mode::kReadOnly);
    benchmark::DoNotOptimize(lib.QueryJumps(TheQuery()).size());
  }
}
BENCHMARK(BM_OpenAndQuery)->Unit(benchmark::kMillisecond);

// Every jump of the season (export, progress without filters).
void BM_QueryEverything(benchmark::State& state) {
  const Library lib(SeasonLibrary(), Library::Mode::kReadOnly);
  for (auto _ : state) benchmark::DoNotOptimize(lib.QueryJumps({}).size());
}
BENCHMARK(BM_QueryEverything)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ec;
  fs::remove(SeasonLibrary(), ec);
  return 0;
}
