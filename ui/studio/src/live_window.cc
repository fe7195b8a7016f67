#include "live_window.h"

#include <QBuffer>
#include <QCloseEvent>
#include <QComboBox>
#include <QDesktopServices>
#include <QFileDialog>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QPainter>
#include <QPainterPath>
#include <QPushButton>
#include <QShortcut>
#include <QSlider>
#include <QSplitter>
#include <QTableWidget>
#include <QTimer>
#include <QUrl>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/athlete_profile.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/live_source.h"
#include "acro/capture/video.h"
#include "acro/fig/score_sheet.h"
#include "acro/library/library.h"
#include "image_view.h"

namespace acro::studio {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The buffer keeps a little more than the longest delay (the replay copies its frames out).
constexpr double kKeepS = LiveWindow::kMaxDelayS + 2.0;
constexpr size_t kMaxFrames = 8000;                          // 62 s at 129 fps
constexpr std::int64_t kMaxBytes = std::int64_t(512) << 20;  // a source's JPEGs
constexpr double kHoldAtEndS = 1.5;  // a replay's last frame held before it starts again

// Stream time t was sent at t + this: the 95th percentile of the frames' lateness (measured
// once per frame as it comes, read by every tick).
double SentOffset(const std::deque<double>& lateness, double max_lateness) {
  if (lateness.size() < 20) return max_lateness;
  std::vector<double> v(lateness.begin(), lateness.end());
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(0.95 * double(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

QString Q(const std::string& s) {
  return QString::fromStdString(s);
}

QByteArray Jpeg(const QImage& image) {
  QByteArray bytes;
  QBuffer out(&bytes);
  out.open(QIODevice::WriteOnly);
  image.save(&out, "JPG", 90);
  return bytes;
}

// The numbers' box a coach reads on the hall's screen: three lines, top left of the picture.
void DrawNumbersBox(QPainter& p,
                    double scale,
                    double width,
                    double top_px,
                    const std::string& top,
                    const std::string& middle,
                    const std::string& bottom) {
  QFont font = p.font();
  font.setPixelSize(static_cast<int>(13 * scale));
  font.setBold(true);
  p.setFont(font);
  const QRectF box(8 * scale, top_px, width * scale, 62 * scale);
  p.setPen(Qt::NoPen);
  p.setBrush(QColor(0, 0, 0, 160));
  p.drawRoundedRect(box, 4 * scale, 4 * scale);
  p.setPen(QColor(255, 255, 255));
  p.drawText(box.adjusted(8 * scale, 4 * scale, 0, 0), Qt::AlignLeft | Qt::AlignTop, Q(top));
  p.setPen(QColor(255, 210, 0));
  p.drawText(box.adjusted(8 * scale, 22 * scale, 0, 0), Qt::AlignLeft | Qt::AlignTop, Q(middle));
  p.setPen(QColor(200, 230, 255));
  p.drawText(box.adjusted(8 * scale, 40 * scale, 0, 0), Qt::AlignLeft | Qt::AlignTop, Q(bottom));
}

}  // namespace

QByteArray LiveWindow::Compress(const capture::VideoFrame& picture) {
  return Jpeg(QImage(picture.pixels.data(),
                     picture.width,
                     picture.height,
                     picture.width * picture.channels,
                     picture.channels == 3 ? QImage::Format_RGB888 : QImage::Format_Grayscale8));
}

QImage LiveWindow::Decompress(const QByteArray& jpeg) {
  QImage image;
  image.loadFromData(jpeg, "JPG");
  return image.convertToFormat(QImage::Format_RGB32);
}

namespace {

std::string RoutineKey(const std::string& source, int number) {
  return source + " " + std::to_string(number);
}

// The profile each athlete of the library was last stored with, where it still is (read only; a
// library that is not there yet, locked or unreadable offers none).
std::vector<std::filesystem::path> LibraryProfiles(const std::filesystem::path& path) {
  std::vector<std::filesystem::path> out;
  if (path.empty() || !std::filesystem::exists(path)) return out;
  try {
    const library::Library lib(path, library::Library::Mode::kReadOnly, 2000);
    for (const library::AthleteSummary& a : lib.ListAthletes())
      for (const library::TrialSummary& t : lib.ListTrials(a.name))  // newest first
        if (!t.athlete_profile_path.empty() && std::filesystem::exists(t.athlete_profile_path)) {
          out.push_back(t.athlete_profile_path);
          break;
        }
  } catch (const std::exception&) {
  }
  return out;
}

}  // namespace

LiveWindow::LiveWindow(pipeline::LiveRequest request,
                       double delay_s,
                       std::optional<pipeline::RoutineAnalysisOptions> analyses,
                       QWidget* parent)
    : QWidget(parent, Qt::Window), request_(std::move(request)) {
  setWindowTitle("Acrolab — live: " + Q(request_.out_dir.string()));
  buffers_.resize(request_.sources.size());
  shown_.resize(request_.sources.size());
  for (size_t k = 0; k < buffers_.size(); ++k)
    buffers_[k].name = capture::LiveSourceName(request_.sources[k]);

  auto* split = new QSplitter(Qt::Horizontal);
  split->addWidget(MakeSources());
  split->addWidget(MakeReplayPane());
  split->setStretchFactor(0, 1);
  split->setStretchFactor(1, 1);
  line_list_ = new QListWidget;
  line_list_->setMaximumHeight(130);
  status_ = new QLabel("starting…");
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(MakeControls(analyses.has_value()));
  layout->addWidget(split, 1);
  layout->addWidget(line_list_);
  layout->addWidget(status_);
  resize(1600, 900);
  StartSession(std::move(analyses));
  SetDelay(std::clamp(delay_s, 0.0, kMaxDelayS));
  timer_ = new QTimer(this);
  connect(timer_, &QTimer::timeout, this, [this] { Tick(); });
  timer_->start(10);
}

// The controls: the delay, the speed, a frame either way, back to live, stop; who is jumping.
QHBoxLayout* LiveWindow::MakeControls(bool choose_athlete) {
  auto* controls = new QHBoxLayout;
  controls->addWidget(new QLabel("Delay"));
  delay_slider_ = new QSlider(Qt::Horizontal);
  delay_slider_->setRange(0, static_cast<int>(kMaxDelayS * 10));  // tenths of a second
  delay_slider_->setMinimumWidth(240);
  delay_slider_->setToolTip("How long after the cameras sent it the picture is shown (0–60 s)");
  controls->addWidget(delay_slider_, 1);
  delay_label_ = new QLabel;
  delay_label_->setMinimumWidth(150);
  controls->addWidget(delay_label_);
  speed_box_ = new QComboBox;
  for (const char* s : {"1×", "½×", "¼×", "⅛×"}) speed_box_->addItem(s);
  speed_box_->setToolTip("Slow motion inside the delay: the picture falls further behind");
  controls->addWidget(speed_box_);
  auto* back = new QPushButton("◀ frame");
  pause_button_ = new QPushButton("Pause");
  auto* forward = new QPushButton("frame ▶");
  auto* live = new QPushButton("Back to delay");
  live->setToolTip("The slider's delay at normal speed (L)");
  for (QPushButton* b : {back, pause_button_, forward, live}) controls->addWidget(b);
  auto* stop = new QPushButton("Stop session");
  controls->addWidget(stop);
  if (choose_athlete) {
    // Who is jumping: each routine cut is analysed for them and stored under their name.
    controls->addWidget(new QLabel("Athlete"));
    athlete_box_ = new QComboBox;
    athlete_box_->setMinimumWidth(220);
    athlete_box_->setToolTip(
        "Each routine cut from now on is analysed for this athlete (and stored under them in the "
        "library)");
    controls->addWidget(athlete_box_);
  }
  connect(delay_slider_, &QSlider::valueChanged, this, [this](int tenths) {
    if (std::abs(tenths / 10.0 - delay_s_) > 1e-9) SetDelay(tenths / 10.0);
  });
  connect(speed_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int i) {
    SetSpeed(1.0 / (1 << i));
  });
  connect(back, &QPushButton::clicked, this, [this] { StepFrame(-1); });
  connect(forward, &QPushButton::clicked, this, [this] { StepFrame(1); });
  connect(pause_button_, &QPushButton::clicked, this, [this] {
    SetSpeed(rate_ > 0 ? 0.0 : 1.0 / (1 << std::max(0, speed_box_->currentIndex())));
  });
  connect(live, &QPushButton::clicked, this, [this] { BackToLive(); });
  connect(stop, &QPushButton::clicked, this, [this] { Stop(); });
  const auto key = [this](QKeySequence k, std::function<void()> f) {
    connect(new QShortcut(k, this), &QShortcut::activated, this, std::move(f));
  };
  key(Qt::Key_Left, [this] { StepFrame(-1); });
  key(Qt::Key_Right, [this] { StepFrame(1); });
  key(Qt::Key_Space, [this] { pause_button_->click(); });
  key(Qt::Key_L, [this] { BackToLive(); });
  return controls;
}

// The sources, each late by the delay, two a row.
QWidget* LiveWindow::MakeSources() {
  auto* sources = new QWidget;
  auto* grid = new QGridLayout(sources);
  grid->setContentsMargins(0, 0, 0, 0);
  for (size_t k = 0; k < buffers_.size(); ++k) {
    auto* label = new QLabel(Q(buffers_[k].name));
    auto* view = new ImageView("waiting for " + Q(buffers_[k].name) + "…");
    const int row = static_cast<int>(k / 2) * 2, column = static_cast<int>(k % 2);
    grid->addWidget(label, row, column);
    grid->addWidget(view, row + 1, column);
    grid->setRowStretch(row + 1, 1);
    views_.push_back(view);
    view_labels_.push_back(label);
  }
  return sources;
}

// The last routine's replay, its speed and report, and its table.
QWidget* LiveWindow::MakeReplayPane() {
  auto* replay = new QWidget;
  auto* replay_layout = new QVBoxLayout(replay);
  replay_layout->setContentsMargins(0, 0, 0, 0);
  auto* replay_top = new QHBoxLayout;
  replay_label_ = new QLabel("Replay: the last routine, as soon as it ends");
  replay_top->addWidget(replay_label_, 1);
  replay_speed_box_ = new QComboBox;
  for (const char* s : {"1×", "½×", "¼×"}) replay_speed_box_->addItem(s);
  replay_speed_box_->setToolTip("The replay's speed");
  replay_top->addWidget(replay_speed_box_);
  report_button_ = new QPushButton("Open its report");
  report_button_->setEnabled(false);
  report_button_->setToolTip("The routine's full analysis, once it is done (its report page)");
  replay_top->addWidget(report_button_);
  replay_layout->addLayout(replay_top);
  replay_view_ = new ImageView("no routine yet");
  replay_layout->addWidget(replay_view_, 2);
  routine_table_ = new QTableWidget(0, 5);
  routine_table_->setHorizontalHeaderLabels(
      {"Jump", "Take-off (s)", "Time of flight (s)", "Landing (m)", "Zone"});
  routine_table_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
  routine_table_->verticalHeader()->hide();
  routine_table_->verticalHeader()->setDefaultSectionSize(22);
  routine_table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  replay_layout->addWidget(routine_table_, 1);
  connect(replay_speed_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int i) {
    replay_rate_ = 1.0 / (1 << i);
  });
  connect(report_button_, &QPushButton::clicked, this, [this] {
    const std::filesystem::path report = replay_report();
    if (!report.empty())
      QDesktopServices::openUrl(QUrl::fromLocalFile(QString::fromStdString(report.string())));
  });
  return replay;
}

// The session: the pipeline's, on a thread of its own, its callbacks queued to this window's
// thread (the frames go into the buffer directly, under its lock); each routine analysed.
void LiveWindow::StartSession(std::optional<pipeline::RoutineAnalysisOptions> analyses) {
  request_.on_frame = [this](const pipeline::LiveFrameSeen& seen) { OnFrame(seen); };
  request_.on_line = [this](const std::string& line) {
    QMetaObject::invokeMethod(
        this, [this, line] { AddLine(line); }, Qt::QueuedConnection);
  };
  if (analyses) {
    analyses->on_line = request_.on_line;
    analyses->on_analysed = [this](const pipeline::LiveRoutine& r,
                                   const std::filesystem::path& report) {
      QMetaObject::invokeMethod(
          this, [this, r, report] { OnAnalysed(r, report); }, Qt::QueuedConnection);
    };
    analyses_.emplace(*analyses);
    FillAthleteList(*analyses);
  }
  request_.on_routine = [this](const pipeline::LiveRoutine& r) {
    if (analyses_) analyses_->Add(r, athlete());
    QMetaObject::invokeMethod(
        this, [this, r] { OnRoutine(r); }, Qt::QueuedConnection);
  };
  thread_ = std::thread([this] {
    try {
      pipeline::LiveSummary s = pipeline::RunLive(request_, &stop_);
      QMetaObject::invokeMethod(
          this,
          [this, s] {
            summary_ = s;
            status_->setText(Q(fmt::format("session ended: {} jumps, {} routines, in {}",
                                           s.jumps.size(),
                                           s.routines.size(),
                                           request_.out_dir.string())));
          },
          Qt::QueuedConnection);
    } catch (const std::exception& e) {
      const std::string line = e.what();
      QMetaObject::invokeMethod(
          this, [this, line] { ShowError(line); }, Qt::QueuedConnection);
    }
    finished_ = true;
  });
}

// The athletes offered: the profile given, the others beside it, the library's athletes; then
// none, and any other file.
void LiveWindow::FillAthleteList(const pipeline::RoutineAnalysisOptions& analyses) {
  std::vector<std::filesystem::path> profiles;
  if (!analyses.athlete.empty()) {
    profiles.push_back(analyses.athlete);
    std::error_code ec;
    std::vector<std::filesystem::path> beside;
    for (const auto& e : std::filesystem::directory_iterator(
             std::filesystem::absolute(analyses.athlete).parent_path(), ec)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file(ec) && (ext == ".yaml" || ext == ".yml")) beside.push_back(e.path());
    }
    std::sort(beside.begin(), beside.end());
    profiles.insert(profiles.end(), beside.begin(), beside.end());
  }
  for (const std::filesystem::path& p : LibraryProfiles(analyses.library)) profiles.push_back(p);
  for (const std::filesystem::path& p : profiles) AddAthleteChoice(p);
  athlete_box_->addItem("No athlete (a default body, not stored)");
  athlete_box_->addItem("Another profile…");
  athlete_box_->setCurrentIndex(analyses.athlete.empty() ? athlete_box_->count() - 2 : 0);
  athlete_ = analyses.athlete;
  connect(athlete_box_, QOverload<int>::of(&QComboBox::activated), this, [this](int i) {
    if (i < static_cast<int>(athlete_paths_.size())) {
      SetAthlete(athlete_paths_[size_t(i)]);
    } else if (i == athlete_box_->count() - 2) {
      SetAthlete({});
    } else {
      const QString file = QFileDialog::getOpenFileName(
          this, "The athlete's profile", QString(), "Athlete profiles (*.yaml *.yml)");
      if (!file.isEmpty()) {
        SetAthlete(file.toStdString());
      } else {
        SetAthlete(athlete());  // back to the one chosen
      }
    }
  });
}

