#include "compare_window.h"

#include <QVBoxLayout>

#include <algorithm>

#include "acro/athlete/body_mesh.h"
#include "acro/report/compare_report.h"
#include "acro/scene/place_scene.h"
#include "acro/views/compare_video.h"
#include "image_view.h"

namespace acro::studio {

namespace {

analysis::CompareJump Jump(Session& s, int index) {
  analysis::CompareJump j;
  j.trial = &s.trial();
  j.analysis = &s.analysis();
  j.body = &s.body();
  j.mesh = analysis::MakeEllipsoidBodyMesh(s.body(), analysis::OverlayBodyMeshOptions());
  j.jump = index;
  j.label = analysis::JumpLabel(s.analysis(), index);
  return j;
}

}  // namespace

CompareWindow::CompareWindow(std::shared_ptr<Session> a_session,
                             int a,
                             std::shared_ptr<Session> b_session,
                             int b,
                             QWidget* parent)
    : QWidget(parent, Qt::Window),
      a_session_(std::move(a_session)),
      b_session_(std::move(b_session)) {
  analysis::CompareJump jb = Jump(*b_session_, b);
  if (b_session_ != a_session_)
    jb.label += " of " + std::filesystem::path(b_session_->files().trial).filename().string();
  Build(Jump(*a_session_, a), std::move(jb));
}

CompareWindow::CompareWindow(std::shared_ptr<Session> a_session,
                             int a,
                             std::shared_ptr<const analysis::SkillGhost> design,
                             QWidget* parent)
    : QWidget(parent, Qt::Window), a_session_(std::move(a_session)), design_(std::move(design)) {
  analysis::CompareJump jb;
  jb.body = &a_session_->body();
  jb.mesh = analysis::MakeEllipsoidBodyMesh(a_session_->body(), analysis::OverlayBodyMeshOptions());
  jb.design = design_.get();
  jb.label = design_->name + " (design)";
  Build(Jump(*a_session_, a), std::move(jb));
}

void CompareWindow::Build(analysis::CompareJump a, analysis::CompareJump b) {
  scene_ = std::make_unique<analysis::CompareScene>(std::move(a), std::move(b));
  ui::CompareVideoOptions options;
  if (a_session_->analysis().bed)
    options.trampoline = analysis::MakeTrampolineScene(*a_session_->analysis().bed);
  const analysis::TimedPanel panel = ui::MakeCompareCharts(scene_->CurvesA(),
                                                           scene_->CurvesB(),
                                                           "A " + scene_->a().label,
                                                           "B " + scene_->b().label,
                                                           scene_->start_s(),
                                                           scene_->end_s(),
                                                           3 * options.view_width,
                                                           320);
  drawer_ = std::make_unique<ui::CompareDrawer>(*scene_, panel, options);
  setWindowTitle(
      QString::fromStdString("Compare: A " + scene_->a().label + "  —  B " + scene_->b().label));
  view_ = new ImageView("");
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(view_);
  resize(drawer_->width() * 2 / 3, drawer_->height() * 2 / 3);
  SetTau(0.0);
}

CompareWindow::~CompareWindow() = default;

double CompareWindow::a_takeoff_s() const {
  return analysis::FindTakeoff(*scene_->a().analysis, scene_->a().jump).takeoff_s;
}

void CompareWindow::SetTau(double tau_s) {
  tau_s_ = std::clamp(tau_s, scene_->start_s(), scene_->end_s());
  drawer_->Draw(tau_s_, &rgb_);
  view_->SetImage(QImage(rgb_.data(),
                         drawer_->width(),
                         drawer_->height(),
                         3 * drawer_->width(),
                         QImage::Format_RGB888)
                      .copy());
}

}  // namespace acro::studio
