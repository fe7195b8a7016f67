#include "main_window.h"

#include "routine_plan_window.h"

#include "library_window.h"
#include "live_window.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDateTime>
#include <QDialog>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableWidget>
#include <QTimer>
#include <QToolBar>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "acro/athlete/body_mesh.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/configuration.h"
#include "acro/pipeline/detect.h"
#include "acro/pose/keypoints.h"
#include "acro/pose/pose_models.h"
#include "acro/report/analysis_report.h"
#include "acro/report/pose_sheet.h"
#include "acro/scene/place_scene.h"
#include "acro/views/scene_overlay.h"
#include "acro/views/trial_view.h"
#include "compare_window.h"
#include "image_view.h"
#include "plot_view.h"
#include "skill_window.h"
#include "timeline.h"

namespace acro::studio {

namespace {

constexpr int kViewWidth = 960, kViewHeight = 540;

QImage ToImage(const std::vector<std::uint8_t>& rgb, int width, int height) {
  return QImage(rgb.data(), width, height, 3 * width, QImage::Format_RGB888).copy();
}

ui::ViewPreset PresetOf(const std::string& name) {
  return name == "front" ? ui::ViewPreset::kFront
         : name == "top" ? ui::ViewPreset::kTop
                         : ui::ViewPreset::kSide;
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setWindowTitle("Acrolab Studio");
  view3d_ = new ImageView("Open a trial: File → Open trial…");
  // A drag orbits about the target (a third of a degree per pixel), the wheel moves closer, a
  // double click goes back to the preset.
  view3d_->SetNavigation([this](QPointF d) { Orbit(-0.35 * d.x(), 0.35 * d.y(), 1.0); },
                         [this](double notches) { Orbit(0, 0, std::pow(0.9, notches)); },
                         [this] { ResetOrbit(); });
  video_grid_ = new QWidget;
  new QGridLayout(video_grid_);
  video_grid_->layout()->setContentsMargins(0, 0, 0, 0);
  LayOutVideoViews(1);
  auto* views = new QSplitter(Qt::Horizontal);
  views->addWidget(view3d_);
  views->addWidget(video_grid_);
  // The 3D view and the videos share the width evenly, whatever the videos' grid.
  views->setStretchFactor(0, 1);
  views->setStretchFactor(1, 1);
  views->setSizes({800, 800});
  timeline_ = new Timeline;
  connect(timeline_, &Timeline::cursorRequested, this, [this](int s) {
    SetPlaying(false);
    SetCursor(s);
  });
  BuildJumpTable();
  QWidget* plot_panel = BuildPlotPanel();
  QWidget* verdict_panel = BuildVerdictPanel();
  QWidget* score_panel = BuildScorePanel();
  auto* tabs = new QTabWidget;
  tabs->addTab(jumps_, "Jumps");
  tabs->addTab(verdict_panel, "Verdict");
  tabs->addTab(score_panel, "Score sheet");
  auto* tables = new QSplitter(Qt::Horizontal);
  tables->addWidget(tabs);
  tables->addWidget(plot_panel);
  tables->setSizes({800, 800});

  auto* vertical = new QSplitter(Qt::Vertical);
  vertical->addWidget(views);
  auto* bottom = new QWidget;
  auto* bottom_layout = new QVBoxLayout(bottom);
  bottom_layout->setContentsMargins(0, 0, 0, 0);
  bottom_layout->addWidget(timeline_);
  bottom_layout->addWidget(tables, 1);
  vertical->addWidget(bottom);
  vertical->setStretchFactor(0, 1);
  vertical->setStretchFactor(1, 0);
  jumps_->setMinimumHeight(120);
  vertical->setSizes({600, 360});
  setCentralWidget(vertical);

  BuildStatusBar();

  timer_ = new QTimer(this);
  timer_->setInterval(15);
  connect(timer_, &QTimer::timeout, this, &MainWindow::Tick);
  BuildMenus();
  resize(1600, 950);
}

void MainWindow::BuildJumpTable() {
  jumps_ = new QTableWidget(0, 9);
  jumps_->setHorizontalHeaderLabels({"#",
                                     "code",
                                     "skill",
                                     "time of flight (s)",
                                     "apex (m)",
                                     "displacement (m)",
                                     "DD",
                                     "verdict",
                                     "silhouette IoU"});
  jumps_->setSelectionBehavior(QAbstractItemView::SelectRows);
  jumps_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  jumps_->horizontalHeader()->setStretchLastSection(true);
  jumps_->verticalHeader()->hide();
  connect(jumps_, &QTableWidget::cellClicked, this, [this](int row, int) {
    if (session_ && row >= 0 && size_t(row) < session_->analysis().jumps.size())
      GoToJump(session_->analysis().jumps[size_t(row)].index);
  });
}

QWidget* MainWindow::BuildPlotPanel() {
  // The plots: the report's figures, the cursor on them, a click moves it; exported as shown.
  plot_ = new PlotView;
  connect(plot_, &PlotView::timeRequested, this, [this](double t) {
    if (!session_) return;
    SetPlaying(false);
    SetCursor(int(std::lround(t * session_->rate_hz())));
  });
  plot_box_ = new QComboBox;
  joint_box_ = new QComboBox;
  connect(
      plot_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int i) { ShowPlot(i); });
  connect(joint_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int) {
    ShowPlot(plot_box_->currentIndex(), joint_box_->currentText().toStdString());
  });
  auto* export_button = new QPushButton("Export…");
  connect(export_button, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(
        this, "Export the plot", {}, "PNG (*.png);;SVG (*.svg);;CSV data (*.csv)");
    if (path.isEmpty()) return;
    try {
      plot_->Export(path.toStdString());
    } catch (const std::exception& e) {
      ShowError(e.what());
    }
  });
  auto* plot_panel = new QWidget;
  auto* plot_layout = new QVBoxLayout(plot_panel);
  plot_layout->setContentsMargins(0, 0, 0, 0);
  auto* plot_bar = new QHBoxLayout;
  plot_bar->addWidget(plot_box_, 1);
  plot_bar->addWidget(joint_box_, 1);
  plot_bar->addWidget(export_button);
  plot_layout->addLayout(plot_bar);
  plot_layout->addWidget(plot_, 1);
  return plot_panel;
}

