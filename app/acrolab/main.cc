// acrolab: the command-line front of Acrolab. Thin by design: parse, call one library function
// per step, print. See docs/cli.md.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "commands.h"

namespace {

constexpr const char* kUsage =
    "usage: acrolab <command> [options]\n"
    "\n"
    "commands:\n"
    "  info FILE [--json]     what a C3D/TRC/CSV file holds: rates, markers, gaps, analog, plates, "
    "events\n"
    "  convert IN OUT         convert between C3D, TRC and CSV (by file extension)\n"
    "  body ...               athlete segments, mass, centre of mass, inertia; tuck/pike ratios\n"
    "  reconstruct TRIAL -o DIR  markers or keypoints to joint angles (.mot, CSV, C3D)\n"
    "  optimize SKILL.yaml -o DIR  keyframe timing / trajectory optimisation of a skill\n"
    "  analyze TRIAL -o DIR   the main job: reconstruct, check the physics, measure every jump,\n"
    "                         report.html with plots\n"
    "\n"
    "  acrolab <command> --help for a command's options; docs/cli.md for everything.\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    if (command == "info") return acro::app::RunInfo(args);
    if (command == "convert") return acro::app::RunConvert(args);
    if (command == "body") return acro::app::RunBody(args);
    if (command == "reconstruct") return acro::app::RunReconstruct(args);
    if (command == "optimize") return acro::app::RunOptimize(args);
    if (command == "analyze") return acro::app::RunAnalyze(args);
    if (command == "--version") {
      std::puts("acrolab 0.1.0");
      return 0;
    }
    std::fprintf(stderr, "acrolab: unknown command '%s'\n%s", command.c_str(), kUsage);
    return 2;
  } catch (const acro::app::UsageError& e) {
    std::fprintf(stderr,
                 "acrolab %s: %s (acrolab %s --help)\n",
                 command.c_str(),
                 e.message.c_str(),
                 command.c_str());
    return 2;
  } catch (const acro::InputError& e) {
    std::fprintf(stderr, "acrolab: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "acrolab: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "acrolab: internal error: %s\n", e.what());
    return 3;
  }
}
