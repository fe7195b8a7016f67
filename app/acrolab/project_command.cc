#include <cstdio>
#include <memory>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/report/projection_overlay.h"
#include "acro/vision/projection.h"
#include "commands.h"

namespace acro::app {

namespace {

struct ProjectArguments {
  std::string trial, calibration, camera, csv, axes = "xyz", video, out, event;
  double offset_s = 0.0, rate = 1.0;
};

int RunProject(const ProjectArguments& args) {
  if (!args.video.empty() && args.out.empty() && args.csv.empty())
    throw UsageError{"--video needs -o OUT.mp4|OUT_DIR or --csv"};
  if (!args.out.empty() && args.video.empty())
    throw UsageError{"-o draws on a video: give --video"};
  const capture::Trial trial = capture::ReadTrial(args.trial);
  const std::vector<vision::Camera> cameras = vision::ReadCameras(args.calibration);
  const vision::AxisMapping axes = vision::ParseAxisMapping(args.axes);
  const vision::VideoSync sync = ParseVideoSync(args.offset_s, args.event, args.rate);
  if (!args.video.empty()) {
    // One video: one camera, its frames numbering the rows.
    capture::VideoReader video(args.video);
    std::string note;
    const vision::Camera camera =
        vision::FitCameraToVideo(vision::FindCamera(cameras, args.camera, args.calibration),
                                 video.info().width, video.info().height, args.video, &note);
    if (!note.empty()) std::fprintf(stderr, "acrolab project: warning: %s\n", note.c_str());
    vision::DemandTrialInsideVideo(sync, trial.duration_s(), video.info().duration_s, args.video);
    if (!args.csv.empty()) {
      const std::vector<vision::ProjectedPoint> points =
          vision::ProjectTrialOnFrames(trial, camera, video.frame_times_s(), sync, axes);
      WriteFileAtomically(args.csv, vision::FormatProjectionCsv(trial, camera, points));
      std::printf("%s: %zu points on %d frames; wrote %s\n",
                  camera.name.c_str(),
                  points.size(),
                  video.num_frames(),
                  args.csv.c_str());
    }
    if (!args.out.empty()) {
      ui::OverlayVideoOptions options;
      options.axes = axes;
      options.sync = sync;
      options.progress = MakeCancellableProgress("overlay", "frames");
      const int frames = ui::WriteProjectionOverlay(video, trial, camera, args.out, options);
      std::printf("wrote %s (%d frames)\n", args.out.c_str(), frames);
    }
    return 0;
  }
  std::string csv;
  int used = 0;
  for (const vision::Camera& camera : cameras) {
    if (!args.camera.empty() && camera.name != args.camera) continue;
    ++used;
    const std::vector<vision::ProjectedPoint> points =
        vision::ProjectTrial(trial, camera, axes, sync.offset_s);
    std::string part = vision::FormatProjectionCsv(trial, camera, points);
    csv += used == 1 ? part : part.substr(part.find('\n') + 1);  // one header
    std::printf("%s: %zu points in front of the camera\n", camera.name.c_str(), points.size());
  }
  if (used == 0) vision::FindCamera(cameras, args.camera, args.calibration);  // names the fault
  if (!args.csv.empty()) {
    WriteFileAtomically(args.csv, csv);
    std::printf("wrote %s\n", args.csv.c_str());
  }
  return 0;
}

}  // namespace

void AddProjectCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<ProjectArguments>();
  CLI::App* command = app.add_subcommand(
      "project",
      "Projects every marker or keypoint of a trial into calibrated cameras (distortion applied), "
      "and with --video draws them on the synced frames: the proof of the geometry, and the "
      "simplest overlay. docs/calibration.md, docs/sync.md.");
  command->add_option("TRIAL", args->trial, "markers or keypoints: C3D, TRC or CSV")->required();
  command
      ->add_option("--calib",
                   args->calibration,
                   "cameras: Pose2Sim/Anipose .toml, Qualisys .qca, OpenCV .yml/.xml")
      ->required();
  command->add_option("--camera", args->camera, "only this camera (default: every one)");
  command->add_option("--offset-s",
                      args->offset_s,
                      "video time of the trial's first sample (video time = offset + rate × "
                      "trial time; `acrolab sync` finds it)");
  command->add_option("--event",
                      args->event,
                      "TRIAL_S:VIDEO_S: an event seen at these times in both (instead of "
                      "--offset-s)");
  command->add_option("--rate", args->rate, "video seconds per trial second (default 1)");
  command->add_option("--axes",
                      args->axes,
                      "how the trial's axes map to the lab's: xyz (default), zxy for a Y-up TRC, "
                      "a minus flips an axis");
  command->add_option("--csv", args->csv, "write camera,frame,time_s,marker,u_px,v_px rows");
  command->add_option("--video", args->video, "the camera's video: frames number the rows");
  command->add_option("-o,--output",
                      args->out,
                      "with --video: draw the points on every frame into OUT.mp4 or a directory "
                      "of PNG frames");
  command->callback([args, run] { *run = [args] { return RunProject(*args); }; });
}

}  // namespace acro::app
