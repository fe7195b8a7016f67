#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/calibration.h"
#include "commands.h"

namespace acro::app {

namespace {

struct IntrinsicsArguments {
  std::string board, out, name = "cam";
  std::vector<std::string> inputs;
  vision::IntrinsicCalibrationOptions options;
  bool no_k3 = false;
};

struct ExtrinsicsArguments {
  std::string points3d, points2d, intrinsics, camera, out;
  std::string detect_bed, corners_csv;
  std::optional<Eigen::Vector2d> bed_c1_near;
  int frame = 0;
};

int RunBedExtrinsics(const ExtrinsicsArguments& args, const vision::Camera& intrinsics) {
  const vision::BedDetection bed = vision::DetectBed(args.detect_bed, args.frame);
  std::printf("%s: bed found, %.0f px², grey %.0f inside against %.0f around\n",
              bed.source.c_str(),
              bed.area_px,
              bed.inside_grey,
              bed.outside_grey);
  const vision::BedCalibration result = vision::CalibrateFromBed(
      intrinsics, vision::ReadPoints3d(args.points3d), bed, args.bed_c1_near);
  std::string csv = "name,u_px,v_px\n";
  for (size_t i = 0; i < result.corners.size(); ++i) {
    const vision::NamedPoint2& c = result.corners[i];
    std::printf("  %s: (%.2f, %.2f) px, %.3f px\n",
                c.name.c_str(),
                c.uv_px.x(),
                c.uv_px.y(),
                result.calibration.residuals_px[i]);
    csv += fmt::format("{},{:.3f},{:.3f}\n", c.name, c.uv_px.x(), c.uv_px.y());
  }
  std::printf("  names: %s\n", result.choice.c_str());
  if (result.other_rms_px > 0) {
    const Eigen::Vector3d& o = result.other_centre_W;
    std::printf("  the other naming: centre (%.4f, %.4f, %.4f) m, RMS %.3f px\n",
                o.x(),
                o.y(),
                o.z(),
                result.other_rms_px);
  }
  if (!args.corners_csv.empty()) {
    WriteFileAtomically(args.corners_csv, csv);
    std::printf("wrote %s\n", args.corners_csv.c_str());
  }
  const Eigen::Vector3d centre = result.calibration.camera.CentreInWorld();
  std::printf("%s: centre (%.4f, %.4f, %.4f) m, reprojection RMS %.3f px over 4 corners\n",
              result.calibration.camera.name.c_str(),
              centre.x(),
              centre.y(),
              centre.z(),
              result.calibration.rms_px);
  vision::WritePose2SimToml({result.calibration.camera}, args.out);
  std::printf("wrote %s\n", args.out.c_str());
  return 0;
}

int RunIntrinsics(IntrinsicsArguments args) {
  const vision::CalibrationBoard board = vision::ParseCalibrationBoard(args.board);
  args.options.estimate_k3 = !args.no_k3;
  args.options.progress = MakeCancellableProgress("calibration", "inputs");
  DemandValidCommandLine(args.options);
  const std::vector<std::filesystem::path> inputs(args.inputs.begin(), args.inputs.end());
  vision::IntrinsicCalibration result = vision::CalibrateIntrinsics(inputs, board, args.options);
  for (const vision::CalibrationView& v : result.views) {
    if (v.used) {
      std::printf("  %s: %d corners, %.3f px RMS\n", v.source.c_str(), v.points, v.rms_px);
    } else {
      std::printf("  %s: skipped, %s\n", v.source.c_str(), v.note.c_str());
    }
  }
  const vision::Camera& c = result.camera;
  std::printf("%s: %d x %d px, fx %.2f fy %.2f, cx %.2f cy %.2f, reprojection RMS %.3f px\n",
              args.name.c_str(),
              c.width_px,
              c.height_px,
              c.K(0, 0),
              c.K(1, 1),
              c.K(0, 2),
              c.K(1, 2),
              result.rms_px);
  result.camera.name = args.name;
  vision::WritePose2SimToml({result.camera}, args.out);
  std::printf("wrote %s\n", args.out.c_str());
  return 0;
}

int RunExtrinsics(const ExtrinsicsArguments& args) {
  const std::vector<vision::Camera> cameras = vision::ReadCameras(args.intrinsics);
  const vision::Camera& intrinsics = vision::FindCamera(cameras, args.camera, args.intrinsics);
  if (args.points2d.empty() == args.detect_bed.empty())
    throw InputError("", "calibrate extrinsics", "give either --points2d or --detect-bed");
  if (!args.detect_bed.empty()) return RunBedExtrinsics(args, intrinsics);
  const vision::ExtrinsicCalibration result = vision::CalibrateExtrinsics(
      intrinsics, vision::ReadPoints3d(args.points3d), vision::ReadPoints2dCsv(args.points2d));
  for (size_t i = 0; i < result.names.size(); ++i)
    std::printf("  %s: %.3f px\n", result.names[i].c_str(), result.residuals_px[i]);
  const Eigen::Vector3d centre = result.camera.CentreInWorld();
  std::printf("%s: centre (%.4f, %.4f, %.4f) m, reprojection RMS %.3f px over %zu points\n",
              result.camera.name.c_str(),
              centre.x(),
              centre.y(),
              centre.z(),
              result.rms_px,
              result.names.size());
  vision::WritePose2SimToml({result.camera}, args.out);
  std::printf("wrote %s\n", args.out.c_str());
  return 0;
}

}  // namespace

void AddCalibrateCommand(CLI::App& app, CommandRunner* run) {
  CLI::App* calibrate = app.add_subcommand(
      "calibrate",
      "Camera calibration: intrinsics from a board, pose from known points (docs/calibration.md).");
  calibrate->require_subcommand(1);

  auto in = std::make_shared<IntrinsicsArguments>();
  CLI::App* intrinsics = calibrate->add_subcommand(
      "intrinsics",
      "Focal lengths, principal point and distortion from photos or videos of a checkerboard or "
      "ChArUco board (OpenCV calibrateCamera); views without a board are reported and skipped, "
      "views far worse than the rest rejected.");
  intrinsics->add_option("IMAGES", in->inputs, "photos (JPEG, PNG, …) or videos of the board")
      ->required();
  intrinsics
      ->add_option("--board",
                   in->board,
                   "checkerboard:COLSxROWS:SQUARE (inner corners, e.g. checkerboard:4x7:60mm) or "
                   "charuco:COLSxROWS:SQUARE:MARKER[:DICT_4X4_50] (squares)")
      ->required();
  intrinsics->add_option("-o,--output", in->out, "the camera, Pose2Sim TOML")->required();
  intrinsics->add_option("--name", in->name, "the camera's name in the file (default cam)");
  intrinsics
      ->add_option(
          "--video-step-s", in->options.video_step_s, "videos: one frame every this many seconds")
      ->check(CLI::Range(0.001, 3600.0));
  intrinsics->add_option("--reject-factor",
                         in->options.reject_factor,
                         "reject a view whose RMS exceeds this many times the median (default 3)");
  intrinsics->add_flag("--no-k3", in->no_k3, "estimate k1 k2 p1 p2 only");
  intrinsics->callback([in, run] { *run = [in] { return RunIntrinsics(*in); }; });

  auto ex = std::make_shared<ExtrinsicsArguments>();
  CLI::App* extrinsics = calibrate->add_subcommand(
      "extrinsics",
      "A camera's pose in the lab from points known in 3D and clicked or detected in its image "
      "(SQPnP, then Levenberg–Marquardt): the trampoline's corners, markers, measured spots.");
  extrinsics
      ->add_option(
          "--points3d",
          ex->points3d,
          "the points in the lab: a CSV name,x_m,y_m,z_m; a C3D or TRC (each marker's mean "
          "position, e.g. BED_C1…C4); or fig-trampoline (the FIG trampoline's corners in "
          "its own frame)")
      ->required();
  extrinsics->add_option("--points2d", ex->points2d, "CSV name,u_px,v_px in the image");
  extrinsics->add_option("--detect-bed",
                         ex->detect_bed,
                         "a photo or video in which to find the trampoline's bed (its corners "
                         "become BED_C1…C4 of --points3d), instead of --points2d");
  extrinsics->add_option("--frame", ex->frame, "with --detect-bed on a video: the frame (0)");
  extrinsics->add_option_function<std::string>(
      "--bed-c1-near",
      [ex](const std::string& text) {
        ex->bed_c1_near = ParseCommaNumbers("--bed-c1-near", text, 2, "U,V");
      },
      "U,V: a pixel near BED_C1, which chooses between the bed's two half-turn namings "
      "(default: the camera on the bed's -y side)");
  extrinsics->add_option(
      "--corners-csv", ex->corners_csv, "write the detected corners (name,u_px,v_px)");
  extrinsics->add_option("--intrinsics", ex->intrinsics, "the camera's calibration (any format)")
      ->required();
  extrinsics->add_option("--camera", ex->camera, "which camera of the file (when it has several)");
  extrinsics->add_option("-o,--output", ex->out, "the camera with its pose, Pose2Sim TOML")
      ->required();
  extrinsics->callback([ex, run] { *run = [ex] { return RunExtrinsics(*ex); }; });
}

}  // namespace acro::app
