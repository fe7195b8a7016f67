#include "acro/vision/calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <type_traits>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/base/text.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "photo_files.h"

#if ACRO_HAVE_ARUCO
#include <opencv2/aruco/charuco.hpp>
#endif

namespace acro::vision {

namespace {

// "60mm", "6cm", "0.06m", "0.06" (metres) → metres; nothing for anything else.
std::optional<double> ParseLength(std::string_view text) {
  double scale = 1.0;
  if (text.size() > 2 && text.substr(text.size() - 2) == "mm") {
    scale = 1e-3;
    text.remove_suffix(2);
  } else if (text.size() > 2 && text.substr(text.size() - 2) == "cm") {
    scale = 1e-2;
    text.remove_suffix(2);
  } else if (text.size() > 1 && text.back() == 'm') {
    text.remove_suffix(1);
  }
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || v <= 0) return std::nullopt;
  return v * scale;
}

#if ACRO_HAVE_ARUCO
// OpenCV's predefined ArUco dictionaries by name.
const std::map<std::string, int>& ArucoDictionaries() {
  using namespace cv::aruco;
  static const std::map<std::string, int> names = {{"DICT_4X4_50", DICT_4X4_50},
                                                   {"DICT_4X4_100", DICT_4X4_100},
                                                   {"DICT_4X4_250", DICT_4X4_250},
                                                   {"DICT_4X4_1000", DICT_4X4_1000},
                                                   {"DICT_5X5_50", DICT_5X5_50},
                                                   {"DICT_5X5_100", DICT_5X5_100},
                                                   {"DICT_5X5_250", DICT_5X5_250},
                                                   {"DICT_5X5_1000", DICT_5X5_1000},
                                                   {"DICT_6X6_50", DICT_6X6_50},
                                                   {"DICT_6X6_100", DICT_6X6_100},
                                                   {"DICT_6X6_250", DICT_6X6_250},
                                                   {"DICT_6X6_1000", DICT_6X6_1000},
                                                   {"DICT_7X7_50", DICT_7X7_50},
                                                   {"DICT_7X7_100", DICT_7X7_100},
                                                   {"DICT_7X7_250", DICT_7X7_250},
                                                   {"DICT_7X7_1000", DICT_7X7_1000},
                                                   {"DICT_ARUCO_ORIGINAL", DICT_ARUCO_ORIGINAL}};
  return names;
}

cv::Ptr<cv::aruco::CharucoBoard> MakeCharucoBoard(const CalibrationBoard& board) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(ArucoDictionaries().at(board.dictionary));
  return cv::aruco::CharucoBoard::create(board.columns,
                                         board.rows,
                                         static_cast<float>(board.square_m),
                                         static_cast<float>(board.marker_m),
                                         dictionary);
}
#endif

// The board's corners found in one grey image: image points and their object points.
struct Detection {
  std::vector<cv::Point2f> image;
  std::vector<cv::Point3f> object;
};

std::optional<Detection> DetectBoard(const cv::Mat& grey, const CalibrationBoard& board) {
  Detection d;
  if (board.kind == CalibrationBoard::Kind::kCheckerboard) {
    const cv::Size pattern(board.columns, board.rows);
    if (!cv::findChessboardCorners(
            grey, pattern, d.image, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
      return std::nullopt;
    cv::cornerSubPix(grey,
                     d.image,
                     cv::Size(11, 11),
                     cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001));
    for (const Eigen::Vector3d& p : board.ObjectPoints())
      d.object.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
    return d;
  }
#if ACRO_HAVE_ARUCO
  const cv::Ptr<cv::aruco::CharucoBoard> charuco = MakeCharucoBoard(board);
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(grey, charuco->dictionary, marker_corners, marker_ids);
  if (marker_ids.empty()) return std::nullopt;
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, grey, charuco, corners, ids);
  // Fewer than six corners do not constrain a view (and may be collinear).
  if (ids.size() < 6) return std::nullopt;
  for (size_t k = 0; k < ids.size(); ++k) {
    d.image.push_back(corners[k]);
    d.object.push_back(charuco->chessboardCorners[static_cast<size_t>(ids[k])]);
  }
  return d;
#else
  return std::nullopt;  // ParseCalibrationBoard refuses ChArUco boards in this build
#endif
}

