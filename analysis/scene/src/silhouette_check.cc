#include "acro/scene/silhouette_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "acro/base/input_error.h"
#include "acro/base/progress.h"

namespace acro::analysis {

namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

// The IoU of two masks within [x0, x1) × [y0, y1).
double BoxIoU(const vision::Mask& a, const vision::Mask& b, int x0, int y0, int x1, int y1) {
  long inter = 0, uni = 0;
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* pa = a.pixels.data() + size_t(y) * size_t(a.width);
    const std::uint8_t* pb = b.pixels.data() + size_t(y) * size_t(b.width);
    for (int x = x0; x < x1; ++x) {
      const bool ia = pa[x] != 0, ib = pb[x] != 0;
      inter += (ia && ib) ? 1 : 0;
      uni += (ia || ib) ? 1 : 0;
    }
  }
  return uni == 0 ? 1.0 : double(inter) / double(uni);
}

// The IoU of the video's foreground with the athlete of `tf` (CompareSilhouettes).
double AthleteIoU(const vision::Mask& real,
                  const TrialFrame& tf,
                  const vision::Camera& camera,
                  double margin) {
  SilhouetteFrame f;
  CompareSilhouettes(real, tf, camera, margin, &f);
  return f.iou;
}

}  // namespace

namespace {

// The athlete of `tf` drawn through `camera` into out->athlete, and the box the two silhouettes are
// compared in: the drawn pixels' box grown by `margin` of its size (+2 px) on each side.
void DrawAthleteAndBox(const TrialFrame& tf,
                       const vision::Camera& camera,
                       double margin,
                       SilhouetteFrame* out) {
  vision::PixelRect drawn;
  out->athlete = vision::RenderSilhouette(
      camera, tf.athlete.mesh.vertices_W, tf.athlete.mesh.triangles, &drawn);
  out->x0 = out->y0 = out->x1 = out->y1 = 0;
  out->iou = 0.0;
  if (drawn.empty()) return;
  const int W = camera.width_px, H = camera.height_px;
  const int gx = static_cast<int>(margin * (drawn.x1 - drawn.x0)) + 2;
  const int gy = static_cast<int>(margin * (drawn.y1 - drawn.y0)) + 2;
  out->x0 = std::max(0, drawn.x0 - gx);
  out->y0 = std::max(0, drawn.y0 - gy);
  out->x1 = std::min(W, drawn.x1 + gx);
  out->y1 = std::min(H, drawn.y1 + gy);
}

}  // namespace

void CompareSilhouettes(const vision::Mask& real,
                        const TrialFrame& tf,
                        const vision::Camera& camera,
                        double margin,
                        SilhouetteFrame* out) {
  DrawAthleteAndBox(tf, camera, margin, out);
  if (out->x1 <= out->x0) return;
  out->iou = BoxIoU(real, out->athlete, out->x0, out->y0, out->x1, out->y1);
}

void CompareSilhouettes(const vision::BackgroundModel& background,
                        const capture::VideoFrame& frame,
                        const vision::BackgroundOptions& options,
                        const TrialFrame& tf,
                        const vision::Camera& camera,
                        double margin,
                        vision::Mask* real,
                        SilhouetteFrame* out) {
  if (camera.width_px != frame.width || camera.height_px != frame.height)
    throw std::invalid_argument("CompareSilhouettes: the camera's picture is not the frame's size");
  DrawAthleteAndBox(tf, camera, margin, out);
  *real =
      background.Foreground(frame, options, vision::PixelRect{out->x0, out->y0, out->x1, out->y1});
  if (out->x1 <= out->x0) return;
  out->iou = BoxIoU(*real, out->athlete, out->x0, out->y0, out->x1, out->y1);
}

SilhouetteCheck CheckSilhouettes(capture::VideoReader& video,
                                 TrialScene& scene,
                                 const vision::Camera& calibrated,
                                 const SilhouetteCheckOptions& options) {
  if (!scene.has_athlete())
    throw std::invalid_argument("CheckSilhouettes: the scene has no athlete to compare");
  const capture::VideoInfo& info = video.info();
  vision::Camera camera = calibrated;  // its pixels are the video's (a padded calibration fits)
  camera.width_px = info.width;
  camera.height_px = info.height;
  std::optional<vision::BackgroundModel> built;
  if (options.background_model == nullptr) built.emplace(video, options.background_frames);
  const vision::BackgroundModel& background = built ? *built : *options.background_model;

  SilhouetteCheck out;
  const std::vector<double>& times = video.frame_times_s();
  // The frames to compare: synced samples inside flights.
  std::vector<int> wanted(times.size(), -1);
  int total = 0;
  for (size_t i = 0; i < times.size(); ++i) {
    const int sample = options.sync.NearestSample(scene.trial(), times[i]);
    if (sample >= 0 && scene.FlightAt(sample) >= 0) {
      wanted[i] = sample;
      ++total;
    }
  }
  TrialFrame tf;
  capture::VideoFrame frame;
  vision::Mask real;
  SilhouetteFrame compared;
  int done = 0;
  // A fresh sequential pass (the background model read frames out of order).
  if (total > 0) {
    int first = 0;
    while (wanted[size_t(first)] < 0) ++first;
    frame = video.Frame(first);
    do {
      const int sample = wanted[size_t(frame.index)];
      if (sample < 0) continue;
      scene.Frame(sample, &tf);
      // The foreground in the athlete's box only: all the comparison reads.
      CompareSilhouettes(
          background, frame, options.background, tf, camera, options.box_margin, &real, &compared);
      const double iou = compared.iou;
      out.frames.push_back(frame.index);
      out.samples.push_back(sample);
      out.flights.push_back(scene.FlightAt(sample));
      out.iou.push_back(iou);
      ++done;
      if (options.progress && !options.progress(done, total)) throw Cancelled();
    } while (done < total && video.ReadNext(&frame));
  }
  int num_flights = 0;
  for (const int f : out.flights) num_flights = std::max(num_flights, f + 1);
  for (int s = 0; s < scene.num_samples(); ++s)
    num_flights = std::max(num_flights, scene.FlightAt(s) + 1);
  out.flight_median_iou.assign(size_t(num_flights), std::numeric_limits<double>::quiet_NaN());
  for (int f = 0; f < num_flights; ++f) {
    std::vector<double> v;
    for (size_t k = 0; k < out.iou.size(); ++k)
      if (out.flights[k] == f) v.push_back(out.iou[k]);
    out.flight_median_iou[size_t(f)] = Median(v);
  }
  out.median_iou = Median(out.iou);
  return out;
}