QWidget* MainWindow::BuildVerdictPanel() {
  verdict_ = new QTableWidget(0, 8);
  verdict_->setHorizontalHeaderLabels({"flight",
                                       "code",
                                       "force (BW)",
                                       "moment (BW·h)",
                                       "momentum variation",
                                       "g fitted (m/s²)",
                                       "verdict",
                                       "what failed"});
  verdict_->setSelectionBehavior(QAbstractItemView::SelectRows);
  verdict_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  verdict_->horizontalHeader()->setStretchLastSection(true);
  verdict_->verticalHeader()->hide();
  connect(verdict_, &QTableWidget::cellClicked, this, [this](int row, int) {
    if (!session_ || row < 0 || size_t(row) >= session_->analysis().check.flights.size()) return;
    const analysis::FlightCheck& f = session_->analysis().check.flights[size_t(row)];
    loop_jump_ = std::make_pair(f.first_frame, f.last_frame);
    // The frames concerned: where the residual nearest its limit has its largest window.
    const analysis::PhysicalCheckOptions& limits = session_->analysis().check_options;
    const double at_s =
        f.window_force_bw / limits.max_force_bw >= f.window_moment_bwh / limits.max_moment_bwh
            ? f.window_force_at_s
            : f.window_moment_at_s;
    SetPlaying(false);
    SetCursor(
        std::clamp(int(std::lround(at_s * session_->rate_hz())), f.first_frame, f.last_frame));
  });
  findings_ = new QLabel;
  findings_->setWordWrap(true);
  findings_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  auto* verdict_panel = new QWidget;
  auto* verdict_layout = new QVBoxLayout(verdict_panel);
  verdict_layout->setContentsMargins(0, 0, 0, 0);
  verdict_layout->addWidget(verdict_, 1);
  verdict_layout->addWidget(findings_);
  return verdict_panel;
}

// The score sheet's columns; a click on the last two goes to the worst measurement.
constexpr int kScoreFaultColumn = 8;

QWidget* MainWindow::BuildScorePanel() {
  score_ = new QTableWidget(0, 10);
  score_->setHorizontalHeaderLabels({"element",
                                     "flight",
                                     "code",
                                     "DD",
                                     "time of flight (s)",
                                     "landing zone",
                                     "margin (cm)",
                                     "HD",
                                     "execution faults (measured: suggested)",
                                     "worst at (s)"});
  score_->setSelectionBehavior(QAbstractItemView::SelectRows);
  score_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  score_->horizontalHeader()->setStretchLastSection(true);
  score_->verticalHeader()->hide();
  connect(score_, &QTableWidget::cellClicked, this, [this](int row, int column) {
    GoToElement(row + 1, column >= kScoreFaultColumn);
  });
  score_summary_ = new QLabel;
  score_summary_->setWordWrap(true);
  score_summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(score_, 1);
  layout->addWidget(score_summary_);
  return panel;
}

namespace {

// How serious a measurement is (fig::MeasuredFault::ThresholdRatio); 0 without a threshold.
double Severity(const fig::MeasuredFault& f) {
  const double r = f.ThresholdRatio();
  return std::isnan(r) ? 0.0 : r;
}

// The element's most serious measurement: a reported fault first, then the nearest to its rule.
const fig::MeasuredFault* WorstMeasurement(const fig::ScoredElement& e) {
  const fig::MeasuredFault* worst = nullptr;
  for (const fig::MeasuredFault& f : e.faults) {
    if (f.frame < 0 || Severity(f) <= 0) continue;
    if (worst == nullptr ||
        std::make_pair(f.reported, Severity(f)) > std::make_pair(worst->reported, Severity(*worst)))
      worst = &f;
  }
  return worst;
}

std::string Unit(const std::string& unit) {
  return unit == "deg" ? "°" : " " + unit;
}

}  // namespace

void MainWindow::FillScoreSheet() {
  const fig::RoutineScore& s = session_->analysis().score;
  score_->setRowCount(int(s.elements.size()));
  for (size_t r = 0; r < s.elements.size(); ++r) {
    const fig::ScoredElement& e = s.elements[r];
    std::string faults;
    for (const fig::MeasuredFault& f : e.faults)
      if (f.reported)
        faults += fmt::format("{}{} {:.3g}{}: −{:.1f}",
                              faults.empty() ? "" : "; ",
                              f.fault,
                              f.value,
                              Unit(f.unit),
                              f.deduction);
    const fig::MeasuredFault* worst = WorstMeasurement(e);
    if (faults.empty())
      faults = worst == nullptr
                   ? "none measured"
                   : fmt::format("none beyond the uncertainty (nearest: {} {:.3g}{} of {:g})",
                                 worst->fault,
                                 worst->value,
                                 Unit(worst->unit),
                                 worst->threshold);
    if (const std::string unseen = fig::DescribeUnmeasured(e); !unseen.empty())
      faults += "; not measured: " + unseen;
    std::vector<std::string> cells = {
        std::to_string(e.element),
        std::to_string(e.flight),
        e.code,
        e.difficulty_counted ? fmt::format("{:.1f}", e.difficulty.total())
                             : fmt::format("({:.1f}) {}", e.difficulty.total(), e.note),
        fmt::format("{:.3f}", e.time_of_flight_s),
        e.landing_zone ? e.landing_zone->zone : "–",
        e.landing_zone && std::isfinite(e.landing_zone->margin_m)
            ? fmt::format(
                  "{:.1f}{}", 100 * e.landing_zone->margin_m, e.landing_zone->uncertain ? " ?" : "")
            : "–",
        e.landing_zone ? fmt::format("{:.1f}", e.landing_zone->deduction) : "–",
        faults,
        worst != nullptr ? fmt::format("{:.2f}", worst->time_s) : "–"};
    for (size_t c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(QString::fromStdString(cells[c]));
      if (c == size_t(kScoreFaultColumn) && e.execution_deduction > 0)
        item->setForeground(QColor(200, 40, 30));
      if (c == 6 && e.landing_zone && e.landing_zone->uncertain)
        item->setForeground(QColor(200, 40, 30));
      score_->setItem(int(r), int(c), item);
    }
  }
  score_->resizeColumnsToContents();
  score_summary_->setText(QString::fromStdString(score_summary()));
}

std::string MainWindow::score_summary() const {
  if (!session_) return "";
  const fig::RoutineScore& s = session_->analysis().score;
  std::string text = fmt::format(
      "<b>{}</b>: {} of {} elements. <b>D {:.1f}</b>{} &nbsp; <b>T {:.3f}</b> (flights {:.4f} s) "
      "&nbsp; <b>H {}</b> "
      "&nbsp; D + T + H{} = <b>{:.3f}</b>; E is the judges' ",
      s.rules_name,
      s.elements.size(),
      s.expected_elements,
      s.difficulty,
      s.difficulty_capped ? fmt::format(" (capped; {:.1f} performed)", s.difficulty_uncapped) : "",
      s.time_of_flight,
      s.time_of_flight_sum_s,
      s.horizontal_displacement ? fmt::format("{:.2f}", *s.horizontal_displacement)
                                : std::string("– (no bed)"),
      s.penalty > 0 ? fmt::format(" − {:.1f}", s.penalty) : "",
      s.total_without_execution);
  text += s.faults_reported == 0
              ? "(the assistant measured no fault beyond the measurement's uncertainty). "
              : fmt::format("(the assistant suggests −{:.1f} from {} fault(s)). ",
                            s.execution_deductions,
                            s.faults_reported);
  std::vector<std::string> why;
  if (s.interrupted)
    why.push_back("interrupted: " + s.interruption + " (scored to its last element)");
  for (const std::string& m : s.requirements_missing)
    why.push_back("requirement not performed: " + m);
  for (const std::string& b : s.rule_breaks) why.push_back(b);
  if (s.valid()) {
    text += "<span style=\"color:#1e8c32\">Valid by these rules.</span>";
  } else {
    text += "<span style=\"color:#c8281e\">Not valid:</span> ";
    for (size_t k = 0; k < why.size(); ++k) text += (k ? "; " : "") + why[k];
    text += ".";
  }
  if (s.close_calls > 0)
    text += fmt::format(" {} landing(s) within the uncertainty of a zone line (?).", s.close_calls);
  return text;
}

