#include "skill_window.h"

#include <QComboBox>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QSlider>
#include <QSplitter>
#include <QTableWidget>
#include <QVBoxLayout>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <fmt/format.h>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/body_mesh.h"
#include "acro/athlete/motion.h"
#include "acro/base/yaml.h"
#include "acro/dynamics/configuration.h"
#include "acro/report/skill_report.h"
#include "acro/scene/athlete_scene.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/design_filmstrip.h"
#include "acro/views/filmstrip.h"
#include "image_view.h"
#include "plot_view.h"

namespace acro::studio {

namespace {

QImage StripImage(const analysis::SkillDesign& design,
                  const std::vector<std::pair<std::string, analysis::SkillTrajectory>>& rows) {
  const ui::DesignFilmstrip strip(design, rows);
  const ui::FilmstripOptions options = ui::DesignFilmstripOptions();
  const std::vector<std::uint8_t> rgb = strip.Render(options);
  const int height = options.height * strip.num_rows();
  return QImage(rgb.data(), options.width, height, 3 * options.width, QImage::Format_RGB888).copy();
}

constexpr double kDeg = 180.0 / std::numbers::pi;

}  // namespace

// What the preview poses: the design's motion and the simulated flight, on the skill's athlete.
struct SkillWindow::Preview {
  analysis::AthleteBody body;
  analysis::Motion design, simulated;
  std::unique_ptr<analysis::AthleteScene> design_scene, simulated_scene;
  Eigen::Vector3d heading_W = Eigen::Vector3d::UnitX();
};

SkillWindow::SkillWindow(QWidget* parent) : QWidget(parent, Qt::Window) {
  setWindowTitle("Acrolab Studio — skill designer");
  keyframes_ = new QTableWidget(0, 3);
  keyframes_->setHorizontalHeaderLabels({"keyframe", "time guess (s)", "optimised (s)"});
  keyframes_->horizontalHeader()->setStretchLastSection(true);
  connect(keyframes_, &QTableWidget::cellChanged, this, [this](int row, int column) {
    // A time guess edited: the next run starts from it (empty: no guess).
    if (!skill_ || column != 1 || row < 0 || size_t(row) >= skill_->keyframes.size()) return;
    bool ok = false;
    const double t = keyframes_->item(row, 1)->text().toDouble(&ok);
    if (ok && t >= 0 && t <= skill_->flight_time_s) {
      skill_->keyframes[size_t(row)].time_s = t;
    } else {
      skill_->keyframes[size_t(row)].time_s.reset();
    }
  });
  connect(keyframes_, &QTableWidget::currentCellChanged, this, [this](int row, int, int, int) {
    if (row >= 0) ShowPose(row);
  });
  pose_ = new QTableWidget(0, 2);
  pose_->setHorizontalHeaderLabels({"angle", "degrees"});
  pose_->horizontalHeader()->setStretchLastSection(true);
  pose_->verticalHeader()->hide();
  connect(pose_, &QTableWidget::cellChanged, this, [this](int row, int column) {
    if (!skill_ || column != 1) return;
    bool ok = false;
    const double deg = pose_->item(row, 1)->text().toDouble(&ok);
    if (!ok) {
      ShowError("'" + pose_->item(row, 1)->text().toStdString() + "' is not a number of degrees");
      return ShowPose(pose_keyframe_);
    }
    EditPose(pose_keyframe_, row, deg);
  });
  strip_ = new ImageView("Open a skill file");
  preview_ = new ImageView("The design and its simulated flight, at the slider's time");
  preview_time_ = new QSlider(Qt::Horizontal);
  preview_time_->setRange(0, 1000);
  connect(preview_time_, &QSlider::valueChanged, this, [this](int v) {
    if (skill_) SetPreviewTime(v / 1000.0 * skill_->flight_time_s);
  });
  timing_ = new PlotView;
  chart_box_ = new QComboBox;
  chart_box_->addItems({"Keyframe timing", "Angular momentum"});
  connect(
      chart_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int) { ShowChart(); });
  summary_ = new QLabel;
  summary_->setWordWrap(true);
  summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  progress_ = new QProgressBar;
  progress_->hide();
  auto* open = new QPushButton("Open skill…");
  auto* save_skill = new QPushButton("Save skill file…");
  auto* model2 = new QPushButton("Run Model 2 (timing)");
  auto* model1 = new QPushButton("Run Model 1 (timing and trajectory)");
  auto* save = new QPushButton("Save the design…");
  auto* ghost = new QPushButton("Show over the athlete");
  ghost->setToolTip(
      "The design as the ghost in every flight of the main window's trial, in the 3D view and "
      "over the video");
  auto* cancel = new QPushButton("Cancel");
  connect(cancel, &QPushButton::clicked, this, [this] { Cancel(); });
  connect(open, &QPushButton::clicked, this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Open a skill", {}, "Skills (*.yaml *.yml)");
    if (!path.isEmpty()) OpenSkill(path.toStdString());
  });
  connect(save_skill, &QPushButton::clicked, this, [this] {
    const QString path =
        QFileDialog::getSaveFileName(this, "Save the skill file", {}, "Skills (*.yaml *.yml)");
    if (!path.isEmpty()) SaveSkill(path.toStdString());
  });
  connect(model2, &QPushButton::clicked, this, [this] { Run(2); });
  connect(model1, &QPushButton::clicked, this, [this] { Run(1); });
  connect(save, &QPushButton::clicked, this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "Save the design in");
    if (!dir.isEmpty()) SaveDesign(dir.toStdString());
  });
  connect(ghost, &QPushButton::clicked, this, [this] { ShowOverAthlete(); });
  auto* buttons = new QHBoxLayout;
  for (QPushButton* b : {open, save_skill, model2, model1, cancel, save, ghost})
    buttons->addWidget(b);
  buttons->addWidget(progress_, 1);
  // Left: the keyframes over the chosen one's pose; right: the filmstrip, the preview with its
  // slider beside the timing chart.
  auto* tables = new QSplitter(Qt::Vertical);
  tables->addWidget(keyframes_);
  tables->addWidget(pose_);
  auto* preview_panel = new QWidget;
  auto* preview_layout = new QVBoxLayout(preview_panel);
  preview_layout->setContentsMargins(0, 0, 0, 0);
  preview_layout->addWidget(preview_, 1);
  preview_layout->addWidget(preview_time_);
  auto* chart_panel = new QWidget;
  auto* chart_layout = new QVBoxLayout(chart_panel);
  chart_layout->setContentsMargins(0, 0, 0, 0);
  chart_layout->addWidget(chart_box_);
  chart_layout->addWidget(timing_, 1);
  auto* lower = new QSplitter(Qt::Horizontal);
  lower->addWidget(preview_panel);
  lower->addWidget(chart_panel);
  auto* right = new QSplitter(Qt::Vertical);
  right->addWidget(strip_);
  right->addWidget(lower);
  auto* middle = new QSplitter(Qt::Horizontal);
  middle->addWidget(tables);
  middle->addWidget(right);
  middle->setSizes({420, 1180});
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(buttons);
  layout->addWidget(middle, 1);
  layout->addWidget(summary_);
  resize(1600, 1000);
}

