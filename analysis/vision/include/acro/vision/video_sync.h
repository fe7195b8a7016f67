#pragma once

// The time line between a trial and a video (docs/sync.md): video_time = offset + rate ×
// trial_time, trial time counted from the trial's first sample, video time from the first frame.

#include <string>

#include "acro/capture/trial.h"

namespace acro::vision {

struct VideoSync {
  double offset_s = 0.0;  ///< the video time of the trial's first sample
  double rate = 1.0;      ///< video seconds per trial second (clock drift, slow-motion video)

  double VideoTime(double trial_time_s) const { return offset_s + rate * trial_time_s; }
  double TrialTime(double video_time_s) const { return (video_time_s - offset_s) / rate; }
  /// The trial sample nearest to `video_time_s`, or −1 when it falls outside the trial (more than
  /// half a sample before the first or after the last).
  int NearestSample(const capture::Trial& trial, double video_time_s) const;
};

/// The sync that puts an event at `trial_time_s` in the trial on `video_time_s` in the video.
VideoSync SyncFromEvent(double trial_time_s, double video_time_s, double rate = 1.0);

/// acro::InputError naming `video` when the sync puts no moment of the trial (0 … trial_duration_s)
/// inside the video (0 … video_duration_s): every time or offset given by hand must land in the
/// media (`--offset-s 1e300` drew a video of nothing). The message has both spans.
void DemandTrialInsideVideo(const VideoSync& sync, double trial_duration_s,
                            double video_duration_s, const std::string& video);

}  // namespace acro::vision
