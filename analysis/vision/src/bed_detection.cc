#include "acro/vision/bed_detection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/text.h"
#include "acro/capture/video.h"
#include "acro/fig/trampoline.h"
#include "photo_files.h"

namespace acro::vision {

namespace {

// The minimum of a one-dimensional `cost` within [lo, hi] by golden-section search, to `tolerance`
// (the bracket's width): the middle of the last bracket.
double GoldenSectionMinimum(const std::function<double(double)>& cost,
                            double lo,
                            double hi,
                            double tolerance) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
  double fa = cost(a), fb = cost(b);
  while (hi - lo > tolerance) {
    if (fa < fb) {
      hi = b;
      b = a;
      fb = fa;
      a = hi - g * (hi - lo);
      fa = cost(a);
    } else {
      lo = a;
      a = b;
      fa = fb;
      b = lo + g * (hi - lo);
      fb = cost(b);
    }
  }
  return 0.5 * (lo + hi);
}

cv::Mat LoadGrey(const std::filesystem::path& path, int frame, std::string* source) {
  if (!IsRegularFile(path)) throw InputError(path.string(), "", "no such file");
  if (IsPhotoFile(path)) {
    *source = path.string();
    cv::Mat grey = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw InputError(path.string(), "", "not an image OpenCV can read");
    return grey;
  }
  capture::VideoReader reader(path, {.pixels = capture::VideoPixels::kGrey});
  const int n = reader.info().num_frames;
  if (frame < 0 || frame >= n)
    throw InputError(path.string(), "frame", fmt::format("{} is not in 0…{}", frame, n - 1));
  capture::VideoFrame f = reader.Frame(frame);
  *source = fmt::format("{}@frame {}", path.string(), frame);
  return cv::Mat(f.height, f.width, CV_8UC1, f.pixels.data()).clone();
}

// Otsu's threshold of the pixels of `grey` at or below `below` (all of them for 255).
double OtsuBelow(const cv::Mat& grey, int below) {
  std::array<double, 256> hist{};
  for (int r = 0; r < grey.rows; ++r) {
    const uint8_t* p = grey.ptr<uint8_t>(r);
    for (int c = 0; c < grey.cols; ++c)
      if (p[c] <= below) hist[p[c]] += 1;
  }
  double total = 0, sum = 0;
  for (int i = 0; i < 256; ++i) total += hist[size_t(i)], sum += i * hist[size_t(i)];
  double w0 = 0, sum0 = 0, best = -1, threshold = below;
  for (int t = 0; t < 255; ++t) {
    w0 += hist[size_t(t)];
    sum0 += t * hist[size_t(t)];
    const double w1 = total - w0;
    if (w0 <= 0 || w1 <= 0) continue;
    const double m0 = sum0 / w0, m1 = (sum - sum0) / w1;
    const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) best = between, threshold = t;
  }
  return threshold;
}

struct Candidate {
  std::vector<cv::Point> quad;     // approximate corners
  std::vector<cv::Point> contour;  // the region's outline
  double area = 0, inside = 0, outside = 0, score = 0;
};

// The solid convex quadrilaterals among the regions of `mask`.
void FindQuads(const cv::Mat& grey, const cv::Mat& mask, std::vector<Candidate>* out) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  const double min_area = 0.002 * double(grey.total());
  for (const std::vector<cv::Point>& contour : contours) {
    const double area = cv::contourArea(contour);
    if (area < min_area) continue;
    std::vector<cv::Point> hull, quad;
    cv::convexHull(contour, hull);
    cv::approxPolyDP(hull, quad, 0.02 * cv::arcLength(hull, true), true);
    if (quad.size() != 4 || !cv::isContourConvex(quad)) continue;
    const double quad_area = cv::contourArea(quad);
    if (area < 0.85 * quad_area) continue;  // not solid: a frame, an L, a crowd
    Candidate c;
    c.quad = quad;
    c.contour = contour;
    c.area = quad_area;
    cv::Mat inside = cv::Mat::zeros(grey.size(), CV_8UC1);
    cv::fillConvexPoly(inside, quad, cv::Scalar(255));
    const int band = std::max(5, int(std::lround(0.01 * std::max(grey.cols, grey.rows))));
    cv::Mat ring;
    cv::dilate(
        inside, ring, cv::getStructuringElement(cv::MORPH_RECT, {2 * band + 1, 2 * band + 1}));
    ring -= inside;
    c.inside = cv::mean(grey, inside)[0];
    c.outside = cv::mean(grey, ring)[0];
    c.score = c.area * std::max(0.0, c.outside - c.inside);
    out->push_back(std::move(c));
  }
}

