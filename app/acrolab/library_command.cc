// acrolab library add | list | show | query | remove | export | progress: the season library
// (docs/library.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/library/add_trial.h"
#include "acro/library/library.h"
#include "acro/library/progress.h"
#include "acro/report/progress_report.h"
#include "commands.h"

namespace acro::app {

namespace {

struct LibraryArguments {
  std::string library = library::DefaultLibraryPath().string();
  // add
  std::vector<std::string> trials;
  library::AddRequest request;
  std::string athlete, video, calibration, analysis_dir;
  bool quiet = false;
  int threads = 0;
  // list, show, remove
  bool athletes = false, designs = false, json = false, csv = false;
  std::vector<std::string> which;
  // query, progress
  library::JumpQuery query;
  std::string metric = "tof", out;
};

// A stored trial by its id, or by its path as given or as the library names it (absolute, links
// resolved, as `add` stored it).
std::optional<library::TrialSummary> FindStoredTrial(const library::Library& lib,
                                                     const std::string& id_or_path) {
  if (std::optional<library::TrialSummary> t = lib.FindTrialSummary(id_or_path)) return t;
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(id_or_path, ec);
  return ec ? std::nullopt : lib.FindTrialSummary(canonical.string());
}

const char* OutcomeWord(library::AddOutcome o) {
  switch (o) {
    case library::AddOutcome::kAdded:
      return "added";
    case library::AddOutcome::kReanalysed:
      return "re-analysed";
    case library::AddOutcome::kUnchanged:
      return "unchanged";
  }
  return "";
}

int RunAdd(LibraryArguments& args) {
  if (args.trials.size() > 1 && !args.analysis_dir.empty())
    throw UsageError{"--analysis names the analysis of one trial; give one TRIAL with it"};
  library::Library lib(args.library, library::Library::Mode::kReadWrite);
  library::AddRequest request = args.request;
  request.athlete_profile = args.athlete;
  request.video = args.video;
  request.calibration = args.calibration;
  request.analysis_dir = args.analysis_dir;
  library::AddOptions options;
  options.analysis.reconstruction.num_threads = args.threads;
  options.warn = [](const std::string& w) {
    std::fprintf(stderr, "acrolab library add: warning: %s\n", w.c_str());
  };
  if (!args.quiet)
    options.analysis.progress = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
    };
  int failed = 0;
  for (const std::string& trial : args.trials) {
    request.trial = trial;
    try {
      const library::AddResult r = library::AddTrial(lib, request, options);
      if (r.outcome == library::AddOutcome::kUnchanged)
        std::printf("unchanged    %s (stored with this content by this Acrolab)\n", r.path.c_str());
      else
        std::printf("%-12s %s: %d jumps, %s%s\n",
                    OutcomeWord(r.outcome),
                    r.path.c_str(),
                    r.num_jumps,
                    r.verdict.c_str(),
                    r.why.empty() ? "" : (" (" + r.why + ")").c_str());
    } catch (const InputError& e) {
      if (args.trials.size() == 1) throw;
      ++failed;
      std::fprintf(stderr, "acrolab: %s\n", e.what());
    }
  }
  if (failed > 0) {
    std::fprintf(stderr,
                 "acrolab library add: %d of %zu trials not added (each said above)\n",
                 failed,
                 args.trials.size());
    return 1;
  }
  return 0;
}

int RunList(const LibraryArguments& args) {
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  if (args.athletes) {
    const std::vector<library::AthleteSummary> list = lib.ListAthletes();
    std::printf("%-24s %8s %8s %9s %9s %7s %7s\n",
                "athlete",
                "stature",
                "mass",
                "profiles",
                "sessions",
                "trials",
                "jumps");
    for (const library::AthleteSummary& a : list)
      std::printf("%-24s %6.2f m %5.1f kg %9d %9d %7d %7d\n",
                  a.name.c_str(),
                  a.stature_m,
                  a.mass_kg,
                  a.num_profiles,
                  a.num_sessions,
                  a.num_trials,
                  a.num_jumps);
    return 0;
  }
  if (args.designs) {
    const std::vector<library::DesignSummary> list = lib.ListDesigns(args.query.athlete);
    std::printf("%6s  %-18s %-8s %-8s %5s  %-20s  %s\n",
                "id",
                "athlete",
                "kind",
                "codes",
                "DD",
                "created",
                "name");
    for (const library::DesignSummary& d : list)
      std::printf("%6lld  %-18s %-8s %-8s %5.1f  %-20s  %s\n",
                  static_cast<long long>(d.id),
                  d.athlete.c_str(),
                  d.kind.c_str(),
                  d.codes.c_str(),
                  d.difficulty,
                  d.created_at.c_str(),
                  d.name.c_str());
    std::printf("%zu designs in %s\n", list.size(), args.library.c_str());
    return 0;
  }
  const std::vector<library::TrialSummary> trials = lib.ListTrials(args.query.athlete);
  if (args.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const library::TrialSummary& t : trials)
      out.push_back({{"id", t.id},
                     {"athlete", t.athlete},
                     {"date", t.session_date},
                     {"path", t.path},
                     {"sha256", t.sha256},
                     {"verdict", t.verdict},
                     {"jumps", t.num_jumps},
                     {"difficulty", t.difficulty},
                     {"time_of_flight_s", t.time_of_flight_s},
                     {"analysis_version", t.analysis_version}});
    std::printf("%s\n", out.dump(1).c_str());
    return 0;
  }
  std::printf("%6s  %-10s  %-18s %5s %6s %8s  %-10s  %s\n",
              "id",
              "date",
              "athlete",
              "jumps",
              "DD",
              "ToF (s)",
              "verdict",
              "trial");
  for (const library::TrialSummary& t : trials)
    std::printf("%6lld  %-10s  %-18s %5d %6.1f %8.3f  %-10s  %s\n",
                static_cast<long long>(t.id),
                t.session_date.c_str(),
                t.athlete.c_str(),
                t.num_jumps,
                t.difficulty,
                t.time_of_flight_s,
                t.verdict.c_str(),
                t.path.c_str());
  std::printf("%zu trials in %s\n", trials.size(), args.library.c_str());
  return 0;
}