// One grey image to look for the board in, and where it came from.
struct Image {
  std::string source;
  cv::Mat grey;
};

// The images of one input: a photo, or frames of a video every step_s seconds.
std::vector<Image> LoadImages(const std::filesystem::path& path, double step_s) {
  std::vector<Image> images;
  if (IsPhotoFile(path)) {
    if (!IsRegularFile(path)) throw InputError(path.string(), "", "no such file");
    cv::Mat grey = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw InputError(path.string(), "", "not an image OpenCV can read");
    images.push_back({path.string(), grey});
    return images;
  }
  capture::VideoReader reader(path, {.pixels = capture::VideoPixels::kGrey});
  const capture::VideoInfo& info = reader.info();
  capture::VideoFrame frame;
  double next_s = -1.0;
  for (int i = 0; i < info.num_frames; ++i) {
    if (!reader.ReadNext(&frame)) break;
    if (frame.time_s + 1e-9 < next_s) continue;
    next_s = frame.time_s + step_s;
    const cv::Mat grey = cv::Mat(frame.height, frame.width, CV_8UC1, frame.pixels.data()).clone();
    images.push_back({fmt::format("{}@frame {}", path.string(), frame.index), grey});
  }
  return images;
}

// Per-view reprojection RMS under a calibration.
double ViewRms(const Detection& d,
               const cv::Mat& K,
               const cv::Mat& dist,
               const cv::Mat& rvec,
               const cv::Mat& tvec) {
  std::vector<cv::Point2f> projected;
  cv::projectPoints(d.object, rvec, tvec, K, dist, projected);
  double sum = 0.0;
  for (size_t k = 0; k < projected.size(); ++k) {
    const cv::Point2f e = projected[k] - d.image[k];
    sum += e.x * e.x + e.y * e.y;
  }
  return std::sqrt(sum / static_cast<double>(projected.size()));
}

}  // namespace

std::vector<Eigen::Vector3d> CalibrationBoard::ObjectPoints() const {
  std::vector<Eigen::Vector3d> points;
  if (kind == Kind::kCheckerboard) {
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < columns; ++c) points.emplace_back(c * square_m, r * square_m, 0.0);
  } else {
    // ChArUco's inner corners, as OpenCV numbers them (row by row).
    for (int r = 1; r < rows; ++r)
      for (int c = 1; c < columns; ++c) points.emplace_back(c * square_m, r * square_m, 0.0);
  }
  return points;
}

CalibrationBoard ParseCalibrationBoard(const std::string& text) {
  auto fail = [&](const std::string& why) -> CalibrationBoard {
    throw InputError("", "--board", "'" + text + "': " + why);
  };
  std::vector<std::string_view> f;
  Split(text, ':', &f);
  CalibrationBoard b;
  if (f.empty() || (f[0] != "checkerboard" && f[0] != "charuco"))
    return fail("starts with checkerboard: or charuco:");
  b.kind = f[0] == "checkerboard" ? CalibrationBoard::Kind::kCheckerboard
                                  : CalibrationBoard::Kind::kCharuco;
  const bool checker = b.kind == CalibrationBoard::Kind::kCheckerboard;
  if (checker ? f.size() != 3 : (f.size() != 4 && f.size() != 5)) {
    return fail(checker ? "expected checkerboard:COLSxROWS:SQUARE, e.g. checkerboard:4x7:60mm"
                        : "expected charuco:COLSxROWS:SQUARE:MARKER[:DICT_4X4_50]");
  }
  const std::string grid(f[1]);
  if (std::sscanf(grid.c_str(), "%dx%d", &b.columns, &b.rows) != 2 ||
      grid != fmt::format("{}x{}", b.columns, b.rows))
    return fail("the grid '" + grid + "' is not COLSxROWS");
  const int minimum = checker ? 2 : 3;
  if (b.columns < minimum || b.rows < minimum || b.columns > 100 || b.rows > 100)
    return fail(fmt::format("the grid {}x{} needs {} to 100 per side ({})",
                            b.columns,
                            b.rows,
                            minimum,
                            checker ? "inner corners" : "squares"));
  const std::optional<double> square = ParseLength(f[2]);
  if (!square) return fail("the square size '" + std::string(f[2]) + "' is not a length (60mm)");
  b.square_m = *square;
  // Printed boards: a square from 1 mm to 1 m (1e300 mm reached OpenCV as an assertion).
  if (!(b.square_m >= 1e-3 && b.square_m <= 1.0))
    return fail(fmt::format("the square size {:g} m is outside 1 mm … 1 m", b.square_m));
  if (!checker) {
    const std::optional<double> marker = ParseLength(f[3]);
    if (!marker || *marker >= b.square_m)
      return fail("the marker size '" + std::string(f[3]) +
                  "' is not a length smaller than the square");
    b.marker_m = *marker;
    b.dictionary = f.size() == 5 ? std::string(f[4]) : "DICT_4X4_50";
#if !ACRO_HAVE_ARUCO
    return fail(
        "ChArUco boards need OpenCV's aruco module, which this build lacks "
        "(scripts/install-deps.sh without --main installs it)");
#else
    if (ArucoDictionaries().count(b.dictionary) == 0)
      return fail("unknown ArUco dictionary '" + b.dictionary + "' (DICT_4X4_50 … DICT_7X7_1000)");
#endif
  }
  return b;
}

