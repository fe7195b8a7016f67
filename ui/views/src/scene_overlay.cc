#include "acro/views/scene_overlay.h"

#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "acro/scene/silhouette_check.h"
#include "acro/views/camera_composite.h"
#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"

namespace acro::ui {

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Show : analysis::SceneShow {
  bool shaded = true;
};

// The actors of one trial scene, built from its first frame and updated in place.
class SceneActors {
 public:
  SceneActors(SceneRenderer* renderer,
              const analysis::TrialFrame& f,
              const Show& show,
              bool athlete,
              double scale_px)
      : renderer_(renderer), show_(show), athlete_(athlete) {
    analysis::SceneLines links = f.keypoint_links;
    links.width_px = 0.6 * scale_px;
    if (athlete_) {
      analysis::SceneMesh mesh = f.athlete.mesh;
      mesh.colour = {0.25f, 0.6f, 1.0f, 0.55f};  // the virtual athlete: blue, see-through
      mesh_ = renderer->AddMesh(mesh);
      // The ghost: the same athlete's mesh, orange and see-through (shown in the flights it is in).
      analysis::SceneMesh ghost = f.athlete.mesh;
      ghost.colour = {1.0f, 0.55f, 0.1f, 0.5f};
      ghost_ = renderer->AddMesh(ghost);
      analysis::SceneLines bones = f.athlete.skeleton;
      bones.colour = {0.95f, 0.95f, 0.95f, 1.0f};  // the trunk; the left red, the right green
      bones.width_px = 0.6 * scale_px;
      bones_ = renderer->AddLines(bones);
      joints_ = renderer->AddPoints(f.athlete.skeleton.points_W, 0.03, {0.1f, 0.5f, 0.1f, 1});
      com_ = renderer->AddPoints(f.athlete.com_W, 0.06, {1.0f, 0.85f, 0.0f, 1});
      analysis::SceneLines trail = f.com_trail;
      trail.width_px = 0.4 * scale_px;
      trail_ = renderer->AddLines(trail);
      analysis::SceneLines residual = f.residual;
      residual.width_px = 0.6 * scale_px;
      residual_ = renderer->AddLines(residual);
    } else {
      links_ = renderer->AddLines(links);
    }
    // Markers are about 14 mm wide; video keypoints are drawn as joints.
    markers_ = renderer->AddPoints(f.markers_W, athlete_ ? 0.01 : 0.02, {1.0f, 0.3f, 0.9f, 1});
    if (!show.shaded) {
      for (const int id :
           {mesh_, ghost_, bones_, joints_, com_, trail_, residual_, links_, markers_})
        if (id >= 0) renderer->SetLit(id, false);
    }
    Update(f, true);
  }

  void Update(const analysis::TrialFrame& f, bool visible) {
    if (athlete_) {
      renderer_->UpdateMesh(mesh_, f.athlete.mesh.vertices_W);
      renderer_->UpdateLines(bones_, f.athlete.skeleton.points_W);
      renderer_->UpdatePoints(joints_, f.athlete.skeleton.points_W);
      renderer_->UpdatePoints(com_, f.athlete.com_W);
      renderer_->UpdateLines(trail_, f.com_trail.points_W);
      renderer_->UpdateLines(residual_, f.residual.points_W);
      renderer_->SetVisible(mesh_, visible && show_.mesh);
      if (f.ghost_shown) renderer_->UpdateMesh(ghost_, f.ghost.mesh.vertices_W);
      renderer_->SetVisible(ghost_, visible && f.ghost_shown);
      renderer_->SetVisible(bones_, visible && show_.skeleton);
      renderer_->SetVisible(joints_, visible && show_.skeleton);
      renderer_->SetVisible(com_, visible && show_.com);
      renderer_->SetVisible(trail_, visible && show_.com && f.com_trail.num_segments() > 0);
      renderer_->SetVisible(residual_, visible && show_.residual);
    } else {
      renderer_->UpdateLines(links_, f.keypoint_links.points_W);
      renderer_->SetVisible(links_, visible && show_.skeleton);
    }
    renderer_->UpdatePoints(markers_, f.markers_W);
    renderer_->SetVisible(markers_, visible && show_.markers && f.markers_W.cols() > 0);
  }