// The line (a, b, c), a·x + b·y + c = 0 with a² + b² = 1, through `pts` (OpenCV's fitLine, Huber).
Eigen::Vector3d HuberLine(const std::vector<cv::Point2f>& pts) {
  cv::Vec4f line;  // direction, then a point
  cv::fitLine(pts, line, cv::DIST_HUBER, 0, 0.01, 0.01);
  const Eigen::Vector2d n(-line[1], line[0]);
  return Eigen::Vector3d(n.x(), n.y(), -n.dot(Eigen::Vector2d(line[2], line[3])));
}

// The line through the outline's points near the
// side p→q.
Eigen::Vector3d FitSide(const std::vector<cv::Point>& contour, cv::Point p, cv::Point q) {
  const Eigen::Vector2d a(p.x, p.y), b(q.x, q.y);
  const Eigen::Vector2d d = (b - a).normalized();
  const double length = (b - a).norm();
  const double near = std::max(3.0, 0.02 * length);
  std::vector<cv::Point2f> pts;
  for (const cv::Point& c : contour) {
    const Eigen::Vector2d x(c.x, c.y);
    const double s = (x - a).dot(d);
    const double off = std::abs((x - a).x() * d.y() - (x - a).y() * d.x());
    if (s > 0.15 * length && s < 0.85 * length && off < near) pts.emplace_back(c.x, c.y);
  }
  if (pts.size() < 5) pts = {cv::Point2f(p.x, p.y), cv::Point2f(q.x, q.y)};
  return HuberLine(pts);
}

// Bilinear grey level at (x, y); the nearest border pixel outside the picture.
double GreyAt(const cv::Mat& grey, double x, double y) {
  x = std::clamp(x, 0.0, grey.cols - 1.001);
  y = std::clamp(y, 0.0, grey.rows - 1.001);
  const int i = int(x), j = int(y);
  const double fx = x - i, fy = y - j;
  const auto g = [&](int c, int r) { return double(grey.at<uint8_t>(r, c)); };
  return (1 - fy) * ((1 - fx) * g(i, j) + fx * g(i + 1, j)) +
         fy * ((1 - fx) * g(i, j + 1) + fx * g(i + 1, j + 1));
}

// The side a→b moved to the grey level's edge: across the side every 2 px of its middle 70 %, the
// place where the grey crosses half-way between the bed's (the inside end of a 12 px profile) and
// its surroundings' (the outside end), nearest the side; a line through those (Huber). The mask's
// outline lies on whole pixels and wherever the threshold cuts the blurred edge; this is the
// edge itself, to a fraction of a pixel. The side as it was when too few profiles cross.
Eigen::Vector3d RefineSide(const cv::Mat& grey,
                           const Eigen::Vector3d& side,
                           const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b,
                           const Eigen::Vector2d& centroid) {
  Eigen::Vector2d n(side.x(), side.y());
  if ((centroid - a).dot(n) > 0) n = -n;  // outward
  const double length = (b - a).norm();
  const Eigen::Vector2d d = (b - a) / length;
  constexpr double kReach = 6.0, kStep = 0.25;
  std::vector<cv::Point2f> pts;
  std::vector<double> profile;
  for (double s = 0.15 * length; s <= 0.85 * length; s += 2.0) {
    const Eigen::Vector2d p = a + s * d;
    profile.clear();
    for (double t = -kReach; t <= kReach + 1e-9; t += kStep)
      profile.push_back(GreyAt(grey, p.x() + t * n.x(), p.y() + t * n.y()));
    const size_t m = profile.size(), end = size_t(2.0 / kStep);
    double inside = 0, outside = 0;
    for (size_t k = 0; k < end; ++k) inside += profile[k], outside += profile[m - 1 - k];
    inside /= double(end);
    outside /= double(end);
    if (outside - inside < 10.0) continue;
    const double level = 0.5 * (inside + outside);
    double best_t = 1e9;
    for (size_t k = 0; k + 1 < m; ++k) {
      if ((profile[k] - level) * (profile[k + 1] - level) > 0 || profile[k] == profile[k + 1])
        continue;
      const double t =
          -kReach + kStep * (double(k) + (level - profile[k]) / (profile[k + 1] - profile[k]));
      if (std::abs(t) < std::abs(best_t)) best_t = t;
    }
    if (std::abs(best_t) <= kReach)
      pts.emplace_back(float(p.x() + best_t * n.x()), float(p.y() + best_t * n.y()));
  }
  if (pts.size() < 10) return side;
  return HuberLine(pts);
}

