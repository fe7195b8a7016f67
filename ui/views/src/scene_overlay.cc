#include "acro/views/scene_overlay.h"

#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/capture/frame_output.h"
#include "acro/scene/silhouette_check.h"
#include "acro/views/camera_composite.h"
#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"
#include "scene_actors.h"

namespace acro::ui {

using internal::SceneActors;
using internal::Show;

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Grows `box` (min, max) by the points.
void Extend(const Eigen::Matrix3Xd& points, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  if (points.cols() == 0) return;
  *lo = lo->cwiseMin(points.rowwise().minCoeff());
  *hi = hi->cwiseMax(points.rowwise().maxCoeff());
}

// The frame pixels the drawn scene can cover: the box of what is shown, grown by 0.1 m (spheres,
// tubes), its corners projected by the camera, grown by `margin_px` (the curved edges of a
// distorted projection, line widths). All of the frame when a corner is behind the camera; an
// empty box when nothing is shown.
PixelBox FrameBox(const analysis::TrialFrame& f,
                  const Show& show,
                  bool athlete,
                  const vision::Camera& camera,
                  double margin_px) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  if (athlete) {
    if (show.mesh) Extend(f.athlete.mesh.vertices_W, &lo, &hi);
    if (f.ghost_shown) Extend(f.ghost.mesh.vertices_W, &lo, &hi);
    if (show.skeleton) Extend(f.athlete.skeleton.points_W, &lo, &hi);
    if (show.com) {
      Extend(f.athlete.com_W, &lo, &hi);
      Extend(f.com_trail.points_W, &lo, &hi);
    }
    if (show.residual) Extend(f.residual.points_W, &lo, &hi);
  } else if (show.skeleton) {
    // Links with both ends missing sit far below the floor (TrialScene): not part of the box.
    const Eigen::Matrix3Xd& p = f.keypoint_links.points_W;
    for (Eigen::Index k = 0; k < p.cols(); ++k)
      if (p(2, k) > -100.0) Extend(p.col(k), &lo, &hi);
  }
  if (show.markers) Extend(f.markers_W, &lo, &hi);
  if (!(lo.array() <= hi.array()).all()) return {};
  lo.array() -= 0.1;
  hi.array() += 0.1;
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner(
        (c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    const std::optional<Eigen::Vector2d> uv = camera.Project(corner);
    if (!uv) return {0, 0, camera.width_px, camera.height_px};
    u0 = std::min(u0, uv->x());
    v0 = std::min(v0, uv->y());
    u1 = std::max(u1, uv->x());
    v1 = std::max(v1, uv->y());
  }
  const auto clamp = [](double x, int limit) {
    return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(limit)));
  };
  return {clamp(std::floor(u0 - margin_px), camera.width_px),
          clamp(std::floor(v0 - margin_px), camera.height_px),
          clamp(std::ceil(u1 + margin_px) + 1, camera.width_px),
          clamp(std::ceil(v1 + margin_px) + 1, camera.height_px)};
}

// The silhouettes' mismatch over the frame, in the compared box: red where the video shows the
// athlete and the model is not, yellow where the model is and the video shows no athlete.
void TintMismatch(const vision::Mask& real,
                  const analysis::SilhouetteFrame& f,
                  std::vector<std::uint8_t>* rgb) {
  constexpr int kAlpha = 150;  // of 255
  const std::uint8_t kRed[3] = {235, 30, 30}, kYellow[3] = {255, 215, 0};
  const int W = real.width;
  for (int y = f.y0; y < f.y1; ++y)
    for (int x = f.x0; x < f.x1; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      const bool r = real.pixels[i] != 0, a = f.athlete.pixels[i] != 0;
      if (r == a) continue;
      const std::uint8_t* c = r ? kRed : kYellow;
      std::uint8_t* p = rgb->data() + 3 * i;
      for (int k = 0; k < 3; ++k)
        p[k] = std::uint8_t((c[k] * kAlpha + p[k] * (255 - kAlpha)) / 255);
    }
}

}  // namespace

struct TrialOverlay::Impl {
  Impl(analysis::TrialScene& scene_in,
       const vision::Camera& calibrated,
       int width,
       int height,
       const SceneOverlayOptions& options_in)
      : scene(scene_in),
        options(options_in),
        camera(Sized(calibrated, width, height)),
        composite(camera),
        renderer(composite.render_camera().width_px, composite.render_camera().height_px) {
    if (options.show.mismatch &&
        (options.background == nullptr || options.background->width() != width ||
         options.background->height() != height || !scene.has_athlete()))
      throw std::invalid_argument(
          "TrialOverlay: the mismatch needs the video's background model and an athlete");
    renderer.LookThrough(composite.render_camera());
    // Sizes in pixels follow the frame: 1 unit is 0.5 % of the diagonal, at least 3 px.
    scale_px = std::max(3.0, 0.005 * std::hypot(width, height));
    text_px = std::max(12, int(0.022 * height));
    margin_px = 0.02 * std::hypot(width, height) + 2 * scale_px;
    static_cast<analysis::SceneShow&>(show) = options.show;
    show.shaded = options.shaded;
  }
  // The camera's pixels are the video's from the top-left corner, whatever the size it was
  // calibrated at (a calibration at the coded size, 1088 px, fits a 1080 px video).
  static vision::Camera Sized(const vision::Camera& c, int width, int height) {
    vision::Camera sized = c;
    sized.width_px = width;
    sized.height_px = height;
    return sized;
  }