int RunShow(const LibraryArguments& args) {
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const std::optional<library::TrialSummary> t = FindStoredTrial(lib, args.which.front());
  if (!t)
    throw InputError(
        args.library, "", "no trial '" + args.which.front() + "' (acrolab library list)");
  const std::string jumps = lib.TrialJumpsJson(t->id);
  if (args.json) {
    std::printf("%s", jumps.c_str());
    return 0;
  }
  std::printf("trial %lld: %s\n  athlete %s, session %s%s\n  SHA-256 %s, %lld bytes\n",
              static_cast<long long>(t->id),
              t->path.c_str(),
              t->athlete.c_str(),
              t->session_date.c_str(),
              t->session_place.empty() ? "" : (", " + t->session_place).c_str(),
              t->sha256.c_str(),
              static_cast<long long>(t->size_bytes));
  if (!t->video_path.empty())
    std::printf("  video %s, calibration %s\n", t->video_path.c_str(), t->calibration_path.c_str());
  std::printf("  analysed %s by Acrolab %s (%s); verdict %s\n",
              t->analysed_at.c_str(),
              t->analysis_version.c_str(),
              t->analysis_source.c_str(),
              t->verdict.c_str());
  std::printf("  %4s %-6s %-28s %8s %7s %7s %5s  %s\n",
              "jump",
              "code",
              "skill",
              "ToF (s)",
              "HD (m)",
              "apex",
              "DD",
              "verdict");
  for (const library::JumpRecord& j : library::ParseJumpsJson(jumps, t->path))
    std::printf("  %4d %-6s %-28s %8.3f %7.2f %7.2f %5.1f  %s\n",
                j.index,
                j.fig_code.c_str(),
                j.skill_name.c_str(),
                j.time_of_flight_s,
                j.displacement_m,
                j.apex_above_bed_m,
                j.difficulty,
                j.verdict.c_str());
  return 0;
}

int RunQuery(const LibraryArguments& args) {
  DemandValidCommandLine(args.query);
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<library::JumpRow> rows = lib.QueryJumps(args.query);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::string text;
  if (args.json)
    text = library::FormatJumpRowsJson(rows);
  else if (args.csv || !args.out.empty())
    text = library::FormatJumpRowsCsv(rows);
  if (!args.out.empty()) {
    WriteFileAtomically(
        args.out, args.json ? library::FormatJumpRowsJson(rows) : library::FormatJumpRowsCsv(rows));
    std::printf("%zu jumps (query %.1f ms) written to %s\n", rows.size(), ms, args.out.c_str());
    return 0;
  }
  if (!text.empty()) {
    std::fputs(text.c_str(), stdout);
    return 0;
  }
  std::printf("%-10s  %-16s %4s %-6s %8s %7s %5s  %-10s  %s\n",
              "date",
              "athlete",
              "jump",
              "code",
              "ToF (s)",
              "HD (m)",
              "DD",
              "verdict",
              "trial");
  for (const library::JumpRow& r : rows)
    std::printf("%-10s  %-16s %4d %-6s %8.3f %7.2f %5.1f  %-10s  %s\n",
                r.session_date.c_str(),
                r.athlete.c_str(),
                r.jump.index,
                r.jump.fig_code.c_str(),
                r.jump.time_of_flight_s,
                r.jump.displacement_m,
                r.jump.difficulty,
                r.jump.verdict_class.c_str(),
                r.trial_path.c_str());
  std::printf("%zu jumps (query %.1f ms)\n", rows.size(), ms);
  return 0;
}

