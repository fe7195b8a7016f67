#include <cstdio>
#include <memory>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/vision/projection.h"
#include "commands.h"

namespace acro::app {

namespace {

struct ProjectArguments {
  std::string trial, calibration, camera, csv, axes = "xyz";
  double offset_s = 0.0;
};

int RunProject(const ProjectArguments& args) {
  const capture::Trial trial = capture::ReadTrial(args.trial);
  const std::vector<vision::Camera> cameras = vision::ReadPose2SimToml(args.calibration);
  const vision::AxisMapping axes = vision::ParseAxisMapping(args.axes);
  std::string csv;
  int used = 0;
  for (const vision::Camera& camera : cameras) {
    if (!args.camera.empty() && camera.name != args.camera) continue;
    ++used;
    const std::vector<vision::ProjectedPoint> points =
        vision::ProjectTrial(trial, camera, axes, args.offset_s);
    std::string part = vision::FormatProjectionCsv(trial, camera, points);
    csv += used == 1 ? part : part.substr(part.find('\n') + 1);  // one header
    std::printf("%s: %zu points in front of the camera\n", camera.name.c_str(), points.size());
  }
  if (used == 0)
    throw InputError(args.calibration, "--camera", "no camera named '" + args.camera + "'");
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
      "Projects every marker or keypoint of a trial into calibrated cameras (distortion applied): "
      "the proof of the geometry, and the simplest overlay. docs/formats/calibration.md.");
  command->add_option("TRIAL", args->trial, "markers or keypoints: C3D, TRC or CSV")->required();
  command->add_option("--calib", args->calibration, "cameras: Pose2Sim/Anipose TOML")->required();
  command->add_option("--camera", args->camera, "only this camera (default: every one)");
  command->add_option("--offset-s",
                      args->offset_s,
                      "video time of the trial's first sample (video time = offset + trial time)");
  command->add_option("--axes",
                      args->axes,
                      "how the trial's axes map to the lab's: xyz (default), zxy for a Y-up TRC, "
                      "a minus flips an axis");
  command->add_option("--csv", args->csv, "write camera,frame,time_s,marker,u_px,v_px rows");
  command->callback([args, run] { *run = [args] { return RunProject(*args); }; });
}

}  // namespace acro::app