LiveWindow::~LiveWindow() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  // The routine being analysed finishes (its folder whole); those waiting are left for
  // `acrolab analyze` (their clips are written).
  if (analyses_) {
    const int dropped = analyses_->DropWaiting();
    if (dropped > 0)
      std::fprintf(stderr,
                   "acrolab-studio: %d routine%s of %s left unanalysed (their clips are there: "
                   "acrolab analyze --video clip.ts --detect-bed)\n",
                   dropped,
                   dropped == 1 ? "" : "s",
                   request_.out_dir.string().c_str());
  }
  closing_ = true;  // (the readers of analyses stop while the running analysis finishes)
  analyses_.reset();
  for (Loader& l : loaders_) l.thread.join();
}

void LiveWindow::closeEvent(QCloseEvent* event) {
  Stop();
  event->accept();
}

void LiveWindow::AddAthleteChoice(const std::filesystem::path& profile) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(profile, ec);
  for (const std::filesystem::path& p : athlete_paths_)
    if (std::filesystem::weakly_canonical(p, ec) == canonical) return;
  std::string name = profile.stem().string();
  try {
    name = analysis::ReadAthleteProfile(profile).name;
  } catch (const std::exception&) {
    // (its file's name: the analysis will say what is wrong with it)
  }
  athlete_box_->insertItem(static_cast<int>(athlete_paths_.size()),
                           Q(fmt::format("{} ({})", name, profile.filename().string())));
  athlete_paths_.push_back(profile);
}

