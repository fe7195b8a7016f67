// Left/right repair over a sequence (acro/pose/left_right.h) on a synthetic walk: a body whose
// limbs swing, its labels turned over by a "network" for a run of frames (the whole body, or the
// legs alone), and for one frame where the shoulders meet; the repair gives back the true labels,
// and a body that really turns (its sides crossing over several frames) is left as it is.

#include <cmath>

#include <gtest/gtest.h>

#include "acro/pose/keypoints.h"
#include "acro/pose/left_right.h"

namespace acro::pose {
namespace {

// Frame t of a side-on walker 300 px tall: left limbs swing forward as the right swing back.
capture::DetectedPerson Walker(int t, double turn = 0.0) {
  capture::DetectedPerson k = capture::DetectedPerson::Zero(3, 33);
  const double swing = 40.0 * std::sin(0.2 * t);
  const double half_width = 25.0 * std::cos(turn);  // the shoulders' half-width seen from the front
  for (int i = 0; i < 33; ++i) {
    const int side = BlazePoseSides()[i];
    double y = 200.0;  // the face
    if (i >= 11) y = i >= 23 ? 350.0 + 25.0 * ((i - 23) / 2) : 260.0 + 20.0 * ((i - 11) / 2);
    // The legs 40 px apart at the hips, the swing never bringing a pair closer than 20 px.
    const double x = 500.0 + 3.0 * t + side * half_width * (i >= 23 ? 1.6 : 1.0) +
                     (i >= 13 ? side * swing * (i >= 25 ? 0.5 : 0.4) : 0.0);
    k.col(i) << x, y, 0.9;
  }
  return k;
}

std::vector<FramePose> Sequence(int n) {
  std::vector<FramePose> frames(n);
  for (int t = 0; t < n; ++t) {
    frames[t].found = true;
    frames[t].frame = t;
    frames[t].keypoints = Walker(t);
  }
  return frames;
}

void Exchange(FramePose* f, bool legs, bool arms) {
  for (const auto& [l, r] : BlazePoseLeftRightPairs())
    if ((l >= 23 && legs) || (l < 23 && arms)) f->keypoints.col(l).swap(f->keypoints.col(r));
}

TEST(LeftRight, ARunOfTurnedLabelsIsTurnedBack) {
  std::vector<FramePose> frames = Sequence(60);
  const std::vector<FramePose> truth = frames;
  for (int t = 20; t < 30; ++t) Exchange(&frames[t], true, true);    // the whole body, 10 frames
  for (int t = 40; t < 44; ++t) Exchange(&frames[t], true, false);   // the legs alone
  EXPECT_EQ(RepairLeftRight(&frames), 14);
  for (int t = 0; t < 60; ++t) EXPECT_TRUE(frames[t].keypoints.isApprox(truth[t].keypoints)) << "frame " << t;
  EXPECT_EQ(frames[25].swapped_groups, 3);
  EXPECT_EQ(frames[41].swapped_groups, 1);
}

TEST(LeftRight, OneHesitatingFrameDoesNotHandTheLabelsBack) {
  // The network turns its labels over at frame 10 and keeps them; frame 30 it hesitates (both
  // shoulders and knees in the middle). The majority is the turned labelling, so frames 0–9 are
  // the ones exchanged — one consistent labelling over the whole chain either way.
  std::vector<FramePose> frames = Sequence(50);
  for (int t = 10; t < 50; ++t) Exchange(&frames[t], true, true);
  frames[30].keypoints.row(0).setConstant(frames[30].keypoints.row(0).mean());
  RepairLeftRight(&frames);
  for (int t = 1; t < 50; ++t) {
    if (t == 30 || t == 31) continue;
    // Consecutive frames agree: the left shoulder stays on one side of the right one.
    const double before = frames[t - 1].keypoints(0, 11) - frames[t - 1].keypoints(0, 12);
    const double now = frames[t].keypoints(0, 11) - frames[t].keypoints(0, 12);
    EXPECT_GT(before * now, 0.0) << "frame " << t;
  }
  EXPECT_GT((frames[29].keypoints(0, 11) - frames[29].keypoints(0, 12)) * (frames[32].keypoints(0, 11) - frames[32].keypoints(0, 12)), 0.0);
}

TEST(LeftRight, ABodyThatReallyTurnsIsLeftAsItIs) {
  // Half a turn over 20 frames: the sides cross gradually.
  std::vector<FramePose> frames(40);
  for (int t = 0; t < 40; ++t) {
    frames[t].found = true;
    frames[t].keypoints = Walker(t, std::clamp((t - 10) / 20.0, 0.0, 1.0) * M_PI);
  }
  const std::vector<FramePose> truth = frames;
  EXPECT_EQ(RepairLeftRight(&frames), 0);
  for (int t = 0; t < 40; ++t) EXPECT_TRUE(frames[t].keypoints.isApprox(truth[t].keypoints));
}

}  // namespace
}  // namespace acro::pose
