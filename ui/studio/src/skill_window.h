#pragma once

// The studio's skill designer: a skill file opened, its keyframes in a table (the time guesses
// editable), the keyframe poses as a filmstrip, Model 2 or Model 1 run on a worker thread with
// its progress, then the objective before and after, the timing chart and the initial against
// the optimised timing as filmstrips; the design saved as `acrolab optimize` writes it (a folder
// that `overlay --ghost` reads). The same library functions as `acrolab optimize`.

#include <QWidget>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "acro/design/skill_optimization.h"

class QLabel;
class QProgressBar;
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
  /// Model 2 (`model` 2) or Model 1 on a worker thread.
  void Run(int model);
  bool running() const { return worker_.joinable() && !done_; }
  /// Stops the run after its current iteration; the result shown before stays.
  void Cancel() { cancel_ = true; }
  const analysis::SkillOptimizationResult* result() const { return result_ ? &*result_ : nullptr; }
  /// Writes the design's folder (result.json, motion.mot, charts, filmstrip, report.html).
  bool SaveDesign(const std::string& dir);
  QTableWidget* keyframes() { return keyframes_; }
  PlotView* timing_plot() { return timing_; }
  /// The line under the window (what the run is doing, or its result).
  std::string summary() const;
  const std::string& last_error() const { return last_error_; }

 private:
  void ShowError(const std::string& message);
  void ShowSkill();
  void ShowResult();
  void Join();

  std::optional<analysis::Skill> skill_;
  std::optional<analysis::SkillOptimizationResult> result_;
  QTableWidget* keyframes_ = nullptr;
  ImageView* strip_ = nullptr;
  PlotView* timing_ = nullptr;
  QLabel* summary_ = nullptr;
  QProgressBar* progress_ = nullptr;
  std::string last_error_;
  std::thread worker_;
  std::atomic<bool> done_{true};
  std::atomic<bool> cancel_{false};
};

}  // namespace acro::studio
