// Argument helpers shared by the commands.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include <fmt/format.h>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/base/file_io.h"
#include "acro/base/temporaries.h"
#include "acro/capture/trial_io.h"
#include "acro/reconstruct/up_axis.h"
#include "acro/vision/sync.h"
#include "commands.h"

namespace acro::app {

void TrialArguments::Declare(CLI::App* command,
                             analysis::ReconstructionOptions* options,
                             bool trial_required) {
  CLI::Option* trial =
      command->add_option("TRIAL", trial_path, "markers or keypoints: C3D, TRC or CSV");
  if (trial_required) trial->required();
  command->add_option("-o,--output", out_dir, "output folder (created)")->required();
  command->add_option(
      "--static", static_path, "static trial for scaling (otherwise a window of the motion)");
  CLI::Option* athlete =
      command->add_option("--athlete", athlete_path, "athlete profile (docs/formats/athlete.md)");
  CLI::Option* height =
      command
          ->add_option("--height", height_m, "without --athlete: stature of a de Leva athlete (m)")
          ->check(CLI::Range(0.5, 2.6));
  CLI::Option* mass =
      command
          ->add_option("--mass", mass_kg, "without --athlete: body mass of a de Leva athlete (kg)")
          ->check(CLI::Range(10.0, 300.0));
  CLI::Option* sex_option =
      command->add_option("--sex", sex, "without --athlete: f or m (de Leva's tables)")
          ->check(CLI::IsMember({"f", "m"}));
  for (CLI::Option* o : {height, mass, sex_option}) athlete->excludes(o);
  command->add_option(
      "--up",
      up,
      "the file's up axis: auto (found from the head and the feet; a Y-up file "
      "from OpenSim or Pose2Sim is turned to Z up with a warning), x, y, z, -x, -y, -z");
  command->add_option_function<std::string>(
      "--markerset",
      [this, options](const std::string& name) {
        markerset = name;
        options->markerset = name;
      },
      "plug_in_gait | helen_hayes | trampoline | coco17 | body25 | body25b | halpe26 | blazepose33 "
      "| FILE.yaml (default: detected from the labels)");
  command
      ->add_option_function<double>(
          "--cutoff",
          [options](double hz) {
            options->cutoff_hz = hz;
            options->filter = hz > 0;
          },
          "marker low-pass cutoff in Hz (default: Winter's residual analysis); 0: no filter")
      ->check(CLI::NonNegativeNumber);
  command->add_flag_callback(
      "--no-scale",
      [options] { options->scale = false; },
      "keep the athlete's segment lengths and default marker offsets");
  command
      ->add_option_function<std::string>(
          "--fit",
          [options](const std::string& how) { options->fit_to_views = how == "views"; },
          "from several cameras: 'views' fits the model to every view's 2D keypoints after the fit "
          "to "
          "the triangulated points (the default), 'points' stops at the triangulated points "
          "(docs/markerless.md)")
      ->check(CLI::IsMember({"views", "points"}));
  command->add_flag(
      "--flight-physics",
      options->fit_flight_physics,
      "from one camera: refit each flight's root as a free flight (the centre of mass on "
      "gravity's parabola, the angular momentum constant), with the twist's mirror image fitted "
      "and reported (docs/one-camera.md, \"Flight physics\": measured, not yet better than the "
      "frame-by-frame fit on real video)");
  command->add_option("--threads", options->num_threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 256));
  command->add_flag("--quiet", quiet, "no progress on stderr");
}

Eigen::VectorXd ParseCommaNumbers(const std::string& option,
                                  const std::string& text,
                                  int count,
                                  const std::string& form) {
  Eigen::VectorXd v(count);
  size_t start = 0;
  for (int k = 0; k < count; ++k) {
    const size_t comma = text.find(',', start);
    if ((k < count - 1) != (comma != std::string::npos))
      throw CLI::ValidationError(option, "needs " + form + ", got '" + text + "'");
    const std::string part = text.substr(start, comma - start);
    if (!CLI::detail::lexical_cast(part, v[k]) || !std::isfinite(v[k]))
      throw CLI::ValidationError(option, "'" + part + "' is not a number");
    start = comma + 1;
  }
  return v;
}