bool MainWindow::GoToElement(int element, bool worst_fault) {
  if (!session_) return false;
  const fig::RoutineScore& s = session_->analysis().score;
  if (element < 1 || element > int(s.elements.size())) return false;
  const fig::ScoredElement& e = s.elements[size_t(element - 1)];
  GoToJump(e.flight);
  score_->selectRow(element - 1);
  if (worst_fault) {
    if (const fig::MeasuredFault* worst = WorstMeasurement(e)) {
      SetPlaying(false);
      SetCursor(std::clamp(worst->frame, 0, session_->num_samples() - 1));
    }
  }
  return true;
}

void MainWindow::BuildStatusBar() {
  status_ = new QLabel;
  progress_ = new QProgressBar;
  progress_->setMaximumWidth(240);
  progress_->hide();
  cancel_ = new QPushButton("Cancel");
  cancel_->hide();
  connect(cancel_, &QPushButton::clicked, this, [this] { cancel_load_ = true; });
  statusBar()->addWidget(status_, 1);
  statusBar()->addPermanentWidget(progress_);
  statusBar()->addPermanentWidget(cancel_);
}

void MainWindow::LayOutVideoViews(int count) {
  auto* grid = static_cast<QGridLayout*>(video_grid_->layout());
  for (const auto& pane : panes_) {
    grid->removeWidget(pane->view);
    delete pane->view;
  }
  panes_.clear();
  for (int k = 0; k < std::max(1, count); ++k) {
    auto pane = std::make_unique<VideoPane>();
    pane->view = new ImageView(count == 0 ? "No video: File → Add a video…" : "");
    // One view; two one above the other (the videos are wide); three or four two by two.
    const int row = count <= 2 ? k : k / 2, column = count <= 2 ? 0 : k % 2;
    grid->addWidget(pane->view, row, column);
    panes_.push_back(std::move(pane));
  }
}

MainWindow::~MainWindow() {
  cancel_load_ = true;
  JoinLoader();
}

void MainWindow::JoinLoader() {
  if (loader_.joinable()) loader_.join();
}

void MainWindow::closeEvent(QCloseEvent* event) {
  cancel_load_ = true;
  JoinLoader();
  event->accept();
}

void MainWindow::AddVideoFromDialogs() {
  if (!session_) return ShowError("Open a trial first: the video is synced with it.");
  if (OneVideoAlone(session_->files()))
    return ShowError("This video is analysed alone: there is no trial to sync another video with.");
  if (session_->num_videos() >= kMaxVideos)
    return ShowError(fmt::format(
        "The session shows {} videos already: at most {}.", session_->num_videos(), kMaxVideos));
  const QString video = QFileDialog::getOpenFileName(
      this, "Add a video of the trial", {}, "Videos (*.mp4 *.mov *.avi *.mkv)");
  if (video.isEmpty()) return;
  const QString calib = QFileDialog::getOpenFileName(
      this, "Its camera calibration", {}, "Calibrations (*.toml *.xml *.yaml *.json)");
  if (calib.isEmpty()) return;
  SessionFiles files = session_->files();
  VideoFiles added;
  added.video = video.toStdString();
  added.calibration = calib.toStdString();
  if (!ChooseCamera(&added)) return;
  files.videos.push_back(added);
  OpenFiles(files, view());
}

