#pragma once

/// \file
/// The trampoline's bed found in one picture, and a camera's pose from it: the extrinsic
/// calibration of a training hall's camera without a board or a click (docs/calibration.md,
/// "The bed detected in a frame").

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/video.h"
#include "acro/vision/calibration.h"
#include "acro/vision/camera.h"

namespace acro::vision {

/// The woven bed as the picture shows it: a dark, solid four-sided region.
struct BedDetection {
  std::string source;  ///< the file, and "@frame N" for a video
  int width_px = 0, height_px = 0;
  /// The corners, refined to sub-pixel by fitting a line to each side; in the picture's order
  /// going round clockwise as displayed (image y down), starting from the one nearest the top left.
  std::array<Eigen::Vector2d, 4> corners_px{};
  double area_px = 0.0;     ///< the region's area
  double inside_grey = 0;   ///< mean grey level inside the region (0–255)
  double outside_grey = 0;  ///< mean grey level in a band around it
};

/// Finds the bed in a photo (JPEG, PNG, …) or in frame `frame` of a video. The bed is the darkest
/// class of the picture (Otsu's threshold, then Otsu's again among the pixels below it: black
/// webbing against pads, mats and the hall), closed over springs and lines, the largest solid
/// convex quadrilateral among its regions by area times contrast with its surroundings. Throws
/// acro::InputError naming the file when it cannot be read or holds no such region.
BedDetection DetectBed(const std::filesystem::path& image_or_video, int frame = 0);
/// The same in a picture already decoded (grey or RGB; a live camera's frame), `source` naming it
/// in the detection and in errors.
BedDetection DetectBed(const capture::VideoFrame& frame, const std::string& source);

/// A camera's pose from the detected bed: the corners named BED_C1…BED_C4 of `points_W` (at
/// least these four; "fig-trampoline" or the bed's markers of a trial), in each of the four
/// orders round the quadrilateral that keep its sense (BED_C1…C4 go counter-clockwise seen from
/// above, so the camera is above the bed), each solved as CalibrateExtrinsics does.
struct BedCalibration {
  ExtrinsicCalibration calibration;  ///< the pose chosen
  std::vector<NamedPoint2> corners;  ///< the detected corners with the names given them
  /// A rectangle looks the same turned half a turn: the pose with the names the other way round
  /// fits as well. Its camera centre (lab, m), and how the choice was made.
  Eigen::Vector3d other_centre_W = Eigen::Vector3d::Zero();
  double other_rms_px = 0.0;
  std::string choice;
};

/// `c1_near_px`: a pixel near where BED_C1 is in the picture (a rough click) chooses between the
/// two poses; without it, the pose whose camera is on the −y side of the bed's centre (in the
/// frame of `points_W`) is taken and `choice` says so. Throws acro::InputError (where "points")
/// when BED_C1…C4 are missing or no order gives a pose with the camera above the bed.
BedCalibration CalibrateFromBed(const Camera& intrinsics,
                                const std::vector<NamedPoint3>& points_W,
                                const BedDetection& bed,
                                const std::optional<Eigen::Vector2d>& c1_near_px = std::nullopt);

/// A camera known only by its picture's size: its focal length and pose from the detected bed
/// (docs/one-camera.md, "The camera from the video alone"). Square pixels, the principal point at
/// the picture's centre, no distortion (a phone's video is corrected in the phone); the focal
/// length is the one at which the bed's four corners fit a FIG bed's rectangle best
/// (CalibrateFromBed at each focal length: a log-spaced search over 0.25–8 picture widths, then
/// golden-section to 0.01 %). Only the bed's perspective tells the focal length: its size in the
/// picture, the athlete's height and gravity's pull all scale with focal length over distance
/// alike.
struct BedFocalCalibration {
  BedCalibration bed;  ///< the pose, with the camera's K at the focal length found
  double focal_px = 0.0;
  /// The focal lengths the corners do not tell from the best: where the fit's squared residuals
  /// (8 coordinates) grow by less than 4σ², σ = 1 px (what the detected corners are good to) —
  /// about two standard deviations. An end at the search's bound (0.25 or 8 picture widths): the
  /// bed seen with too little perspective to tell.
  double focal_low_px = 0.0, focal_high_px = 0.0;
  /// The same from the bed's homography in closed form (Zhang's two constraints on the image of
  /// the absolute conic, K = diag(f, f, 1) about the centre), NaN where both are degenerate: a
  /// second method, a check on the search.
  double closed_form_px = 0.0;
};

/// Throws acro::InputError (where "bed") when no focal length gives a pose with the camera above
/// the bed, or the best fit is worse than 3 px RMS (the quadrilateral is not a rectangle's
/// picture).
BedFocalCalibration CalibrateFromBedUnknownFocal(
    int width_px,
    int height_px,
    const std::vector<NamedPoint3>& points_W,
    const BedDetection& bed,
    const std::optional<Eigen::Vector2d>& c1_near_px = std::nullopt);

/// The bed in 3D from its detection in several calibrated views (docs/markerless.md, "The bed"):
/// each view's four corner rays meet the bed's plane (horizontal, z = height in the cameras'
/// world, Z up) in a quadrilateral, and at the right height the views' quadrilaterals coincide.
/// The height is the one where their centres agree best (a search over ±10 m around the cameras'
/// mean height, then golden-section to a millimetre); the centre is the mean of the views' centres
/// there, the long axis the mean direction of their longer sides, the size their mean sides.
struct BedFromViews {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d long_axis_W = Eigen::Vector3d::UnitX();
  double length_m = 0.0, width_m = 0.0;  ///< the mean quadrilateral's sides
  /// RMS distance of the views' centres from their mean at that height (m): how well they agree.
  double spread_m = 0.0;
  int views = 0;
};

/// Needs two views or more (cameras[i] with beds[i], at most 12). The views agree when their beds
/// meet on one plane as a trampoline's (sides within 25 % of FIG's 4.28 × 2.14 m, centres within
/// 15 cm RMS); the largest subset of views that agrees is taken (the least spread among subsets of
/// one size), so a view whose detection took a mat or a dark wall for the bed is left out
/// (`views` says how many were used). Throws acro::InputError (where "bed") when no two agree.
BedFromViews LocateBedFromViews(const std::vector<Camera>& cameras,
                                const std::vector<BedDetection>& beds);

}  // namespace acro::vision
