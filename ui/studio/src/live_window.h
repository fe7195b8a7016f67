#pragma once

// The studio's live mode (docs/live.md, "The window"): the hall's cameras shown N seconds late
// (a slider, 0–60 s), in slow motion or a frame at a time inside that delay, and every routine
// replayed by itself as soon as it is cut, with what the image motion measured drawn over it —
// the soles' path, each landing's spot and number, each jump's time of flight and zone. The
// session is pipeline::RunLive, as `acrolab live`'s: recorded frame-exact, jumps.jsonl, a folder
// per routine.

#include <QByteArray>
#include <QImage>
#include <QStringList>
#include <QWidget>

#include <array>
#include <atomic>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "acro/pipeline/live.h"
#include "acro/pipeline/live_analyses.h"

class QComboBox;
class QHBoxLayout;
class QLabel;
class QListWidget;
class QPushButton;
class QSlider;
class QTableWidget;
class QTimer;

namespace acro::studio {

class ImageView;

class LiveWindow : public QWidget {
 public:
  static constexpr double kMaxDelayS = 60.0;
  /// A frame as the delay buffer keeps it (JPEG, quality 90), and back (the window's hot path on
  /// the sources' threads and the display's: tests/bench/studio_bench).
  static QByteArray Compress(const capture::VideoFrame& picture);
  static QImage Decompress(const QByteArray& jpeg);

  /// Starts the session at once, on a thread of its own: `request`'s sources, folder and options
  /// (its callbacks are the window's). A session that cannot start (a folder in use) is a dialog.
  /// With `analyses`, each routine is analysed as it is cut (pipeline::RoutineAnalysisQueue, its
  /// callbacks the window's) and its report offered beside its replay.
  LiveWindow(pipeline::LiveRequest request,
             double delay_s,
             std::optional<pipeline::RoutineAnalysisOptions> analyses = {},
             QWidget* parent = nullptr);
  /// Stops the session: the sources closed, what was recorded kept, the open routine cut.
  ~LiveWindow() override;

  /// The delay (s, 0–60): the sources shown that long after they sent, at normal speed.
  void SetDelay(double seconds);
  double delay() const { return delay_s_; }
  /// How far behind the sources the picture is now (grows in slow motion, and when paused).
  double shown_delay() const;
  /// 1, ½, ¼, ⅛; 0 pauses. Slower than 1 falls behind, up to the buffer's 60 s.
  void SetSpeed(double rate);
  double speed() const { return rate_; }
  /// A frame later (1) or earlier (−1) of the first source, paused.
  void StepFrame(int direction);
  /// Back to the slider's delay at normal speed.
  void BackToLive();
  /// The athlete each routine cut from now on is analysed for, and stored under with a library:
  /// a profile's path; empty: a default body, not stored. The list on screen offers the profile
  /// given, the others in its folder, the library's athletes and any other file.
  void SetAthlete(const std::filesystem::path& profile);
  std::filesystem::path athlete() const;
  /// The list's entries as shown, for the tests.
  QStringList athlete_choices() const;
  /// Ends the session (the window stays, with what it holds).
  void Stop();
  bool running() const { return !finished_; }

  int source_count() const { return static_cast<int>(buffers_.size()); }
  /// The frame a source's view shows: its index (from the connection's first frame), stream time
  /// on the session's time line, and when it was put up (capture::LiveClockNow).
  struct Shown {
    int index = -1;
    double time_s = std::numeric_limits<double>::quiet_NaN();
    double at_s = std::numeric_limits<double>::quiet_NaN();
  };
  Shown shown(int source) const;
  QImage shown_image(int source) const;
  /// The source's clock: stream time t was sent at t + this (s on LiveClockNow's clock), the 95th
  /// percentile of arrival − stream time over its last 256 frames (a frame is only shown once it
  /// has arrived; with B-frames, pictures are sent ahead of their time).
  double sent_offset(int source) const;

