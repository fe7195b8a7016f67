#pragma once

// The commands of `acrolab`. Each one declares its arguments to CLI11 (so that `--help` comes
// from the same declarations as the parsing), and after parsing runs: read, call one library
// function per step, print. docs/cli.md.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "acro/athlete/athlete_body.h"
#include "acro/base/progress.h"
#include "acro/capture/trial.h"
#include "acro/capture/video.h"
#include "acro/design/skill_optimization.h"
#include "acro/pipeline/trial_input.h"
#include "acro/pipeline/video_input.h"
#include "acro/pipeline/views_input.h"
#include "acro/reconstruct/reconstruction.h"
#include "acro/report/skill_report.h"
#include "acro/vision/camera.h"
#include "acro/vision/image_flights.h"
#include "acro/vision/video_sync.h"

namespace acro::app {

/// What a parsed command does; returns the exit status. Bad input surfaces as acro::InputError,
/// which main() prints as one line (status 1); a bad command line as UsageError (status 2).
using CommandRunner = std::function<int()>;

/// Each adds its subcommand to `app`; when the command line selects it, parsing sets *run.
void AddInfoCommand(CLI::App& app, CommandRunner* run);
void AddConvertCommand(CLI::App& app, CommandRunner* run);
void AddBodyCommand(CLI::App& app, CommandRunner* run);
void AddReconstructCommand(CLI::App& app, CommandRunner* run);
void AddOptimizeCommand(CLI::App& app, CommandRunner* run);
void AddAnalyzeCommand(CLI::App& app, CommandRunner* run);
void AddVideoCommand(CLI::App& app, CommandRunner* run);
void AddProjectCommand(CLI::App& app, CommandRunner* run);
void AddCalibrateCommand(CLI::App& app, CommandRunner* run);
void AddSyncCommand(CLI::App& app, CommandRunner* run);
/// `acrolab overlay`: with the 3D views (ACRO_HAVE_VIEWS), else a command that says how to get
/// them.
void AddOverlayCommand(CLI::App& app, CommandRunner* run);
void AddCompareCommand(CLI::App& app, CommandRunner* run);
/// `acrolab synchro A B`: a synchro pair scored element by element.
void AddSynchroCommand(CLI::App& app, CommandRunner* run);
/// `acrolab library …` (the season library) and `acrolab batch`.
void AddLibraryCommand(CLI::App& app, CommandRunner* run);
void AddBatchCommand(CLI::App& app, CommandRunner* run);
/// `acrolab detect`: 2D keypoints from video (docs/pose.md).
void AddDetectCommand(CLI::App& app, CommandRunner* run);
/// `acrolab live`: live sources recorded and watched for jumps and routines (docs/live.md).
void AddLiveCommand(CLI::App& app, CommandRunner* run);
/// What `overlay` and `compare` run in a build without the 3D views: throws the UsageError that
/// says how to get them.
int NeedTheViews();

/// An option given an empty value ("--frames ''") is refused by name, never read as "not given".
inline const CLI::Validator kNotEmpty(
    [](std::string& value) {
      return value.empty() ? std::string("an empty value") : std::string();
    },
    "NOT EMPTY");

/// A command line that parses but does not make sense (contradictory options, an Options struct
/// that is not valid): main() prints it with the usage hint and exits with status 2.
struct UsageError {
  std::string message;
};

/// What every command that reconstructs a trial takes: TRIAL, --static, --athlete or
/// --height/--mass/--sex, --markerset, -o, --cutoff, --no-scale, --threads, --quiet.
struct TrialArguments {
  std::string trial_path, static_path, athlete_path, markerset, out_dir, sex = "f";
  std::string up = "auto";  ///< --up: the file's up axis (auto: found from the head and feet)
  double height_m = 1.75, mass_kg = 65.0;
  bool quiet = false;
  /// Declares these options on `command`; those of the reconstruction write into `options`
  /// (which must outlive the parse).
  void Declare(CLI::App* command,
               analysis::ReconstructionOptions* options,
               bool trial_required = true);
  /// What the pipeline opens (TRIAL, --static, --up, the athlete or the default body's numbers).
  pipeline::TrialRequest Request() const;
};

/// pipeline::OpenTrial, its warnings on stderr as "acrolab COMMAND: warning: …" (the default
/// athlete's too when `uses_athlete`).
pipeline::TrialInput OpenTrialFor(const std::string& command,
                                  const pipeline::TrialRequest& request,
                                  bool uses_athlete = true);

/// Several cameras' 2D keypoints instead of a trial (docs/markerless.md): --detections CAM=PATH
/// (repeated), --calib, --keypoints, --rate, --offset CAM=FRAMES (repeated; the others are synced
/// from the detections unless --no-sync).
struct ViewsArguments {
  std::vector<std::string> detections, offsets;
  std::string calibration, keypoints = "body25b";
  double rate_hz = 0;
  bool no_sync = false;
  void Declare(CLI::App* command);
  bool given() const { return !detections.empty(); }
  /// The pipeline's request, with the trial's --up and athlete (UsageError for options that do not
  /// go together).
  pipeline::ViewsRequest Request(const TrialArguments& trial) const;
};

/// `--bed-line Y0,SLOPE`: the bed's rest line in the picture, y = Y0 + SLOPE·x (px). UsageError
/// for anything else.
vision::BedLine ParseBedLine(const std::string& text);

/// pipeline::OpenViews with a progress bar unless `quiet`, its warnings on stderr.
pipeline::ViewsInput OpenViewsFor(const std::string& command,
                                  const pipeline::ViewsRequest& request,
                                  bool quiet);

/// Throws UsageError with `why` when `options.IsValid` fails (the reason reaches the user).
template <typename Options>
void DemandValidCommandLine(const Options& options) {
  std::string why;
  if (!options.IsValid(&why)) throw UsageError{why};
}

/// A --cutoff at or above the trial's Nyquist frequency is a command-line mistake (UsageError).
void CheckCutoffBelowNyquist(const analysis::ReconstructionOptions& options,
                             const capture::Trial& trial);

/// `count` finite numbers separated by commas ("x,y,z", "u,v"), for `option`; `form` names them in
/// the error ("X,Y,Z"). Throws CLI::ValidationError.
Eigen::VectorXd ParseCommaNumbers(const std::string& option,
                                  const std::string& text,
                                  int count,
                                  const std::string& form);

/// The sync of the command line: --event TRIAL_S:VIDEO_S when given, else --offset-s; --rate for
/// both. Throws UsageError for a malformed --event or a rate that is not positive.
vision::VideoSync ParseVideoSync(double offset_s, const std::string& event, double rate);

/// A calibrated camera's video of a trial, as `overlay` and `analyze` take it: --video, --calib,
/// --camera, and the sync (--offset-s, --event or --sync auto, --rate).
struct VideoArguments {
  std::string video, calibration, camera, event, sync;
  /// --video given again: the second and later (analyze takes several cameras' videos).
  std::vector<std::string> more_videos;
  double offset_s = 0.0, rate = 1.0;
  /// Declares the options on `command`; --video and --calib required when `required`.
  void Declare(CLI::App* command, bool required);
  /// The video as the pipeline opens it (UsageError for options that do not go together).
  pipeline::VideoRequest Request() const;
};

/// The pipeline's video input, its warnings on stderr.
pipeline::VideoInput OpenVideoFor(const VideoArguments& video);

/// Checks, before any work, the -o of a command that draws a video: an .mp4 file (its folder must
/// take it), or a folder of PNG frames (a name with no extension, or an existing directory).
/// UsageError for any other extension (`-o x.avi` used to write a folder of PNGs named x.avi), or
/// for a folder when `mp4_only`.
void CheckVideoOutput(const std::string& out, bool mp4_only = false);

/// A progress bar per step on stderr (a new bar when the step changes), never cancelling (Ctrl-C
/// stops the program); nothing with `quiet`.
Progress MakeStepProgress(bool quiet);

/// What `optimize` and `design` share: Model 2 (then Model 1), the flight simulation, the
/// filmstrip.
struct SkillRunArguments {
  bool simulate = false, video = false;
  analysis::SkillOptimizationOptions options;
  /// Declares --model, --fixed-joints, --video and --intervals on `command`.
  void Declare(CLI::App* command);
};
/// Checks the options and the output folder before any work (UsageError, acro::InputError).
void PrepareSkillRun(SkillRunArguments& args, const std::string& out_dir);
/// Optimises `skill`, simulates it when asked, writes result.json, the timing and momentum plots,
/// motion.c3d/.mot, the filmstrip and report.html (with `more`'s extra lines) and what `write_more`
/// writes into the staging folder, all moved into `out_dir` at once; prints the summary on stdout,
/// progress on stderr ("acrolab COMMAND: …").
analysis::SkillOptimizationResult RunSkill(
    const std::string& command,
    const analysis::Skill& skill,
    SkillRunArguments& args,
    const std::string& out_dir,
    const ui::SkillReportExtras& more,
    const std::function<std::vector<std::string>(const std::filesystem::path&)>& write_more);
/// Stores a designed skill (its file and output folder) in the season library `library_path`.
void StoreDesign(const std::string& library_path,
                 const std::string& skill_path,
                 const analysis::Skill& skill,
                 const std::string& out_dir);
void AddDesignCommand(CLI::App& app, CommandRunner* run);
void AddRoutineCommand(CLI::App& app, CommandRunner* run);

/// Progress on stderr: "LABEL [####    ] 42% (done/total UNIT)" redrawn in place on a terminal, one
/// line at the end otherwise (logs, pipes).
std::function<void(int, int)> MakeProgressBar(const std::string& label, const std::string& unit);
/// The inverse-kinematics bar.
std::function<void(int, int)> MakeFrameProgress();
/// The same bar for library calls that can be cancelled through their progress callback (a
/// command line does not cancel: Ctrl-C stops the program).
std::function<bool(int, int)> MakeCancellableProgress(const std::string& label,
                                                      const std::string& unit);

}  // namespace acro::app