vision::VideoSync ParseVideoSync(double offset_s, const std::string& event, double rate) {
  if (!(rate > 0) || !std::isfinite(rate)) throw UsageError{"--rate must be a positive number"};
  if (event.empty()) return {offset_s, rate};
  double trial_s = 0, video_s = 0;
  char end = 0;
  if (std::sscanf(event.c_str(), "%lf:%lf%c", &trial_s, &video_s, &end) != 2 ||
      !std::isfinite(trial_s) || !std::isfinite(video_s))
    throw UsageError{"--event '" + event + "' is not TRIAL_S:VIDEO_S, e.g. 3.52:3.89"};
  return vision::SyncFromEvent(trial_s, video_s, rate);
}

void VideoArguments::Declare(CLI::App* command, bool required) {
  CLI::Option* v = command
                       ->add_option_function<std::vector<std::string>>(
                           "--video",
                           [this](const std::vector<std::string>& all) {
                             video = all.empty() ? "" : all[0];
                             more_videos.assign(all.begin() + (all.empty() ? 0 : 1), all.end());
                           },
                           "the calibrated camera's video of the trial")
                       ->take_all();
  CLI::Option* c = command->add_option(
      "--calib", calibration, "cameras: Pose2Sim/Anipose .toml, Qualisys .qca, OpenCV .yml/.xml");
  if (required) {
    v->required();
    c->required();
  }
  command->add_option("--camera", camera, "the video's camera (default: the only one)");
  command->add_option("--offset-s",
                      offset_s,
                      "video time of the trial's first sample (video time = offset + rate × "
                      "trial time)");
  command->add_option("--event", event, "TRIAL_S:VIDEO_S: an event seen in both");
  command->add_option("--sync", sync, "auto: find the offset from the video's image motion");
  command->add_option("--rate", rate, "video seconds per trial second (default 1)");
}

