#include "acro/views/compare_video.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "acro/base/input_error.h"
#include "acro/base/progress.h"
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

struct CompareDrawer::Impl {
  Impl(analysis::CompareScene& scene_in,
       const analysis::TimedPanel& panel_in,
       const CompareVideoOptions& options_in)
      : scene(scene_in), panel(panel_in), options(options_in) {}
  analysis::CompareScene& scene;
  analysis::TimedPanel panel;
  CompareVideoOptions options;
  XDisplay display;  // before the renderers, which need it
  std::array<View, 3> views;
  FreeViewpoint view;
  analysis::CompareFrame f;
  RenderImage image, text;
  int vw = 0, vh = 0, width = 0, height = 0;
};

CompareDrawer::CompareDrawer(analysis::CompareScene& scene,
                             const analysis::TimedPanel& panel,
                             const CompareVideoOptions& options)
    : impl_(std::make_unique<Impl>(scene, panel, options)) {
  Impl& m = *impl_;
  m.vw = options.view_width;
  m.vh = options.view_height;
  m.width = 3 * m.vw;
  m.height = m.vh + (panel.rgb.empty() ? 0 : panel.height);
  if (!panel.rgb.empty() && panel.width != m.width)
    throw std::invalid_argument("CompareDrawer: the panel is not three views wide");
  scene.Frame(scene.start_s(), &m.f);
  // From the side of A's take-off: across its heading, level, looking at mid-flight height.
  const analysis::TakeoffPlacement pa = FindTakeoff(*scene.a().analysis, scene.a().jump);
  m.view = PresetViewpoint(options.view,
                           pa.feet_W + Eigen::Vector3d(0, 0, 1.9),
                           options.view == ViewPreset::kTop ? 14.0 : 11.0,
                           pa.heading_W);
  m.view.view_angle_deg = 32.0;
  const std::array<std::string, 3> labels = {
      "A  " + scene.a().label, "B  " + scene.b().label, "A and B (blue)"};
  for (int k = 0; k < 3; ++k) {
    View& v = m.views[size_t(k)];
    v.renderer = std::make_unique<SceneRenderer>(m.vw, m.vh, 4);
    v.renderer->SetBackground({0.93f, 0.94f, 0.96f, 1.0f});
    v.renderer->SetSceneLights({{0.3, 0.5, -1}, {-0.4, 0.2, -1}}, 0.5, 0.5);
    if (options.trampoline) internal::AddTrampoline(v.renderer.get(), *options.trampoline);
    if (k != 1) {
      analysis::SceneMesh a = m.f.a.mesh;
      a.colour = kSkinA;
      v.a = v.renderer->AddMesh(a);
    }
    if (k != 0) {
      analysis::SceneMesh b = m.f.b.mesh;
      b.colour = k == 1 ? kBlueB : kGhostB;
      v.b = v.renderer->AddMesh(b);
    }
    v.renderer->LookFrom(m.view);
    v.label = labels[size_t(k)];
  }
}

CompareDrawer::~CompareDrawer() = default;

int CompareDrawer::width() const {
  return impl_->width;
}
int CompareDrawer::height() const {
  return impl_->height;
}

void CompareDrawer::Draw(double tau, std::vector<std::uint8_t>* out) {
  Impl& m = *impl_;
  const int vw = m.vw, vh = m.vh, width = m.width, height = m.height;
  std::vector<std::uint8_t>& rgb = *out;
  rgb.assign(size_t(width) * size_t(height) * 3, 255);
  m.scene.Frame(tau, &m.f);
  const int text_px = std::max(12, vh / 30);
  for (int k = 0; k < 3; ++k) {
    View& v = m.views[size_t(k)];
    if (v.a >= 0) v.renderer->UpdateMesh(v.a, m.f.a.mesh.vertices_W);
    if (v.b >= 0) v.renderer->UpdateMesh(v.b, m.f.b.mesh.vertices_W);
    // Following: the view B alone follows B, the others A.
    if (m.options.follow)
      v.renderer->LookFrom(FollowViewpoint(m.view, k == 1 ? m.f.b.com_W : m.f.a.com_W));
    v.renderer->Render(&m.image);
    for (int y = 0; y < vh; ++y)
      for (int x = 0; x < vw; ++x) {
        const std::uint8_t* c = m.image.rgba.data() + (size_t(y) * size_t(vw) + size_t(x)) * 4;
        std::uint8_t* o = rgb.data() + (size_t(y) * size_t(width) + size_t(k * vw + x)) * 3;
        o[0] = c[0];
        o[1] = c[1];
        o[2] = c[2];
      }
    RenderTextLine(v.label, text_px, {1, 1, 1, 1}, &m.text);
    BlendOver(m.text, k * vw + text_px / 2, text_px / 2, width, height, &rgb);
  }
  char clock[32];
  std::snprintf(clock, sizeof clock, "%+.3f s from take-off", tau);
  RenderTextLine(clock, text_px, {1, 1, 1, 1}, &m.text);
  BlendOver(m.text, text_px / 2, vh - m.text.height - text_px / 2, width, height, &rgb);
  // The panel, with the cursor at τ on each plot.
  const analysis::TimedPanel& panel = m.panel;
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
}

int WriteCompareVideo(analysis::CompareScene& scene,
                      const analysis::TimedPanel& panel,
                      const std::filesystem::path& output,
                      const CompareVideoOptions& options) {
  CompareDrawer drawer(scene, panel, options);
  capture::VideoWriterOptions w = options.video;
  w.fps = options.fps;
  capture::FrameOutput out(output, drawer.width(), drawer.height(), w);
  std::vector<std::uint8_t> rgb;
  const double step = 1.0 / (options.fps * std::max(1e-3, options.slow));
  const int total = static_cast<int>(std::floor((scene.end_s() - scene.start_s()) / step)) + 1;
  for (int i = 0; i < total; ++i) {
    drawer.Draw(scene.start_s() + i * step, &rgb);
    out.Write(i, rgb);
    if (options.progress && !options.progress(i + 1, total))
      throw Cancelled(output.string() + ": cancelled; nothing written");
  }
  out.Finish();
  return total;
}

}  // namespace acro::ui
