#include "networks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "acro/base/input_error.h"

namespace acro::pose::internal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kDetectorSize = 224;
constexpr int kNumAnchors = 2254;
constexpr int kLandmarkSize = 256;
constexpr int kNumLandmarks = 39;
constexpr int kHeatmapSize = 64;

double Sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Loads an ONNX network and checks that it answers with the outputs MediaPipe's graph reads
// (another version of the package, or a damaged file, is refused here in one line).
cv::dnn::Net LoadNetwork(const std::filesystem::path& onnx, int input_size,
                         const std::vector<std::pair<cv::String, int>>& outputs) {
  cv::dnn::Net net;
  try {
    net = cv::dnn::readNetFromONNX(onnx.string());
  } catch (const cv::Exception& e) {
    throw InputError(onnx.string(), "", "not a network OpenCV's DNN can read (damaged? run scripts/install-models.sh)");
  }
  if (net.empty()) throw InputError(onnx.string(), "", "an empty network (run scripts/install-models.sh)");
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  int dims[] = {1, 3, input_size, input_size};
  net.setInput(cv::Mat(4, dims, CV_32F, cv::Scalar(0.5)));
  std::vector<cv::String> names;
  for (const auto& [name, size] : outputs) names.push_back(name);
  std::vector<cv::Mat> blobs;
  try {
    net.forward(blobs, names);
  } catch (const cv::Exception& e) {
    throw InputError(onnx.string(), "", fmt::format("does not run as a {0}×{0} pose network (another model? run "
                                                    "scripts/install-models.sh)", input_size));
  }
  for (std::size_t k = 0; k < outputs.size(); ++k)
    if (static_cast<int>(blobs[k].total()) != outputs[k].second)
      throw InputError(onnx.string(), std::string("output ") + outputs[k].first,
                       fmt::format("{} values, {} expected (another model version? run scripts/install-models.sh)",
                                   blobs[k].total(), outputs[k].second));
  return net;
}

// MediaPipe's SSD anchors for the pose detector (ssd_anchors_calculator with its pose_detection
// options): strides 8, 16, 32, 32, 32, layers of one stride merged into one grid, two anchors per
// layer and cell (aspect 1 and the interpolated scale), centres at cell centres, fixed size 1.
std::vector<Eigen::Vector2d> MakeAnchors() {
  std::vector<Eigen::Vector2d> anchors;
  const std::vector<std::pair<int, int>> grids = {{8, 2}, {16, 2}, {32, 6}};  // stride, anchors per cell
  for (const auto& [stride, per_cell] : grids) {
    const int cells = (kDetectorSize + stride - 1) / stride;
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x)
        for (int k = 0; k < per_cell; ++k) anchors.emplace_back((x + 0.5) / cells, (y + 0.5) / cells);
  }
  return anchors;
}

double Iou(const PersonCandidate& a, const PersonCandidate& b) {
  const Eigen::Vector2d lo = a.box_min_px.cwiseMax(b.box_min_px), hi = a.box_max_px.cwiseMin(b.box_max_px);
  if ((hi - lo).minCoeff() <= 0) return 0.0;
  const double inter = (hi - lo).prod();
  const double area_a = (a.box_max_px - a.box_min_px).prod(), area_b = (b.box_max_px - b.box_min_px).prod();
  return inter / (area_a + area_b - inter);
}

// MediaPipe's weighted non-maximum suppression (IoU over 0.3): each kept detection's box and
// keypoints are the score-weighted mean of the detections it suppresses; its score is its own.
std::vector<PersonCandidate> WeightedNms(std::vector<PersonCandidate> all) {
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.score > b.score; });
  std::vector<PersonCandidate> kept;
  while (!all.empty()) {
    const PersonCandidate top = all.front();
    PersonCandidate mean = top;
    mean.box_min_px.setZero();
    mean.box_max_px.setZero();
    for (auto& k : mean.keypoints_px) k.setZero();
    double total = 0.0;
    std::vector<PersonCandidate> rest;
    for (const PersonCandidate& c : all) {
      if (Iou(top, c) > 0.3) {
        total += c.score;
        mean.box_min_px += c.score * c.box_min_px;
        mean.box_max_px += c.score * c.box_max_px;
        for (int k = 0; k < 4; ++k) mean.keypoints_px[k] += c.score * c.keypoints_px[k];
      } else {
        rest.push_back(c);
      }
    }
    if (total <= 0.0) {  // only the top itself, with a zero box
      kept.push_back(top);
      all.erase(all.begin());
      continue;
    }
    mean.box_min_px /= total;
    mean.box_max_px /= total;
    for (auto& k : mean.keypoints_px) k /= total;
    kept.push_back(mean);
    all = std::move(rest);
  }
  return kept;
}