  /// The routine being replayed (0: none yet), its source, and the stream time of its frame up.
  int replay_routine() const { return replay_ ? replay_->routine.number : 0; }
  std::string replay_source() const { return replay_ ? replay_->routine.source : ""; }
  double replay_time_s() const;
  QImage replay_image() const;
  /// The report of the routine replayed, once its analysis is done (empty before, or without
  /// analyses).
  std::filesystem::path replay_report() const;
  /// Whether the replay shows the routine's full analysis: its overlay video (the athlete's model
  /// over the picture) and its score sheet's elements, in place of the image motion's marks — as
  /// soon as the analysis is done and its video read.
  bool replay_shows_analysis() const { return replay_ && replay_->analysed != nullptr; }
  /// The replay's table as shown (rows of cells), for the tests.
  std::vector<std::vector<std::string>> replay_table() const;
  /// Every line of the session so far (the jumps, routines, sources' ends), oldest first.
  QStringList lines() const { return lines_; }
  std::string last_error() const { return last_error_; }
  /// After the session ended: what RunLive returned.
  const std::optional<pipeline::LiveSummary>& summary() const { return summary_; }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  // One frame in the delay buffer: the picture as JPEG (about 30 KB at 640 px against 690 KB raw:
  // a minute of two cameras in 120 MB), with what the watcher saw in it (the picture's px).
  struct Buffered {
    int index = 0;
    double time_s = 0, arrival_s = 0;
    QByteArray jpeg;
    bool found = false, in_air = false;
    double sole_x = 0, sole_y = 0;
  };
  struct Buffer {
    std::string name;
    std::deque<Buffered> frames;
    std::int64_t bytes = 0;       // the frames' JPEG
    std::deque<double> lateness;  // arrival − stream time, the last 256 frames past the 30th
    double max_lateness = -std::numeric_limits<double>::infinity();
    double sent_offset = 0;                          // see sent_offset()
    std::optional<std::array<double, 2>> rest_line;  // y0, slope in the picture's px
    double picture_per_full_px = 1.0;
  };
  // A routine's full analysis, for its replay: its overlay video's frames (JPEG at the live
  // pictures' width, times on the session's time line) and its jumps and score sheet.
  struct Analysed {
    std::vector<Buffered> frames;
    struct Jump {
      double takeoff_s = 0, landing_s = 0, time_of_flight_s = 0, difficulty = 0;
      std::string code, name;
      int element = 0;
      std::string zone;  // "A" or outside it, "" without a bed
      std::vector<std::string> faults;
    };
    std::vector<Jump> jumps;  // complete flights
    std::string score;        // "D 3.4 · T 7.305 · H 4.80 · E suggested −1.2"
  };
  // Reads `report`'s folder (overlay.mp4, jumps.json, score.json) off the window's thread.
  // Throws acro::InputError for what cannot be read; returns null when stopped.
  static std::shared_ptr<const Analysed> LoadAnalysed(const std::filesystem::path& report,
                                                      double clip_start_s,
                                                      int width,
                                                      const std::atomic<bool>& stop);
  struct Replay {
    pipeline::LiveRoutine routine;
    std::shared_ptr<const Analysed> analysed;  // once the routine's analysis is read
    std::vector<Buffered> frames;
    std::optional<std::array<double, 2>> rest_line;
    double picture_per_full_px = 1.0;
    double t_s = 0;     // stream time of the frame up
    double held_s = 0;  // at the end: how long it has been held before starting again
    int shown = -1;
    QImage image;
  };

  QHBoxLayout* MakeControls(bool choose_athlete);
  QWidget* MakeSources();
  QWidget* MakeReplayPane();
  void StartSession(std::optional<pipeline::RoutineAnalysisOptions> analyses);
  void FillAthleteList(const pipeline::RoutineAnalysisOptions& analyses);
  void OnFrame(const pipeline::LiveFrameSeen& seen);
  void OnRoutine(const pipeline::LiveRoutine& routine);
  void AddLine(const std::string& line);
  void ShowError(const std::string& line);
  void Tick();
  void ShowSource(int k, double view_s, double now);
  void AdvanceReplay(double dt);
  QImage DrawReplayFrame(const Replay& r, size_t k) const;
  QImage DrawAnalysedFrame(const Replay& r, size_t k) const;
  void OnAnalysed(const pipeline::LiveRoutine& routine, const std::filesystem::path& report);
  void ShowAnalysed(const std::string& key, std::shared_ptr<const Analysed> analysed);
  void FillRoutineTable();
  void ReplayLabel();

  pipeline::LiveRequest request_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> finished_{false};
  std::atomic<bool> closing_{false};  // the window going: the analyses' readers stop
  std::thread thread_;
  mutable std::mutex mutex_;  // the buffers (written by the sources' threads)
  std::vector<Buffer> buffers_;

  double delay_s_ = 5.0;
  double rate_ = 1.0;
  double view_s_ = std::numeric_limits<double>::quiet_NaN();  // the sent clock shown
  // Paused: each source's offset as it was (the 95th percentile moves as frames come, and a
  // paused picture must not).
  std::vector<double> paused_offset_;
  double last_tick_s_ = 0;
  std::vector<Shown> shown_;
  std::optional<Replay> replay_;
  double replay_rate_ = 1.0;
  QStringList lines_;
  std::string last_error_;
  std::optional<pipeline::LiveSummary> summary_;
  std::optional<pipeline::RoutineAnalysisQueue> analyses_;
  // Each routine's report once analysed, by "source number".
  std::map<std::string, std::filesystem::path> reports_;
  // The last routine's analysis read for its replay (one at most: a routine's overlay video is
  // 30–40 MB of JPEG), by the same key; the threads that read them, each with its end.
  std::string analysed_key_;
  std::shared_ptr<const Analysed> analysed_last_;
  struct Loader {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;
  };
  std::vector<Loader> loaders_;
  int picture_width_ = 640;  // the live pictures' width (the analysis's video is scaled to it)
  QPushButton* report_button_ = nullptr;
  mutable std::mutex athlete_mutex_;  // the athlete (read by the session's thread)
  std::filesystem::path athlete_;
  std::vector<std::filesystem::path> athlete_paths_;  // the list's profiles, in its order
  QComboBox* athlete_box_ = nullptr;
  void AddAthleteChoice(const std::filesystem::path& profile);

  std::vector<ImageView*> views_;
  std::vector<QLabel*> view_labels_;
  ImageView* replay_view_ = nullptr;
  QLabel* replay_label_ = nullptr;
  QTableWidget* routine_table_ = nullptr;
  QSlider* delay_slider_ = nullptr;
  QLabel* delay_label_ = nullptr;
  QComboBox* speed_box_ = nullptr;
  QComboBox* replay_speed_box_ = nullptr;
  QPushButton* pause_button_ = nullptr;
  QListWidget* line_list_ = nullptr;
  QLabel* status_ = nullptr;
  QTimer* timer_ = nullptr;
};

}  // namespace acro::studio