bool IntrinsicCalibrationOptions::IsValid(std::string* why) const {
  if (!(reject_factor > 1.0) || !(reject_floor_px >= 0.0)) {
    *why = "reject_factor must exceed 1 and reject_floor_px be ≥ 0";
    return false;
  }
  if (!(video_step_s > 0.0)) {
    *why = fmt::format("video step {} s is not positive", video_step_s);
    return false;
  }
  if (min_views < 2) {
    *why = "at least two views are needed";
    return false;
  }
  return true;
}

IntrinsicCalibration CalibrateIntrinsics(const std::vector<std::filesystem::path>& inputs,
                                         const CalibrationBoard& board,
                                         const IntrinsicCalibrationOptions& options) {
  DemandValidOptions(options, "calibration options");
  IntrinsicCalibration result;
  std::vector<Detection> detections;
  std::vector<size_t> view_of_detection;
  cv::Size size;
  std::string size_source;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (Image& image : LoadImages(inputs[i], options.video_step_s)) {
      if (size.width == 0) {
        size = image.grey.size();
        size_source = image.source;
      } else if (image.grey.size() != size) {
        throw InputError(image.source,
                         "",
                         fmt::format("image is {} x {} px but {} is {} x {}: one camera, one size",
                                     image.grey.cols,
                                     image.grey.rows,
                                     size_source,
                                     size.width,
                                     size.height));
      }
      CalibrationView view;
      view.source = image.source;
      if (std::optional<Detection> d = DetectBoard(image.grey, board)) {
        view.board_found = true;
        view.points = static_cast<int>(d->image.size());
        view_of_detection.push_back(result.views.size());
        detections.push_back(std::move(*d));
      } else {
        view.note = "no board found";
      }
      result.views.push_back(std::move(view));
    }
    if (options.progress && !options.progress(static_cast<int>(i + 1), int(inputs.size())))
      throw Cancelled("calibration: cancelled");
  }

  std::vector<bool> active(detections.size(), true);
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  double rms = 0.0;
  const int flags = options.estimate_k3 ? 0 : cv::CALIB_FIX_K3;
  for (;;) {
    std::vector<std::vector<cv::Point3f>> object;
    std::vector<std::vector<cv::Point2f>> image;
    std::vector<size_t> used;
    for (size_t k = 0; k < detections.size(); ++k) {
      if (!active[k]) continue;
      object.push_back(detections[k].object);
      image.push_back(detections[k].image);
      used.push_back(k);
    }
    if (static_cast<int>(used.size()) < options.min_views) {
      throw InputError(size_source.empty() ? "calibration" : size_source,
                       "",
                       fmt::format("the board was usable in {} of {} images; {} are needed",
                                   used.size(),
                                   result.views.size(),
                                   options.min_views));
    }
    try {
      rms = cv::calibrateCamera(object, image, size, K, dist, rvecs, tvecs, flags);
    } catch (const cv::Exception& e) {  // its assertion text, as the images' fault
      throw InputError(size_source.empty() ? "calibration" : size_source,
                       "",
                       "no camera fits the board's corners (OpenCV: " + e.err + ")");
    }
    // Per-view RMS; the worst view above the threshold is rejected and the rest recalibrated.
    std::vector<double> view_rms(used.size());
    for (size_t j = 0; j < used.size(); ++j)
      view_rms[j] = ViewRms(detections[used[j]], K, dist, rvecs[j], tvecs[j]);
    std::vector<double> sorted = view_rms;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double threshold =
        std::max(options.reject_factor * sorted[sorted.size() / 2], options.reject_floor_px);
    const size_t worst =
        static_cast<size_t>(std::max_element(view_rms.begin(), view_rms.end()) - view_rms.begin());
    for (size_t j = 0; j < used.size(); ++j)
      result.views[view_of_detection[used[j]]].rms_px = view_rms[j];
    if (view_rms[worst] <= threshold || static_cast<int>(used.size()) <= options.min_views) {
      for (size_t j = 0; j < used.size(); ++j) result.views[view_of_detection[used[j]]].used = true;
      break;
    }
    active[used[worst]] = false;
    result.views[view_of_detection[used[worst]]].note = fmt::format(
        "rejected: {:.2f} px RMS against a {:.2f} px threshold", view_rms[worst], threshold);
  }

  Camera& c = result.camera;
  c.width_px = size.width;
  c.height_px = size.height;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c.K(i, j) = K.at<double>(i, j);
  c.distortion.assign(dist.ptr<double>(), dist.ptr<double>() + (options.estimate_k3 ? 5 : 4));
  result.rms_px = rms;
  return result;
}

