#pragma once

// The studio's compare mode: two jumps aligned at take-off — of the open trial, of two trials, or a
// jump against a designed skill — in the three views of `acrolab compare` (A, B, both) over their
// curves in one chart, at the main window's cursor (τ from A's take-off). Drawn by ui/views'
// CompareDrawer, as the command's video is.

#include <QWidget>

#include <memory>
#include <string>
#include <vector>

#include "acro/scene/compare_scene.h"
#include "acro/scene/skill_ghost.h"
#include "acro/studio/session.h"

namespace acro::ui {
class CompareDrawer;
}

namespace acro::studio {

class ImageView;

class CompareWindow : public QWidget {
 public:
  /// Jump `a` (1-based, as jumps.json numbers them) of `a_session`'s trial against jump `b` of
  /// `b_session`'s (the same session or another). Throws acro::InputError naming a jump that is
  /// not there.
  CompareWindow(std::shared_ptr<Session> a_session,
                int a,
                std::shared_ptr<Session> b_session,
                int b,
                QWidget* parent = nullptr);
  /// Jump `a` of `a_session`'s trial against a designed skill posed on that trial's athlete.
  CompareWindow(std::shared_ptr<Session> a_session,
                int a,
                std::shared_ptr<const analysis::SkillGhost> design,
                QWidget* parent = nullptr);
  ~CompareWindow() override;

  /// Draws the instant τ (s from the take-offs), clamped to the comparison's span.
  void SetTau(double tau_s);
  double tau() const { return tau_s_; }
  analysis::CompareScene& scene() { return *scene_; }
  /// The take-off time of A (s, trial time): τ = cursor time − this.
  double a_takeoff_s() const;

 private:
  void Build(analysis::CompareJump a, analysis::CompareJump b);

  std::shared_ptr<Session> a_session_, b_session_;  // what the jumps point into
  std::shared_ptr<const analysis::SkillGhost> design_;
  std::unique_ptr<analysis::CompareScene> scene_;
  std::unique_ptr<ui::CompareDrawer> drawer_;
  ImageView* view_ = nullptr;
  std::vector<std::uint8_t> rgb_;
  double tau_s_ = 0.0;
};

}  // namespace acro::studio
