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

// One job: a trial and the `library add` options of its line.
struct Job {
  int number = 0;                  ///< 1-based, in the list's order
  std::string where;               ///< "LIST:line" for messages
  std::vector<std::string> words;  ///< TRIAL then options
  library::AddRequest request;
};

// A line's words: blanks separate, '…' and "…" quote, \ escapes (a subset of the shell's).
std::vector<std::string> SplitWords(const std::string& line, const std::string& where) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  char quote = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) {
        quote = 0;
      } else if (c == '\\' && quote == '"' && i + 1 < line.size()) {
        word += line[++i];
      } else {
        word += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (c == '\\' && i + 1 < line.size()) {
      word += line[++i];
      in_word = true;
    } else if (c == ' ' || c == '\t') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else if (c == '#' && !in_word) {
      break;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (quote) throw InputError(where, "", "a quote is not closed");
  if (in_word) words.push_back(word);
  return words;
}

std::string ShellQuote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_./=:,+@%") == std::string::npos)
    return word;
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The value after `option` in the words, or empty.
std::string OptionValue(const std::vector<std::string>& words, const std::string& option) {
  for (size_t i = 1; i + 1 < words.size(); ++i)
    if (words[i] == option) return words[i + 1];
  return {};
}

std::vector<Job> ReadJobs(const BatchArguments& args) {
  std::vector<Job> jobs;
  const std::filesystem::path source = args.source;
  if (std::filesystem::is_directory(source)) {
    // Every C3D and TRC under DIR, in name order.
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(source)) {
      const std::string ext = LowerExtension(entry.path());
      if (entry.is_regular_file() && (ext == "c3d" || ext == "trc")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      Job j;
      j.where = f.string();
      j.words = {std::filesystem::absolute(f).lexically_normal().string()};
      jobs.push_back(j);
    }
  } else {
    std::ifstream in(source);
    if (!in) throw InputError(args.source, "", "neither a directory nor a readable job list");
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      const std::string where = fmt::format("{}: line {}", args.source, number);
      std::vector<std::string> words = SplitWords(line, where);
      if (words.empty()) continue;
      // A relative trial path is relative to the list's folder.
      std::filesystem::path trial = words[0];
      if (trial.is_relative()) trial = source.parent_path() / trial;
      words[0] = std::filesystem::absolute(trial).lexically_normal().string();
      for (size_t i = 1; i < words.size(); ++i) {
        static const std::vector<std::string> kTakes = {
            "--athlete", "--session", "--place", "--notes", "--video", "--calib"};
        if (std::find(kTakes.begin(), kTakes.end(), words[i]) == kTakes.end() ||
            i + 1 == words.size())
          throw InputError(where,
                           "",
                           "'" + words[i] +
                               "' is not one of --athlete, --session, --place, --notes, "
                               "--video, --calib with its value");
        if (words[i] != "--session" && words[i] != "--place" && words[i] != "--notes") {
          std::filesystem::path file = words[i + 1];
          if (file.is_relative())
            words[i + 1] = (source.parent_path() / file).lexically_normal().string();
        }
        ++i;
      }
      Job j;
      j.where = where;
      j.words = words;
      jobs.push_back(j);
    }
  }
  for (size_t k = 0; k < jobs.size(); ++k) {
    Job& j = jobs[k];
    j.number = int(k + 1);
    if (OptionValue(j.words, "--athlete").empty()) {
      if (args.athlete.empty())
        throw InputError(
            j.where, "", "no --athlete for this trial (give one to batch, or on the line)");
      j.words.insert(j.words.end(), {"--athlete", args.athlete});
    }
    if (OptionValue(j.words, "--session").empty() && !args.session.empty())
      j.words.insert(j.words.end(), {"--session", args.session});
    j.request.trial = j.words[0];
    j.request.athlete_profile = OptionValue(j.words, "--athlete");
    if (!args.analyses.empty())
      j.request.analysis_dir =
          std::filesystem::path(args.analyses) / fmt::format("job-{}", j.number);
  }
  return jobs;
}

// The command that runs one job: `acrolab library add …` into the library, or with
// --analyses-to, `acrolab analyze …` into its own folder (for machines that do not share the
// library's disk).
std::vector<std::string> JobCommand(const BatchArguments& args,
                                    const Job& job,
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
  std::vector<Job> jobs = ReadJobs(args);
  if (jobs.empty()) throw InputError(args.source, "", "no trials (C3D or TRC) to add");
  if (args.only_job > int(jobs.size()))
    throw UsageError{fmt::format("--job {}: the list has {} jobs", args.only_job, jobs.size())};
  const std::string self = CurrentExecutable().empty() ? "acrolab" : CurrentExecutable();

  // What is left to do, from the library's state: an interrupted batch starts again here.
  std::vector<const Job*> pending;
  int unchanged = 0;
  std::vector<std::string> failures;
  if (!args.analyses_to.empty()) {
    // Analyses into folders: a job whose folder holds its analysis is done.
    for (const Job& j : jobs) {
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
    for (const Job& j : jobs) {
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
    for (const Job* j : pending) {
      std::string line;
      for (const std::string& w : JobCommand(args, *j, "acrolab", false))
        line += (line.empty() ? "" : " ") + ShellQuote(w);
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
  for (const Job* j : pending) commands.push_back(JobCommand(args, *j, self, true));
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