SilhouetteSync RefineSyncBySilhouettes(capture::VideoReader& video,
                                       TrialScene& scene,
                                       const vision::Camera& calibrated,
                                       const SilhouetteCheckOptions& options,
                                       double half_range_s,
                                       int frame_stride) {
  if (!scene.has_athlete())
    throw std::invalid_argument("RefineSyncBySilhouettes: the scene has no athlete to compare");
  if (!(half_range_s >= 0) || frame_stride < 1 || scene.rate_hz() <= 0)
    throw std::invalid_argument("RefineSyncBySilhouettes: a range ≥ 0 and a stride ≥ 1");
  const capture::VideoInfo& info = video.info();
  vision::Camera camera = calibrated;
  camera.width_px = info.width;
  camera.height_px = info.height;
  std::optional<vision::BackgroundModel> built;
  if (options.background_model == nullptr) built.emplace(video, options.background_frames);
  const vision::BackgroundModel& background = built ? *built : *options.background_model;
  // The frames: every frame_stride-th one in a flight at the starting sync.
  const std::vector<double>& times = video.frame_times_s();
  std::vector<int> frames;
  for (size_t i = 0; i < times.size(); ++i) {
    const int sample = options.sync.NearestSample(scene.trial(), times[i]);
    if (sample >= 0 && scene.FlightAt(sample) >= 0) frames.push_back(int(i));
  }
  std::vector<int> chosen;
  for (size_t k = 0; k < frames.size(); k += size_t(frame_stride)) chosen.push_back(frames[k]);
  // Their foregrounds, once (decoded in order).
  std::vector<vision::Mask> real;
  capture::VideoFrame frame;
  for (size_t k = 0; k < chosen.size(); ++k) {
    if (k == 0 || chosen[k] != frame.index + 1) {
      frame = video.Frame(chosen[k]);
    } else if (!video.ReadNext(&frame)) {
      break;
    }
    real.push_back(background.Foreground(frame, options.background));
    if (options.progress && !options.progress(int(k + 1), int(chosen.size()))) throw Cancelled();
  }
  SilhouetteSync out;
  out.sync = options.sync;
  out.median_iou = -1;
  const double step = options.sync.rate / scene.rate_hz();  // one sample, in video time
  const int steps = static_cast<int>(std::floor(half_range_s / step + 1e-9));
  TrialFrame tf;
  for (int s = -steps; s <= steps; ++s) {
    vision::VideoSync sync = options.sync;
    sync.offset_s += s * step;
    std::vector<double> ious;
    for (size_t k = 0; k < real.size(); ++k) {
      const int sample = sync.NearestSample(scene.trial(), times[size_t(chosen[k])]);
      if (sample < 0) continue;
      scene.Frame(sample, &tf);
      ious.push_back(AthleteIoU(real[k], tf, camera, options.box_margin));
    }
    const double median = ious.empty() ? 0.0 : Median(ious);
    out.offsets_s.push_back(sync.offset_s);
    out.median_ious.push_back(median);
    if (median > out.median_iou) {
      out.median_iou = median;
      out.sync = sync;
    }
  }
  return out;
}

AutoVideoSync SyncVideoAutomatically(TrialScene& scene,
                                     const vision::Camera& camera,
                                     capture::VideoReader& video,
                                     const vision::AutoSyncOptions& motion,
                                     SilhouetteCheckOptions silhouettes) {
  AutoVideoSync out;
  // The motion pass in grey (luma alone, no colour conversion), then the reader as it came.
  const capture::VideoPixels handed = video.pixels();
  video.SetPixels(capture::VideoPixels::kGrey);
  try {
    out.motion = vision::SyncFromImageMotion(scene.trial(), camera, video, motion);
  } catch (...) {
    video.SetPixels(handed);
    throw;
  }
  video.SetPixels(handed);
  silhouettes.sync = out.motion.sync;
  const double frame_s = 1.0 / std::max(1.0, video.info().average_fps);
  out.refined = RefineSyncBySilhouettes(video, scene, camera, silhouettes, frame_s);
  return out;
}

void AttachSilhouetteCheck(const SilhouetteCheck& check, TrialAnalysis* analysis) {
  for (JumpMetrics& j : analysis->jumps) {
    const size_t f = static_cast<size_t>(j.index - 1);
    if (f < check.flight_median_iou.size() && std::isfinite(check.flight_median_iou[f]))
      j.silhouette_iou = check.flight_median_iou[f];
  }
}

}  // namespace acro::analysis
