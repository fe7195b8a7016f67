// acrolab library add | list | show | query | remove | export | progress: the season library
// (docs/library.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/library/add_trial.h"
#include "acro/library/library.h"
#include "acro/library/progress.h"
#include "acro/report/library_text.h"
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

// A library this run created and into which nothing went is removed when the run ends (a failed
// first `library add` leaves no empty library behind: nothing half-written).
struct NewLibraryGuard {
  std::filesystem::path path;
  bool created = false, stored = false;
  ~NewLibraryGuard() {
    if (!created || stored) return;
    std::error_code ec;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"})
      std::filesystem::remove(path.string() + suffix, ec);
  }
};

int RunAdd(LibraryArguments& args) {
  if (args.trials.size() > 1 && !args.analysis_dir.empty())
    throw UsageError{"--analysis names the analysis of one trial; give one TRIAL with it"};
  NewLibraryGuard guard{args.library, !PathExists(args.library)};
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
      guard.stored = true;
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
  if (args.athletes)
    std::fputs(ui::FormatAthleteTable(lib.ListAthletes()).c_str(), stdout);
  else if (args.designs)
    std::fputs(ui::FormatDesignTable(lib.ListDesigns(args.query.athlete), args.library).c_str(),
               stdout);
  else if (args.json)
    std::fputs(ui::FormatTrialListJson(lib.ListTrials(args.query.athlete)).c_str(), stdout);
  else
    std::fputs(ui::FormatTrialTable(lib.ListTrials(args.query.athlete), args.library).c_str(),
               stdout);
  return 0;
}

int RunShow(const LibraryArguments& args) {
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const std::optional<library::TrialSummary> t = FindStoredTrial(lib, args.which.front());
  if (!t)
    throw InputError(
        args.library, "", "no trial '" + args.which.front() + "' (acrolab library list)");
  const std::string jumps = lib.TrialJumpsJson(t->id);
  std::fputs((args.json ? jumps : ui::FormatTrialDetails(*t, jumps)).c_str(), stdout);
  return 0;
}

int RunQuery(const LibraryArguments& args) {
  DemandValidCommandLine(args.query);
  const library::Library lib(args.library, library::Library::Mode::kReadOnly);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<library::JumpRow> rows = lib.QueryJumps(args.query);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const std::string data =
      args.json ? library::FormatJumpRowsJson(rows) : library::FormatJumpRowsCsv(rows);
  if (!args.out.empty()) {
    WriteFileAtomically(args.out, data);
    std::printf("%zu jumps (query %.1f ms) written to %s\n", rows.size(), ms, args.out.c_str());
  } else {
    std::fputs((args.json || args.csv ? data : ui::FormatJumpRowTable(rows, ms)).c_str(), stdout);
  }
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
  WriteFileAtomically(args.out, ui::FormatLibraryExportJson(lib, args.library));
  std::printf("%zu trials written to %s\n", lib.ListTrials().size(), args.out.c_str());
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
  progress
      ->add_option("--metric",
                   args->metric,
                   "tof, hd, dd, apex, verdict (per jump), faults (per element), T or H (per "
                   "routine, as the score sheet counts them) (default tof)")
      ->check(CLI::IsMember({"tof", "hd", "dd", "apex", "verdict", "faults", "T", "H"}));
  progress->add_option("-o,--output", args->out, "output folder (created)")->required();
  DeclareLibraryOption(progress, args.get());
  progress->callback([args, run] { *run = [args] { return RunProgress(*args); }; });
}

}  // namespace acro::app
