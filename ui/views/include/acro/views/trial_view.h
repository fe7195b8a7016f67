#pragma once

// A trial in a free 3D view (the studio's 3D view): the athlete — or the keypoints — as the
// overlay draws them, over the trampoline when the trial's bed is known, seen from a viewpoint the
// caller sets (the presets, an orbit, following the athlete), rendered offscreen into RGB. Needs an
// X display (it holds one: display.h).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "acro/scene/place_scene.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/scene_renderer.h"
#include "acro/vision/camera.h"

namespace acro::ui {

class TrialFreeView {
 public:
  /// A view of `width` × `height` pixels (not multisampled: 4× cost more than the rest of a
  /// studio frame step on Mesa's software rasteriser, docs/performance.md). Throws
  /// std::invalid_argument for a size outside 1–16384, acro::InputError when no X display can be
  /// had.
  TrialFreeView(analysis::TrialScene& scene,
                int width,
                int height,
                const analysis::SceneShow& show,
                const std::optional<analysis::TrampolineScene>& trampoline = std::nullopt);
  ~TrialFreeView();
  TrialFreeView(const TrialFreeView&) = delete;
  TrialFreeView& operator=(const TrialFreeView&) = delete;

  int width() const;
  int height() const;
  /// Where the view looks from; with `follow`, its target moves onto the athlete's centre of mass
  /// (the keypoints' mean without an athlete) at each render, the eye keeping its offset.
  void SetViewpoint(const FreeViewpoint& view, bool follow = false);
  const FreeViewpoint& viewpoint() const;
  /// The viewpoint the last render used (followed when following).
  const FreeViewpoint& rendered_viewpoint() const;
  /// What to show (the athlete's mesh, skeleton, the markers, the COM and its path, the
  /// residual) from the next render on.
  void SetShow(const analysis::SceneShow& show);
  const analysis::SceneShow& show() const;
  /// Draws these cameras as frustums `depth_m` deep (the calibrated cameras of the session's
  /// videos), replacing any drawn before.
  void SetCameras(const std::vector<vision::Camera>& cameras, double depth_m = 1.0);
  /// Renders trial sample `sample` into `rgb` (width × height × 3, rows top to bottom).
  void Render(int sample, std::vector<std::uint8_t>* rgb);
  /// The scene frame last rendered.
  const analysis::TrialFrame& frame() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::ui
