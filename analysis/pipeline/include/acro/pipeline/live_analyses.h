#pragma once

/// \file
/// Each routine cut in the hall analysed as its clip is written (docs/live.md): `acrolab analyze
/// --video clip.ts --detect-bed --model M --no-filmstrip-videos [--athlete A]` into the routine's
/// `analysis/`, then, with a library, `acrolab library add clip.ts --analysis …` — one routine at a
/// time, each in a process of its own (as `batch` runs its trials: a routine that cannot be
/// analysed never stops the recording) and at a lower priority than the recording's threads (nice
/// 10: an analysis never makes a camera's packets wait). `acrolab live` and the studio's live mode
/// queue their routines here.

#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "acro/pipeline/live.h"

namespace acro::pipeline {

struct RoutineAnalysisOptions {
  /// The acrolab program that analyses (the door's own executable, or the one beside it).
  std::filesystem::path acrolab;
  std::string model = "heavy";  ///< the detector: heavy, full or lite
  /// The camera's intrinsics for each analysis (`analyze --detect-bed --intrinsics C --camera N`:
  /// the pose from the bed); empty: the focal length from the bed too.
  std::filesystem::path intrinsics;
  std::string camera;
  std::filesystem::path athlete;  ///< the athlete's profile; empty: a default athlete
  /// Store each analysis there, under its athlete (a routine analysed for no athlete is not
  /// stored, and the line says so).
  std::filesystem::path library;
  /// Each outcome as a line ("… routine 2 analysed in 49.9 s: …/report.html", "… not analysed:
  /// why", "… in the library …"), from the queue's thread.
  std::function<void(const std::string&)> on_line;
  /// Each routine analysed, with its report, from the queue's thread.
  std::function<void(const LiveRoutine&, const std::filesystem::path& report)> on_analysed;
  bool IsValid(std::string* why) const;
};

class RoutineAnalysisQueue {
 public:
  /// Throws std::invalid_argument for invalid options.
  explicit RoutineAnalysisQueue(RoutineAnalysisOptions options);
  /// Waits for the routines queued to be analysed (an interrupt stops the running one: the
  /// process's children are the interrupt handler's).
  ~RoutineAnalysisQueue();
  RoutineAnalysisQueue(const RoutineAnalysisQueue&) = delete;
  RoutineAnalysisQueue& operator=(const RoutineAnalysisQueue&) = delete;

  /// Queues a routine whose clip was written (one without a clip is ignored), for the options'
  /// athlete.
  void Add(const LiveRoutine& routine);
  /// The same for `athlete` (a profile; empty: a default body, and not stored in a library): the
  /// athlete chosen on the window's screen when the routine was cut.
  void Add(const LiveRoutine& routine, const std::filesystem::path& athlete);
  /// Forgets the routines not yet started (a window closing: the one running finishes); returns
  /// how many.
  int DropWaiting();

 private:
  void Work();
  void Analyse(const LiveRoutine& r, const std::filesystem::path& athlete);

  RoutineAnalysisOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<LiveRoutine, std::filesystem::path>> queue_;  // and its athlete
  bool closing_ = false;
  std::thread worker_;
};

}  // namespace acro::pipeline