bool MainWindow::ChooseCamera(VideoFiles* video) {
  // A calibration of several cameras: which one filmed it.
  try {
    const std::vector<vision::Camera> cameras = vision::ReadCameras(video->calibration);
    if (cameras.size() > 1) {
      QStringList names;
      for (const vision::Camera& c : cameras) names << QString::fromStdString(c.name);
      bool ok = false;
      const QString name = QInputDialog::getItem(
          this, "Which camera", "The camera that filmed it", names, 0, false, &ok);
      if (!ok) return false;
      video->camera = name.toStdString();
    }
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
  return true;
}

void MainWindow::BeginWork(const std::string& line) {
  JoinLoader();
  SetPlaying(false);
  cancel_load_ = false;
  loaded_ = false;
  progress_->setRange(0, 0);
  progress_->show();
  cancel_->show();
  status_->setText(QString::fromStdString(line));
}

std::function<bool(const std::string&, int, int)> MainWindow::WorkerProgress() {
  return [this](const std::string& step, int done, int total) {
    QMetaObject::invokeMethod(
        this,
        [this, step, done, total] {
          status_->setText(QString::fromStdString(step));
          progress_->setRange(0, std::max(0, total));
          progress_->setValue(done);
        },
        Qt::QueuedConnection);
    return !cancel_load_.load();
  };
}

void MainWindow::AskDetectPoses() {
  if (!session_ || !session_->has_video())
    return ShowError("Open a trial with its video first: the athlete is detected in the video.");
  int k = 0;
  bool ok = true;
  if (session_->num_videos() > 1) {
    QStringList names;
    for (int v = 0; v < session_->num_videos(); ++v)
      names << QString::fromStdString(
          std::filesystem::path(session_->files().videos[size_t(v)].video).filename().string());
    const QString name =
        QInputDialog::getItem(this, "Detect the athlete", "In the video", names, 0, false, &ok);
    if (!ok) return;
    k = int(names.indexOf(name));
  }
  const QString model = QInputDialog::getItem(this,
                                              "Detect the athlete",
                                              "BlazePose model (heavy: the most accurate through "
                                              "somersaults; full: about four times faster)",
                                              {"heavy", "full", "lite"},
                                              0,
                                              false,
                                              &ok);
  if (ok) DetectPoses(k, model.toStdString());
}

bool MainWindow::DetectPoses(int k, const std::string& model) {
  if (!session_ || k < 0 || k >= session_->num_videos()) {
    ShowError("Open a trial with its video first: the athlete is detected in the video.");
    return false;
  }
  if (busy()) {
    ShowError("Still working on the previous files: wait or cancel.");
    return false;
  }
  pose::LandmarkModel landmarks = pose::LandmarkModel::kHeavy;
  try {
    landmarks = pose::ParseLandmarkModel(model);
    pose::FindPoseModels(landmarks);  // not installed: its one line now, not after a wait
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
  const std::filesystem::path video = session_->files().videos.at(size_t(k)).video;
  BeginWork("detecting the athlete in " + video.filename().string());
  loader_ = std::thread([this, video, landmarks, k, session = session_] {
    Progress progress;
    progress.report = WorkerProgress();
    std::vector<capture::DetectedPerson> poses;
    int found = 0;
    std::string error, where;
    try {
      const pose::VideoPoses r = pipeline::DetectPosesInCache(video, landmarks, progress);
      poses.assign(size_t(r.info.num_frames), capture::DetectedPerson::Zero(3, 33));
      for (const pose::FramePose& f : r.frames) {
        if (!f.found || f.frame < 0 || size_t(f.frame) >= poses.size()) continue;
        poses[size_t(f.frame)] = f.keypoints;
        ++found;
      }
      where = pipeline::PoseCacheDirectory(video).string();
    } catch (const std::exception& e) {
      error = e.what();
    }
    QMetaObject::invokeMethod(
        this,
        [this, k, session, poses = std::move(poses), found, error, where]() mutable {
          progress_->hide();
          cancel_->hide();
          loaded_ = true;
          if (!error.empty() && cancel_load_) {
            status_->setText(
                "Detection cancelled: the frames done are kept; a second run goes on from there.");
            return;
          }
          if (!error.empty()) return ShowError(error);
          if (session != session_ || size_t(k) >= panes_.size()) return;  // another session since
          VideoPane& pane = *panes_[size_t(k)];
          pane.poses = std::move(poses);
          status_->setText(QString::fromStdString(
              fmt::format("{} of {} frames with the athlete's keypoints (kept in {})",
                          found,
                          pane.poses.size(),
                          where)));
          if (pane.frame_index >= 0) DrawVideo(k);
        },
        Qt::QueuedConnection);
  });
  return true;
}

int MainWindow::detected_frames(int k) const {
  const VideoPane& pane = *panes_.at(size_t(k));
  int n = 0;
  for (const capture::DetectedPerson& p : pane.poses) n += p.row(2).maxCoeff() > 0 ? 1 : 0;
  return n;
}

void MainWindow::BuildMenus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("Open &trial…", this, [this] {
    const QString trial = QFileDialog::getOpenFileName(
        this, "Open a trial", {}, "Trials (*.c3d *.trc *.csv);;All files (*)");
    if (trial.isEmpty()) return;
    const QString athlete = QFileDialog::getOpenFileName(
        this, "The athlete's profile (cancel: a default athlete)", {}, "Profiles (*.yaml *.yml)");
    SessionFiles files;
    files.trial = trial.toStdString();
    files.athlete = athlete.toStdString();
    OpenFiles(files);
  });
  file->addAction("Analyse one &video…", this, [this] {
    // One camera alone (docs/one-camera.md): the athlete detected, the camera from its
    // calibration or, cancelled, from the bed in the first frame.
    const QString video = QFileDialog::getOpenFileName(
        this, "Analyse one video", {}, "Videos (*.mp4 *.mov *.mkv *.avi *.ts);;All files (*)");
    if (video.isEmpty()) return;
    const QString calib = QFileDialog::getOpenFileName(
        this,
        "Its camera's calibration (cancel: the camera from the bed in its first frame)",
        {},
        "Calibrations (*.toml *.yaml *.yml *.xml *.qca.txt);;All files (*)");
    const QString athlete = QFileDialog::getOpenFileName(
        this, "The athlete's profile (cancel: a default athlete)", {}, "Profiles (*.yaml *.yml)");
    SessionFiles files;
    files.athlete = athlete.toStdString();
    VideoFiles v;
    v.video = video.toStdString();
    v.calibration = calib.toStdString();
    if (!v.calibration.empty() && !ChooseCamera(&v)) return;
    files.videos.push_back(v);
    OpenFiles(files);
  });
  file->addAction("Open &athlete…", this, [this] {
    if (!session_) return ShowError("Open a trial first: the athlete is whom it is analysed for.");
    const QString athlete =
        QFileDialog::getOpenFileName(this, "The athlete's profile", {}, "Profiles (*.yaml *.yml)");
    if (athlete.isEmpty()) return;
    // The trial analysed again for this athlete (personalised model), the videos kept in sync.
    SessionFiles files = session_->files();
    files.athlete = athlete.toStdString();
    OpenFiles(files, view());
  });
  file->addAction("Add a &video…", this, [this] { AddVideoFromDialogs(); });
  file->addAction("Open from &library…", this, [this] { OpenFromLibrary(); });
  file->addAction("&Open session…", this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Open a session", {}, "Sessions (*.acrolab)");
    if (!path.isEmpty()) OpenSessionFile(path.toStdString());
  });
  file->addAction("&Save session…", this, [this] {
    const QString path =
        QFileDialog::getSaveFileName(this, "Save the session", {}, "Sessions (*.acrolab)");
    if (!path.isEmpty()) SaveSessionFile(path.toStdString());
  });
  file->addAction("Open s&kill (designer)…", this, [this] { OpenSkillDesigner(); });
  file->addAction("&Plan a routine…", this, [this] { OpenRoutinePlanner(); });
  file->addAction("&Watch live…", this, [this] { AskWatchLive(); });
  file->addSeparator();
  file->addAction("&Compare two jumps…", this, [this] { AskCompare(); });
  QMenu* video_menu = menuBar()->addMenu("&Video");
  video_menu->addAction("&Detect the athlete (2D keypoints)…", this, [this] { AskDetectPoses(); });
  file->addSeparator();
  QAction* quit = file->addAction("&Quit", this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  BuildTransport();
}

void MainWindow::BuildTransport() {
  QToolBar* transport = addToolBar("Transport");
  const auto add = [&](const QString& text, const QKeySequence& key, auto slot) {
    QAction* a = transport->addAction(text, this, slot);
    a->setShortcut(key);
    a->setShortcutContext(Qt::WindowShortcut);
    a->setToolTip(text + "  (" + key.toString() + ")");
    return a;
  };
  add("|◀ take-off", QKeySequence(Qt::Key_PageUp), [this] { StepTakeoff(-1); });
  add("◀ frame", QKeySequence(Qt::Key_Left), [this] { StepFrame(-1); });
  add("play / pause", QKeySequence(Qt::Key_Space), [this] { SetPlaying(!playing_, 1); });
  add("frame ▶", QKeySequence(Qt::Key_Right), [this] { StepFrame(1); });
  add("take-off ▶|", QKeySequence(Qt::Key_PageDown), [this] { StepTakeoff(1); });
  // J, K, L as in video players: backwards, pause, forwards.
  add("J", QKeySequence(Qt::Key_J), [this] { SetPlaying(true, -1); })->setVisible(false);
  add("K", QKeySequence(Qt::Key_K), [this] { SetPlaying(false); })->setVisible(false);
  add("L", QKeySequence(Qt::Key_L), [this] { SetPlaying(true, 1); })->setVisible(false);
  transport->addSeparator();
  speed_box_ = new QComboBox;
  for (const char* s : {"speed 1", "speed ½", "speed ¼", "speed ⅛"}) speed_box_->addItem(s);
  connect(speed_box_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    speed_ = 1.0 / double(1 << i);
  });
  transport->addWidget(speed_box_);
  loop_ = transport->addAction("loop the jump");
  loop_->setCheckable(true);
  transport->addSeparator();
  preset_box_ = new QComboBox;
  for (const char* s : {"side", "front", "top"}) preset_box_->addItem(s);
  connect(preset_box_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    ResetOrbit();
  });
  transport->addWidget(preset_box_);
  follow_ = transport->addAction("follow");
  follow_->setCheckable(true);
  connect(follow_, &QAction::toggled, this, [this](bool) { Redraw(); });
  // What the 3D view shows.
  transport->addSeparator();
  for (const auto& [name, tip] : {std::pair{"mesh", "the athlete's body"},
                                  {"skeleton", "the segments, left red, right green"},
                                  {"markers", "the measured markers or keypoints"},
                                  {"com", "the centre of mass and its path since take-off"},
                                  {"cameras", "the videos' cameras as frustums"}}) {
    QAction* a = transport->addAction(name);
    a->setCheckable(true);
    a->setToolTip(QString("Show ") + tip + " in the 3D view");
    connect(a, &QAction::toggled, this, [this](bool) { ApplyShow(); });
    show_actions_.push_back(a);
  }
  SetShown("mesh,skeleton,com");
}