// The affine map (for warpAffine's inverse mapping) from an output pixel (x, y) of a `size` square
// tensor to the image: the tensor's corners are the region's corners (MediaPipe's crop maps the
// rotated box's corners onto the tensor's, so pixel x sits at x / size of the side).
cv::Mat TensorToImage(const Roi& roi, int size) {
  const double c = std::cos(roi.rotation), s = std::sin(roi.rotation);
  const double k = roi.size_px / size;
  cv::Mat m(2, 3, CV_64F);
  m.at<double>(0, 0) = c * k;
  m.at<double>(0, 1) = -s * k;
  m.at<double>(0, 2) = roi.centre_px.x() - 0.5 * roi.size_px * (c - s);
  m.at<double>(1, 0) = s * k;
  m.at<double>(1, 1) = c * k;
  m.at<double>(1, 2) = roi.centre_px.y() - 0.5 * roi.size_px * (s + c);
  return m;
}

}  // namespace

double WrapAngle(double a) { return a - 2 * kPi * std::floor((a + kPi) / (2 * kPi)); }

Roi RoiFromAlignment(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
  Roi roi;
  roi.centre_px = p0;
  roi.size_px = 2.0 * (p1 - p0).norm() * 1.25;
  roi.rotation = WrapAngle(kPi / 2 - std::atan2(-(p1.y() - p0.y()), p1.x() - p0.x()));
  return roi;
}

PersonDetectorNet::PersonDetectorNet(const std::filesystem::path& onnx)
    : net_(LoadNetwork(onnx, kDetectorSize, {{"Identity", kNumAnchors * 12}, {"Identity_1", kNumAnchors}})),
      anchors_(MakeAnchors()) {}

std::vector<PersonCandidate> PersonDetectorNet::Detect(const cv::Mat& rgb, const cv::Rect2d& region_px,
                                                       double min_score) {
  // The region letterboxed into a square of its longer side, outside the image black (→ −1).
  auto t0 = std::chrono::steady_clock::now();
  Roi square;
  square.centre_px = {region_px.x + 0.5 * region_px.width, region_px.y + 0.5 * region_px.height};
  square.size_px = std::max(region_px.width, region_px.height);
  cv::Mat crop;
  cv::warpAffine(rgb, crop, TensorToImage(square, kDetectorSize), cv::Size(kDetectorSize, kDetectorSize),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0));
  net_.setInput(cv::dnn::blobFromImage(crop, 1.0 / 127.5, cv::Size(), cv::Scalar(127.5, 127.5, 127.5), false, false));
  times_.crop_s += Since(t0);
  t0 = std::chrono::steady_clock::now();
  std::vector<cv::Mat> out;
  net_.forward(out, std::vector<cv::String>{"Identity", "Identity_1"});
  times_.network_s += Since(t0);
  t0 = std::chrono::steady_clock::now();
  ++times_.runs;
  const float* boxes = out[0].ptr<float>();
  const float* logits = out[1].ptr<float>();

  // Decoding (tensors_to_detections with the pose detector's options: XYWH, scale 224).
  const auto to_image = [&](double u, double v) {
    return Eigen::Vector2d(square.centre_px.x() + (u - 0.5) * square.size_px,
                           square.centre_px.y() + (v - 0.5) * square.size_px);
  };
  std::vector<PersonCandidate> found;
  for (int i = 0; i < kNumAnchors; ++i) {
    const double score = Sigmoid(std::clamp<double>(logits[i], -100.0, 100.0));
    if (score < min_score) continue;
    const float* r = boxes + 12 * i;
    const Eigen::Vector2d& a = anchors_[i];
    const double xc = r[0] / kDetectorSize + a.x(), yc = r[1] / kDetectorSize + a.y();
    const double w = r[2] / static_cast<double>(kDetectorSize), h = r[3] / static_cast<double>(kDetectorSize);
    if (!(w >= 0 && h >= 0)) continue;
    PersonCandidate c;
    c.score = score;
    c.box_min_px = to_image(xc - w / 2, yc - h / 2);
    c.box_max_px = to_image(xc + w / 2, yc + h / 2);
    for (int k = 0; k < 4; ++k)
      c.keypoints_px[k] = to_image(r[4 + 2 * k] / kDetectorSize + a.x(), r[5 + 2 * k] / kDetectorSize + a.y());
    found.push_back(c);
  }
  std::vector<PersonCandidate> kept = WeightedNms(std::move(found));
  times_.post_s += Since(t0);
  return kept;
}