void LiveWindow::SetAthlete(const std::filesystem::path& profile) {
  {
    const std::lock_guard<std::mutex> lock(athlete_mutex_);
    athlete_ = profile;
  }
  if (athlete_box_ == nullptr) return;
  if (profile.empty()) {
    athlete_box_->setCurrentIndex(athlete_box_->count() - 2);
    AddLine("the next routines: no athlete (a default body, not stored in a library)");
    return;
  }
  AddAthleteChoice(profile);
  std::error_code ec;
  for (size_t i = 0; i < athlete_paths_.size(); ++i)
    if (std::filesystem::weakly_canonical(athlete_paths_[i], ec) ==
        std::filesystem::weakly_canonical(profile, ec)) {
      athlete_box_->setCurrentIndex(static_cast<int>(i));
      AddLine("the next routines: " + athlete_box_->itemText(static_cast<int>(i)).toStdString());
    }
}

std::filesystem::path LiveWindow::athlete() const {
  const std::lock_guard<std::mutex> lock(athlete_mutex_);
  return athlete_;
}

QStringList LiveWindow::athlete_choices() const {
  QStringList out;
  if (athlete_box_ != nullptr)
    for (int i = 0; i < athlete_box_->count(); ++i) out << athlete_box_->itemText(i);
  return out;
}