std::string MainWindow::shown() const {
  std::string list;
  for (const QAction* a : show_actions_)
    if (a->isChecked()) list += (list.empty() ? "" : ",") + a->text().toStdString();
  return list;
}

void MainWindow::SetShown(const std::string& list) {
  const ShownParts parts = ParseShownParts(list);
  const analysis::SceneShow& show = parts.scene;
  const bool on[] = {show.mesh, show.skeleton, show.markers, show.com, parts.cameras};
  for (size_t k = 0; k < show_actions_.size(); ++k) {
    const QSignalBlocker block(show_actions_[k]);
    show_actions_[k]->setChecked(on[k]);
  }
  ApplyShow();
}

void MainWindow::ApplyShow() {
  if (!free_view_ || !session_) return;
  ShowInView();
  Redraw();
}

void MainWindow::ShowInView() {
  if (!free_view_ || !session_) return;
  const ShownParts parts = ParseShownParts(shown());
  free_view_->SetShow(parts.scene);
  std::vector<vision::Camera> shown_cameras;
  for (int k = 0; parts.cameras && k < session_->num_videos(); ++k)
    shown_cameras.push_back(session_->camera(k));
  free_view_->SetCameras(shown_cameras);
}

void MainWindow::Orbit(double azimuth_deg, double elevation_deg, double distance_scale) {
  orbit_azimuth_deg_ += azimuth_deg;
  orbit_elevation_deg_ = std::clamp(orbit_elevation_deg_ + elevation_deg, -80.0, 80.0);
  orbit_distance_scale_ = std::clamp(orbit_distance_scale_ * distance_scale, 0.2, 5.0);
  Redraw();
}

void MainWindow::ResetOrbit() {
  orbit_azimuth_deg_ = orbit_elevation_deg_ = 0.0;
  orbit_distance_scale_ = 1.0;
  Redraw();
}

void MainWindow::AskWatchLive() {
  bool ok = false;
  const QString sources = QInputDialog::getText(
      this,
      "Watch live",
      "Cameras or streams, separated by spaces (/dev/video0, udp://0.0.0.0:5000, rtsp://…):",
      QLineEdit::Normal,
      "/dev/video0",
      &ok);
  if (!ok || sources.trimmed().isEmpty()) return;
  const QString folder = QFileDialog::getExistingDirectory(
      this, "A new or empty folder for the session's recordings and routines");
  if (folder.isEmpty()) return;
  pipeline::LiveRequest request;
  for (const QString& s : sources.split(' ', Qt::SkipEmptyParts))
    request.sources.push_back(s.toStdString());
  request.out_dir = folder.toStdString();
  std::string why;
  if (!request.IsValid(&why)) return ShowError(why);
  auto* live = new LiveWindow(std::move(request), 5.0);
  live->setAttribute(Qt::WA_DeleteOnClose);
  live->show();
}

