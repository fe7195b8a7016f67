#pragma once

// The workstation window (`acrolab-studio`, docs/studio.md): a free 3D view of the athlete and the
// calibrated camera's video with the athlete drawn over it, both at one cursor; the timeline of
// the whole trial with its jumps; the transport (play and pause, a frame either way, the next or
// previous take-off, ½ to ⅛ speed, a loop over the jump); the jump table. What it shows comes from
// the library (ui/views draws, analysis computes): no analysis here. Opening and analysing run on
// a worker thread with progress and cancel; a bad file is a dialog with its one-line error and
// the session open stays as it was.

#include <QMainWindow>

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "acro/capture/video.h"
#include "acro/scene/designed_skill.h"
#include "acro/studio/session.h"

class QAction;
class QComboBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QTableWidget;
class QTimer;

namespace acro::ui {
class TrialFreeView;
class TrialOverlay;
}  // namespace acro::ui

namespace acro::studio {

class CompareWindow;
class SkillWindow;
class ImageView;
class PlotView;
class Timeline;

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Opens the files on a worker thread (the window stays live; progress in the status bar); the
  /// session open until then stays if it fails. `view` is where to put the cursor and the view.
  void OpenFiles(const SessionFiles& files, const SessionView& view = {});
  void OpenSessionFile(const std::string& path);
  /// Writes the session file; false (and the dialog) when it cannot be written.
  bool SaveSessionFile(const std::string& path);
  bool busy() const { return loader_.joinable() && !loaded_; }
  Session* session() { return session_.get(); }

  int cursor() const { return cursor_; }
  void SetCursor(int sample);
  /// One video frame either way (one trial sample without a video).
  void StepFrame(int direction);
  /// The next (+1) or previous (−1) take-off.
  void StepTakeoff(int direction);
  /// Puts the cursor at jump `index`'s take-off (1-based) and loops that jump when playing.
  void GoToJump(int index);
  void SetPlaying(bool playing, int direction = 1);
  bool playing() const { return playing_; }
  void SetSpeed(double speed);
  SessionView view() const;
  /// Compare mode: jumps `a` and `b` of the trial side by side at the cursor (a window of their
  /// own), and B as a ghost in A's flight over the video and in the 3D view. The cursor goes to
  /// A's take-off. False (and the dialog) for a jump that is not there.
  bool OpenCompare(int a, int b);
  /// The same with jump `b` of another trial (opened and analysed on the worker, without its
  /// video); a bad file is the dialog and nothing changes.
  void OpenCompareWithTrial(int a, SessionFiles other, int b);
  /// The same with a designed skill (`acrolab optimize`'s folder) posed on this athlete.
  bool OpenCompareWithDesign(int a, const std::string& design_dir);
  /// A design (the skill designer's) as the ghost in every flight, over the video and in 3D.
  void ShowDesignGhost(const analysis::DesignedSkill& design);
  CompareWindow* compare() { return compare_.get(); }
  /// The skill designer (File → Open skill…), opened on `path` when given.
  SkillWindow* OpenSkillDesigner(const std::string& path = "");

  Timeline* timeline() { return timeline_; }
  ImageView* video_view() { return video_view_; }
  PlotView* plot() { return plot_; }
  /// Shows figure `index` of the analysis' figures (the report's: COM and feet, residual force and
  /// moment, angular momentum, the joint's angle and torque) for `joint`.
  void ShowPlot(int index, const std::string& joint = "");
  /// The figures offered (their titles), in the plot box's order.
  int plot_count() const;
  std::string plot_title(int index) const;
  QTableWidget* jump_table() { return jumps_; }
  /// The verdict panel: a row per judged flight (residuals, momentum, gravity, what failed); a
  /// click puts the cursor where its largest residual window starts and loops the judged frames.
  QTableWidget* verdict_table() { return verdict_; }
  /// The video frame shown (−1: none), as decoded (before the overlay), and the 3D view's scene
  /// frame: what a test compares with the reader and the scene.
  int video_frame_index() const { return video_frame_index_; }
  const capture::VideoFrame& filmed_frame() const { return filmed_; }
  const analysis::TrialFrame* view_frame() const;
  /// The last error shown in a dialog (empty: none).
  const std::string& last_error() const { return last_error_; }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void BuildMenus();
  /// Opens `files` as a session on the worker thread (progress, Cancel), then `done` on the
  /// window's thread; a failure is the dialog and `done` is not called.
  void OpenInBackground(const SessionFiles& files,
                        std::function<void(std::shared_ptr<Session>)> done);
  bool ShowCompare(int a, const std::function<std::unique_ptr<CompareWindow>()>& make);
  void AskCompare();
  void Adopt(std::shared_ptr<Session> session, const SessionView& view);
  void ShowError(const std::string& message);
  void Redraw();
  void DrawVideo();
  void Tick();
  void FillJumpTable();
  void FillPlots();
  void FillVerdict();
  void JoinLoader();

  std::shared_ptr<Session> session_;
  std::unique_ptr<ui::TrialFreeView> free_view_;
  std::unique_ptr<ui::TrialOverlay> overlay_;
  std::unique_ptr<CompareWindow> compare_;
  std::shared_ptr<Session> compare_other_;  // the other trial a ghost jump comes from
  std::unique_ptr<SkillWindow> designer_;
  ImageView* view3d_ = nullptr;
  ImageView* video_view_ = nullptr;
  Timeline* timeline_ = nullptr;
  QTableWidget* jumps_ = nullptr;
  QTableWidget* verdict_ = nullptr;
  QLabel* findings_ = nullptr;
  PlotView* plot_ = nullptr;
  QComboBox* plot_box_ = nullptr;
  QComboBox* joint_box_ = nullptr;
  QComboBox* speed_box_ = nullptr;
  QComboBox* preset_box_ = nullptr;
  QAction* follow_ = nullptr;
  QAction* loop_ = nullptr;
  QLabel* status_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QPushButton* cancel_ = nullptr;
  QTimer* timer_ = nullptr;

  int cursor_ = 0;
  bool playing_ = false;
  int direction_ = 1;
  double speed_ = 1.0;
  double play_position_ = 0.0;  // fractional sample while playing
  qint64 last_tick_ms_ = 0;
  std::optional<std::pair<int, int>> loop_jump_;  // take-off, landing samples
  int video_frame_index_ = -1;
  int reader_next_ = -1;  // the frame the video reader's next ReadNext returns
  capture::VideoFrame filmed_, drawn_;
  /// The last frames decoded (1080p: 6 MB each): a step back, or a loop over a few frames, needs
  /// no seek (a seek decodes from the keyframe before: about 120 ms at 1080p here).
  std::deque<capture::VideoFrame> recent_;
  std::vector<std::uint8_t> rgb3d_;
  std::string last_error_;

  std::thread loader_;
  std::atomic<bool> cancel_load_{false};
  std::atomic<bool> loaded_{true};
};

}  // namespace acro::studio
