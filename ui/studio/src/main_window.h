#pragma once

// The workstation window (`acrolab-studio`, docs/studio.md): a free 3D view of the athlete and up
// to four calibrated cameras' videos with the athlete drawn over each, all at one cursor; the
// timeline of the whole trial with its jumps; the transport (play and pause, a frame either way,
// the next or previous take-off, ½ to ⅛ speed, a loop over the jump); the jump table. What it shows
// comes from the library (ui/views draws, analysis computes): no analysis here. Opening and
// analysing run on a worker thread with progress and cancel; a bad file is a dialog with its
// one-line error and the session open stays as it was.

#include <QMainWindow>

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "acro/capture/detections.h"
#include "acro/capture/video.h"
#include "acro/scene/skill_ghost.h"
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
class RoutinePlanWindow;
class SkillWindow;
class LibraryDialog;
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
  /// What the 3D view shows, as a list ("mesh,skeleton,com"; the toolbar's toggles).
  std::string shown() const;
  void SetShown(const std::string& list);
  /// Turns the 3D view about its target (degrees, added to the orbit so far) and moves it closer
  /// (a scale < 1) or farther; ResetOrbit goes back to the preset.
  void Orbit(double azimuth_deg, double elevation_deg, double distance_scale);
  void ResetOrbit();
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
  void ShowDesignGhost(const analysis::SkillGhost& design);
  CompareWindow* compare() { return compare_.get(); }
  /// The skill designer (File → Open skill…), opened on `path` when given.
  SkillWindow* OpenSkillDesigner(const std::string& path = "");
  /// File → Plan a routine…: FIG codes checked against a rule file (D, validity, what is missing).
  RoutinePlanWindow* OpenRoutinePlanner();
  /// File → Open from library…: the library's trials in a dialog (LibraryDialog); the one chosen
  /// opens with its athlete and video. An unreadable library is the dialog with its one line.
  /// `library` empty: the one of SetLibrary (default ~/.local/share/acrolab/library.sqlite).
  /// `modal` false (tests): the dialog is shown and returned, and accepting it opens the trial.
  LibraryDialog* OpenFromLibrary(const std::string& library = "", bool modal = true);
  void SetLibrary(const std::string& library) { library_ = library; }

  Timeline* timeline() { return timeline_; }
  ImageView* view3d() { return view3d_; }
  /// The video views: one per video of the session (up to four, in a grid), or one empty view.
  int num_video_views() const { return int(panes_.size()); }
  ImageView* video_view(int k = 0) { return panes_.at(size_t(k))->view; }
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
  /// The score sheet panel (docs/scoring.md): a row per element of the routine (code, DD, time of
  /// flight, landing zone and margin, HD, the execution faults reported with their measurement)
  /// and the routine's D, T, H and validity below. A click on a row puts the cursor at the
  /// element's take-off and loops it; a click on its faults, at the instant its worst measurement
  /// is worst (GoToElement).
  QTableWidget* score_table() { return score_; }
  std::string score_summary() const;
  /// Element `element` (1-based, as on the sheet): its take-off, or with `worst_fault` the frame
  /// where its most serious measurement (a reported fault first, then the nearest to its rule's
  /// threshold) is worst. False when there is no such element.
  bool GoToElement(int element, bool worst_fault);
  /// Video `k`'s frame shown (−1: none), as decoded (before the overlay), and the 3D view's scene
  /// frame: what a test compares with the reader and the scene.
  int video_frame_index(int k = 0) const { return panes_.at(size_t(k))->frame_index; }
  const capture::VideoFrame& filmed_frame(int k = 0) const { return panes_.at(size_t(k))->filmed; }
  const analysis::TrialFrame* view_frame() const;
  /// Video → Detect the athlete: the 2D keypoints of video `k` with BlazePose's `model` (lite,
  /// full, heavy) on the worker, progress and Cancel in the status bar, kept beside the video
  /// (pipeline::PoseCacheDirectory: a second run reads them back, a cancelled one goes on), then
  /// drawn over the video, left blue, right orange. False (and the dialog) without a video, with
  /// the models not installed, or while the worker is busy.
  bool DetectPoses(int k, const std::string& model = "heavy");
  /// The frames of video `k` with the athlete's keypoints (0 before DetectPoses), and the frame as
  /// drawn (the overlay and the keypoints over the decoded frame).
  int detected_frames(int k = 0) const;
  /// Video `k`'s keypoints at `frame` (nullptr before DetectPoses, or beyond the video).
  const capture::DetectedPerson* detected_pose(int k, int frame) const {
    const auto& poses = panes_.at(size_t(k))->poses;
    return frame >= 0 && size_t(frame) < poses.size() ? &poses[size_t(frame)] : nullptr;
  }
  const capture::VideoFrame& drawn_frame(int k = 0) const { return panes_.at(size_t(k))->drawn; }
  /// The status bar's line (what the worker is doing, or what is open).
  std::string status_text() const;
  /// The last error shown in a dialog (empty: none).
  const std::string& last_error() const { return last_error_; }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void BuildMenus();
  // The parts of the window the constructor assembles.
  void BuildJumpTable();
  QWidget* BuildPlotPanel();
  QWidget* BuildVerdictPanel();
  QWidget* BuildScorePanel();
  void BuildStatusBar();
  void BuildTransport();
  // File → Add a video: the video, its calibration, the camera when it holds several.
  void AddVideoFromDialogs();
  // A calibration of several cameras: asks which one filmed the video (false: cancelled, or the
  // calibration cannot be read, said in a dialog).
  bool ChooseCamera(VideoFiles* video);
  // Video → Detect the athlete: which video (when several) and which model, then DetectPoses.
  void AskDetectPoses();
  // The worker's start on the window's thread: the status bar's progress and Cancel shown, `line`
  // said; and the progress the worker reports through (each step in the status bar, false once
  // Cancel is pressed).
  void BeginWork(const std::string& line);
  std::function<bool(const std::string&, int, int)> WorkerProgress();
  /// What the 3D view shows (its parts, the cameras) as the toggles say; ApplyShow redraws too.
  void ShowInView();
  void ApplyShow();
  /// Opens `files` as a session on the worker thread (progress, Cancel), then `done` on the
  /// window's thread; a failure is the dialog and `done` is not called.
  void OpenInBackground(const SessionFiles& files,
                        std::function<void(std::shared_ptr<Session>)> done);
  bool ShowCompare(int a, const std::function<std::unique_ptr<CompareWindow>()>& make);
  void AskCompare();
  /// File → Watch live…: the sources and a folder asked for, the live mode opened (docs/live.md).
  void AskWatchLive();
  void Adopt(std::shared_ptr<Session> session, const SessionView& view);
  void ShowError(const std::string& message);
  void Redraw();
  void DrawVideo(int k);
  /// `count` video views (at least one) in a grid: one, two one above the other, or two by two.
  void LayOutVideoViews(int count);
  void Tick();
  void FillJumpTable();
  void FillPlots();
  void FillVerdict();
  void FillScoreSheet();
  void JoinLoader();

  std::shared_ptr<Session> session_;
  std::unique_ptr<ui::TrialFreeView> free_view_;
  std::unique_ptr<CompareWindow> compare_;
  std::shared_ptr<Session> compare_other_;  // the other trial a ghost jump comes from
  std::unique_ptr<SkillWindow> designer_;
  std::unique_ptr<RoutinePlanWindow> planner_;
  ImageView* view3d_ = nullptr;
  /// One video view: its camera's video with the athlete drawn over it.
  struct VideoPane {
    ImageView* view = nullptr;
    std::unique_ptr<ui::TrialOverlay> overlay;
    int frame_index = -1;
    int reader_next = -1;  // the frame the video reader's next ReadNext returns
    capture::VideoFrame filmed, drawn;
    /// The last frames decoded (1080p: 6 MB each): a step back, or a loop over a few frames,
    /// needs no seek (a seek decodes from the keyframe before: about 120 ms at 1080p here).
    std::deque<capture::VideoFrame> recent;
    /// The detector's keypoints per frame (BlazePose's 33; empty: not detected).
    std::vector<capture::DetectedPerson> poses;
  };
  std::vector<std::unique_ptr<VideoPane>> panes_;
  QWidget* video_grid_ = nullptr;
  Timeline* timeline_ = nullptr;
  QTableWidget* jumps_ = nullptr;
  QTableWidget* verdict_ = nullptr;
  QLabel* findings_ = nullptr;
  QTableWidget* score_ = nullptr;
  QLabel* score_summary_ = nullptr;
  PlotView* plot_ = nullptr;
  QComboBox* plot_box_ = nullptr;
  QComboBox* joint_box_ = nullptr;
  QComboBox* speed_box_ = nullptr;
  QComboBox* preset_box_ = nullptr;
  QAction* follow_ = nullptr;
  std::vector<QAction*> show_actions_;  // mesh, skeleton, markers, com
  double orbit_azimuth_deg_ = 0.0, orbit_elevation_deg_ = 0.0, orbit_distance_scale_ = 1.0;
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
  std::vector<std::uint8_t> rgb3d_;
  std::string last_error_;
  std::string library_;
  std::unique_ptr<LibraryDialog> library_dialog_;

  std::thread loader_;
  std::atomic<bool> cancel_load_{false};
  std::atomic<bool> loaded_{true};
};

}  // namespace acro::studio