SkillWindow::~SkillWindow() {
  cancel_ = true;
  Join();
}

std::string SkillWindow::summary() const {
  return summary_->text().toStdString();
}

void SkillWindow::Join() {
  if (worker_.joinable()) worker_.join();
}

void SkillWindow::ShowError(const std::string& message) {
  last_error_ = message;
  auto* box = new QMessageBox(
      QMessageBox::Critical, "Acrolab", QString::fromStdString(message), QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

bool SkillWindow::OpenSkill(const std::string& path) {
  if (running()) {
    ShowError("An optimisation is running: wait for it.");
    return false;
  }
  try {
    analysis::Skill skill = analysis::ReadSkill(path);
    skill_ = std::move(skill);
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
  result_.reset();
  sim_.reset();
  ShowSkill();
  return true;
}

void SkillWindow::ShowSkill() {
  const analysis::SkillDesign design(*skill_);
  const Eigen::VectorXd times = design.InitialTimes();
  const QSignalBlocker block(keyframes_);
  keyframes_->setRowCount(design.num_keyframes());
  for (int i = 0; i < design.num_keyframes(); ++i) {
    const analysis::SkillKeyframe& k = skill_->keyframes[size_t(i)];
    auto* name = new QTableWidgetItem(QString::fromStdString(k.name));
    name->setFlags(name->flags() & ~Qt::ItemIsEditable);
    keyframes_->setItem(i, 0, name);
    keyframes_->setItem(
        i, 1, new QTableWidgetItem(k.time_s ? QString::number(*k.time_s, 'f', 3) : QString()));
    keyframes_->setItem(i, 2, new QTableWidgetItem(QString()));
    keyframes_->item(i, 2)->setFlags(Qt::ItemIsEnabled);
  }
  keyframes_->resizeColumnsToContents();
  setWindowTitle(QString::fromStdString("Skill designer — " + skill_->name));
  summary_->setText(QString::fromStdString(
      fmt::format("{} ({}) for {}: {} keyframes, flight time {:.3f} s. The filmstrip shows the "
                  "keyframes' motion at eight instants with the initial timing.",
                  skill_->name,
                  skill_->fig_code,
                  skill_->athlete.name,
                  design.num_keyframes(),
                  skill_->flight_time_s)));
  try {
    strip_->SetImage(
        StripImage(design, {{"initial timing", analysis::MakeKeyframeTrajectory(design, times)}}));
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
  ShowPose(std::clamp(pose_keyframe_, 0, design.num_keyframes() - 1));
  MakePreview();
}

void SkillWindow::ShowPose(int keyframe) {
  if (!skill_ || keyframe < 0 || size_t(keyframe) >= skill_->keyframes.size()) return;
  pose_keyframe_ = keyframe;
  const analysis::SkillKeyframe& k = skill_->keyframes[size_t(keyframe)];
  const std::vector<std::string> names =
      analysis::MakeCoordinateNames(analysis::SkillDesign(*skill_).model());
  const QSignalBlocker block(pose_);
  pose_->setRowCount(3 + int(k.joint_angles_rad.size()));
  const auto row = [&](int r, const std::string& name, double rad) {
    auto* label = new QTableWidgetItem(QString::fromStdString(name));
    label->setFlags(label->flags() & ~Qt::ItemIsEditable);
    pose_->setItem(r, 0, label);
    pose_->setItem(r, 1, new QTableWidgetItem(QString::number(rad * kDeg, 'g', 6)));
  };
  row(0, "somersault", k.somersault_rad);
  row(1, "tilt", k.tilt_rad);
  row(2, "twist", k.twist_rad);
  for (int j = 0; j < k.joint_angles_rad.size(); ++j)
    row(3 + j, names[size_t(dynamics::kRootNq + j)], k.joint_angles_rad(j));
  pose_->setHorizontalHeaderLabels({QString::fromStdString("pose of " + k.name), "degrees"});
  pose_->resizeColumnsToContents();
}

bool SkillWindow::EditPose(int keyframe, int row, double degrees) {
  if (!skill_ || keyframe < 0 || size_t(keyframe) >= skill_->keyframes.size()) return false;
  if (running()) {
    ShowError("An optimisation is running: wait for it, or cancel it, before editing.");
    ShowPose(keyframe);
    return false;
  }
  analysis::Skill edited = *skill_;
  analysis::SkillKeyframe& k = edited.keyframes[size_t(keyframe)];
  const double rad = degrees / kDeg;
  if (row == 0) {
    k.somersault_rad = rad;
  } else if (row == 1) {
    k.tilt_rad = rad;
  } else if (row == 2) {
    k.twist_rad = rad;
  } else if (row - 3 < k.joint_angles_rad.size()) {
    k.joint_angles_rad(row - 3) = rad;
  } else {
    return false;
  }
  // The edited skill as the file reader would take it: what it refuses (keyframes 170° or more
  // apart, a value that is not finite) is refused here with its words.
  try {
    const std::filesystem::path dir = std::filesystem::path(skill_->source).parent_path();
    analysis::SkillFromYaml(
        ParseYaml(analysis::FormatSkillYaml(edited, dir), skill_->source + " (edited)"), dir);
  } catch (const std::exception& e) {
    ShowError(e.what());
    ShowPose(keyframe);
    return false;
  }
  skill_ = std::move(edited);
  result_.reset();
  sim_.reset();
  ShowSkill();
  summary_->setText(QString::fromStdString(
      fmt::format("{} of {} set to {:g}°: run Model 2 or Model 1 again (the last result went with "
                  "the old pose).",
                  pose_->item(row, 0)->text().toStdString(),
                  skill_->keyframes[size_t(keyframe)].name,
                  degrees)));
  return true;
}

bool SkillWindow::SaveSkill(const std::string& path) {
  if (!skill_) {
    ShowError("Nothing to save: open a skill file first.");
    return false;
  }
  try {
    analysis::WriteSkill(path, *skill_);
    summary_->setText(QString::fromStdString("saved the skill file " + path));
    return true;
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
}

void SkillWindow::MakePreview() {
  preview_scenes_.reset();
  if (!skill_) return;
  try {
    const analysis::SkillDesign design(*skill_);
    auto p = std::make_unique<Preview>();
    p->body = analysis::MakeAthleteBody(skill_->athlete);
    const analysis::BodyMesh mesh =
        analysis::MakeEllipsoidBodyMesh(p->body, analysis::OverlayBodyMeshOptions());
    p->design = analysis::SampleSkillMotion(
        design,
        result_ ? result_->optimized
                : analysis::MakeKeyframeTrajectory(design, design.InitialTimes()));
    p->design_scene = std::make_unique<analysis::AthleteScene>(p->body, mesh, p->design);
    if (sim_) {
      p->simulated = analysis::SimulatedSkillMotion(design, *sim_);
      p->simulated_scene = std::make_unique<analysis::AthleteScene>(p->body, mesh, p->simulated);
    }
    p->heading_W = dynamics::GetRootQuaternion(p->design.q.col(0)) * Eigen::Vector3d::UnitX();
    preview_scenes_ = std::move(p);
  } catch (const std::exception& e) {
    return ShowError(e.what());
  }
  SetPreviewTime(preview_time_->value() / 1000.0 * skill_->flight_time_s);
}

void SkillWindow::SetPreviewTime(double t_s) {
  if (!preview_scenes_) return;
  Preview& p = *preview_scenes_;
  std::vector<ui::FilmstripRow> rows;
  ui::FilmstripRow design;
  design.scene = p.design_scene.get();
  design.frames = {analysis::FrameNearestTime(p.design, t_s)};
  design.rate_hz = p.design.rate_hz;
  design.label = fmt::format("{} at {:.3f} s", result_ ? "the design" : "initial timing", t_s);
  design.colour = {1.0f, 0.66f, 0.5f, 1.0f};
  rows.push_back(design);
  if (p.simulated_scene) {
    ui::FilmstripRow sim;
    sim.scene = p.simulated_scene.get();
    sim.frames = {analysis::FrameNearestTime(p.simulated, t_s)};
    sim.rate_hz = p.simulated.rate_hz;
    sim.label = "its simulated flight";
    sim.colour = {0.45f, 0.65f, 1.0f, 1.0f};
    rows.push_back(sim);
  }
  ui::FilmstripOptions options;
  options.width = 520;
  options.height = 300;
  try {
    const std::vector<std::uint8_t> rgb = ui::RenderFilmstrips(rows, p.heading_W, options);
    const int height = options.height * int(rows.size());
    preview_->SetImage(
        QImage(rgb.data(), options.width, height, 3 * options.width, QImage::Format_RGB888).copy());
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
}

bool SkillWindow::ShowOverAthlete() {
  if (!skill_ || !result_) {
    ShowError("Run Model 2 or Model 1 first: the ghost is the optimised design.");
    return false;
  }
  if (!ghost_target_) {
    ShowError("Open a trial in the main window: the design is drawn in its flights.");
    return false;
  }
  try {
    ghost_target_(analysis::MakeSkillGhost(analysis::SkillDesign(*skill_), *result_));
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
  return true;
}

void SkillWindow::Run(int model) {
  if (!skill_) return ShowError("Open a skill file first.");
  if (running()) return;
  Join();
  done_ = false;
  cancel_ = false;
  progress_->setRange(0, 0);
  progress_->show();
  const analysis::Skill skill = *skill_;
  worker_ = std::thread([this, skill, model] {
    std::optional<analysis::SkillOptimizationResult> result;
    std::optional<analysis::SkillSimulationResult> sim;
    std::string error;
    try {
      const analysis::SkillDesign design(skill);
      analysis::SkillOptimizationOptions options;
      options.model =
          model == 1 ? analysis::SkillModel::kTrajectory : analysis::SkillModel::kTiming;
      options.progress = [this](const std::string& line) {
        QMetaObject::invokeMethod(
            this,
            [this, line] { summary_->setText(QString::fromStdString(line)); },
            Qt::QueuedConnection);
      };
      options.cancelled = [this] { return cancel_.load(); };
      result = analysis::OptimizeSkill(design, options);
      // Does it fly as designed? The joints follow it, the root flies under gravity.
      QMetaObject::invokeMethod(
          this,
          [this] { summary_->setText("simulating the flight of the optimised design"); },
          Qt::QueuedConnection);
      sim = analysis::SimulateSkill(design, result->optimized);
    } catch (const std::exception& e) {
      error = e.what();
    }
    QMetaObject::invokeMethod(
        this,
        [this, result, sim, error] {
          progress_->hide();
          done_ = true;
          if (cancel_) {
            // Asked for: a line, not an error; what was shown before stays.
            summary_->setText(
                "Cancelled: the optimisation stopped; the result shown is the "
                "previous one, if any.");
            return;
          }
          if (!error.empty()) return ShowError(error);
          result_ = result;
          sim_ = sim;
          ShowResult();
        },
        Qt::QueuedConnection);
  });
}

void SkillWindow::ShowResult() {
  const analysis::SkillDesign design(*skill_);
  const analysis::SkillOptimizationResult& r = *result_;
  {
    const QSignalBlocker block(keyframes_);
    for (int i = 0; i < design.num_keyframes() && i < keyframes_->rowCount(); ++i)
      keyframes_->item(i, 2)->setText(QString::number(r.optimized.times_s(i), 'f', 3));
  }
  ShowChart();
  std::string text = fmt::format(
      "Model {}: J {:.4g} → {:.4g} ({:.1f} times smaller); angular momentum variation {:.1f} % → "
      "{:.1f} %. The filmstrip shows the initial timing above the optimised one.",
      analysis::SkillModelNumber(r.model),
      r.objective_initial,
      r.objective,
      r.objective_initial / r.objective,
      100 * r.angular_momentum_variation_initial,
      100 * r.angular_momentum_variation);
  if (sim_) {
    std::string line = analysis::FormatSkillSimulation(*sim_);
    line[0] = char(std::toupper(static_cast<unsigned char>(line[0])));
    text += "\n" + line + ".";
    for (const std::string& w : sim_->warnings) text += "\nWarning: " + w;
  }
  summary_->setText(QString::fromStdString(text));
  try {
    strip_->SetImage(StripImage(
        design,
        {{"initial timing", r.initial},
         {fmt::format("optimised timing (model {})", analysis::SkillModelNumber(r.model)),
          r.optimized}}));
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
  MakePreview();
}

void SkillWindow::SetChartIndex(int index) {
  chart_box_->setCurrentIndex(index);
}

void SkillWindow::ShowChart() {
  if (!skill_ || !result_) return;
  const analysis::SkillDesign design(*skill_);
  timing_->SetChart(chart_box_->currentIndex() == 1 ? ui::MakeSkillMomentumChart(design, *result_)
                                                    : ui::MakeSkillTimingChart(design, *result_));
}

bool SkillWindow::SaveDesign(const std::string& dir) {
  if (!skill_ || !result_) {
    ShowError("Nothing to save: run Model 2 or Model 1 first.");
    return false;
  }
  try {
    const analysis::SkillDesign design(*skill_);
    ui::WriteSkillOutputs(dir, design, *result_, sim_ ? &*sim_ : nullptr);
    return true;
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
}

}  // namespace acro::studio
