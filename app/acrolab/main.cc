// acrolab: the command-line front of Acrolab. Thin by design: parse, call one library function
// per step, print. See docs/cli.md.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "acro/base/input_error.h"
#include "acro/base/interrupts.h"
#include "acro/base/progress.h"
#include "acro/base/version.h"
#include "acro/library/library.h"
#include "commands.h"

namespace {

// "acrolab analyze" for messages about the parsed subcommand, "acrolab" before one is known.
std::string CommandName(const CLI::App& app) {
  std::string name = "acrolab";
  for (const CLI::App* level = &app;;) {
    const std::vector<CLI::App*> parsed = level->get_subcommands();
    if (parsed.empty()) return name;
    level = parsed.front();
    name += " " + level->get_name();
  }
}

// The first number option of the parsed command whose value is not a finite number, as the line
// to print; empty when all are. One rule for every FLOAT option of every command (`--offset-s nan`
// and `--time nan` used to be taken).
std::string NonFiniteOption(const CLI::App& app) {
  for (const CLI::App* level = &app;;) {
    for (const CLI::Option* option : level->get_options()) {
      if (option->get_type_name().rfind("FLOAT", 0) != 0) continue;
      for (const std::string& value : option->results()) {
        char* end = nullptr;
        const double number = std::strtod(value.c_str(), &end);
        if (end != value.c_str() && !std::isfinite(number))
          return option->get_name() + ": '" + value + "' is not a finite number";
      }
    }
    const std::vector<CLI::App*> parsed = level->get_subcommands();
    if (parsed.empty()) return "";
    level = parsed.front();
  }
}

int Main(int argc, char** argv) {
  CLI::App app(
      "Acrolab: training analysis for trampoline and other aerial sports. docs/cli.md has every "
      "command and output.",
      "acrolab");
  app.set_version_flag("--version", std::string("acrolab ") + acro::AcrolabVersion());
  app.require_subcommand(1);
  app.fallthrough(false);
  acro::app::CommandRunner run;
  acro::app::AddInfoCommand(app, &run);
  acro::app::AddConvertCommand(app, &run);
  acro::app::AddBodyCommand(app, &run);
  acro::app::AddReconstructCommand(app, &run);
  acro::app::AddOptimizeCommand(app, &run);
  acro::app::AddDesignCommand(app, &run);
  acro::app::AddRoutineCommand(app, &run);
  acro::app::AddAnalyzeCommand(app, &run);
  acro::app::AddVideoCommand(app, &run);
  acro::app::AddProjectCommand(app, &run);
  acro::app::AddCalibrateCommand(app, &run);
  acro::app::AddSyncCommand(app, &run);
  acro::app::AddOverlayCommand(app, &run);
  acro::app::AddCompareCommand(app, &run);
  acro::app::AddSynchroCommand(app, &run);
  acro::app::AddLibraryCommand(app, &run);
  acro::app::AddBatchCommand(app, &run);
  acro::app::AddDetectCommand(app, &run);
  acro::app::AddLiveCommand(app, &run);

  // Parse: --help and --version exit 0; a bad command line exits 2 with one line and the hint.
  if (argc > 1 && argv[1][0] != '-' &&
      app.get_subcommands([&](CLI::App* c) { return c->get_name() == argv[1]; }).empty()) {
    std::fprintf(stderr, "acrolab: unknown command '%s' (acrolab --help)\n", argv[1]);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string name = CommandName(app);
    // CLI11 repeats the value given: escaped, as every message (a terminal escape typed into an
    // option must not reach the terminal raw).
    std::fprintf(stderr,
                 "%s: %s (%s --help)\n",
                 name.c_str(),
                 acro::EscapeForTerminal(e.what()).c_str(),
                 name.c_str());
    return 2;
  }

  // Run.
  const std::string name = CommandName(app);
  if (const std::string bad = NonFiniteOption(app); !bad.empty()) {
    std::fprintf(stderr,
                 "%s: %s (%s --help)\n",
                 name.c_str(),
                 acro::EscapeForTerminal(bad).c_str(),
                 name.c_str());
    return 2;
  }
  try {
    return run();
  } catch (const acro::app::UsageError& e) {
    std::fprintf(stderr,
                 "%s: %s (%s --help)\n",
                 name.c_str(),
                 acro::EscapeForTerminal(e.message).c_str(),
                 name.c_str());
    return 2;
  } catch (const acro::InputError& e) {
    std::fprintf(stderr, "acrolab: %s\n", e.what());
    return 1;
  } catch (const acro::Cancelled& e) {  // the work stopped by its progress (a door's own cancel)
    std::fprintf(stderr, "acrolab: %s\n", acro::EscapeForTerminal(e.what()).c_str());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A file system refusal (a link loop, no permission, a vanished folder) is the named path's
    // fault, never an internal error.
    const std::string path = e.path1().empty() ? std::string() : e.path1().string() + ": ";
    std::fprintf(
        stderr, "acrolab: %s\n", acro::EscapeForTerminal(path + e.code().message()).c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "acrolab: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(
        stderr, "acrolab: internal error: %s\n", acro::EscapeForTerminal(e.what()).c_str());
    return 3;
  }
}

}  // namespace

int main(int argc, char** argv) {
  acro::InstallInterruptCleanup();
  // A library locked by another process: said at once, with the wait (docs/library.md, "Locks").
  acro::library::Library::SetLockNotice(
      [](const std::string& line) { std::fprintf(stderr, "acrolab: %s\n", line.c_str()); });
  return acro::ExitStatusUnlessInterrupted(Main(argc, argv));
}