// The corners where neighbouring sides meet (corner i joins side i−1 and side i); `fallback`
// where two sides are near parallel or meet far from it.
std::array<Eigen::Vector2d, 4> Intersect(const std::array<Eigen::Vector3d, 4>& sides,
                                         const std::array<Eigen::Vector2d, 4>& fallback,
                                         double limit_px) {
  std::array<Eigen::Vector2d, 4> corners = fallback;
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d x = sides[(i + 3) % 4].cross(sides[i]);
    if (std::abs(x.z()) <= 1e-9) continue;
    const Eigen::Vector2d c(x.x() / x.z(), x.y() / x.z());
    if ((c - fallback[i]).norm() < limit_px) corners[i] = c;
  }
  return corners;
}

}  // namespace

namespace {

BedDetection DetectBedInGrey(cv::Mat grey, const std::string& source) {
  BedDetection bed;
  bed.source = source;
  bed.width_px = grey.cols;
  bed.height_px = grey.rows;
  cv::GaussianBlur(grey, grey, {5, 5}, 0);
  // The darkest class (black webbing); failing that, the dark one (a bed lit brighter than the
  // rest of the hall is dark).
  const double t1 = OtsuBelow(grey, 255);
  const double t2 = OtsuBelow(grey, int(t1));
  std::vector<Candidate> candidates;
  const int k = std::max(3, int(std::lround(0.004 * std::max(grey.cols, grey.rows)))) | 1;
  for (double t : {t2, t1}) {
    cv::Mat mask;
    cv::threshold(grey, mask, t, 255, cv::THRESH_BINARY_INV);
    // Opened first, so that the springs' and the frame's thin dark strokes along the bed's sides
    // come off it; then closed over thin bright lines across it.
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {k, k});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, kernel);
    FindQuads(grey, mask, &candidates);
    // The darkest class first: the mats and pads around a bed are dark too, and larger.
    if (std::any_of(
            candidates.begin(), candidates.end(), [](const Candidate& c) { return c.score > 0; }))
      break;
  }
  if (candidates.empty())
    throw InputError(bed.source,
                     "bed",
                     "no trampoline bed found: no dark, solid four-sided region of at least 0.2 % "
                     "of the picture");
  const Candidate& best = *std::max_element(
      candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.score < b.score;
      });
  if (best.score <= 0)
    throw InputError(bed.source,
                     "bed",
                     "no trampoline bed found: no four-sided region darker than its surroundings");
  // Clockwise as displayed (image y down: positive signed area), from the top left.
  std::vector<cv::Point> q = best.quad;
  double signed_area = 0;
  for (size_t i = 0; i < 4; ++i)
    signed_area += double(q[i].x) * q[(i + 1) % 4].y - double(q[(i + 1) % 4].x) * q[i].y;
  if (signed_area < 0) std::reverse(q.begin(), q.end());
  const auto first = std::min_element(
      q.begin(), q.end(), [](cv::Point a, cv::Point b) { return a.x + a.y < b.x + b.y; });
  std::rotate(q.begin(), first, q.end());
  std::array<Eigen::Vector3d, 4> sides;
  for (size_t i = 0; i < 4; ++i) sides[i] = FitSide(best.contour, q[i], q[(i + 1) % 4]);
  std::array<Eigen::Vector2d, 4> approximate;
  for (size_t i = 0; i < 4; ++i) approximate[i] = Eigen::Vector2d(q[i].x, q[i].y);
  const double limit = 0.05 * std::max(grey.cols, grey.rows);
  const std::array<Eigen::Vector2d, 4> traced = Intersect(sides, approximate, limit);
  const Eigen::Vector2d centroid = 0.25 * (traced[0] + traced[1] + traced[2] + traced[3]);
  for (size_t i = 0; i < 4; ++i)
    sides[i] = RefineSide(grey, sides[i], traced[i], traced[(i + 1) % 4], centroid);
  bed.corners_px = Intersect(sides, traced, 3.0);
  bed.area_px = best.area;
  bed.inside_grey = best.inside;
  bed.outside_grey = best.outside;
  return bed;
}

}  // namespace

