#include "acro/pipeline/live_analyses.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "acro/base/process.h"

namespace acro::pipeline {

bool RoutineAnalysisOptions::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& text) {
    if (why != nullptr) *why = text;
    return false;
  };
  if (acrolab.empty()) return fail("the acrolab program to analyse with is not given");
  if (model != "heavy" && model != "full" && model != "lite")
    return fail("the detector '" + model + "' is none of heavy, full, lite");
  return true;
}

RoutineAnalysisQueue::RoutineAnalysisQueue(RoutineAnalysisOptions options)
    : options_(std::move(options)) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("RoutineAnalysisQueue: " + why);
  worker_ = std::thread([this] { Work(); });
}

RoutineAnalysisQueue::~RoutineAnalysisQueue() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void RoutineAnalysisQueue::Add(const LiveRoutine& routine) {
  Add(routine, options_.athlete);
}

void RoutineAnalysisQueue::Add(const LiveRoutine& routine, const std::filesystem::path& athlete) {
  if (!routine.clip_error.empty()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back({routine, athlete});
  }
  wake_.notify_all();
}

int RoutineAnalysisQueue::DropWaiting() {
  const std::lock_guard<std::mutex> lock(mutex_);
  const int n = static_cast<int>(queue_.size());
  queue_.clear();
  return n;
}

void RoutineAnalysisQueue::Work() {
  // Linux's nice value is a thread's, and the processes this thread starts inherit it: the
  // analyses yield to the recording.
  ::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), 10);
  for (;;) {
    LiveRoutine r;
    std::filesystem::path athlete;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return closing_ || !queue_.empty(); });
      if (queue_.empty()) return;
      r = queue_.front().first;
      athlete = queue_.front().second;
      queue_.pop_front();
    }
    // Nothing here may end the recording (an exception out of this thread would end the
    // program), nor the next routines' analyses.
    try {
      Analyse(r, athlete);
    } catch (const std::exception& e) {
      if (options_.on_line)
        options_.on_line(
            fmt::format("{}  routine {} not analysed: {}", r.source, r.number, e.what()));
    }
  }
}

void RoutineAnalysisQueue::Analyse(const LiveRoutine& r, const std::filesystem::path& athlete) {
  const auto line = [this](const std::string& text) {
    if (options_.on_line) options_.on_line(text);
  };
  const std::filesystem::path out = r.folder / "analysis";
  const std::string clip = (r.folder / "clip.ts").string();
  std::vector<std::string> analyze = {options_.acrolab.string(),
                                      "analyze",
                                      "--video",
                                      clip,
                                      "--detect-bed",
                                      "--model",
                                      options_.model,
                                      "--no-filmstrip-videos",
                                      "--quiet",
                                      "-o",
                                      out.string()};
  if (!athlete.empty()) analyze.insert(analyze.end(), {"--athlete", athlete.string()});
  if (!options_.intrinsics.empty())
    analyze.insert(analyze.end(), {"--intrinsics", options_.intrinsics.string()});
  if (!options_.camera.empty()) analyze.insert(analyze.end(), {"--camera", options_.camera});
  if (!r.bed_picture.empty())
    analyze.insert(analyze.end(), {"--bed-picture", r.bed_picture.string()});
  bool analysed = false;
  RunProcesses({analyze}, 1, [&](size_t, const ProcessOutcome& o) {
    analysed = o.ok();
    line(o.ok() ? fmt::format("{}  routine {} analysed in {:.1f} s: {}",
                              r.source,
                              r.number,
                              o.seconds,
                              (out / "report.html").string())
                : fmt::format("{}  routine {} not analysed ({:.1f} s): {}",
                              r.source,
                              r.number,
                              o.seconds,
                              o.last_error_line));
  });
  if (!analysed) return;
  if (!options_.library.empty() && athlete.empty()) {
    line(fmt::format("{}  routine {} not stored in the library: no athlete was chosen for it",
                     r.source,
                     r.number));
  } else if (!options_.library.empty()) {
    // The analysis stored as it is (library add --analysis: the clip is one of its inputs).
    const std::vector<std::string> add = {options_.acrolab.string(),
                                          "library",
                                          "add",
                                          clip,
                                          "--analysis",
                                          out.string(),
                                          "--athlete",
                                          athlete.string(),
                                          "--library",
                                          options_.library.string(),
                                          "--quiet"};
    RunProcesses({add}, 1, [&](size_t, const ProcessOutcome& o) {
      line(o.ok() ? fmt::format("{}  routine {} in the library {}",
                                r.source,
                                r.number,
                                options_.library.string())
                  : fmt::format("{}  routine {} not added to the library: {}",
                                r.source,
                                r.number,
                                o.last_error_line));
    });
  }
  if (options_.on_analysed) options_.on_analysed(r, out / "report.html");
}

}  // namespace acro::pipeline