void LiveWindow::Stop() {
  stop_ = true;
  status_->setText("stopping: the open routine cut, the recordings closed…");
}

void LiveWindow::OnFrame(const pipeline::LiveFrameSeen& seen) {
  Buffered f;
  f.index = seen.picture->index;
  f.time_s = seen.picture->time_s;
  f.arrival_s = seen.arrival_s;
  f.jpeg = Compress(*seen.picture);  // outside the lock: the window's reads never wait for it
  f.in_air = seen.in_air;
  const std::lock_guard<std::mutex> lock(mutex_);
  Buffer& b = buffers_.at(static_cast<size_t>(seen.source_index));
  b.name = *seen.source;
  b.picture_per_full_px = seen.picture_per_full_px;
  if (seen.rest_line != nullptr)
    b.rest_line = std::array<double, 2>{seen.rest_line->y0_px * seen.picture_per_full_px,
                                        seen.rest_line->slope};
  const double late = f.arrival_s - f.time_s;
  b.max_lateness = std::max(b.max_lateness, late);
  // The frames FFmpeg read to learn the stream come out together: their lateness is not the
  // stream's.
  if (f.index >= 30) {
    b.lateness.push_back(late);
    if (b.lateness.size() > 256) b.lateness.pop_front();
  }
  b.sent_offset = SentOffset(b.lateness, b.max_lateness);
  // Times that went back (a sender that restarted its clock): what would follow this frame goes.
  while (!b.frames.empty() && b.frames.back().time_s >= f.time_s) {
    b.bytes -= b.frames.back().jpeg.size();
    b.frames.pop_back();
  }
  b.bytes += f.jpeg.size();
  b.frames.push_back(std::move(f));
  // Where the watcher saw the athlete: in this frame, and in those that waited for its
  // background (already in the buffer).
  if (seen.athlete != nullptr)
    for (const vision::MotionSighting& a : *seen.athlete) {
      if (!a.found) continue;
      const auto it = std::lower_bound(
          b.frames.begin(), b.frames.end(), a.time_s - 1e-6, [](const Buffered& g, double x) {
            return g.time_s < x;
          });
      if (it == b.frames.end() || std::abs(it->time_s - a.time_s) > 1e-6) continue;
      it->found = true;
      it->sole_x = a.sole_px.x() * seen.picture_per_full_px;
      it->sole_y = a.sole_px.y() * seen.picture_per_full_px;
    }
  while (b.frames.size() > 1 && (b.frames.size() > kMaxFrames || b.bytes > kMaxBytes ||
                                 b.frames.back().time_s - b.frames.front().time_s > kKeepS)) {
    b.bytes -= b.frames.front().jpeg.size();
    b.frames.pop_front();
  }
}

double LiveWindow::sent_offset(int source) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return buffers_.at(static_cast<size_t>(source)).sent_offset;
}

LiveWindow::Shown LiveWindow::shown(int source) const {
  return shown_.at(size_t(source));
}

QImage LiveWindow::shown_image(int source) const {
  return views_.at(size_t(source))->image();
}

double LiveWindow::shown_delay() const {
  return std::isfinite(view_s_) ? capture::LiveClockNow() - view_s_ : delay_s_;
}

void LiveWindow::SetDelay(double seconds) {
  delay_s_ = std::clamp(seconds, 0.0, kMaxDelayS);
  const QSignalBlocker block(delay_slider_);
  delay_slider_->setValue(static_cast<int>(std::lround(delay_s_ * 10)));
  BackToLive();
}

void LiveWindow::BackToLive() {
  rate_ = 1.0;
  speed_box_->setCurrentIndex(0);
  pause_button_->setText("Pause");
  view_s_ = capture::LiveClockNow() - delay_s_;
  last_tick_s_ = capture::LiveClockNow();
  Tick();
}