namespace {

// Rows of `columns` comma-separated fields after a name, skipping blank lines and a header.
template <typename Row>
std::vector<Row> ReadNamedRows(const std::filesystem::path& path, int columns) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(16) << 20);
  LineCursor lines(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  std::vector<Row> rows;
  std::vector<std::string_view> f;
  std::string_view line;
  while (lines.Next(&line)) {
    line = Trim(line);
    if (line.empty() || line.front() == '#') continue;
    Split(line, ',', &f);
    if (rows.empty() && Trim(f[0]) == "name") continue;
    const std::string where = fmt::format("line {}", lines.line_number());
    if (static_cast<int>(f.size()) != columns + 1)
      throw InputError(
          file, where, fmt::format("{} fields, expected a name and {} numbers", f.size(), columns));
    Row row;
    row.name = std::string(Trim(f[0]));
    double v[3] = {0, 0, 0};
    for (int k = 0; k < columns; ++k) {
      const std::string s(Trim(f[static_cast<size_t>(k + 1)]));
      char* end = nullptr;
      v[k] = std::strtod(s.c_str(), &end);
      if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v[k]))
        throw InputError(file, where, fmt::format("'{}' is not a number", s));
    }
    for (const Row& other : rows)
      if (other.name == row.name)
        throw InputError(file, where, "the name '" + row.name + "' appears twice");
    if constexpr (std::is_same_v<Row, NamedPoint3>) {
      row.p_W = Eigen::Vector3d(v[0], v[1], v[2]);
    } else {
      row.uv_px = Eigen::Vector2d(v[0], v[1]);
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw InputError(file, "", "no points in the file");
  return rows;
}

}  // namespace

std::vector<NamedPoint3> ReadPoints3dCsv(const std::filesystem::path& path) {
  return ReadNamedRows<NamedPoint3>(path, 3);
}

std::vector<NamedPoint2> ReadPoints2dCsv(const std::filesystem::path& path) {
  return ReadNamedRows<NamedPoint2>(path, 2);
}