BedDetection DetectBed(const std::filesystem::path& image_or_video, int frame) {
  std::string source;
  cv::Mat grey = LoadGrey(image_or_video, frame, &source);
  return DetectBedInGrey(grey, source);
}

BedDetection DetectBed(const capture::VideoFrame& frame, const std::string& source) {
  if (frame.width <= 0 || frame.height <= 0 || (frame.channels != 1 && frame.channels != 3) ||
      frame.pixels.size() != static_cast<size_t>(frame.width) * frame.height * frame.channels)
    throw InputError(source, "bed", "an empty or malformed picture");
  cv::Mat grey;
  const cv::Mat view(frame.height,
                     frame.width,
                     frame.channels == 1 ? CV_8UC1 : CV_8UC3,
                     const_cast<std::uint8_t*>(frame.pixels.data()));
  if (frame.channels == 1)
    grey = view.clone();
  else
    cv::cvtColor(view, grey, cv::COLOR_RGB2GRAY);
  return DetectBedInGrey(grey, source);
}

BedCalibration CalibrateFromBed(const Camera& intrinsics,
                                const std::vector<NamedPoint3>& points_W,
                                const BedDetection& bed,
                                const std::optional<Eigen::Vector2d>& c1_near_px) {
  std::array<Eigen::Vector3d, 4> corner_W;
  for (int k = 0; k < 4; ++k) {
    const std::string name = fmt::format("BED_C{}", k + 1);
    const auto it = std::find_if(
        points_W.begin(), points_W.end(), [&](const NamedPoint3& p) { return p.name == name; });
    if (it == points_W.end())
      throw InputError("", "points", "no " + name + " among the 3D points (BED_C1…C4 are needed)");
    corner_W[size_t(k)] = it->p_W;
  }
  const Eigen::Vector3d centre_W = 0.25 * (corner_W[0] + corner_W[1] + corner_W[2] + corner_W[3]);
  // Up: BED_C1…C4 go counter-clockwise seen from above.
  const Eigen::Vector3d up =
      (corner_W[1] - corner_W[0]).cross(corner_W[3] - corner_W[0]).normalized();
  struct Solution {
    BedCalibration result;
    Eigen::Vector3d centre_W;
  };
  std::vector<Solution> solutions;
  // Seen from above, counter-clockwise; in a picture from above the bed (y down), clockwise: the
  // names follow the detected order, from each of its four corners.
  for (int shift = 0; shift < 4; ++shift) {
    std::vector<NamedPoint2> named;
    for (int k = 0; k < 4; ++k)
      named.push_back({fmt::format("BED_C{}", k + 1), bed.corners_px[size_t((shift + 4 - k) % 4)]});
    try {
      Solution s;
      s.result.calibration = CalibrateExtrinsics(intrinsics, points_W, named);
      s.result.corners = named;
      s.centre_W = s.result.calibration.camera.CentreInWorld();
      if ((s.centre_W - centre_W).dot(up) <= 0) continue;  // below the bed: the mirror image
      solutions.push_back(std::move(s));
    } catch (const InputError&) {
      // this order puts a corner behind the camera
    }
  }
  if (solutions.empty())
    throw InputError("", "points", "no naming of the bed's corners puts the camera above the bed");
  std::sort(solutions.begin(), solutions.end(), [](const Solution& a, const Solution& b) {
    return a.result.calibration.rms_px < b.result.calibration.rms_px;
  });
  // The best and its half-turn twin (the corners named two places on), if it is there.
  const Solution& best = solutions[0];
  const Solution* twin = nullptr;
  for (size_t i = 1; i < solutions.size(); ++i)
    if ((solutions[i].result.corners[0].uv_px - best.result.corners[2].uv_px).norm() < 1e-9)
      twin = &solutions[i];
  const Solution* chosen = &best;
  std::string choice;
  if (twin) {
    if (c1_near_px) {
      const double d_best = (best.result.corners[0].uv_px - *c1_near_px).norm();
      const double d_twin = (twin->result.corners[0].uv_px - *c1_near_px).norm();
      if (d_twin < d_best) chosen = twin;
      choice = fmt::format(
          "BED_C1 is the corner nearest ({:.0f}, {:.0f}) px", c1_near_px->x(), c1_near_px->y());
    } else {
      // The side of the bed the camera is on, along the bed's own width (y) axis.
      const Eigen::Vector3d y_axis = (corner_W[0] - corner_W[3]).normalized();
      if ((twin->centre_W - centre_W).dot(y_axis) < (best.centre_W - centre_W).dot(y_axis))
        chosen = twin;
      choice =
          "the camera on the bed's −y side (BED_C3–C4); the bed looks the same turned half a "
          "turn: give the pixel near BED_C1 to choose";
    }
  } else {
    choice = "one naming fits";
  }
  const Solution* other = chosen == &best ? twin : &best;
  BedCalibration result = chosen->result;
  result.choice = choice;
  if (other && other != chosen) {
    result.other_centre_W = other->centre_W;
    result.other_rms_px = other->result.calibration.rms_px;
  }
  return result;
}