void LiveWindow::SetSpeed(double rate) {
  const bool was_paused = rate_ == 0;
  rate_ = std::clamp(rate, 0.0, 1.0);
  pause_button_->setText(rate_ > 0 ? "Pause" : "Play");
  if (rate_ > 0) speed_box_->setCurrentIndex(std::clamp(int(std::lround(-std::log2(rate_))), 0, 3));
  if (rate_ == 0 && !was_paused) {
    const std::lock_guard<std::mutex> lock(mutex_);
    paused_offset_.clear();
    for (const Buffer& b : buffers_) paused_offset_.push_back(b.sent_offset);
  }
}

void LiveWindow::StepFrame(int direction) {
  SetSpeed(0.0);
  if (buffers_.empty()) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  const Buffer& b = buffers_[0];
  if (b.frames.empty() || paused_offset_.empty()) return;
  if (!std::isfinite(view_s_)) return;
  const double offset = paused_offset_[0];
  // The frame the view's clock selects now (as ShowSource picks it: the last sent by then) — not
  // the one on screen, which the next tick updates: two steps before it are two frames.
  const auto it = std::upper_bound(
      b.frames.begin(), b.frames.end(), view_s_ - offset, [](double x, const Buffered& g) {
        return x < g.time_s;
      });
  const std::ptrdiff_t last = static_cast<std::ptrdiff_t>(b.frames.size()) - 1;
  // (−1: the clock before the oldest frame kept; a step forward shows that frame)
  const std::ptrdiff_t at = (it - b.frames.begin()) - 1;
  const std::ptrdiff_t k = std::clamp<std::ptrdiff_t>(at + direction, 0, last);
  // Halfway to the next frame: the frame stays up whatever the clock's rounding.
  const double next =
      k < last ? b.frames[size_t(k + 1)].time_s : b.frames[size_t(k)].time_s + 1.0 / 30;
  view_s_ = (b.frames[size_t(k)].time_s + next) / 2 + offset;
}

void LiveWindow::Tick() {
  const double now = capture::LiveClockNow();
  const double dt = std::max(0.0, now - last_tick_s_);
  last_tick_s_ = now;
  if (!std::isfinite(view_s_)) view_s_ = now - delay_s_;
  view_s_ += rate_ * dt;
  // Never later than the slider's delay, never older than the buffer (a pause held for a minute
  // moves on with the buffer's end: said).
  const bool at_end = view_s_ < now - kMaxDelayS;
  view_s_ = std::clamp(view_s_, now - kMaxDelayS, now - delay_s_);
  for (int k = 0; k < source_count(); ++k) ShowSource(k, view_s_, now);
  const double behind = now - view_s_;
  delay_label_->setText(
      Q(fmt::format("{:.1f} s late{}",
                    behind,
                    rate_ == 0  ? (at_end ? ", paused at the buffer's end" : ", paused")
                    : rate_ < 1 ? fmt::format(", {:g}×", rate_)
                                : "")));
  AdvanceReplay(dt);
}

void LiveWindow::ShowSource(int k, double view_s, double now) {
  Buffered f;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const Buffer& b = buffers_[size_t(k)];
    if (b.frames.empty()) return;
    const double offset =
        rate_ == 0 && size_t(k) < paused_offset_.size() ? paused_offset_[size_t(k)] : b.sent_offset;
    // The last frame sent by then (stream time + offset ≤ the clock shown).
    const auto it = std::upper_bound(
        b.frames.begin(), b.frames.end(), view_s - offset, [](double x, const Buffered& g) {
          return x < g.time_s;
        });
    if (it == b.frames.begin()) return;  // not yet that far back
    f = *std::prev(it);
    view_labels_[size_t(k)]->setText(Q(b.name));
  }
  Shown& s = shown_[size_t(k)];
  if (f.time_s == s.time_s && f.index == s.index) return;
  views_[size_t(k)]->SetImage(Decompress(f.jpeg));
  s = {f.index, f.time_s, now};
}

void LiveWindow::AddLine(const std::string& line) {
  lines_.push_back(Q(line));
  line_list_->addItem(Q(line));
  line_list_->scrollToBottom();
  status_->setText(Q(line));
}

