// acrolab batch DIR|LIST: many trials into the library, each as its own `acrolab library add`
// process, N at a time; resumable from the library's state (docs/library.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/interrupts.h"
#include "acro/base/process.h"
#include "acro/library/add_trial.h"
#include "acro/library/batch_jobs.h"
#include "acro/library/library.h"
#include "commands.h"

namespace acro::app {

namespace {

struct BatchArguments {
  std::string source;
  int jobs = 2;
  std::string library = library::DefaultLibraryPath().string();
  std::string athlete, session;
  bool print_jobs = false;
  int only_job = 0;
  std::string analyses_to, analyses;
};

// The command that runs one job: `acrolab library add …` into the library, or with
// --analyses-to, `acrolab analyze …` into its own folder (for machines that do not share the
// library's disk).
std::vector<std::string> JobCommand(const BatchArguments& args,
                                    const library::BatchJob& job,
                                    const std::string& self,
                                    bool here) {
  std::vector<std::string> argv = {self};
  if (!args.analyses_to.empty()) {
    argv.insert(
        argv.end(),
        {"analyze",
         job.words[0],
         "--athlete",
         job.request.athlete_profile.string(),
         "--no-images",
         "--quiet",
         "-o",
         (std::filesystem::path(args.analyses_to) / fmt::format("job-{}", job.number)).string()});
    return argv;
  }
  argv.insert(argv.end(), {"library", "add"});
  argv.insert(argv.end(), job.words.begin(), job.words.end());
  if (!job.request.analysis_dir.empty() &&
      std::filesystem::exists(job.request.analysis_dir / "analysis.json"))
    argv.insert(argv.end(), {"--analysis", job.request.analysis_dir.string()});
  argv.insert(argv.end(), {"--library", args.library, "--quiet"});
  if (!here) return argv;  // (another machine's scheduler decides its threads)
  // The cores shared among the jobs running at once (more threads than cores only slows them).
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  argv.insert(argv.end(),
              {"--threads", std::to_string(std::max(1, cores / std::max(1, args.jobs)))});
  return argv;
}

int RunBatch(const BatchArguments& args) {
  if (!args.analyses.empty() && !args.analyses_to.empty())
    throw UsageError{"--analyses-to makes the analyses, --analyses stores them: one at a time"};
  library::BatchDefaults defaults;
  defaults.athlete = args.athlete;
  defaults.session = args.session;
  defaults.analyses = args.analyses;
  std::vector<library::BatchJob> jobs = library::ReadBatchJobs(args.source, defaults);
  if (jobs.empty()) throw InputError(args.source, "", "no trials (C3D or TRC) to add");
  if (args.only_job > int(jobs.size()))
    throw UsageError{fmt::format("--job {}: the list has {} jobs", args.only_job, jobs.size())};
  const std::string self = CurrentExecutable().empty() ? "acrolab" : CurrentExecutable();

  // What is left to do, from the library's state: an interrupted batch starts again here.
  std::vector<const library::BatchJob*> pending;
  int unchanged = 0;
  std::vector<std::string> failures;
  if (!args.analyses_to.empty()) {
    // Analyses into folders: a job whose folder holds its analysis is done.
    for (const library::BatchJob& j : jobs) {
      if (args.only_job > 0 && j.number != args.only_job) continue;
      const std::filesystem::path done = std::filesystem::path(args.analyses_to) /
                                         fmt::format("job-{}", j.number) / "analysis.json";
      if (std::filesystem::exists(done))
        ++unchanged;
      else
        pending.push_back(&j);
    }
  } else {
    // Opening it for writing creates (or migrates) the library once, before the jobs share it.
    const library::Library lib(args.library, library::Library::Mode::kReadWrite);
    for (const library::BatchJob& j : jobs) {
      if (args.only_job > 0 && j.number != args.only_job) continue;
      try {
        library::AddRequest request = j.request;
        if (!std::filesystem::exists(request.analysis_dir / "analysis.json"))
          request.analysis_dir.clear();
        if (library::PlanAdd(lib, request).outcome == library::AddOutcome::kUnchanged)
          ++unchanged;
        else
          pending.push_back(&j);
      } catch (const InputError& e) {
        failures.push_back(e.what());
      }
    }
  }
  if (args.print_jobs) {
    for (const library::BatchJob* j : pending) {
      std::string line;
      for (const std::string& w : JobCommand(args, *j, "acrolab", false))
        line += (line.empty() ? "" : " ") + library::ShellQuote(w);
      std::printf("%s\n", line.c_str());
    }
    std::fprintf(
        stderr, "acrolab batch: %zu jobs to run, %d unchanged\n", pending.size(), unchanged);
    return 0;
  }

  std::fprintf(stderr,
               "batch: %zu trials: %d already in the library, %zu to %s with %d at a time\n",
               jobs.size(),
               unchanged,
               pending.size(),
               args.analyses_to.empty() ? "add" : "analyse",
               args.jobs);
  std::vector<std::vector<std::string>> commands;
  for (const library::BatchJob* j : pending) commands.push_back(JobCommand(args, *j, self, true));
  const auto bar = MakeProgressBar("batch", "trials");
  int done = 0, ok = 0;
  const auto start = std::chrono::steady_clock::now();
  bar(0, int(commands.size()));
  RunProcesses(commands, args.jobs, [&](size_t k, const ProcessOutcome& outcome) {
    ++done;
    if (outcome.ok()) {
      ++ok;
    } else {
      std::string why = outcome.last_error_line;
      if (outcome.signal != 0)
        why = fmt::format("stopped by signal {}{}", outcome.signal, why.empty() ? "" : ": " + why);
      if (why.empty()) why = fmt::format("exit status {}", outcome.exit_status);
      // The job's one line names the file already (acrolab: FILE: where: what).
      if (why.rfind("acrolab: ", 0) == 0) why = why.substr(9);
      const std::string& trial = pending[k]->words[0];
      failures.push_back(why.rfind(trial, 0) == 0 ? why : trial + ": " + why);
    }
    bar(done, int(commands.size()));
  });
  // Stopped by Ctrl-C or SIGTERM: the jobs it killed are not failures, and the interrupt thread's
  // line is the batch's last word (run it again to go on).
  if (acro::InterruptReceived()) return acro::ExitStatusUnlessInterrupted(1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("batch: %zu trials: %d %s, %d unchanged, %zu failed (%.1f s)\n",
              jobs.size(),
              ok,
              args.analyses_to.empty() ? "added" : "analysed",
              unchanged,
              failures.size(),
              seconds);
  for (const std::string& f : failures) std::printf("  failed: %s\n", f.c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace

void AddBatchCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<BatchArguments>();
  CLI::App* command = app.add_subcommand(
      "batch",
      "Adds many trials to the library, each analysed by its own process, -j at a time; one bad "
      "file never stops the batch, and a batch stopped half-way goes on where it stopped when run "
      "again. SOURCE is a folder (every C3D and TRC under it) or a job list: one trial per line "
      "with its own --athlete, --session, --place, --notes, --video, --calib. docs/library.md.");
  command->add_option("SOURCE", args->source, "a folder or a job list file")->required();
  command->add_option("-j,--jobs", args->jobs, "trials analysed at once (default 2)")
      ->check(CLI::Range(1, 256));
  command->add_option("--athlete", args->athlete, "the profile for trials whose line names none");
  command->add_option(
      "--session", args->session, "the session date for trials whose line names none");
  command->add_option("--library",
                      args->library,
                      "the library file (default ~/.local/share/acrolab/library.sqlite)");
  command->add_flag("--print-jobs",
                    args->print_jobs,
                    "print the command of each job left to do, one per line, and run none (for "
                    "GNU parallel or a cluster's scheduler)");
  command
      ->add_option(
          "--job", args->only_job, "run only job K of the list (1-based; a Slurm array index)")
      ->check(CLI::Range(1, 100000000));
  command->add_option("--analyses-to",
                      args->analyses_to,
                      "analyse into ROOT/job-K (acrolab analyze) instead of adding: for machines "
                      "that do not share the library's disk");
  command->add_option("--analyses",
                      args->analyses,
                      "store the analyses of --analyses-to's ROOT/job-K where present (analysing "
                      "the rest)");
  command->callback([args, run] { *run = [args] { return RunBatch(*args); }; });
}

}  // namespace acro::app