namespace {

// The four corners of a view's bed on the plane z = h (nothing when a ray misses it or the camera
// is not above it).
std::optional<std::array<Eigen::Vector3d, 4>> CornersOnPlane(const Camera& camera,
                                                             const BedDetection& bed,
                                                             double h) {
  const Eigen::Vector3d c = camera.CentreInWorld();
  if (!(c.z() > h + 0.05)) return std::nullopt;
  std::array<Eigen::Vector3d, 4> out;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d d = camera.RayInWorld(bed.corners_px[k]);
    if (!(d.z() < -1e-6)) return std::nullopt;
    const double s = (h - c.z()) / d.z();
    out[k] = c + s * d;
  }
  return out;
}

struct PlaneFit {
  double cost = std::numeric_limits<double>::infinity();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int views = 0;
};

// The views' centres on the plane z = h: their mean weighted by how steeply each camera looks at
// the bed (a grazing view's corners slide far along the plane for a pixel), and the weighted RMS
// distance from it.
PlaneFit FitAt(const std::vector<Camera>& cameras,
               const std::vector<BedDetection>& beds,
               double h) {
  PlaneFit fit;
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> weights;
  for (size_t v = 0; v < cameras.size(); ++v) {
    const auto corners = CornersOnPlane(cameras[v], beds[v], h);
    if (!corners) continue;
    const Eigen::Vector3d centre =
        0.25 * ((*corners)[0] + (*corners)[1] + (*corners)[2] + (*corners)[3]);
    const Eigen::Vector3d to = (centre - cameras[v].CentreInWorld()).normalized();
    centres.push_back(centre);
    weights.push_back(to.z() * to.z());
  }
  fit.views = static_cast<int>(centres.size());
  if (fit.views < 2) return fit;
  double w = 0;
  for (size_t i = 0; i < centres.size(); ++i) {
    fit.centre += weights[i] * centres[i];
    w += weights[i];
  }
  fit.centre /= w;
  double sum = 0;
  for (size_t i = 0; i < centres.size(); ++i)
    sum += weights[i] * (centres[i] - fit.centre).squaredNorm();
  fit.cost = std::sqrt(sum / w);
  return fit;
}

}  // namespace