LandmarkNet::LandmarkNet(const std::filesystem::path& onnx)
    : net_(LoadNetwork(onnx, kLandmarkSize,
                       {{"Identity", kNumLandmarks * 5},
                        {"Identity_1", 1},
                        {"Identity_3", kNumLandmarks * kHeatmapSize * kHeatmapSize}})) {}

LandmarkResult LandmarkNet::Run(const cv::Mat& rgb, const Roi& roi) {
  auto t0 = std::chrono::steady_clock::now();
  cv::Mat crop;
  cv::warpAffine(rgb, crop, TensorToImage(roi, kLandmarkSize), cv::Size(kLandmarkSize, kLandmarkSize),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  net_.setInput(cv::dnn::blobFromImage(crop, 1.0 / 255.0, cv::Size(), cv::Scalar(), false, false));
  times_.crop_s += Since(t0);
  t0 = std::chrono::steady_clock::now();
  std::vector<cv::Mat> out;
  net_.forward(out, std::vector<cv::String>{"Identity", "Identity_1", "Identity_3"});
  times_.network_s += Since(t0);
  t0 = std::chrono::steady_clock::now();
  ++times_.runs;
  const float* raw = out[0].ptr<float>();
  const float* heat = out[2].ptr<float>();  // NCHW: [39][64][64]

  LandmarkResult result;
  result.roi = roi;
  result.pose_score = out[1].ptr<float>()[0];
  const double c = std::cos(roi.rotation), s = std::sin(roi.rotation);
  for (int i = 0; i < kNumLandmarks; ++i) {
    double u = raw[5 * i] / kLandmarkSize, v = raw[5 * i + 1] / kLandmarkSize;
    // Heatmap refinement (MediaPipe: a 7 × 7 window around the regressed point, the
    // confidence-weighted mean of the cells when the window's peak is at least 0.5).
    const int col = static_cast<int>(u * kHeatmapSize), row = static_cast<int>(v * kHeatmapSize);
    double peak = 0.0;
    if (col >= 0 && col < kHeatmapSize && row >= 0 && row < kHeatmapSize) {
      double sum = 0.0, su = 0.0, sv = 0.0;
      const float* channel = heat + static_cast<std::size_t>(i) * kHeatmapSize * kHeatmapSize;
      for (int y = std::max(row - 3, 0); y <= std::min(row + 3, kHeatmapSize - 1); ++y)
        for (int x = std::max(col - 3, 0); x <= std::min(col + 3, kHeatmapSize - 1); ++x) {
          const double conf = Sigmoid(channel[y * kHeatmapSize + x]);
          sum += conf;
          su += x * conf;
          sv += y * conf;
          peak = std::max(peak, conf);
        }
      if (peak >= 0.5 && sum > 0.0) {
        u = su / sum / kHeatmapSize;
        v = sv / sum / kHeatmapSize;
      }
    }
    // Back to the image through the region's rotation.
    const double du = (u - 0.5) * roi.size_px, dv = (v - 0.5) * roi.size_px;
    result.landmarks(0, i) = roi.centre_px.x() + c * du - s * dv;
    result.landmarks(1, i) = roi.centre_px.y() + s * du + c * dv;
    result.landmarks(2, i) = raw[5 * i + 2] / kLandmarkSize * roi.size_px;
    result.landmarks(3, i) = Sigmoid(raw[5 * i + 3]);
    result.landmarks(4, i) = Sigmoid(raw[5 * i + 4]);
    result.landmarks(5, i) = peak;
  }
  times_.post_s += Since(t0);
  return result;
}

double LandmarkResult::Quality() const {
  const double presence = landmarks.block<1, 33>(4, 0).mean();
  const double visibility = landmarks.block<1, 33>(3, 0).mean();
  return pose_score * presence * (0.5 + 0.5 * visibility);
}

Roi LandmarkResult::NextRoi() const {
  return RoiFromAlignment(landmarks.block<2, 1>(0, 33), landmarks.block<2, 1>(0, 34));
}

}  // namespace acro::pose::internal