void LiveWindow::ShowError(const std::string& line) {
  last_error_ = line;
  AddLine(line);
  auto* box =
      new QMessageBox(QMessageBox::Critical, "Acrolab live", Q(line), QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

void LiveWindow::OnRoutine(const pipeline::LiveRoutine& routine) {
  Replay r;
  r.routine = routine;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto b = std::find_if(buffers_.begin(), buffers_.end(), [&](const Buffer& x) {
      return x.name == routine.source;
    });
    if (b == buffers_.end()) return;
    const double from = routine.first_takeoff_s - request_.pre_roll_s;
    const double to = routine.last_landing_s + request_.post_roll_s;
    for (const Buffered& f : b->frames)
      if (f.time_s >= from && f.time_s <= to)
        r.frames.push_back(f);  // the JPEGs shared, not copied
    r.rest_line = b->rest_line;
    r.picture_per_full_px = b->picture_per_full_px;
  }
  if (r.frames.empty()) return;  // older than the buffer
  picture_width_ = Decompress(r.frames.front().jpeg).width();
  if (analysed_last_ && analysed_key_ == RoutineKey(routine.source, routine.number))
    r.analysed = analysed_last_;
  r.t_s = (r.analysed ? r.analysed->frames : r.frames).front().time_s;
  replay_ = std::move(r);
  ReplayLabel();
  FillRoutineTable();
  report_button_->setEnabled(!replay_report().empty());
  AdvanceReplay(0.0);
}

void LiveWindow::ReplayLabel() {
  const pipeline::LiveRoutine& routine = replay_->routine;
  replay_label_->setText(
      Q(fmt::format("Replay: {} routine {}{} — {} jumps{}",
                    routine.source,
                    routine.number,
                    routine.interrupted ? " (interrupted)" : "",
                    routine.jumps.size(),
                    replay_->analysed ? " — its full analysis" : " — from the image motion")));
}

void LiveWindow::FillRoutineTable() {
  const auto cell = [&](int row, int column, const std::string& text) {
    auto* item = new QTableWidgetItem(Q(text));
    item->setToolTip(Q(text));
    routine_table_->setItem(row, column, item);
  };
  routine_table_->clearSpans();
  routine_table_->clearContents();
  if (replay_->analysed) {
    // The full analysis: each element's skill, difficulty, time of flight, landing and the faults
    // measured; the score sheet's numbers below.
    const Analysed& a = *replay_->analysed;
    routine_table_->setColumnCount(6);
    routine_table_->setHorizontalHeaderLabels(
        {"Jump", "Skill", "DD", "Time of flight (s)", "Landing", "Faults"});
    routine_table_->setRowCount(static_cast<int>(a.jumps.size()) + 1);
    double sum = 0;
    for (size_t k = 0; k < a.jumps.size(); ++k) {
      const Analysed::Jump& j = a.jumps[k];
      sum += j.time_of_flight_s;
      const int row = static_cast<int>(k);
      cell(row, 0, std::to_string(k + 1));
      cell(row, 1, j.code + " " + j.name);
      cell(row, 2, fmt::format("{:.1f}", j.difficulty));
      cell(row, 3, fmt::format("{:.3f}", j.time_of_flight_s));
      cell(row, 4, j.zone);
      std::string faults;
      for (const std::string& f : j.faults) faults += (faults.empty() ? "" : ", ") + f;
      cell(row, 5, faults);
    }
    const int last = static_cast<int>(a.jumps.size());
    cell(last, 0, "all");
    cell(last, 1, a.score.empty() ? fmt::format("time of flight {:.3f} s", sum) : a.score);
    routine_table_->setSpan(last, 1, 1, 5);
    return;
  }
  routine_table_->setColumnCount(5);
  routine_table_->setHorizontalHeaderLabels(
      {"Jump", "Take-off (s)", "Time of flight (s)", "Landing (m)", "Zone"});
  const std::vector<pipeline::LiveJump>& jumps = replay_->routine.jumps;
  routine_table_->setRowCount(static_cast<int>(jumps.size()) + 1);
  double sum = 0;
  for (size_t k = 0; k < jumps.size(); ++k) {
    const pipeline::LiveJump& j = jumps[k];
    const int row = static_cast<int>(k);
    sum += j.jump.time_of_flight_s();
    cell(row, 0, std::to_string(k + 1));
    cell(row, 1, fmt::format("{:.3f}", j.jump.takeoff_s));
    cell(row, 2, fmt::format("{:.3f}", j.jump.time_of_flight_s()));
    cell(row,
         3,
         std::isfinite(j.landing_along_bed_m) ? fmt::format("{:+.2f}", j.landing_along_bed_m) : "");
    cell(row, 4, j.zone);
  }
  const int last = static_cast<int>(jumps.size());
  cell(last, 0, "all");
  cell(last, 2, fmt::format("{:.3f} (T {:.3f})", sum, fig::TruncateTimeOfFlight(sum, 0.005)));
}

std::vector<std::vector<std::string>> LiveWindow::replay_table() const {
  std::vector<std::vector<std::string>> rows;
  for (int r = 0; r < routine_table_->rowCount(); ++r) {
    rows.emplace_back();
    for (int c = 0; c < routine_table_->columnCount(); ++c) {
      const QTableWidgetItem* item = routine_table_->item(r, c);
      rows.back().push_back(item != nullptr ? item->text().toStdString() : "");
    }
  }
  return rows;
}

void LiveWindow::OnAnalysed(const pipeline::LiveRoutine& routine,
                            const std::filesystem::path& report) {
  const std::string key = RoutineKey(routine.source, routine.number);
  reports_[key] = report;
  report_button_->setEnabled(!replay_report().empty());
  // Its overlay video and score sheet read for the replay on a thread of their own (a second or
  // two for a routine: the picture goes on meanwhile).
  const double clip_start = routine.clip_start_s;
  const int width = picture_width_;
  // (the readers that have finished joined first: one thread a routine, not one a session)
  loaders_.erase(std::remove_if(loaders_.begin(),
                                loaders_.end(),
                                [](Loader& l) {
                                  if (!l.done->load()) return false;
                                  l.thread.join();
                                  return true;
                                }),
                 loaders_.end());
  auto done = std::make_shared<std::atomic<bool>>(false);
  std::thread reader([this, key, report, clip_start, width, done] {
    try {
      std::shared_ptr<const Analysed> a = LoadAnalysed(report, clip_start, width, closing_);
      if (a != nullptr)
        QMetaObject::invokeMethod(
            this, [this, key, a] { ShowAnalysed(key, a); }, Qt::QueuedConnection);
    } catch (const std::exception& e) {
      const std::string line =
          fmt::format("routine {}: its analysis cannot be replayed: {}", key, e.what());
      QMetaObject::invokeMethod(
          this, [this, line] { AddLine(line); }, Qt::QueuedConnection);
    }
    done->store(true);
  });
  loaders_.push_back({std::move(reader), done});
}

void LiveWindow::ShowAnalysed(const std::string& key, std::shared_ptr<const Analysed> analysed) {
  analysed_key_ = key;
  analysed_last_ = analysed;
  if (!replay_ || RoutineKey(replay_->routine.source, replay_->routine.number) != key) return;
  // The replay goes on from where it was, in the analysis's video.
  replay_->analysed = std::move(analysed);
  replay_->shown = -1;
  const std::vector<Buffered>& frames = replay_->analysed->frames;
  replay_->t_s = std::clamp(replay_->t_s, frames.front().time_s, frames.back().time_s);
  ReplayLabel();
  FillRoutineTable();
  AdvanceReplay(0.0);
}

std::shared_ptr<const LiveWindow::Analysed> LiveWindow::LoadAnalysed(
    const std::filesystem::path& report,
    double clip_start_s,
    int width,
    const std::atomic<bool>& stop) {
  const std::filesystem::path dir = report.parent_path();
  auto a = std::make_shared<Analysed>();
  const std::filesystem::path jumps_file = dir / "jumps.json";
  const std::vector<std::uint8_t> jumps_bytes = ReadFileBytes(jumps_file, std::int64_t(64) << 20);
  for (const library::JumpRecord& j : library::ParseJumpsJson(
           std::string(jumps_bytes.begin(), jumps_bytes.end()), jumps_file.string())) {
    if (j.partial) continue;
    Analysed::Jump out;
    out.takeoff_s = clip_start_s + j.takeoff_s;
    out.time_of_flight_s = j.time_of_flight_s;
    out.landing_s = out.takeoff_s + j.time_of_flight_s;
    out.difficulty = j.difficulty;
    out.code = j.fig_code;
    out.name = j.skill_name;
    out.element = j.element;
    if (j.landing_in_zone_a) out.zone = *j.landing_in_zone_a ? "zone A" : "outside A";
    for (std::string fault : j.faults) {  // "legs_apart": "legs apart"
      std::replace(fault.begin(), fault.end(), '_', ' ');
      out.faults.push_back(fault);
    }
    a->jumps.push_back(std::move(out));
  }
  const std::filesystem::path score_file = dir / "score.json";
  if (std::filesystem::exists(score_file)) {
    const std::vector<std::uint8_t> bytes = ReadFileBytes(score_file, std::int64_t(64) << 20);
    const nlohmann::json score =
        nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, /*allow_exceptions=*/false);
    const auto number = [&](const char* key) {
      return score.is_object() && score.contains(key) && score[key].is_number()
                 ? score[key].get<double>()
                 : kNaN;
    };
    const double D = number("D"), T = number("T"), H = number("H"),
                 E = number("execution_deductions_suggested");
    if (std::isfinite(D) && std::isfinite(T))
      a->score = fmt::format("D {:.1f} · T {:.3f}{}{}",
                             D,
                             T,
                             std::isfinite(H) ? fmt::format(" · H {:.2f}", H) : "",
                             std::isfinite(E) ? fmt::format(" · faults measured −{:.1f}", E) : "");
  }
  capture::VideoReader video(dir / "overlay.mp4");
  if (video.num_frames() < 1)
    throw InputError((dir / "overlay.mp4").string(), "", "holds no frame");
  capture::VideoFrame f = video.Frame(0);
  do {
    if (stop.load()) return nullptr;
    const QImage image(f.pixels.data(), f.width, f.height, f.width * 3, QImage::Format_RGB888);
    Buffered b;
    b.index = f.index;
    b.time_s = clip_start_s + f.time_s;
    b.jpeg =
        Jpeg(image.width() > width ? image.scaledToWidth(width, Qt::SmoothTransformation) : image);
    a->frames.push_back(std::move(b));
  } while (video.ReadNext(&f));
  return a;
}

