#include "acro/views/scene_overlay.h"

#include <chrono>
#include <optional>

#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
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
      mesh.colour = {0.95f, 0.7f, 0.45f, 0.6f};
      mesh_ = renderer->AddMesh(mesh);
      analysis::SceneLines bones = f.athlete.skeleton;
      bones.colour = {0.15f, 0.95f, 0.3f, 1.0f};
      bones.width_px = 0.6 * scale_px;
      bones_ = renderer->AddLines(bones);
      joints_ = renderer->AddPoints(f.athlete.skeleton.points_W, 0.03, {0.1f, 0.5f, 0.1f, 1});
      com_ = renderer->AddPoints(f.athlete.com_W, 0.06, {1.0f, 0.85f, 0.0f, 1});
      trail_ = renderer->AddPoints(f.com_trail_W, 0.015, {1.0f, 0.85f, 0.0f, 1});
      analysis::SceneLines residual = f.residual;
      residual.width_px = 0.6 * scale_px;
      residual_ = renderer->AddLines(residual);
    } else {
      links_ = renderer->AddLines(links);
    }
    // Markers are about 14 mm wide; video keypoints are drawn as joints.
    markers_ = renderer->AddPoints(f.markers_W, athlete_ ? 0.01 : 0.02, {1.0f, 0.3f, 0.9f, 1});
    if (!show.shaded) {
      for (const int id : {mesh_, bones_, joints_, com_, trail_, residual_, links_, markers_})
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
      renderer_->UpdatePoints(trail_, f.com_trail_W);
      renderer_->UpdateLines(residual_, f.residual.points_W);
      renderer_->SetVisible(mesh_, visible && show_.mesh);
      renderer_->SetVisible(bones_, visible && show_.skeleton);
      renderer_->SetVisible(joints_, visible && show_.skeleton);
      renderer_->SetVisible(com_, visible && show_.com);
      renderer_->SetVisible(trail_, visible && show_.com && f.com_trail_W.cols() > 1);
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
  int mesh_ = -1, bones_ = -1, joints_ = -1, com_ = -1, trail_ = -1, residual_ = -1, links_ = -1,
      markers_ = -1;
};

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

  const XDisplay display;
  const CameraComposite composite(camera);
  const vision::Camera& pinhole = composite.render_camera();
  SceneRenderer renderer(pinhole.width_px, pinhole.height_px);
  renderer.LookThrough(pinhole);
  // Sizes in pixels follow the frame: 1 unit is 0.5 % of the diagonal, at least 3 px.
  const double scale_px = std::max(3.0, 0.005 * std::hypot(info.width, info.height));
  const int text_px = std::max(12, int(0.022 * info.height));
  std::optional<SceneRenderer> hud;
  int hud_text = -1;
  if (options.heads_up) {
    hud.emplace(std::min(info.width, text_px * 40), text_px * 2, 0);
    hud_text = hud->AddText(" ", text_px, {1, 1, 1, 1});
  }

  capture::VideoWriterOptions w = options.video;
  if (info.average_fps > 0) w.fps = info.average_fps;
  capture::FrameOutput out(output, info.width, info.height, w);

  analysis::TrialFrame tf;
  std::optional<SceneActors> actors;
  RenderImage render, strip;
  capture::VideoFrame frame;
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
        Show show;
        static_cast<analysis::SceneShow&>(show) = options.show;
        show.shaded = options.shaded;
        actors.emplace(&renderer, tf, show, scene.has_athlete(), scale_px);
      } else {
        actors->Update(tf, true);
      }
      in_flight = scene.FlightAt(sample) >= 0;
      timing.scene_s += Since(start);
      start = Clock::now();
      renderer.Render(&render);
      timing.render_s += Since(start);
      start = Clock::now();
      composite.Composite(render, &frame.pixels);
      if (hud) {
        hud->UpdateText(hud_text, tf.heads_up);
        hud->SetColour(hud_text, tf.heads_up_colour);
        hud->Render(&strip);
        BlendOver(strip, 0, 0, info.width, info.height, &frame.pixels);
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
