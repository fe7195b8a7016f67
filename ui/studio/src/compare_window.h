#pragma once

// The studio's compare mode: two jumps of the open trial aligned at take-off, in the three views of
// `acrolab compare` (A, B, both) over their curves, at the main window's cursor (τ from A's
// take-off). Drawn by ui/views' CompareDrawer, as the command's video is.

#include <QWidget>

#include <memory>
#include <string>
#include <vector>

#include "acro/scene/compare_scene.h"
#include "acro/studio/session.h"

namespace acro::ui {
class CompareDrawer;
}

namespace acro::studio {

class ImageView;

class CompareWindow : public QWidget {
 public:
  /// Jumps `a` and `b` (1-based, as jumps.json numbers them) of `session`'s trial. Throws
  /// acro::InputError naming a jump that is not there.
  CompareWindow(std::shared_ptr<Session> session, int a, int b, QWidget* parent = nullptr);
  ~CompareWindow() override;

  /// Draws the instant τ (s from the take-offs), clamped to the comparison's span.
  void SetTau(double tau_s);
  double tau() const { return tau_s_; }
  analysis::CompareScene& scene() { return *scene_; }
  /// The take-off time of A (s, trial time): τ = cursor time − this.
  double a_takeoff_s() const;

 private:
  std::shared_ptr<Session> session_;
  std::unique_ptr<analysis::CompareScene> scene_;
  std::unique_ptr<ui::CompareDrawer> drawer_;
  ImageView* view_ = nullptr;
  std::vector<std::uint8_t> rgb_;
  double tau_s_ = 0.0;
};

}  // namespace acro::studio