std::filesystem::path LiveWindow::replay_report() const {
  if (!replay_) return {};
  const auto it = reports_.find(RoutineKey(replay_->routine.source, replay_->routine.number));
  return it == reports_.end() ? std::filesystem::path() : it->second;
}

double LiveWindow::replay_time_s() const {
  return replay_ ? replay_->t_s : kNaN;
}

QImage LiveWindow::replay_image() const {
  return replay_view_->image();
}

void LiveWindow::AdvanceReplay(double dt) {
  if (!replay_) return;
  Replay& r = *replay_;
  const std::vector<Buffered>& frames = r.analysed ? r.analysed->frames : r.frames;
  const double end = frames.back().time_s;
  if (r.t_s >= end) {
    r.held_s += dt;
    if (r.held_s > kHoldAtEndS) {
      r.held_s = 0;
      r.t_s = frames.front().time_s;
    }
  } else {
    r.t_s = std::min(end, r.t_s + replay_rate_ * dt);
  }
  const auto it =
      std::upper_bound(frames.begin(), frames.end(), r.t_s, [](double x, const Buffered& g) {
        return x < g.time_s;
      });
  const int k = static_cast<int>(std::max<std::ptrdiff_t>(0, (it - frames.begin()) - 1));
  if (k == r.shown) return;
  r.shown = k;
  r.image = r.analysed ? DrawAnalysedFrame(r, static_cast<size_t>(k))
                       : DrawReplayFrame(r, static_cast<size_t>(k));
  replay_view_->SetImage(r.image);
}