int RunRemove(const LibraryArguments& args) {
  library::Library lib(args.library, library::Library::Mode::kReadWrite);
  int missing = 0;
  for (const std::string& w : args.which) {
    const std::optional<library::TrialSummary> t = FindStoredTrial(lib, w);
    const std::string path = t ? t->path : w;
    if (lib.RemoveTrial(path)) {
      std::printf("removed %s (the file itself is untouched)\n", path.c_str());
    } else {
      std::fprintf(
          stderr, "acrolab library remove: no trial '%s' in %s\n", w.c_str(), args.library.c_str());
      ++missing;
    }
  }
  return missing > 0 ? 1 : 0;
}

int RunExport(const LibraryArguments& args) {
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const std::string ext = LowerExtension(args.out);
  if (ext != "csv" && ext != "json")
    throw UsageError{"-o " + args.out +
                     ": give a .csv (every jump) or .json (every trial with "
                     "its jumps.json) file"};
  if (ext == "csv") {
    library::JumpQuery all;
    all.include_partial = true;
    const std::vector<library::JumpRow> rows = lib.QueryJumps(all);
    WriteFileAtomically(args.out, library::FormatJumpRowsCsv(rows));
    std::printf("%zu jumps written to %s\n", rows.size(), args.out.c_str());
    return 0;
  }
  nlohmann::json out;
  out["library"] = args.library;
  out["schema_version"] = lib.schema_version();
  out["trials"] = nlohmann::json::array();
  const std::vector<library::TrialSummary> trials = lib.ListTrials();
  for (const library::TrialSummary& t : trials)
    out["trials"].push_back({{"id", t.id},
                             {"athlete", t.athlete},
                             {"date", t.session_date},
                             {"place", t.session_place},
                             {"path", t.path},
                             {"sha256", t.sha256},
                             {"video", t.video_path},
                             {"calibration", t.calibration_path},
                             {"analysis_version", t.analysis_version},
                             {"analysed_at", t.analysed_at},
                             {"verdict", t.verdict},
                             {"jumps", nlohmann::json::parse(lib.TrialJumpsJson(t.id))}});
  WriteFileAtomically(args.out, out.dump(1) + "\n");
  std::printf("%zu trials written to %s\n", trials.size(), args.out.c_str());
  return 0;
}

int RunProgress(const LibraryArguments& args) {
  library::JumpQuery query = args.query;
  query.include_partial = false;
  DemandValidCommandLine(query);
  const library::ProgressMetric metric = library::ParseProgressMetric(args.metric);
  CheckOutputDirectory(args.out);
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const library::Progress progress =
      library::CalcProgress(lib.QueryJumps(query), metric, query.athlete, query.fig_code);
  OutputTransaction outputs(args.out);
  ui::WriteProgressReport(progress, outputs.staging());
  outputs.Commit();
  std::printf("%s%s: %s over %zu sessions (%zu jumps), trend %+.3g %s per 30 days\n",
              progress.athlete.c_str(),
              progress.fig_code.empty() ? "" : (" " + progress.fig_code).c_str(),
              progress.metric_name.c_str(),
              progress.sessions.size(),
              progress.points.size(),
              30 * progress.trend_slope_per_day,
              progress.unit.c_str());
  std::printf("report: %s\n", (outputs.dir() / "progress.html").string().c_str());
  return 0;
}

void DeclareLibraryOption(CLI::App* command, LibraryArguments* args) {
  command->add_option("--library",
                      args->library,
                      "the library file (default ~/.local/share/acrolab/library.sqlite)");
}

void DeclareFilters(CLI::App* command, LibraryArguments* args, bool athlete_required) {
  library::JumpQuery& q = args->query;
  CLI::Option* a =
      command->add_option("--athlete", q.athlete, "the athlete's name (as her profile gives it)");
  if (athlete_required) a->required();
  command->add_option("--code", q.fig_code, "a FIG code, e.g. 821o");
  command->add_option("--from", q.date_from, "first session date, YYYY-MM-DD");
  command->add_option("--to", q.date_to, "last session date, YYYY-MM-DD");
}

}  // namespace

void AddLibraryCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<LibraryArguments>();
  CLI::App* lib = app.add_subcommand(
      "library",
      "The season library: trials, their jumps and verdicts, athletes and sessions in one SQLite "
      "file; queries and progress charts. docs/library.md.");
  lib->require_subcommand(1);

  CLI::App* add = lib->add_subcommand(
      "add",
      "Analyses each TRIAL (as acrolab analyze does, without a video) and stores it; an unchanged "
      "file already stored by this Acrolab is left alone, a changed one is analysed again.");
  add->add_option("TRIAL", args->trials, "C3D, TRC or CSV trials")->required();
  add->add_option("--athlete", args->athlete, "the athlete's profile (docs/formats/athlete.md)")
      ->required();
  add->add_option("--session",
                  args->request.session_date,
                  "the session's date, YYYY-MM-DD (default: the file's modification date)");
  add->add_option("--place", args->request.session_place, "where the session was");
  add->add_option("--notes", args->request.session_notes, "the session's notes");
  add->add_option("--video", args->video, "a video of the trial, attached");
  add->add_option("--calib", args->calibration, "its camera calibration, attached");
  add->add_option("--analysis",
                  args->analysis_dir,
                  "store this acrolab analyze output of TRIAL instead of analysing");
  add->add_flag("--force", args->request.force, "analyse again even when unchanged");
  add->add_flag("--quiet", args->quiet, "no progress on stderr");
  add->add_option("--threads", args->threads, "worker threads of the analysis (default: all cores)")
      ->check(CLI::Range(1, 256));
  DeclareLibraryOption(add, args.get());
  add->callback([args, run] { *run = [args] { return RunAdd(*args); }; });

  CLI::App* list = lib->add_subcommand("list", "The stored trials, newest session first.");
  list->add_option("--athlete", args->query.athlete, "only this athlete's");
  list->add_flag("--athletes", args->athletes, "the athletes instead, with their counts");
  list->add_flag("--designs",
                 args->designs,
                 "the designed skills and routines instead (acrolab optimize --library)");
  list->add_flag("--json", args->json, "as JSON");
  DeclareLibraryOption(list, args.get());
  list->callback([args, run] { *run = [args] { return RunList(*args); }; });

  CLI::App* show = lib->add_subcommand("show", "One stored trial and its jumps.");
  show->add_option("TRIAL", args->which, "its id (acrolab library list) or path")
      ->required()
      ->expected(1);
  show->add_flag("--json", args->json, "its stored jumps.json");
  DeclareLibraryOption(show, args.get());
  show->callback([args, run] { *run = [args] { return RunShow(*args); }; });

  CLI::App* query =
      lib->add_subcommand("query", "The jumps that match the filters, as a table, CSV or JSON.");
  DeclareFilters(query, args.get(), false);
  library::JumpQuery& q = args->query;
  query->add_option("--verdict", q.verdict_class, "pass, fail or 'not judged'");
  query->add_option("--tof-min", q.min_time_of_flight_s, "shortest time of flight (s)");
  query->add_option("--tof-max", q.max_time_of_flight_s, "longest time of flight (s)");
  query->add_option("--hd-min", q.min_displacement_m, "least horizontal displacement (m)");
  query->add_option("--hd-max", q.max_displacement_m, "most horizontal displacement (m)");
  query->add_flag("--partial", q.include_partial, "include partial flights");
  query->add_flag("--json", args->json, "as JSON");
  query->add_flag("--csv", args->csv, "as CSV");
  query->add_option("-o,--output", args->out, "write to this file (CSV, or JSON with --json)");
  DeclareLibraryOption(query, args.get());
  query->callback([args, run] { *run = [args] { return RunQuery(*args); }; });

  CLI::App* remove = lib->add_subcommand(
      "remove", "Removes trials (by id or path) and their jumps; the files are untouched.");
  remove->add_option("TRIAL", args->which, "ids or paths")->required();
  DeclareLibraryOption(remove, args.get());
  remove->callback([args, run] { *run = [args] { return RunRemove(*args); }; });

  CLI::App* exp = lib->add_subcommand(
      "export", "Every jump as CSV, or every trial with its jumps as JSON, by -o's extension.");
  exp->add_option("-o,--output", args->out, "FILE.csv or FILE.json")->required();
  DeclareLibraryOption(exp, args.get());
  exp->callback([args, run] { *run = [args] { return RunExport(*args); }; });

  CLI::App* progress = lib->add_subcommand(
      "progress",
      "An athlete's season: the metric per jump, session medians and trend, landings on the bed "
      "per session with zone A; DIR/progress.html with PNG and SVG charts and progress.csv.");
  DeclareFilters(progress, args.get(), true);
  progress->add_option("--metric", args->metric, "tof, hd, dd, apex or verdict (default tof)")
      ->check(CLI::IsMember({"tof", "hd", "dd", "apex", "verdict"}));
  progress->add_option("-o,--output", args->out, "output folder (created)")->required();
  DeclareLibraryOption(progress, args.get());
  progress->callback([args, run] { *run = [args] { return RunProgress(*args); }; });
}

}  // namespace acro::app