void CheckVideoOutput(const std::string& out, bool mp4_only) {
  const std::filesystem::path path(out);
  const std::string ext = LowerExtension(path);
  if (ext == "mp4") {
    CheckOutputDirectory(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
    ResolveOutputTarget(path);  // a directory, a block device or a link loop refused now
    return;
  }
  if (mp4_only) throw UsageError{"-o: " + out + ": an .mp4 file is written here"};
  if (!ext.empty() && !IsDirectory(path))
    throw UsageError{"-o: " + out + ": ." + ext +
                     " cannot be written; give an .mp4 file, or a folder for PNG frames"};
  CheckOutputDirectory(path);
}

pipeline::TrialRequest TrialArguments::Request() const {
  pipeline::TrialRequest r;
  r.trial = trial_path;
  r.static_trial = static_path;
  r.up = up;
  r.athlete.profile = athlete_path;
  r.athlete.height_m = height_m;
  r.athlete.mass_kg = mass_kg;
  r.athlete.sex = sex == "f" ? analysis::Sex::kFemale : analysis::Sex::kMale;
  return r;
}

pipeline::TrialInput OpenTrialFor(const std::string& command,
                                  const pipeline::TrialRequest& request,
                                  bool uses_athlete) {
  pipeline::TrialInput input = pipeline::OpenTrial(request);
  std::vector<std::string> lines = input.warnings;
  if (uses_athlete && !input.athlete.warning.empty()) lines.push_back(input.athlete.warning);
  for (const std::string& w : lines)
    std::fprintf(stderr, "acrolab %s: warning: %s\n", command.c_str(), w.c_str());
  return input;
}

void ViewsArguments::Declare(CLI::App* command) {
  command->add_option("--detections",
                      detections,
                      "CAM=PATH, one per camera (at least two): a camera of --calib and its 2D "
                      "keypoints — a folder of OpenPose JSON, a CSV or a Sports2D TRC; instead of "
                      "TRIAL (docs/markerless.md)");
  command->add_option("--calib", calibration, "with --detections: the cameras' calibration");
  command->add_option("--keypoints",
                      keypoints,
                      "with --detections: the JSON files' keypoint set: body25b (default), body25, "
                      "coco17, halpe26");
  command
      ->add_option("--rate",
                   rate_hz,
                   "with --detections: the videos' frame rate (Hz); JSON files carry no time")
      ->check(CLI::PositiveNumber);
  command->add_option(
      "--offset",
      offsets,
      "with --detections: CAM=FRAMES, where that camera's frame 0 falls on the first "
      "camera's time line (repeated); the others are found from the detections");
  command->add_flag("--no-sync",
                    no_sync,
                    "with --detections: take the cameras as started together (offsets 0 unless "
                    "--offset)");
}

vision::BedLine ParseBedLine(const std::string& text) {
  Eigen::VectorXd v;
  try {
    v = ParseCommaNumbers("--bed-line", text, 2, "Y0,SLOPE");
  } catch (const CLI::ValidationError& e) {  // parsed in a command's run, not by CLI11's parse
    throw UsageError{e.what()};
  }
  vision::BedLine line;
  line.y0_px = v[0];
  line.slope = v[1];
  line.source = "--bed-line";
  return line;
}

pipeline::ViewsRequest ViewsArguments::Request(const TrialArguments& trial) const {
  if (!trial.trial_path.empty())
    throw UsageError{"give TRIAL or --detections (several cameras' keypoints), not both"};
  if (calibration.empty())
    throw UsageError{"--detections needs --calib (the cameras' calibration)"};
  if (!(rate_hz > 0)) throw UsageError{"--detections needs --rate (the videos' frame rate, Hz)"};
  if (!trial.static_path.empty()) throw UsageError{"--static goes with TRIAL, not --detections"};
  pipeline::ViewsRequest r;
  for (const std::string& d : detections) r.cameras.push_back(pipeline::ParseCameraSource(d));
  for (const std::string& o : offsets) {
    const size_t eq = o.find('=');
    char* end = nullptr;
    const std::string number = eq == std::string::npos ? "" : o.substr(eq + 1);
    const double frames = std::strtod(number.c_str(), &end);
    if (eq == std::string::npos || number.empty() || *end != '\0' || !std::isfinite(frames) ||
        std::abs(frames) > 1e7)
      throw UsageError{"--offset: expected CAM=FRAMES (a number of frames), got '" + o + "'"};
    const std::string camera = o.substr(0, eq);
    bool matched = false;
    for (pipeline::CameraSource& c : r.cameras)
      if (c.camera == camera) {
        c.offset_frames = frames;
        matched = true;
      }
    if (!matched) throw UsageError{"--offset: camera '" + camera + "' has no --detections"};
  }
  r.calibration = calibration;
  r.keypoint_set = keypoints;
  r.rate_hz = rate_hz;
  r.sync = !no_sync;
  r.up = trial.up;
  r.athlete.profile = trial.athlete_path;
  r.athlete.height_m = trial.height_m;
  r.athlete.mass_kg = trial.mass_kg;
  r.athlete.sex = trial.sex == "f" ? analysis::Sex::kFemale : analysis::Sex::kMale;
  return r;
}

pipeline::ViewsInput OpenViewsFor(const std::string& command,
                                  const pipeline::ViewsRequest& request,
                                  bool quiet) {
  pipeline::ViewsInput views = pipeline::OpenViews(request, MakeStepProgress(quiet));
  if (!quiet) {
    for (size_t v = 0; v < views.offsets.size(); ++v)
      std::fprintf(stderr,
                   "sync: camera %s: offset %.2f frames (%s)\n",
                   views.offsets[v].camera.c_str(),
                   views.offsets[v].offset_frames,
                   views.offset_origin[v].c_str());
    std::fputs(views.triangulation.BriefReport().c_str(), stderr);
  }
  std::vector<std::string> lines = views.input.warnings;
  if (!views.input.athlete.warning.empty()) lines.push_back(views.input.athlete.warning);
  for (const std::string& w : lines)
    std::fprintf(stderr, "acrolab %s: warning: %s\n", command.c_str(), w.c_str());
  return views;
}

pipeline::VideoRequest VideoArguments::Request() const {
  if (!more_videos.empty())
    throw UsageError{"--video is given " + std::to_string(1 + more_videos.size()) +
                     " times: this takes one video (analyze without TRIAL takes several cameras')"};
  if (video.empty() != calibration.empty())
    throw UsageError{"--video and --calib go together (the camera's video and its calibration)"};
  if (!sync.empty() && sync != "auto")
    throw UsageError{"--sync takes 'auto' (or give --offset-s or --event)"};
  if (!sync.empty() && !event.empty())
    throw UsageError{"--sync auto and --event both set the sync: give one"};
  const vision::VideoSync given =
      ParseVideoSync(offset_s, event, rate);  // a malformed --event or --rate, now
  pipeline::VideoRequest r;
  r.video = video;
  r.calibration = calibration;
  r.camera = camera;
  r.sync.rate = rate;
  r.sync.offset_s = given.offset_s;
  r.sync.kind =
      sync == "auto" ? pipeline::SyncRequest::Kind::kAuto : pipeline::SyncRequest::Kind::kOffset;
  return r;
}

pipeline::VideoInput OpenVideoFor(const VideoArguments& args) {
  pipeline::VideoInput video(args.Request());
  for (const std::string& w : video.warnings()) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return video;
}

Progress MakeStepProgress(bool quiet) {
  Progress progress;
  if (quiet) return progress;
  auto step = std::make_shared<std::string>();
  auto bar = std::make_shared<std::function<void(int, int)>>();
  progress.report = [step, bar](const std::string& name, int done, int total) {
    if (name != *step) {
      *step = name;
      *bar = MakeProgressBar(name, "frames");
    }
    (*bar)(done, total);
    return true;
  };
  return progress;
}

int NeedTheViews() {
  throw UsageError{
      "this acrolab was built without the 3D views (VTK): run scripts/install-deps.sh, then "
      "scripts/build.sh (ACRO_BUILD_UI=ON)"};
}

std::function<void(int, int)> MakeProgressBar(const std::string& label, const std::string& unit) {
  const bool tty = isatty(fileno(stderr)) != 0;
  return [tty, label, unit](int done, int total) {
    if (!tty && done < total) return;
    const int width = 40;
    const int filled = total > 0 ? done * width / total : width;
    // A terminal redraws the bar in place; a log (stderr not a terminal) gets the last state only,
    // with no carriage return.
    std::fprintf(stderr,
                 "%s%s [%s%s] %3d%% (%d/%d %s)",
                 tty ? "\r" : "",
                 label.c_str(),
                 std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), ' ').c_str(),
                 total > 0 ? done * 100 / total : 100,
                 done,
                 total,
                 unit.c_str());
    if (done >= total) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
}

std::function<void(int, int)> MakeFrameProgress() {
  return MakeProgressBar("inverse kinematics", "frames");
}

std::function<bool(int, int)> MakeCancellableProgress(const std::string& label,
                                                      const std::string& unit) {
  return [bar = MakeProgressBar(label, unit)](int done, int total) {
    bar(done, total);
    return true;
  };
}

void CheckCutoffBelowNyquist(const analysis::ReconstructionOptions& options,
                             const capture::Trial& trial) {
  if (options.filter && options.cutoff_hz > 0 && options.cutoff_hz >= 0.5 * trial.point_rate_hz)
    throw UsageError{fmt::format(
        "--cutoff {:g} Hz is at or above the trial's Nyquist frequency, {:g} Hz (its rate is {:g} "
        "Hz)",
        options.cutoff_hz,
        0.5 * trial.point_rate_hz,
        trial.point_rate_hz)};
}

}  // namespace acro::app
