#include "acro/views/compare_video.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "acro/views/camera_composite.h"
#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"
#include "scene_actors.h"

namespace acro::ui {

namespace {

constexpr analysis::Rgba kSkinA{0.9f, 0.62f, 0.45f, 1.0f};
constexpr analysis::Rgba kBlueB{0.25f, 0.55f, 1.0f, 1.0f};
constexpr analysis::Rgba kGhostB{0.25f, 0.55f, 1.0f, 0.45f};

// One of the three views: its renderer, the athletes it shows, and its label.
struct View {
  std::unique_ptr<SceneRenderer> renderer;
  int a = -1;  // actor ids, −1 when not shown
  int b = -1;
  std::string label;
};

}  // namespace

int WriteCompareVideo(analysis::CompareScene& scene,
                      const analysis::TimedPanel& panel,
                      const std::filesystem::path& output,
                      const CompareVideoOptions& options) {
  const int vw = options.view_width, vh = options.view_height;
  const int width = 3 * vw;
  const int height = vh + (panel.rgb.empty() ? 0 : panel.height);
  if (!panel.rgb.empty() && panel.width != width)
    throw std::invalid_argument("WriteCompareVideo: the panel is not three views wide");
  const XDisplay display;

  analysis::CompareFrame f;
  scene.Frame(scene.start_s(), &f);
  // From the side of A's take-off: across its heading, level, looking at mid-flight height.
  const analysis::TakeoffPlacement pa = FindTakeoff(*scene.a().analysis, scene.a().jump);
  FreeViewpoint view = PresetViewpoint(options.view,
                                       pa.feet_W + Eigen::Vector3d(0, 0, 1.9),
                                       options.view == ViewPreset::kTop ? 14.0 : 11.0,
                                       pa.heading_W);
  view.view_angle_deg = 32.0;

  std::array<View, 3> views;
  const std::array<std::string, 3> labels = {
      "A  " + scene.a().label, "B  " + scene.b().label, "A and B (blue)"};
  for (int k = 0; k < 3; ++k) {
    View& v = views[size_t(k)];
    v.renderer = std::make_unique<SceneRenderer>(vw, vh, 4);
    v.renderer->SetBackground({0.93f, 0.94f, 0.96f, 1.0f});
    v.renderer->SetSceneLights({{0.3, 0.5, -1}, {-0.4, 0.2, -1}}, 0.5, 0.5);
    if (options.trampoline) internal::AddTrampoline(v.renderer.get(), *options.trampoline);
    if (k != 1) {
      analysis::SceneMesh a = f.a.mesh;
      a.colour = kSkinA;
      v.a = v.renderer->AddMesh(a);
    }
    if (k != 0) {
      analysis::SceneMesh b = f.b.mesh;
      b.colour = k == 1 ? kBlueB : kGhostB;
      v.b = v.renderer->AddMesh(b);
    }
    v.renderer->LookFrom(view);
    v.label = labels[size_t(k)];
  }

  capture::VideoWriterOptions w = options.video;
  w.fps = options.fps;
  capture::FrameOutput out(output, width, height, w);
  std::vector<std::uint8_t> rgb(size_t(width) * size_t(height) * 3);
  RenderImage image, text;
  const int text_px = std::max(12, vh / 30);
  const double step = 1.0 / (options.fps * std::max(1e-3, options.slow));
  const int total = static_cast<int>(std::floor((scene.end_s() - scene.start_s()) / step)) + 1;
  for (int i = 0; i < total; ++i) {
    const double tau = scene.start_s() + i * step;
    scene.Frame(tau, &f);
    std::fill(rgb.begin(), rgb.end(), 255);
    for (int k = 0; k < 3; ++k) {
      View& v = views[size_t(k)];
      if (v.a >= 0) v.renderer->UpdateMesh(v.a, f.a.mesh.vertices_W);
      if (v.b >= 0) v.renderer->UpdateMesh(v.b, f.b.mesh.vertices_W);
      // Following: the view B alone follows B, the others A.
      if (options.follow)
        v.renderer->LookFrom(FollowViewpoint(view, k == 1 ? f.b.com_W : f.a.com_W));
      v.renderer->Render(&image);
      for (int y = 0; y < vh; ++y)
        for (int x = 0; x < vw; ++x) {
          const std::uint8_t* c = image.rgba.data() + (size_t(y) * size_t(vw) + size_t(x)) * 4;
          std::uint8_t* o = rgb.data() + (size_t(y) * size_t(width) + size_t(k * vw + x)) * 3;
          o[0] = c[0];
          o[1] = c[1];
          o[2] = c[2];
        }
      RenderTextLine(v.label, text_px, {1, 1, 1, 1}, &text);
      BlendOver(text, k * vw + text_px / 2, text_px / 2, width, height, &rgb);
    }
    char clock[32];
    std::snprintf(clock, sizeof clock, "%+.3f s from take-off", tau);
    RenderTextLine(clock, text_px, {1, 1, 1, 1}, &text);
    BlendOver(text, text_px / 2, vh - text.height - text_px / 2, width, height, &rgb);
    // The panel, with the cursor at τ on each plot.
    if (!panel.rgb.empty()) {
      std::memcpy(rgb.data() + size_t(vh) * size_t(width) * 3, panel.rgb.data(), panel.rgb.size());
      const double u = (tau - panel.start_s) / (panel.end_s - panel.start_s);
      for (const std::array<double, 4>& span : panel.cursor_spans_px) {
        const int x = static_cast<int>(std::lround(span[0] + u * (span[1] - span[0])));
        for (int y = static_cast<int>(span[2]); y < static_cast<int>(span[3]); ++y)
          for (int dx = -1; dx <= 0; ++dx) {
            const int xx = x + dx;
            if (xx < 0 || xx >= width || y < 0 || y >= panel.height) continue;
            std::uint8_t* o = rgb.data() + (size_t(vh + y) * size_t(width) + size_t(xx)) * 3;
            o[0] = 200;
            o[1] = 30;
            o[2] = 30;
          }
      }
    }
    out.Write(i, rgb);
    if (options.progress && !options.progress(i + 1, total))
      throw InputError(output.string(), "", "cancelled; nothing written");
  }
  out.Finish();
  return total;
}

}  // namespace acro::ui
