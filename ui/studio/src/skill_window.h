#pragma once

// The studio's skill designer: a skill file opened, its keyframes in a table (the time guesses
// editable) and the chosen keyframe's pose in another (its somersault, tilt, twist and every joint
// angle editable, checked as the file reader checks them), the keyframe poses as a filmstrip,
// Model 2 or Model 1 run on a worker thread with its progress and Cancel, then the objective before
// and after, the timing chart, the initial against the optimised timing as filmstrips, the flight
// simulated (the landing it reaches against the design's, side by side at any instant), the design
// drawn as the ghost in the main window's flights; the skill file and the design (the folder
// `acrolab optimize` writes, which `overlay --ghost` reads) saved. The same library functions as
// `acrolab optimize`.

#include <QWidget>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"
#include "acro/scene/skill_ghost.h"

class QComboBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QTableWidget;

namespace acro::studio {

class ImageView;
class PlotView;

class SkillWindow : public QWidget {
  Q_OBJECT

 public:
  explicit SkillWindow(QWidget* parent = nullptr);
  ~SkillWindow() override;

  /// Reads a skill file; a bad one is a dialog with its one-line error and the skill open stays.
  bool OpenSkill(const std::string& path);
  /// Writes the skill as edited (a skill file ReadSkill reads back); false and the dialog when it
  /// cannot be written.
  bool SaveSkill(const std::string& path);
  /// Sets pose value `row` of keyframe `keyframe` (row 0–2 somersault, tilt, twist, then the joint
  /// angles in model order) to `degrees`, as an edit in the pose table does: refused with the
  /// dialog (the skill unchanged) when the reader would refuse the result. The last run's result
  /// no longer describes the skill and goes.
  bool EditPose(int keyframe, int row, double degrees);
  /// Model 2 (`model` 2) or Model 1 on a worker thread; the flight is simulated after it.
  void Run(int model);
  bool running() const { return worker_.joinable() && !done_; }
  /// Stops the run after its current iteration; the result shown before stays.
  void Cancel() { cancel_ = true; }
  const analysis::Skill* skill() const { return skill_ ? &*skill_ : nullptr; }
  const analysis::SkillOptimizationResult* result() const { return result_ ? &*result_ : nullptr; }
  const analysis::SkillSimulationResult* simulation() const { return sim_ ? &*sim_ : nullptr; }
  /// Writes the design's folder (result.json, motion.mot, charts, filmstrip, report.html).
  bool SaveDesign(const std::string& dir);
  /// Where "Show over the athlete" sends the design (the main window's ghost).
  void SetGhostTarget(std::function<void(const analysis::SkillGhost&)> target) {
    ghost_target_ = std::move(target);
  }
  /// Sends the design to the ghost target; false and the dialog without a result.
  bool ShowOverAthlete();
  /// The preview at `t_s` from take-off: the design (optimised, or the initial timing) and the
  /// simulated flight side by side.
  void SetPreviewTime(double t_s);
  QTableWidget* keyframes() { return keyframes_; }
  QTableWidget* pose() { return pose_; }
  PlotView* timing_plot() { return timing_; }
  /// The chart beside the preview: 0 the keyframe timing, 1 the angular momentum.
  void ShowChart(int index) {
    SetChartIndex(index);
    ShowChart();
  }
  ImageView* preview() { return preview_; }
  /// The line under the window (what the run is doing, or its result).
  std::string summary() const;
  const std::string& last_error() const { return last_error_; }

 private:
  void ShowError(const std::string& message);
  void ShowSkill();
  void ShowPose(int keyframe);
  void ShowResult();
  void ShowChart();
  void SetChartIndex(int index);
  void MakePreview();
  void Join();

  std::optional<analysis::Skill> skill_;
  std::optional<analysis::SkillOptimizationResult> result_;
  std::optional<analysis::SkillSimulationResult> sim_;
  struct Preview;
  std::unique_ptr<Preview> preview_scenes_;
  std::function<void(const analysis::SkillGhost&)> ghost_target_;
  int pose_keyframe_ = 0;
  QTableWidget* keyframes_ = nullptr;
  QTableWidget* pose_ = nullptr;
  ImageView* strip_ = nullptr;
  ImageView* preview_ = nullptr;
  QSlider* preview_time_ = nullptr;
  PlotView* timing_ = nullptr;
  QComboBox* chart_box_ = nullptr;
  QLabel* summary_ = nullptr;
  QProgressBar* progress_ = nullptr;
  std::string last_error_;
  std::thread worker_;
  std::atomic<bool> done_{true};
  std::atomic<bool> cancel_{false};
};

}  // namespace acro::studio
