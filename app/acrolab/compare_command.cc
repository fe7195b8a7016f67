// `acrolab compare A[:JUMP] B[:JUMP]`: two jumps side by side, aligned at take-off, in 3D views
// over the curves of both. Built only with the views (ACRO_HAVE_VIEWS).

#include <cstdio>
#include <memory>
#include <optional>

#include "acro/pipeline/steps.h"
#include "commands.h"

#ifdef ACRO_HAVE_VIEWS

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/body_mesh.h"
#include "acro/base/file_io.h"
#include "acro/capture/trial_io.h"
#include "acro/report/compare_report.h"
#include "acro/scene/compare_scene.h"
#include "acro/scene/place_scene.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/compare_video.h"
#endif

namespace acro::app {

namespace {

struct CompareArguments {
  std::string a, b, athlete_a, athlete_b, out, view = "side";
  double slow = 1.0;
  bool follow = false;
};

#ifdef ACRO_HAVE_VIEWS
// "trial.c3d:3" → (trial.c3d, 3); no ":N" suffix → (the path, 0: the first complete jump).
std::pair<std::string, int> SplitJump(const std::string& text) {
  const size_t colon = text.rfind(':');
  if (colon != std::string::npos && colon + 1 < text.size() &&
      text.find_first_not_of("0123456789", colon + 1) == std::string::npos) {
    const std::string digits = text.substr(colon + 1);
    if (digits.size() > 6 || std::stoi(digits) < 1)
      throw UsageError{"'" + text + "': jumps are numbered from 1, as in jumps.json"};
    const int jump = std::stoi(digits);
    return {text.substr(0, colon), jump};
  }
  return {text, 0};
}

// A trial read and analysed for an athlete.
struct Analysed {
  std::string path, athlete;
  capture::Trial trial;
  analysis::AthleteBody body;
  analysis::TrialAnalysis analysis;
};

// One side: an analysed trial (shared when both jumps are of one trial) and the jump chosen.
struct Side {
  std::shared_ptr<const Analysed> trial;
  int jump = 0;
  std::string label;
};

Side Choose(const std::string& spec,
            const std::string& athlete,
            std::shared_ptr<const Analysed> same) {
  Side side;
  const auto [path, jump] = SplitJump(spec);
  if (same && same->path == path && same->athlete == athlete) {
    side.trial = same;
  } else {
    std::fprintf(stderr, "analysing %s\n", path.c_str());
    auto analysed = std::make_shared<Analysed>();
    analysed->path = path;
    analysed->athlete = athlete;
    // Opened as every door opens a trial: upright, its athlete or the one default body.
    pipeline::TrialRequest request;
    request.trial = path;
    request.athlete.profile = athlete;
    pipeline::TrialInput input = OpenTrialFor("compare", request);
    analysed->analysis = pipeline::Analyze(input);
    analysed->trial = std::move(input.trial);
    analysed->body = std::move(input.athlete.body);
    side.trial = analysed;
  }
  const analysis::TrialAnalysis& a = side.trial->analysis;
  side.jump = jump;
  if (jump == 0) {  // the first complete jump
    for (const analysis::JumpMetrics& j : a.jumps)
      if (!j.partial()) {
        side.jump = j.index;
        break;
      }
    if (side.jump == 0) throw UsageError{path + ": no complete jump to compare"};
  }
  analysis::FindTakeoff(a, side.jump);  // names a jump that does not exist
  side.label = analysis::JumpLabel(a, side.jump);
  return side;
}

analysis::CompareJump ToCompare(const Side& side) {
  const Analysed& t = *side.trial;
  return {&t.trial,
          &t.analysis,
          &t.body,
          analysis::MakeEllipsoidBodyMesh(t.body, analysis::OverlayBodyMeshOptions()),
          side.jump,
          side.label};
}

int RunCompare(const CompareArguments& args) {
  if (!(args.slow >= 1 && args.slow <= 16)) throw UsageError{"--slow must be between 1 and 16"};
  CheckVideoOutput(args.out);
  const Side a = Choose(args.a, args.athlete_a, nullptr);
  const Side b = Choose(args.b, args.athlete_b.empty() ? args.athlete_a : args.athlete_b, a.trial);
  analysis::CompareScene scene(ToCompare(a), ToCompare(b));
  ui::CompareVideoOptions options;
  options.slow = args.slow;
  options.view = args.view == "front" ? ui::ViewPreset::kFront
                 : args.view == "top" ? ui::ViewPreset::kTop
                                      : ui::ViewPreset::kSide;
  options.follow = args.follow;
  if (a.trial->analysis.bed)
    options.trampoline = analysis::MakeTrampolineScene(*a.trial->analysis.bed);
  const analysis::TimedPanel panel = ui::MakeCompareCharts(scene.CurvesA(),
                                                           scene.CurvesB(),
                                                           "A " + a.label,
                                                           "B " + b.label,
                                                           scene.start_s(),
                                                           scene.end_s(),
                                                           3 * options.view_width,
                                                           320);
  options.progress = MakeCancellableProgress("compare", "frames");
  const int frames = ui::WriteCompareVideo(scene, panel, args.out, options);
  std::printf(
      "A: %s\nB: %s\nwrote %s (%d frames; B moved %.2f m and turned %.1f deg onto A's take-off)\n",
      a.label.c_str(),
      b.label.c_str(),
      args.out.c_str(),
      frames,
      scene.b_to_a().translation().norm(),
      Eigen::AngleAxisd(scene.b_to_a().linear()).angle() * 180 / M_PI);
  return 0;
}
#endif

}  // namespace

void AddCompareCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<CompareArguments>();
  CLI::App* command = app.add_subcommand(
      "compare",
      "Two jumps side by side, aligned at take-off (the second placed on the first's take-off "
      "feet and heading), from the side: each alone and both superimposed, over their centre of "
      "mass heights and somersault and twist angles. docs/overlay.md.");
  command
      ->add_option(
          "A",
          args->a,
          "TRIAL[:JUMP] (jumps numbered as in jumps.json; default: the first complete one)")
      ->required();
  command->add_option("B", args->b, "TRIAL[:JUMP], the same trial or another")->required();
  command->add_option("--athlete", args->athlete_a, "athlete profile of A (and of B)");
  command->add_option("--athlete-b", args->athlete_b, "athlete profile of B, when another");
  command->add_option("--slow", args->slow, "play K times slower (1–16)");
  command
      ->add_option("--view",
                   args->view,
                   "side (default: from the athlete's right), front or top, for A's take-off")
      ->check(CLI::IsMember({"side", "front", "top"}));
  command->add_flag("--follow",
                    args->follow,
                    "the views follow the athletes' centres of mass (same direction and distance)");
  command->add_option("-o,--output", args->out, "OUT.mp4 or a directory of PNG frames")->required();
  command->callback([args, run] {
#ifdef ACRO_HAVE_VIEWS
    *run = [args] { return RunCompare(*args); };
#else
    *run = NeedTheViews;
#endif
  });
}

}  // namespace acro::app
