#include "acro/views/trial_view.h"

#include <optional>

#include "acro/views/display.h"
#include "scene_actors.h"

namespace acro::ui {

struct TrialFreeView::Impl {
  // No multisampling: on Mesa's software rasteriser 4x costs more than the rest of a frame step.
  Impl(analysis::TrialScene& scene_in, int w, int h) : scene(scene_in), renderer(w, h, 0) {}
  analysis::TrialScene& scene;
  XDisplay display;  // before the renderer, which needs it
  SceneRenderer renderer;
  internal::Show show;
  std::optional<internal::SceneActors> actors;
  FreeViewpoint view, rendered;
  bool follow = false;
  analysis::TrialFrame tf;
  RenderImage image;
  std::vector<int> cameras;  // the frustums' actors
};

TrialFreeView::TrialFreeView(analysis::TrialScene& scene,
                             int width,
                             int height,
                             const analysis::SceneShow& show,
                             const std::optional<analysis::TrampolineScene>& trampoline)
    : impl_(std::make_unique<Impl>(scene, width, height)) {
  Impl& m = *impl_;
  static_cast<analysis::SceneShow&>(m.show) = show;
  m.renderer.SetBackground({0.93f, 0.94f, 0.96f, 1.0f});
  m.renderer.SetSceneLights({{0.3, 0.5, -1}, {-0.4, 0.2, -1}}, 0.5, 0.5);
  if (trampoline) internal::AddTrampoline(&m.renderer, *trampoline);
  m.view = PresetViewpoint(ViewPreset::kSide, Eigen::Vector3d(0, 0, 2), 12.0);
  m.rendered = m.view;
}

TrialFreeView::~TrialFreeView() = default;

int TrialFreeView::width() const {
  return impl_->renderer.width();
}
int TrialFreeView::height() const {
  return impl_->renderer.height();
}

void TrialFreeView::SetViewpoint(const FreeViewpoint& view, bool follow) {
  impl_->view = view;
  impl_->follow = follow;
}

const FreeViewpoint& TrialFreeView::viewpoint() const {
  return impl_->view;
}
const FreeViewpoint& TrialFreeView::rendered_viewpoint() const {
  return impl_->rendered;
}
const analysis::TrialFrame& TrialFreeView::frame() const {
  return impl_->tf;
}

void TrialFreeView::SetShow(const analysis::SceneShow& show) {
  static_cast<analysis::SceneShow&>(impl_->show) = show;
  if (impl_->actors) impl_->actors->SetShow(impl_->show);
}

const analysis::SceneShow& TrialFreeView::show() const {
  return impl_->show;
}

void TrialFreeView::SetCameras(const std::vector<vision::Camera>& cameras, double depth_m) {
  Impl& m = *impl_;
  for (const int id : m.cameras) m.renderer.SetVisible(id, false);
  // Actors are kept (the renderer has no removal): hidden ones are reused first.
  size_t k = 0;
  for (const vision::Camera& camera : cameras) {
    analysis::SceneLines frustum = analysis::MakeCameraFrustum(camera, depth_m);
    frustum.colour = {0.2f, 0.2f, 0.25f, 1.0f};
    frustum.width_px = 2.0;
    if (k < m.cameras.size()) {
      m.renderer.UpdateLines(m.cameras[k], frustum.points_W);
      m.renderer.SetVisible(m.cameras[k], true);
    } else {
      m.cameras.push_back(m.renderer.AddLines(frustum));
    }
    ++k;
  }
}

void TrialFreeView::Render(int sample, std::vector<std::uint8_t>* rgb) {
  Impl& m = *impl_;
  m.scene.Frame(sample, &m.tf);
  if (!m.actors) {
    m.actors.emplace(&m.renderer, m.tf, m.show, m.scene.has_athlete(), 3.0);
  } else {
    m.actors->Update(m.tf, true);
  }
  m.rendered = m.view;
  if (m.follow) {
    Eigen::Vector3d target = m.view.target_W;
    if (m.scene.has_athlete()) {
      target = m.tf.athlete.com_W;
    } else if (m.tf.markers_W.cols() > 0) {
      target = m.tf.markers_W.rowwise().mean();
    }
    m.rendered = FollowViewpoint(m.view, target);
  }
  m.renderer.LookFrom(m.rendered);
  m.renderer.Render(&m.image);
  const size_t n = size_t(m.image.width) * size_t(m.image.height);
  rgb->resize(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) (*rgb)[3 * i + size_t(c)] = m.image.rgba[4 * i + size_t(c)];
}

}  // namespace acro::ui
