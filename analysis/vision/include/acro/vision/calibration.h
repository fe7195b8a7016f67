#pragma once

// Camera calibration (docs/calibration.md): the intrinsics from photos or video frames of a
// checkerboard or ChArUco board, and a camera's pose from known 3D points and their pixels. OpenCV
// does the detection and the estimation (calibrateCamera, solvePnP); no OpenCV type appears here.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/fig/trampoline.h"

#include "acro/vision/camera.h"

namespace acro::vision {

/// A calibration target. A checkerboard is counted by its inner corners (OpenCV's pattern size), a
/// ChArUco board by its squares.
struct CalibrationBoard {
  enum class Kind { kCheckerboard, kCharuco };
  Kind kind = Kind::kCheckerboard;
  int columns = 0;
  int rows = 0;
  double square_m = 0.0;
  double marker_m = 0.0;   ///< ChArUco only: the side of its ArUco markers
  std::string dictionary;  ///< ChArUco only: OpenCV's predefined dictionary, e.g. "DICT_4X4_50"

  /// The board's points (corners) in its own plane, z = 0, metres, in detection order.
  std::vector<Eigen::Vector3d> ObjectPoints() const;
};

/// Parses "checkerboard:COLSxROWS:SIZE" (inner corners, square side) or
/// "charuco:COLSxROWS:SQUARE:MARKER[:DICT_…]" (squares; default dictionary DICT_4X4_50); sizes in
/// mm, cm or m ("60mm"). Throws acro::InputError (where "--board") naming what is wrong.
CalibrationBoard ParseCalibrationBoard(const std::string& text);

/// What became of one photo or video frame.
struct CalibrationView {
  std::string source;  ///< the file, with "@frame N" for a video frame
  bool board_found = false;
  bool used = false;    ///< in the final calibration
  int points = 0;       ///< corners detected
  double rms_px = 0.0;  ///< this view's reprojection RMS (final calibration, or the one that
                        ///< rejected it)
  std::string note;     ///< why it was skipped or rejected; empty when used
};

struct IntrinsicCalibrationOptions {
  /// A view whose RMS exceeds both reject_factor × the median view RMS and reject_floor_px is
  /// rejected and the calibration repeated without it (once per round, worst view first).
  double reject_factor = 3.0;
  double reject_floor_px = 1.0;
  /// Estimate k3 as well as k1 k2 p1 p2 (OpenCV's default does; few views constrain it poorly).
  bool estimate_k3 = true;
  /// Video inputs: one frame every this many seconds.
  double video_step_s = 0.5;
  /// Fewer usable views than this is an error.
  int min_views = 3;
  /// Called after each input with (inputs done, inputs in all); returns false to cancel.
  std::function<bool(int, int)> progress;

  bool IsValid(std::string* why) const;
};

struct IntrinsicCalibration {
  Camera camera;  ///< size, K and distortion; the pose is the identity
  double rms_px = 0.0;
  std::vector<CalibrationView> views;
};

/// Calibrates one camera from photos (any format OpenCV reads) and videos (frames every
/// video_step_s, decoded by capture::VideoReader) of the board. Views without a board are
/// reported and skipped; all inputs must have one image size. Throws acro::InputError for an
/// unreadable input, mixed sizes, too few views, or a cancelled run.
IntrinsicCalibration CalibrateIntrinsics(const std::vector<std::filesystem::path>& inputs,
                                         const CalibrationBoard& board,
                                         const IntrinsicCalibrationOptions& options = {});

/// A named point in the lab (metres) or in an image (pixels).
struct NamedPoint3 {
  std::string name;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
};
struct NamedPoint2 {
  std::string name;
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();
};

/// Reads "name,x_m,y_m,z_m" rows (a header line starting with "name" is skipped). Throws
/// acro::InputError naming the file and line.
std::vector<NamedPoint3> ReadPoints3dCsv(const std::filesystem::path& path);

/// The FIG trampoline's corners in the trampoline's own frame (origin at the centre of the bed at
/// rest, x along its length, z up, metres): the bed's BED_C1 (+x, +y), BED_C2 (−x, +y), BED_C3
/// (−x, −y), BED_C4 (+x, −y) at 4.28 m × 2.14 m, the frame's outer corners FRAME_C1…C4 (same order)
/// at 5.05 m × 2.91 m, level with the bed, and the floor under them, FLOOR_C1…C4, 1.155 m below
/// (FIG Apparatus Norms, trampoline). The names of the bed corners are the sample trials' markers.
std::vector<NamedPoint3> FigTrampolinePoints();

/// 3D points from `source`: "fig-trampoline" (above), a C3D or TRC trial (each marker's mean
/// position over its valid samples), or a points CSV (ReadPoints3dCsv). Throws acro::InputError.
std::vector<NamedPoint3> ReadPoints3d(const std::string& source);

/// Reads "name,u_px,v_px" rows likewise.
std::vector<NamedPoint2> ReadPoints2dCsv(const std::filesystem::path& path);

struct ExtrinsicCalibration {
  Camera camera;  ///< the intrinsics given, with the pose found
  double rms_px = 0.0;
  std::vector<std::string> names;    ///< the points used, in the order of the residuals
  std::vector<double> residuals_px;  ///< per point, distance between pixel and projection
};

/// The pose of a camera with known intrinsics from at least four points named in both lists
/// (names matched; unmatched ones ignored): SQPnP for a first pose, then Levenberg–Marquardt on
/// the reprojection error. Throws acro::InputError (where "points") with fewer than four matches
/// or when the points are degenerate (the solution puts a point behind the camera).
ExtrinsicCalibration CalibrateExtrinsics(const Camera& intrinsics,
                                         const std::vector<NamedPoint3>& points_W,
                                         const std::vector<NamedPoint2>& pixels);

}  // namespace acro::vision