  analysis::TrialScene& scene;
  SceneOverlayOptions options;
  vision::Camera camera;
  XDisplay display;  // before the renderer, which needs it
  CameraComposite composite;
  SceneRenderer renderer;
  Show show;
  double scale_px = 3, margin_px = 0;
  int text_px = 12;
  analysis::TrialFrame tf;
  std::optional<SceneActors> actors;
  RenderImage render, strip;
  analysis::SilhouetteFrame silhouettes;
  vision::Mask real;
  std::string heads_up;
};

TrialOverlay::TrialOverlay(analysis::TrialScene& scene,
                           const vision::Camera& camera,
                           int width,
                           int height,
                           const SceneOverlayOptions& options)
    : impl_(std::make_unique<Impl>(scene, camera, width, height, options)) {}

TrialOverlay::~TrialOverlay() = default;

const analysis::TrialFrame& TrialOverlay::frame() const {
  return impl_->tf;
}

void TrialOverlay::Draw(int sample, capture::VideoFrame* frame, OverlayTiming* timing) {
  Impl& m = *impl_;
  if (frame->width != m.camera.width_px || frame->height != m.camera.height_px ||
      frame->channels != 3)
    throw std::invalid_argument("TrialOverlay::Draw: not an RGB frame of the overlay's size");
  OverlayTiming ignored;
  OverlayTiming& t = timing != nullptr ? *timing : ignored;
  auto start = Clock::now();
  m.scene.Frame(sample, &m.tf);
  if (!m.actors) {
    m.actors.emplace(&m.renderer, m.tf, m.show, m.scene.has_athlete(), m.scale_px);
  } else {
    m.actors->Update(m.tf, true);
  }
  const bool in_flight = m.scene.FlightAt(sample) >= 0;
  t.scene_s += Since(start);
  // Only the part of the frame the scene covers is rendered, read back and composited.
  const PixelBox box = FrameBox(m.tf, m.show, m.scene.has_athlete(), m.camera, m.margin_px);
  start = Clock::now();
  if (!box.empty()) m.renderer.Render(m.composite.RenderRegion(box), &m.render);
  t.render_s += Since(start);
  start = Clock::now();
  // The silhouettes are compared on the frame as filmed, the mismatch drawn over the render.
  const bool mismatch = m.options.show.mismatch && in_flight;
  if (mismatch) {
    analysis::CompareSilhouettes(*m.options.background,
                                 *frame,
                                 m.options.background_options,
                                 m.tf,
                                 m.camera,
                                 m.options.box_margin,
                                 &m.real,
                                 &m.silhouettes);
  }
  if (!box.empty()) m.composite.Composite(m.render, box, &frame->pixels);
  m.heads_up = m.tf.heads_up;
  if (mismatch) {
    TintMismatch(m.real, m.silhouettes, &frame->pixels);
    m.heads_up += fmt::format("  IoU {:.2f}", m.silhouettes.iou);
  }
  if (m.options.heads_up) {
    RenderTextLine(m.heads_up, m.text_px, m.tf.heads_up_colour, &m.strip);
    BlendOver(m.strip,
              m.text_px / 2,
              m.text_px / 2,
              m.camera.width_px,
              m.camera.height_px,
              &frame->pixels);
  }
  t.composite_s += Since(start);
}

OverlayTiming WriteSceneOverlay(capture::VideoReader& video,
                                analysis::TrialScene& scene,
                                const vision::Camera& camera,
                                const std::filesystem::path& output,
                                const SceneOverlayOptions& options) {
  const capture::VideoInfo& info = video.info();
  const int first = std::max(0, options.first_frame);
  const int last = options.last_frame < 0 ? info.num_frames - 1
                                          : std::min(options.last_frame, info.num_frames - 1);
  if (first > last)
    throw InputError(info.path,
                     "--frames",
                     "frames " + std::to_string(first) + ".." + std::to_string(options.last_frame) +
                         " are not in the video (" + std::to_string(info.num_frames) + " frames)");
  const int slow = std::max(1, options.slow);
  TrialOverlay overlay(scene, camera, info.width, info.height, options);

  capture::VideoWriterOptions w = options.video;
  if (info.average_fps > 0) w.fps = info.average_fps;
  capture::FrameOutput out(output, info.width, info.height, w);

  capture::VideoFrame frame;
  OverlayTiming timing;
  const int total = last - first + 1;
  auto start = Clock::now();
  // By index: the pass starts at `first` whatever this reader read before (the shared reader of
  // a door has built its background and synced on it).
  frame = video.Frame(first);
  timing.decode_s += Since(start);
  while (true) {
    ++timing.frames_read;
    const double t = video.frame_times_s()[size_t(frame.index)];
    const int sample = options.sync.NearestSample(scene.trial(), t);
    const bool in_flight = sample >= 0 && scene.FlightAt(sample) >= 0;
    if (sample >= 0) overlay.Draw(sample, &frame, &timing);
    start = Clock::now();
    const int copies = in_flight && out.is_video() ? slow : 1;
    for (int c = 0; c < copies; ++c) out.Write(frame.index, frame.pixels);
    timing.frames_written += copies;
    timing.encode_s += Since(start);
    if (options.progress && !options.progress(frame.index - first + 1, total))
      throw Cancelled(output.string() + ": cancelled; nothing written");
    if (frame.index >= last) break;
    start = Clock::now();
    const bool more = video.ReadNext(&frame);
    timing.decode_s += Since(start);
    if (!more) break;
  }
  start = Clock::now();
  out.Finish();
  timing.encode_s += Since(start);
  return timing;
}

}  // namespace acro::ui