void MainWindow::ShowError(const std::string& message) {
  last_error_ = message;
  status_->setText(QString::fromStdString(message));
  // Not modal: the window stays live (and a test can read it).
  auto* box = new QMessageBox(
      QMessageBox::Critical, "Acrolab", QString::fromStdString(message), QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

void MainWindow::OpenFiles(const SessionFiles& files, const SessionView& view) {
  OpenInBackground(files, [this, view](std::shared_ptr<Session> opened) {
    // The session is handed over whole; the previous one goes only now.
    Adopt(std::move(opened), view);
  });
}

void MainWindow::OpenInBackground(const SessionFiles& files,
                                  std::function<void(std::shared_ptr<Session>)> done) {
  if (busy()) return ShowError("Still opening the previous files: wait or cancel.");
  BeginWork("opening " +
            (OneVideoAlone(files) ? files.videos[0].video + " (one video alone)" : files.trial));
  loader_ = std::thread([this, files, done] {
    const auto report = WorkerProgress();
    std::shared_ptr<Session> opened;
    std::string error;
    try {
      opened = Session::Open(files, report);
    } catch (const std::exception& e) {
      error = e.what();
    }
    QMetaObject::invokeMethod(
        this,
        [this, opened, error, done]() mutable {
          progress_->hide();
          cancel_->hide();
          loaded_ = true;
          if (!error.empty() && cancel_load_) {
            // Asked for: a line, not an error; what was open stays.
            status_->setText("Cancelled: nothing was opened; what was open stays.");
            return;
          }
          if (!error.empty()) return ShowError(error);
          done(std::move(opened));
        },
        Qt::QueuedConnection);
  });
}

void MainWindow::Adopt(std::shared_ptr<Session> session, const SessionView& view) {
  compare_.reset();
  compare_other_.reset();
  for (const auto& pane : panes_) pane->overlay.reset();
  free_view_.reset();
  SetShown(view.show);  // before the 3D view exists: nothing drawn yet
  session_ = std::move(session);
  std::optional<analysis::TrampolineScene> trampoline;
  if (session_->analysis().bed)
    trampoline = analysis::MakeTrampolineScene(*session_->analysis().bed);
  LayOutVideoViews(session_->num_videos());
  try {
    free_view_ = std::make_unique<ui::TrialFreeView>(
        session_->scene(), kViewWidth, kViewHeight, analysis::SceneShow{}, trampoline);
    for (int k = 0; k < session_->num_videos(); ++k) {
      ui::SceneOverlayOptions options;
      options.show = analysis::ParseSceneShow("mesh,skeleton,com");
      options.sync = session_->sync(k);
      const capture::VideoInfo& info = session_->video(k).info();
      panes_[size_t(k)]->overlay = std::make_unique<ui::TrialOverlay>(
          session_->scene(), session_->camera(k), info.width, info.height, options);
    }
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
  ShowInView();
  std::vector<Timeline::Jump> jumps;
  for (const analysis::JumpMetrics& j : session_->analysis().jumps)
    jumps.push_back({j.flight.takeoff_frame,
                     j.flight.landing_frame,
                     fmt::format("{}  {}", j.index, j.fig_code),
                     j.check.has_value(),
                     j.check.has_value() && j.check->pass});
  // The events: each flight's take-off and landing, and the trial file's own.
  std::vector<Timeline::Event> events;
  for (const analysis::JumpMetrics& j : session_->analysis().jumps) {
    events.push_back({j.flight.takeoff_frame, fmt::format("take-off {}", j.index), false});
    events.push_back({j.flight.landing_frame, fmt::format("landing {}", j.index), false});
  }
  for (const capture::Event& e : session_->trial().events)
    events.push_back({int(std::lround(e.time_s * session_->rate_hz())),
                      e.context.empty() ? e.label : e.context + " " + e.label,
                      true});
  timeline_->SetTrial(
      session_->num_samples(), session_->rate_hz(), std::move(jumps), std::move(events));
  FillJumpTable();
  FillVerdict();
  FillScoreSheet();
  FillPlots();
  setWindowTitle(QString::fromStdString(
      "Acrolab Studio — " + (OneVideoAlone(session_->files())
                                 ? session_->files().videos[0].video + " (one video alone)"
                                 : session_->files().trial)));
  std::string note = fmt::format("{} samples at {:g} Hz, {} jumps",
                                 session_->num_samples(),
                                 session_->rate_hz(),
                                 session_->analysis().jumps.size());
  for (int k = 0; k < session_->num_videos(); ++k)
    note += fmt::format("; video{} synced: video time = {:.4f} s + trial time",
                        session_->num_videos() > 1 ? " " + std::to_string(k + 1) : "",
                        session_->sync(k).offset_s);
  for (const std::string& w : session_->warnings()) note += "; warning: " + w;
  status_->setText(QString::fromStdString(note));
  {
    const QSignalBlocker block(preset_box_);
    preset_box_->setCurrentIndex(view.preset == "front" ? 1 : view.preset == "top" ? 2 : 0);
  }
  follow_->setChecked(view.follow);
  orbit_azimuth_deg_ = view.orbit_azimuth_deg;
  orbit_elevation_deg_ = view.orbit_elevation_deg;
  orbit_distance_scale_ = view.orbit_distance_scale;
  SetSpeed(view.speed);
  SetCursor(std::clamp(view.cursor_sample, 0, session_->num_samples() - 1));
}

void MainWindow::FillJumpTable() {
  const std::vector<analysis::JumpMetrics>& jumps = session_->analysis().jumps;
  jumps_->setRowCount(int(jumps.size()));
  for (size_t r = 0; r < jumps.size(); ++r) {
    const analysis::JumpMetrics& j = jumps[r];
    const std::vector<std::string> cells = {
        std::to_string(j.index),
        j.fig_code,
        j.skill_name,
        fmt::format("{:.3f}", j.time_of_flight_s()),
        fmt::format("{:.2f}", j.apex_m()),
        fmt::format("{:.2f}", j.displacement_from_takeoff_m),
        fmt::format("{:.1f}", j.difficulty.total_tenths() / 10.0),
        j.verdict,
        j.silhouette_iou ? fmt::format("{:.2f}", *j.silhouette_iou) : "–"};
    for (size_t c = 0; c < cells.size(); ++c)
      jumps_->setItem(int(r), int(c), new QTableWidgetItem(QString::fromStdString(cells[c])));
  }
  jumps_->resizeColumnsToContents();
}

void MainWindow::FillVerdict() {
  const analysis::PhysicalCheck& check = session_->analysis().check;
  verdict_->setRowCount(int(check.flights.size()));
  for (size_t r = 0; r < check.flights.size(); ++r) {
    const analysis::FlightCheck& f = check.flights[r];
    std::string code;
    for (const analysis::JumpMetrics& j : session_->analysis().jumps)
      if (j.index == f.flight + 1) code = j.fig_code;
    const std::vector<std::string> cells = {std::to_string(f.flight + 1),
                                            code,
                                            fmt::format("{:.3f}", f.window_force_bw),
                                            fmt::format("{:.4f}", f.window_moment_bwh),
                                            fmt::format("{:.1f} %", 100 * f.momentum_variation),
                                            fmt::format("{:.2f}", f.fitted_gravity_m_per_s2),
                                            f.pass ? "pass" : "fail",
                                            f.FailureText()};
    for (size_t c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(QString::fromStdString(cells[c]));
      if (c == 6) item->setForeground(f.pass ? QColor(30, 140, 50) : QColor(200, 40, 30));
      verdict_->setItem(int(r), int(c), item);
    }
  }
  verdict_->resizeColumnsToContents();
  // The cause found and the correction suggested (never applied), or why there is nothing to fix.
  std::string text = "<b>" + check.verdict + "</b>";
  for (const analysis::Finding& f : check.findings) text += "<br>" + f.text;
  if (check.pass)
    text +=
        "<br>Every judged flight's residuals are under their limits and its angular "
        "momentum steady: nothing to correct.";
  findings_->setText(QString::fromStdString(text));
}

void MainWindow::FillPlots() {
  joint_box_->clear();
  const std::vector<std::string>& names =
      session_->analysis().reconstruction.motion.coordinate_names;
  for (size_t k = dynamics::kRootNq; k < names.size(); ++k)
    joint_box_->addItem(QString::fromStdString(names[k]));
  const int hip = joint_box_->findText("r_hip_flexion");
  joint_box_->setCurrentIndex(hip >= 0 ? hip : 0);
  ShowPlot(0, joint_box_->currentText().toStdString());
}

void MainWindow::ShowPlot(int index, const std::string& joint) {
  if (!session_) return;
  ui::AnalysisReportOptions options;
  options.joint = joint.empty() ? joint_box_->currentText().toStdString() : joint;
  // With a video, the silhouette IoU per filmed flight frame (the report's figure).
  const analysis::SilhouetteCheck& silhouettes = session_->silhouettes();
  for (size_t k = 0; k < silhouettes.iou.size(); ++k) {
    options.silhouette_time_s.push_back(silhouettes.samples[k] / session_->rate_hz());
    options.silhouette_iou.push_back(silhouettes.iou[k]);
  }
  std::vector<ui::ReportFigure> figures;
  try {
    figures = ui::MakeAnalysisFigures(session_->analysis(), options);
  } catch (const std::exception& e) {
    return ShowError(e.what());
  }
  plot_box_->clear();
  for (const ui::ReportFigure& f : figures)
    plot_box_->addItem(QString::fromStdString(f.chart.title));
  index = std::clamp(index, 0, int(figures.size()) - 1);
  plot_box_->setCurrentIndex(index);
  if (index >= 0) plot_->SetChart(figures[size_t(index)].chart);
  plot_->SetCursorTime(cursor_ / session_->rate_hz());
}

std::string MainWindow::status_text() const {
  return status_->text().toStdString();
}

int MainWindow::plot_count() const {
  return plot_box_->count();
}

std::string MainWindow::plot_title(int index) const {
  return plot_box_->itemText(index).toStdString();
}

const analysis::TrialFrame* MainWindow::view_frame() const {
  return free_view_ ? &free_view_->frame() : nullptr;
}

void MainWindow::SetCursor(int sample) {
  if (!session_) return;
  cursor_ = std::clamp(sample, 0, session_->num_samples() - 1);
  if (!playing_) play_position_ = cursor_;
  timeline_->SetCursor(cursor_);
  Redraw();
}

RoutinePlanWindow* MainWindow::OpenRoutinePlanner() {
  if (!planner_) planner_ = std::make_unique<RoutinePlanWindow>();
  planner_->show();
  planner_->raise();
  return planner_.get();
}

SkillWindow* MainWindow::OpenSkillDesigner(const std::string& path) {
  if (!designer_) {
    designer_ = std::make_unique<SkillWindow>(this);
    designer_->SetGhostTarget([this](const analysis::SkillGhost& d) { ShowDesignGhost(d); });
  }
  designer_->show();
  if (!path.empty()) designer_->OpenSkill(path);
  return designer_.get();
}

void MainWindow::AskCompare() {
  if (!session_) return ShowError("Open a trial first: compare mode starts from one of its jumps.");
  // A: a jump of this trial; B: another of its jumps, a jump of another trial, or a design.
  QDialog dialog(this);
  dialog.setWindowTitle("Compare two jumps");
  auto* a = new QSpinBox;
  auto* b = new QSpinBox;
  const int jumps = int(session_->analysis().jumps.size());
  a->setRange(1, std::max(1, jumps));
  b->setRange(1, 99);
  a->setValue(std::min(2, jumps));
  b->setValue(std::min(3, jumps));
  auto* kind = new QComboBox;
  kind->addItems({"a jump of this trial",
                  "a jump of another trial",
                  "a designed skill (acrolab optimize's folder)"});
  auto* path = new QLineEdit;
  auto* athlete = new QLineEdit;
  athlete->setPlaceholderText("the other trial's athlete (empty: this one's)");
  athlete->setText(QString::fromStdString(session_->files().athlete));
  auto* browse = new QPushButton("Browse…");
  connect(browse, &QPushButton::clicked, &dialog, [&] {
    const QString chosen =
        kind->currentIndex() == 2
            ? QFileDialog::getExistingDirectory(&dialog, "The design's folder")
            : QFileDialog::getOpenFileName(
                  &dialog, "The other trial", {}, "Trials (*.c3d *.trc *.csv);;All files (*)");
    if (!chosen.isEmpty()) path->setText(chosen);
  });
  const auto update = [&] {
    path->setEnabled(kind->currentIndex() > 0);
    browse->setEnabled(kind->currentIndex() > 0);
    athlete->setEnabled(kind->currentIndex() == 1);
    b->setEnabled(kind->currentIndex() < 2);
  };
  connect(kind, QOverload<int>::of(&QComboBox::currentIndexChanged), &dialog, update);
  update();
  auto* file_row = new QHBoxLayout;
  file_row->addWidget(path, 1);
  file_row->addWidget(browse);
  auto* form = new QFormLayout;
  form->addRow("A: jump of this trial", a);
  form->addRow("B is", kind);
  form->addRow("B's trial or design", file_row);
  form->addRow("B's athlete", athlete);
  form->addRow("B: jump", b);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  auto* layout = new QVBoxLayout(&dialog);
  layout->addLayout(form);
  layout->addWidget(buttons);
  if (dialog.exec() != QDialog::Accepted) return;
  if (kind->currentIndex() > 0 && path->text().isEmpty())
    return ShowError("Choose B's trial or design.");
  if (kind->currentIndex() == 0) {
    OpenCompare(a->value(), b->value());
  } else if (kind->currentIndex() == 1) {
    SessionFiles other;
    other.trial = path->text().toStdString();
    other.athlete = athlete->text().toStdString();
    OpenCompareWithTrial(a->value(), other, b->value());
  } else {
    OpenCompareWithDesign(a->value(), path->text().toStdString());
  }
}

bool MainWindow::OpenCompare(int a, int b) {
  if (!session_) {
    ShowError("Open a trial first: compare mode shows two of its jumps.");
    return false;
  }
  return ShowCompare(a, [&] {
    auto window = std::make_unique<CompareWindow>(session_, a, session_, b, this);
    session_->scene().SetGhostJump(b);
    return window;
  });
}

void MainWindow::OpenCompareWithTrial(int a, SessionFiles other, int b) {
  if (!session_) return ShowError("Open a trial first: compare mode starts from one of its jumps.");
  // Only the jump is needed: the other trial's video stays closed.
  other.videos.clear();
  OpenInBackground(other, [this, a, b](std::shared_ptr<Session> opened) {
    ShowCompare(a, [&] {
      auto window = std::make_unique<CompareWindow>(session_, a, opened, b, this);
      session_->scene().SetGhostJump(
          opened->analysis(),
          opened->body(),
          analysis::MakeEllipsoidBodyMesh(opened->body(), analysis::OverlayBodyMeshOptions()),
          b,
          window->scene().b().label);
      compare_other_ = opened;
      return window;
    });
  });
}

bool MainWindow::OpenCompareWithDesign(int a, const std::string& design_dir) {
  if (!session_) {
    ShowError("Open a trial first: compare mode starts from one of its jumps.");
    return false;
  }
  return ShowCompare(a, [&] {
    auto design = std::make_shared<const analysis::SkillGhost>(
        analysis::ReadSkillGhost(design_dir, analysis::MakeStandardHumanModel(session_->body())));
    auto window = std::make_unique<CompareWindow>(session_, a, design, this);
    session_->scene().SetGhostDesign(*design, session_->body());
    return window;
  });
}

bool MainWindow::ShowCompare(int a, const std::function<std::unique_ptr<CompareWindow>()>& make) {
  try {
    std::unique_ptr<CompareWindow> window = make();
    compare_ = std::move(window);
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
  compare_->show();
  GoToJump(a);
  return true;
}

void MainWindow::ShowDesignGhost(const analysis::SkillGhost& design) {
  if (!session_) return ShowError("Open a trial first: the design is drawn in its flights.");
  try {
    session_->scene().SetGhostDesign(design, session_->body());
  } catch (const std::exception& e) {
    return ShowError(e.what());
  }
  status_->setText(QString::fromStdString(
      "ghost: " + design.name +
      " (design) at every flight's take-off, in the 3D view and over the video"));
  Redraw();
}

void MainWindow::Redraw() {
  if (session_) plot_->SetCursorTime(cursor_ / session_->rate_hz());
  if (session_ && compare_ && compare_->isVisible())
    compare_->SetTau(cursor_ / session_->rate_hz() - compare_->a_takeoff_s());
  if (!session_) return;
  if (free_view_) {
    // The preset looks at the athlete's take-off heading from mid-flight height over the bed (or
    // the trial's first centre of mass).
    const analysis::TrialAnalysis& a = session_->analysis();
    Eigen::Vector3d target = a.check.frames.com_W.cols() > 0
                                 ? Eigen::Vector3d(a.check.frames.com_W.col(0))
                                 : Eigen::Vector3d(0, 0, 1.5);
    if (a.bed) target = a.bed->centre_W + Eigen::Vector3d(0, 0, 2.0);
    const ui::ViewPreset preset = PresetOf(preset_box_->currentText().toStdString());
    ui::FreeViewpoint v =
        ui::PresetViewpoint(preset, target, preset == ui::ViewPreset::kTop ? 14 : 12);
    v.view_angle_deg = 35;
    // The user's orbit about the target, and closer or farther.
    v = ui::OrbitViewpoint(v, orbit_azimuth_deg_, orbit_elevation_deg_);
    v.eye_W = v.target_W + orbit_distance_scale_ * (v.eye_W - v.target_W);
    free_view_->SetViewpoint(v, follow_->isChecked());
    free_view_->Render(cursor_, &rgb3d_);
    view3d_->SetImage(ToImage(rgb3d_, free_view_->width(), free_view_->height()));
  }
  for (int k = 0; k < session_->num_videos(); ++k) DrawVideo(k);
}

void MainWindow::DrawVideo(int k) {
  VideoPane& pane = *panes_.at(size_t(k));
  const int frame = session_->VideoFrameOf(cursor_, k);
  if (frame < 0) {
    pane.frame_index = -1;
    pane.view->SetImage({});
    return;
  }
  if (frame != pane.frame_index) {
    capture::VideoReader& video = session_->video(k);
    const auto cached = std::find_if(pane.recent.begin(),
                                     pane.recent.end(),
                                     [frame](const auto& f) { return f.index == frame; });
    try {
      if (cached != pane.recent.end()) {
        pane.filmed = *cached;
      } else if (frame == pane.reader_next && video.ReadNext(&pane.filmed)) {
        // The frame after the last decoded is read on (playing, stepping forward); any other is
        // sought.
        pane.reader_next = pane.filmed.index + 1;
      } else {
        pane.filmed = video.Frame(frame);
        pane.reader_next = frame + 1;
      }
    } catch (const std::exception& e) {
      return ShowError(e.what());
    }
    if (cached == pane.recent.end()) {
      pane.recent.push_back(pane.filmed);
      constexpr size_t kRecentFrames = 8;
      if (pane.recent.size() > kRecentFrames) pane.recent.pop_front();
    }
    pane.frame_index = frame;
  }
  pane.drawn = pane.filmed;
  if (pane.overlay) {
    const int sample = session_->SampleOf(frame, k);
    if (sample >= 0) pane.overlay->Draw(sample, &pane.drawn);
  }
  // The detector's keypoints over the model (Video → Detect the athlete).
  if (size_t(frame) < pane.poses.size() && pane.drawn.channels == 3)
    ui::DrawSkeleton(pane.drawn.width,
                     pane.drawn.height,
                     pane.poses[size_t(frame)],
                     pose::BlazePoseEdges(),
                     pose::BlazePoseSides(),
                     0.2,
                     &pane.drawn.pixels);
  pane.view->SetImage(ToImage(pane.drawn.pixels, pane.drawn.width, pane.drawn.height));
}

void MainWindow::StepFrame(int direction) {
  if (!session_) return;
  SetPlaying(false);
  if (session_->has_video()) {
    const int now = session_->VideoFrameOf(cursor_);
    const int next = (now < 0 ? 0 : now) + (direction > 0 ? 1 : -1);
    const int sample = session_->SampleOf(next);
    if (sample >= 0) return SetCursor(sample);
  }
  SetCursor(cursor_ + (direction > 0 ? 1 : -1));
}

void MainWindow::StepTakeoff(int direction) {
  if (!session_) return;
  const std::vector<analysis::JumpMetrics>& jumps = session_->analysis().jumps;
  if (direction > 0) {
    for (const analysis::JumpMetrics& j : jumps)
      if (j.flight.takeoff_frame > cursor_) return GoToJump(j.index);
  } else {
    for (auto it = jumps.rbegin(); it != jumps.rend(); ++it)
      if (it->flight.takeoff_frame < cursor_) return GoToJump(it->index);
  }
}

void MainWindow::GoToJump(int index) {
  if (!session_) return;
  for (const analysis::JumpMetrics& j : session_->analysis().jumps) {
    if (j.index != index) continue;
    loop_jump_ = std::make_pair(j.flight.takeoff_frame, j.flight.landing_frame);
    jumps_->selectRow(index - 1);
    const bool was_playing = playing_;
    SetPlaying(false);
    SetCursor(j.flight.takeoff_frame);
    if (was_playing) SetPlaying(true);
    return;
  }
}

void MainWindow::SetSpeed(double speed) {
  speed_ = speed;
  const int index = speed >= 1 ? 0 : speed >= 0.5 ? 1 : speed >= 0.25 ? 2 : 3;
  speed_box_->setCurrentIndex(index);
}

void MainWindow::SetPlaying(bool playing, int direction) {
  playing_ = playing && session_ != nullptr;
  direction_ = direction >= 0 ? 1 : -1;
  play_position_ = cursor_;
  last_tick_ms_ = QDateTime::currentMSecsSinceEpoch();
  if (playing_) {
    timer_->start();
  } else {
    timer_->stop();
  }
}

void MainWindow::Tick() {
  if (!session_ || !playing_) return;
  const qint64 now = QDateTime::currentMSecsSinceEpoch();
  const double elapsed_s = (now - last_tick_ms_) / 1000.0;
  last_tick_ms_ = now;
  play_position_ += direction_ * elapsed_s * speed_ * session_->rate_hz();
  int sample = int(std::lround(play_position_));
  if (loop_->isChecked() && loop_jump_) {
    const auto [first, last] = *loop_jump_;
    if (sample > last) {
      play_position_ = first;
      sample = first;
    } else if (sample < first) {
      play_position_ = last;
      sample = last;
    }
  }
  if (sample < 0 || sample >= session_->num_samples()) {
    SetPlaying(false);
    sample = std::clamp(sample, 0, session_->num_samples() - 1);
  }
  if (sample != cursor_) {
    cursor_ = sample;
    timeline_->SetCursor(cursor_);
    Redraw();
  }
}

SessionView MainWindow::view() const {
  SessionView v;
  v.cursor_sample = cursor_;
  v.speed = speed_;
  v.preset = preset_box_->currentText().toStdString();
  v.follow = follow_->isChecked();
  v.show = shown();
  v.orbit_azimuth_deg = orbit_azimuth_deg_;
  v.orbit_elevation_deg = orbit_elevation_deg_;
  v.orbit_distance_scale = orbit_distance_scale_;
  return v;
}

bool MainWindow::SaveSessionFile(const std::string& path) {
  if (!session_) {
    ShowError("Nothing to save: open a trial first.");
    return false;
  }
  try {
    WriteSessionFile(path, session_->files(), view());
    status_->setText(QString::fromStdString("saved " + path));
    return true;
  } catch (const std::exception& e) {
    ShowError(e.what());
    return false;
  }
}

void MainWindow::OpenSessionFile(const std::string& path) {
  try {
    const auto [files, view] = ReadSessionFile(path);
    OpenFiles(files, view);
  } catch (const std::exception& e) {
    ShowError(e.what());
  }
}

LibraryDialog* MainWindow::OpenFromLibrary(const std::string& library, bool modal) {
  const std::string path =
      !library.empty() ? library
                       : (!library_.empty() ? library_ : library::DefaultLibraryPath().string());
  try {
    library_dialog_ = std::make_unique<LibraryDialog>(path, this);
  } catch (const std::exception& e) {
    ShowError(e.what());
    return nullptr;
  }
  connect(library_dialog_.get(), &QDialog::accepted, this, [this] {
    if (const std::optional<SessionFiles> files = library_dialog_->SelectedFiles())
      OpenFiles(*files);
  });
  if (modal) {
    library_dialog_->exec();
    return nullptr;
  }
  library_dialog_->show();
  return library_dialog_.get();
}

}  // namespace acro::studio
