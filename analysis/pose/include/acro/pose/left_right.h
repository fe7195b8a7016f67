#pragma once

/// \file
/// Left and right made continuous over a sequence (docs/pose.md, "Left and right"). A pose network
/// labels each frame by itself and now and then turns its labels over — a whole body, or only the
/// legs, from one frame to the next — while a real body turns over several frames. Over each run
/// of frames with a pose, the labelling of each group (legs; arms and face) is chosen by dynamic
/// programming (Viterbi over four states: as the network says, legs exchanged, arms exchanged,
/// both) so that the keypoints move least from frame to frame, with a small cost for each frame a
/// group is exchanged so that the network's labels stand where nothing says otherwise. A frame
/// where the network hesitates (the shoulders meet in the image) does not break the chain, as a
/// frame-by-frame choice would.

#include <vector>

#include "acro/pose/pose_tracker.h"

namespace acro::pose {

struct LeftRightOptions {
  /// The cost of a group exchanged for one frame, in torso lengths per keypoint: what a frame of
  /// movement must save to be worth it. Small, so that only the chain's majority decides.
  double exchange_cost = 0.02;
  bool IsValid(std::string* why) const;
};

/// Exchanges left and right in `frames` where the chains say (BlazePose's 33 keypoints), sets each
/// frame's swapped_groups (bits added to what it had), and returns the number of frames changed.
/// A frame without a pose ends a chain.
int RepairLeftRight(std::vector<FramePose>* frames, const LeftRightOptions& options = {});

}  // namespace acro::pose