namespace {

// The bed from these views, or an empty optional with the reason in *why.
std::optional<BedFromViews> LocateFromAll(const std::vector<Camera>& cameras,
                                          const std::vector<BedDetection>& beds,
                                          std::string* why) {
  double top = -std::numeric_limits<double>::infinity(), mean = 0;
  for (const Camera& c : cameras) {
    top = std::max(top, c.CentreInWorld().z());
    mean += c.CentreInWorld().z() / static_cast<double>(cameras.size());
  }
  // The height: coarse steps, then golden-section search around the best.
  // Heights seen from above by more views come first (a plane seen by fewer views agrees more
  // easily), then the least spread.
  double best_h = 0, best = std::numeric_limits<double>::infinity();
  int best_views = 0;
  for (double h = mean - 10.0; h < top; h += 0.05) {
    const PlaneFit f = FitAt(cameras, beds, h);
    if (f.views > best_views || (f.views == best_views && f.cost < best)) {
      best = f.cost;
      best_h = h;
      best_views = f.views;
    }
  }
  if (!std::isfinite(best)) {
    *why = "fewer than two views see the bed from above";
    return std::nullopt;
  }
  const auto cost = [&](double h) {
    const PlaneFit f = FitAt(cameras, beds, h);
    return f.views < best_views ? std::numeric_limits<double>::infinity() : f.cost;
  };
  const double found = GoldenSectionMinimum(cost, best_h - 0.05, best_h + 0.05, 1e-3);
  const double h = std::isfinite(cost(found)) ? found : best_h;
  const PlaneFit fit = FitAt(cameras, beds, h);
  BedFromViews out;
  out.centre_W = fit.centre;
  out.spread_m = fit.cost;
  out.views = fit.views;
  // The size and the long axis: each view's quadrilateral, its longer pair of opposite sides.
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  double w = 0;
  for (size_t v = 0; v < cameras.size(); ++v) {
    const auto q = CornersOnPlane(cameras[v], beds[v], h);
    if (!q) continue;
    const double s02 = 0.5 * (((*q)[1] - (*q)[0]).norm() + ((*q)[3] - (*q)[2]).norm());
    const double s13 = 0.5 * (((*q)[2] - (*q)[1]).norm() + ((*q)[0] - (*q)[3]).norm());
    Eigen::Vector3d along = s02 >= s13 ? ((*q)[1] - (*q)[0]) + ((*q)[2] - (*q)[3])
                                       : ((*q)[2] - (*q)[1]) + ((*q)[3] - (*q)[0]);
    along.z() = 0;
    along.normalize();
    if (axis.dot(along) < 0 || (axis.isZero() && along.x() < 0)) along = -along;
    const Eigen::Vector3d to = (fit.centre - cameras[v].CentreInWorld()).normalized();
    const double weight = to.z() * to.z();
    axis += weight * along;
    out.length_m += weight * std::max(s02, s13);
    out.width_m += weight * std::min(s02, s13);
    w += weight;
  }
  out.long_axis_W = axis.normalized();
  out.length_m /= w;
  out.width_m /= w;
  if (std::abs(out.length_m / fig::kBedLength_m - 1) > 0.25 ||
      std::abs(out.width_m / fig::kBedWidth_m - 1) > 0.25 || out.spread_m > 0.15) {
    *why = fmt::format(
        "{:.2f} × {:.2f} m (FIG: {:.2f} × {:.2f}), centres {:.2f} m apart (RMS) at height {:.2f} m",
        out.length_m,
        out.width_m,
        fig::kBedLength_m,
        fig::kBedWidth_m,
        out.spread_m,
        h);
    return std::nullopt;
  }
  return out;
}

}  // namespace

namespace {

// The focal length of a camera with square pixels, its principal point at the centre, from the
// homography that takes the bed's plane (metres, in-plane axes) to its picture: Zhang's (2000)
// constraints on the image of the absolute conic ω = K⁻ᵀK⁻¹ = diag(w, w, 1) with w = 1/f², from
// r1 ⟂ r2 and |r1| = |r2|, solved together in least squares. NaN when they do not tell (the
// bed square to the camera's axis, or a negative w).
double FocalFromHomography(const std::array<Eigen::Vector2d, 4>& plane_m,
                           const std::array<Eigen::Vector2d, 4>& pixels,
                           const Eigen::Vector2d& centre_px) {
  std::vector<cv::Point2f> from, to;
  for (size_t k = 0; k < 4; ++k) {
    from.emplace_back(static_cast<float>(plane_m[k].x()), static_cast<float>(plane_m[k].y()));
    to.emplace_back(static_cast<float>(pixels[k].x() - centre_px.x()),
                    static_cast<float>(pixels[k].y() - centre_px.y()));
  }
  const cv::Mat h = cv::getPerspectiveTransform(from, to, cv::DECOMP_SVD);
  Eigen::Matrix3d H;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) H(r, c) = h.at<double>(r, c);
  const Eigen::Vector3d h1 = H.col(0), h2 = H.col(1);
  // Each constraint as a·w + b = 0, both in the same units (1/m²): least squares as they are. (Each
  // scaled to unit size first, a constraint that the view makes degenerate — r1 ⟂ r2 for a bed
  // seen square from its side — weighed as much as the other and read 4308 px for the sample's
  // 1480.)
  const double a[2] = {h1.x() * h2.x() + h1.y() * h2.y(),
                       h1.x() * h1.x() + h1.y() * h1.y() - h2.x() * h2.x() - h2.y() * h2.y()};
  const double b[2] = {h1.z() * h2.z(), h1.z() * h1.z() - h2.z() * h2.z()};
  double num = 0, den = 0;
  for (int i = 0; i < 2; ++i) {
    num += a[i] * b[i];
    den += a[i] * a[i];
  }
  if (!(den > 0)) return std::nan("");
  const double w = -num / den;
  if (!(w > 0) || !std::isfinite(w)) return std::nan("");
  return 1.0 / std::sqrt(w);
}

}  // namespace