 private:
  SceneRenderer* renderer_;
  Show show_;
  bool athlete_;
  int mesh_ = -1, ghost_ = -1, bones_ = -1, joints_ = -1, com_ = -1, trail_ = -1, residual_ = -1,
      links_ = -1, markers_ = -1;
};

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

OverlayTiming WriteSceneOverlay(capture::VideoReader& video,
                                analysis::TrialScene& scene,
                                const vision::Camera& calibrated,
                                const std::filesystem::path& output,
                                const SceneOverlayOptions& options) {
  const capture::VideoInfo& info = video.info();
  // The camera's pixels are the video's from the top-left corner, whatever the size it was
  // calibrated at (a calibration at the coded size, 1088 px, fits a 1080 px video).
  vision::Camera camera = calibrated;
  camera.width_px = info.width;
  camera.height_px = info.height;
  const int first = std::max(0, options.first_frame);
  const int last = options.last_frame < 0 ? info.num_frames - 1
                                          : std::min(options.last_frame, info.num_frames - 1);
  if (first > last)
    throw InputError(info.path,
                     "--frames",
                     "frames " + std::to_string(first) + ".." + std::to_string(options.last_frame) +
                         " are not in the video (" + std::to_string(info.num_frames) + " frames)");
  const int slow = std::max(1, options.slow);
  if (options.show.mismatch &&
      (options.background == nullptr || options.background->width() != info.width ||
       options.background->height() != info.height || !scene.has_athlete()))
    throw std::invalid_argument(
        "WriteSceneOverlay: the mismatch needs the video's background model and an athlete");

  const XDisplay display;
  const CameraComposite composite(camera);
  const vision::Camera& pinhole = composite.render_camera();
  SceneRenderer renderer(pinhole.width_px, pinhole.height_px);
  renderer.LookThrough(pinhole);
  // Sizes in pixels follow the frame: 1 unit is 0.5 % of the diagonal, at least 3 px.
  const double scale_px = std::max(3.0, 0.005 * std::hypot(info.width, info.height));
  const int text_px = std::max(12, int(0.022 * info.height));

  capture::VideoWriterOptions w = options.video;
  if (info.average_fps > 0) w.fps = info.average_fps;
  capture::FrameOutput out(output, info.width, info.height, w);

  Show show;
  static_cast<analysis::SceneShow&>(show) = options.show;
  show.shaded = options.shaded;
  const double margin_px = 0.02 * std::hypot(info.width, info.height) + 2 * scale_px;
  analysis::TrialFrame tf;
  std::optional<SceneActors> actors;
  RenderImage render, strip;
  capture::VideoFrame frame;
  analysis::SilhouetteFrame silhouettes;
  vision::Mask real;
  std::string heads_up;
  OverlayTiming timing;
  const int total = last - first + 1;
  auto start = Clock::now();
  if (first > 0) {
    frame = video.Frame(first);
  } else if (!video.ReadNext(&frame)) {
    throw InputError(info.path, "", "no frame to read");
  }
  timing.decode_s += Since(start);
  while (true) {
    ++timing.frames_read;
    const double t = video.frame_times_s()[size_t(frame.index)];
    const int sample = options.sync.NearestSample(scene.trial(), t);
    bool in_flight = false;
    if (sample >= 0) {
      start = Clock::now();
      scene.Frame(sample, &tf);
      if (!actors) {
        actors.emplace(&renderer, tf, show, scene.has_athlete(), scale_px);
      } else {
        actors->Update(tf, true);
      }
      in_flight = scene.FlightAt(sample) >= 0;
      timing.scene_s += Since(start);
      // Only the part of the frame the scene covers is rendered, read back and composited.
      const PixelBox box = FrameBox(tf, show, scene.has_athlete(), camera, margin_px);
      start = Clock::now();
      if (!box.empty()) renderer.Render(composite.RenderRegion(box), &render);
      timing.render_s += Since(start);
      start = Clock::now();
      // The silhouettes are compared on the frame as filmed, the mismatch drawn over the render.
      const bool mismatch = options.show.mismatch && in_flight;
      if (mismatch) {
        real = options.background->Foreground(frame, options.background_options);
        analysis::CompareSilhouettes(real, tf, camera, options.box_margin, &silhouettes);
      }
      if (!box.empty()) composite.Composite(render, box, &frame.pixels);
      heads_up = tf.heads_up;
      if (mismatch) {
        TintMismatch(real, silhouettes, &frame.pixels);
        heads_up += fmt::format("  IoU {:.2f}", silhouettes.iou);
      }
      if (options.heads_up) {
        RenderTextLine(heads_up, text_px, tf.heads_up_colour, &strip);
        BlendOver(strip, text_px / 2, text_px / 2, info.width, info.height, &frame.pixels);
      }
      timing.composite_s += Since(start);
    }
    start = Clock::now();
    const int copies = in_flight && out.is_video() ? slow : 1;
    for (int c = 0; c < copies; ++c) out.Write(frame.index, frame.pixels);
    timing.frames_written += copies;
    timing.encode_s += Since(start);
    if (options.progress && !options.progress(frame.index - first + 1, total))
      throw InputError(output.string(), "", "cancelled; nothing written");
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