// The frame with what the image motion measured over it: the bed's rest line, the soles' path
// through the flight so far, every landing so far with its number, and the running numbers.
QImage LiveWindow::DrawReplayFrame(const Replay& r, size_t k) const {
  QImage image = Decompress(r.frames[k].jpeg);
  const double t = r.frames[k].time_s;
  QPainter p(&image);
  p.setRenderHint(QPainter::Antialiasing);
  const double scale = image.width() / 640.0;  // sizes chosen for a 640-px picture
  if (r.rest_line) {
    QPen pen(QColor(255, 255, 255, 200), 1.5 * scale, Qt::DashLine);
    p.setPen(pen);
    const double y0 = (*r.rest_line)[0], slope = (*r.rest_line)[1];
    p.drawLine(QPointF(0, y0), QPointF(image.width(), y0 + slope * image.width()));
  }
  const std::vector<pipeline::LiveJump>& jumps = r.routine.jumps;
  // The jump in the air now, or the last one landed.
  const pipeline::LiveJump* current = nullptr;
  int landed = 0;
  double sum = 0;
  for (const pipeline::LiveJump& j : jumps) {
    if (j.jump.landing_s <= t) {
      ++landed;
      sum += j.jump.time_of_flight_s();
    }
    if (j.jump.takeoff_s <= t) current = &j;
  }
  if (current != nullptr && t < current->jump.landing_s) {
    // The soles' path since the take-off.
    p.setPen(Qt::NoPen);
    p.setBrush(QColor(255, 210, 0));
    for (size_t i = 0; i <= k; ++i) {
      const Buffered& f = r.frames[i];
      if (f.time_s >= current->jump.takeoff_s && f.found)
        p.drawEllipse(QPointF(f.sole_x, f.sole_y), 2.5 * scale, 2.5 * scale);
    }
  }
  QFont font = p.font();
  font.setPixelSize(static_cast<int>(13 * scale));
  font.setBold(true);
  p.setFont(font);
  for (size_t i = 0; i < jumps.size(); ++i) {
    const pipeline::LiveJump& j = jumps[i];
    if (j.jump.landing_s > t) continue;
    const QPointF at(j.jump.landing_px.x() * r.picture_per_full_px,
                     j.jump.landing_px.y() * r.picture_per_full_px);
    const bool latest = static_cast<int>(i) + 1 == landed;
    p.setPen(QPen(latest ? QColor(0, 230, 120) : QColor(0, 160, 255), 2 * scale));
    p.setBrush(Qt::NoBrush);
    p.drawEllipse(at, 6 * scale, 3 * scale);
    p.drawText(at + QPointF((i % 2 == 0 ? -14.0 : 8.0) * scale, -6 * scale),
               QString::number(i + 1));
  }
  // The numbers: what a coach reads on the hall's screen.
  std::string top = fmt::format("{} · routine {}", r.routine.source, r.routine.number);
  std::string middle;
  if (current != nullptr && t < current->jump.landing_s) {
    middle = fmt::format("jump {} of {} · in the air {:.2f} s",
                         current - jumps.data() + 1,
                         jumps.size(),
                         t - current->jump.takeoff_s);
  } else if (landed > 0) {
    const pipeline::LiveJump& j = jumps[size_t(landed - 1)];
    middle = fmt::format("jump {}: {:.3f} s{}",
                         landed,
                         j.jump.time_of_flight_s(),
                         j.zone.empty() ? "" : "  zone " + j.zone);
  } else {
    middle = "before the first take-off";
  }
  const std::string bottom =
      fmt::format("time of flight {:.3f} s over {} jump{}", sum, landed, landed == 1 ? "" : "s");
  DrawNumbersBox(p, scale, 300, 8 * scale, top, middle, bottom);
  return image;
}

// A frame of the analysis's overlay video (the athlete's model over the picture, drawn by
// `analyze`) with the score sheet's numbers: the element in the air or the last one landed.
QImage LiveWindow::DrawAnalysedFrame(const Replay& r, size_t k) const {
  const Analysed& a = *r.analysed;
  QImage image = Decompress(a.frames[k].jpeg);
  const double t = a.frames[k].time_s;
  QPainter p(&image);
  p.setRenderHint(QPainter::Antialiasing);
  const double scale = image.width() / 640.0;
  const Analysed::Jump* current = nullptr;
  int landed = 0;
  for (const Analysed::Jump& j : a.jumps) {
    if (j.landing_s <= t) ++landed;
    if (j.takeoff_s <= t) current = &j;
  }
  std::string middle;
  if (current != nullptr && t < current->landing_s) {
    middle = fmt::format("jump {} of {} · {} {} · DD {:.1f}",
                         current - a.jumps.data() + 1,
                         a.jumps.size(),
                         current->code,
                         current->name,
                         current->difficulty);
  } else if (landed > 0) {
    const Analysed::Jump& j = a.jumps[size_t(landed - 1)];
    middle = fmt::format("jump {}: {} · {:.3f} s{}",
                         landed,
                         j.code,
                         j.time_of_flight_s,
                         j.zone.empty() ? "" : " · " + j.zone);
  } else {
    middle = "before the first take-off";
  }
  // (bottom left: the overlay video has its own line of numbers along its top)
  DrawNumbersBox(p,
                 scale,
                 380,
                 image.height() - 70 * scale,
                 fmt::format("{} · routine {} · full analysis", r.routine.source, r.routine.number),
                 middle,
                 a.score.empty() ? "no score sheet" : a.score);
  return image;
}

}  // namespace acro::studio