BedFocalCalibration CalibrateFromBedUnknownFocal(int width_px,
                                                 int height_px,
                                                 const std::vector<NamedPoint3>& points_W,
                                                 const BedDetection& bed,
                                                 const std::optional<Eigen::Vector2d>& c1_near_px) {
  if (width_px <= 0 || height_px <= 0)
    throw InputError(bed.source, "bed", fmt::format("a picture {} x {} px", width_px, height_px));
  const auto camera_at = [&](double f) {
    Camera c;
    c.name = "bed";
    c.width_px = width_px;
    c.height_px = height_px;
    c.K << f, 0, 0.5 * width_px, 0, f, 0.5 * height_px, 0, 0, 1;
    return c;
  };
  // The fit's RMS at each focal length; infinite where no naming puts the camera above the bed.
  const auto rms_at = [&](double f) {
    try {
      return CalibrateFromBed(camera_at(f), points_W, bed, c1_near_px).calibration.rms_px;
    } catch (const InputError&) {
      return std::numeric_limits<double>::infinity();
    }
  };
  const double lo = 0.25 * width_px, hi = 8.0 * width_px;
  constexpr int kSteps = 64;
  std::vector<double> fs(kSteps + 1), rms(kSteps + 1);
  int best = 0;
  for (int i = 0; i <= kSteps; ++i) {
    fs[size_t(i)] = lo * std::pow(hi / lo, static_cast<double>(i) / kSteps);
    rms[size_t(i)] = rms_at(fs[size_t(i)]);
    if (rms[size_t(i)] < rms[size_t(best)]) best = i;
  }
  if (!std::isfinite(rms[size_t(best)]))
    throw InputError(
        bed.source, "bed", "no focal length puts the camera above the bed the picture shows");
  // Golden-section on log f between the best grid point's neighbours.
  const double log_f = GoldenSectionMinimum([&](double x) { return rms_at(std::exp(x)); },
                                            std::log(fs[size_t(std::max(0, best - 1))]),
                                            std::log(fs[size_t(std::min(kSteps, best + 1))]),
                                            1e-4);
  BedFocalCalibration out;
  out.focal_px = std::exp(log_f);
  out.bed = CalibrateFromBed(camera_at(out.focal_px), points_W, bed, c1_near_px);
  const double best_rms = out.bed.calibration.rms_px;
  if (best_rms > 3.0)
    throw InputError(bed.source,
                     "bed",
                     fmt::format("the bed's corners fit a FIG bed's rectangle {:.1f} px RMS at "
                                 "best (focal length {:.0f} px): not a trampoline's bed",
                                 best_rms,
                                 out.focal_px));
  // The focal lengths the corners tell apart from the best: where the squared residuals' sum
  // (8 coordinates) grows by 4σ² with σ = 1 px, what DetectBed's corners are good to (1.2–1.9 px
  // from the truth on the sample, about 1 px of it a bias) — about two standard deviations.
  // Found by bisection on each side of the best, from the grid's first point beyond.
  const double limit = best_rms * best_rms + 4.0 * 1.0 / 8.0;
  const auto within = [&](double f) {
    const double r = rms_at(f);
    return r * r <= limit;
  };
  const auto edge = [&](double inside, double outside) {
    for (int i = 0; i < 40; ++i) {
      const double mid = std::sqrt(inside * outside);
      (within(mid) ? inside : outside) = mid;
    }
    return inside;
  };
  // Every focal length that fits as well counts, not only those next to the best: a bed seen
  // from its own height can fit as well at a focal length four times the true one (the camera
  // then put just under the bed's plane, refused, at the true one).
  int first = -1, last = -1;
  for (int i = 0; i <= kSteps; ++i)
    if (rms[size_t(i)] * rms[size_t(i)] <= limit) {
      if (first < 0) first = i;
      last = i;
    }
  out.focal_low_px = out.focal_px;
  out.focal_high_px = out.focal_px;
  if (first >= 0) {
    out.focal_low_px = std::min(out.focal_low_px, fs[size_t(first)]);
    out.focal_high_px = std::max(out.focal_high_px, fs[size_t(last)]);
  }
  // The ends refined between the last grid point inside and the next one out (or the bound).
  {
    int below = -1, above = -1;
    for (int i = 0; i <= kSteps; ++i) {
      if (fs[size_t(i)] < out.focal_low_px) below = i;
      if (above < 0 && fs[size_t(i)] > out.focal_high_px) above = i;
    }
    out.focal_low_px = below >= 0 ? edge(out.focal_low_px, fs[size_t(below)]) : lo;
    out.focal_high_px = above >= 0 ? edge(out.focal_high_px, fs[size_t(above)]) : hi;
  }
  // The closed form, with the corners named as the pose names them.
  std::array<Eigen::Vector2d, 4> plane{}, pixels{};
  {
    std::array<Eigen::Vector3d, 4> corner_W;
    for (int k = 0; k < 4; ++k) {
      const std::string name = fmt::format("BED_C{}", k + 1);
      for (const NamedPoint3& p : points_W)
        if (p.name == name) corner_W[size_t(k)] = p.p_W;
      for (const NamedPoint2& p : out.bed.corners)
        if (p.name == name) pixels[size_t(k)] = p.uv_px;
    }
    const Eigen::Vector3d e1 = (corner_W[1] - corner_W[0]).normalized();
    const Eigen::Vector3d up = e1.cross(corner_W[3] - corner_W[0]).normalized();
    const Eigen::Vector3d e2 = up.cross(e1);
    for (size_t k = 0; k < 4; ++k) {
      const Eigen::Vector3d d = corner_W[k] - corner_W[0];
      plane[k] = Eigen::Vector2d(d.dot(e1), d.dot(e2));
    }
  }
  out.closed_form_px =
      FocalFromHomography(plane, pixels, Eigen::Vector2d(0.5 * width_px, 0.5 * height_px));
  return out;
}