std::vector<NamedPoint3> FigTrampolinePoints() {
  std::vector<NamedPoint3> points;
  const double sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
  const double bx = fig::kBedLength_m / 2, by = fig::kBedWidth_m / 2;
  const double fx = fig::kFrameLength_m / 2, fy = fig::kFrameWidth_m / 2;
  for (int k = 0; k < 4; ++k)
    points.push_back({fmt::format("BED_C{}", k + 1), {sx[k] * bx, sy[k] * by, 0.0}});
  for (int k = 0; k < 4; ++k)
    points.push_back({fmt::format("FRAME_C{}", k + 1), {sx[k] * fx, sy[k] * fy, 0.0}});
  for (int k = 0; k < 4; ++k) {
    points.push_back(
        {fmt::format("FLOOR_C{}", k + 1), {sx[k] * fx, sy[k] * fy, -fig::kBedHeight_m}});
  }
  return points;
}

std::vector<NamedPoint3> ReadPoints3d(const std::string& source) {
  if (source == "fig-trampoline") return FigTrampolinePoints();
  const std::string ext = LowerExtension(source);
  if (ext != "c3d" && ext != "trc") return ReadPoints3dCsv(source);
  const capture::Trial trial = capture::ReadTrial(source);
  std::vector<NamedPoint3> points;
  for (int p = 0; p < trial.num_points(); ++p) {
    if (trial.points[static_cast<size_t>(p)].type != capture::PointType::kMarker) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int f = 0; f < trial.num_frames; ++f)
      if (trial.valid(f, p)) {
        sum += trial.position(f, p);
        ++n;
      }
    if (n > 0) points.push_back({trial.points[static_cast<size_t>(p)].label, sum / n});
  }
  if (points.empty()) throw InputError(source, "", "no marker with a valid sample");
  return points;
}

ExtrinsicCalibration CalibrateExtrinsics(const Camera& intrinsics,
                                         const std::vector<NamedPoint3>& points_W,
                                         const std::vector<NamedPoint2>& pixels) {
  ExtrinsicCalibration result;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const NamedPoint2& q : pixels) {
    for (const NamedPoint3& p : points_W) {
      if (p.name != q.name) continue;
      object.emplace_back(p.p_W.x(), p.p_W.y(), p.p_W.z());
      image.emplace_back(q.uv_px.x(), q.uv_px.y());
      result.names.push_back(q.name);
    }
  }
  if (object.size() < 4) {
    throw InputError(
        "",
        "points",
        fmt::format("{} points are named in both the 3D and the 2D list; at least 4 are needed",
                    object.size()));
  }
  cv::Mat K(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K.at<double>(i, j) = intrinsics.K(i, j);
  const cv::Mat dist(intrinsics.distortion, true);
  // Four points that coincide (or lie on one line) pin no pose: said, not left to OpenCV's
  // assertions.
  double spread = 0.0;
  for (const cv::Point3d& a : object)
    for (const cv::Point3d& b : object) spread = std::max(spread, cv::norm(a - b));
  if (!(spread > 1e-3))
    throw InputError(
        "", "points", fmt::format("the {} 3D points coincide (all within 1 mm)", object.size()));
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_SQPNP))
      throw InputError("", "points", "no camera pose fits these points (SQPnP failed)");
    cv::solvePnPRefineLM(object, image, K, dist, rvec, tvec);
  } catch (const cv::Exception& e) {
    throw InputError("", "points", "no camera pose fits these points (OpenCV: " + e.err + ")");
  }

  result.camera = intrinsics;
  result.camera.R_KW = RotationFromRodrigues(
      Eigen::Vector3d(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)));
  result.camera.t_KW = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  double sum = 0.0;
  for (size_t k = 0; k < object.size(); ++k) {
    const Eigen::Vector3d p(object[k].x, object[k].y, object[k].z);
    const std::optional<Eigen::Vector2d> uv = result.camera.Project(p);
    if (!uv) {
      throw InputError("",
                       "points",
                       "the pose found puts '" + result.names[k] +
                           "' behind the camera: the points are degenerate or mismatched");
    }
    const double e = (*uv - Eigen::Vector2d(image[k].x, image[k].y)).norm();
    result.residuals_px.push_back(e);
    sum += e * e;
  }
  result.rms_px = std::sqrt(sum / static_cast<double>(object.size()));
  return result;
}

}  // namespace acro::vision
