#include "skill_window.h"

#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

#include <fmt/format.h>

#include "acro/report/skill_report.h"
#include "acro/views/design_filmstrip.h"
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

}  // namespace

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
  strip_ = new ImageView("Open a skill file");
  timing_ = new PlotView;
  summary_ = new QLabel;
  summary_->setWordWrap(true);
  progress_ = new QProgressBar;
  progress_->hide();
  auto* open = new QPushButton("Open skill…");
  auto* model2 = new QPushButton("Run Model 2 (timing)");
  auto* model1 = new QPushButton("Run Model 1 (timing and trajectory)");
  auto* save = new QPushButton("Save the design…");
  auto* cancel = new QPushButton("Cancel");
  connect(cancel, &QPushButton::clicked, this, [this] { Cancel(); });
  connect(open, &QPushButton::clicked, this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Open a skill", {}, "Skills (*.yaml *.yml)");
    if (!path.isEmpty()) OpenSkill(path.toStdString());
  });
  connect(model2, &QPushButton::clicked, this, [this] { Run(2); });
  connect(model1, &QPushButton::clicked, this, [this] { Run(1); });
  connect(save, &QPushButton::clicked, this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "Save the design in");
    if (!dir.isEmpty()) SaveDesign(dir.toStdString());
  });
  auto* buttons = new QHBoxLayout;
  for (QPushButton* b : {open, model2, model1, cancel, save}) buttons->addWidget(b);
  buttons->addWidget(progress_, 1);
  auto* right = new QVBoxLayout;
  right->addWidget(strip_, 3);
  right->addWidget(timing_, 2);
  auto* middle = new QHBoxLayout;
  middle->addWidget(keyframes_, 1);
  middle->addLayout(right, 3);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(buttons);
  layout->addLayout(middle, 1);
  layout->addWidget(summary_);
  resize(1500, 900);
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
    } catch (const std::exception& e) {
      error = e.what();
    }
    QMetaObject::invokeMethod(
        this,
        [this, result, error] {
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
  timing_->SetChart(ui::MakeSkillTimingChart(design, r));
  summary_->setText(QString::fromStdString(fmt::format(
      "Model {}: J {:.4g} → {:.4g} ({:.1f} times smaller); angular momentum variation {:.1f} % → "
      "{:.1f} %. The filmstrip shows the initial timing above the optimised one.",
      analysis::SkillModelNumber(r.model),
      r.objective_initial,
      r.objective,
      r.objective_initial / r.objective,
      100 * r.angular_momentum_variation_initial,
      100 * r.angular_momentum_variation)));
  try {
    strip_->SetImage(StripImage(
        design,
        {{"initial timing", r.initial},
         {fmt::format("optimised timing (model {})", analysis::SkillModelNumber(r.model)),
          r.optimized}}));
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
}

bool SkillWindow::SaveDesign(const std::string& dir) {
  if (!skill_ || !result_) {
    ShowError("Nothing to save: run Model 2 or Model 1 first.");
    return false;
  }
  try {
    const analysis::SkillDesign design(*skill_);
    ui::WriteSkillOutputs(dir, design, *result_, nullptr);
    return true;
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
}

}  // namespace acro::studio