BedFromViews LocateBedFromViews(const std::vector<Camera>& cameras,
                                const std::vector<BedDetection>& beds) {
  const int n = static_cast<int>(beds.size());
  if (static_cast<int>(cameras.size()) != n || n < 2)
    throw InputError(
        "", "bed", fmt::format("{} views of the bed: locating it needs at least 2", n));
  if (n > 12) throw InputError("", "bed", fmt::format("{} views of the bed: at most 12", n));
  // The most views that agree: every subset, the largest first (a detector that took a mat or a
  // dark wall for the bed is left out).
  std::string first_why;
  for (int m = n; m >= 2; --m) {
    std::optional<BedFromViews> best;
    for (unsigned mask = 0; mask < (1u << n); ++mask) {
      if (__builtin_popcount(mask) != m) continue;
      std::vector<Camera> c;
      std::vector<BedDetection> b;
      for (int i = 0; i < n; ++i)
        if (mask & (1u << i)) {
          c.push_back(cameras[i]);
          b.push_back(beds[i]);
        }
      std::string why;
      const std::optional<BedFromViews> found = LocateFromAll(c, b, &why);
      if (first_why.empty() && m == n) first_why = why;
      if (found && found->views == m && (!best || found->spread_m < best->spread_m)) best = found;
    }
    if (best) return *best;
  }
  throw InputError(
      "",
      "bed",
      fmt::format(
          "no two of the {} views agree on a trampoline's bed (all of them: {})", n, first_why));
}

}  // namespace acro::vision
