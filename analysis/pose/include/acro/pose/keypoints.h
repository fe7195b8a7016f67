#pragma once

/// \file
/// The detector's keypoints (docs/pose.md, "Outputs"): BlazePose's own 33, and the BODY_25B-style
/// set the rest of Acrolab and Pose2Sim read.

#include <string>
#include <vector>

#include "acro/capture/detections.h"

namespace acro::pose {

/// BlazePose's 33 landmarks in the network's order (nose, left_eye_inner, …, right_foot_index):
/// MediaPipe's names, "left" being the person's left.
const std::vector<std::string>& BlazePoseNames();

/// How far OpenPose's hips are from BlazePose's, towards the shoulders, as a fraction of the torso
/// (hips' centre to shoulders' centre): 0.08, measured (docs/pose.md, "Two definitions of the hip").
inline constexpr double kBody25bHipShift = 0.08;

/// BODY_25B (capture::KeypointSetNames("body25b")) from BlazePose's 33 (a 3 × 33 matrix of u px,
/// v px, confidence): the face, shoulders, elbows, wrists, knees and ankles as they are; the hips
/// moved kBody25bHipShift of the torso towards the shoulders, where OpenPose puts them;
/// Neck = the shoulders' mid-point (the lower confidence of the two); heels = heels; big toes =
/// BlazePose's foot index (the tip of the foot). Head (the top of the head) and the small toes
/// have no BlazePose counterpart: confidence 0 (absent).
capture::DetectedPerson Body25bFromBlazePose(const capture::DetectedPerson& blazepose);

/// The BlazePose landmarks whose left and right are swapped when a person's sides are exchanged:
/// pairs (left index, right index).
const std::vector<std::pair<int, int>>& BlazePoseLeftRightPairs();

/// The skeleton's edges between BlazePose landmarks, for drawing (face, arms, hands, torso, legs,
/// feet), and each landmark's side: +1 left, −1 right, 0 the nose.
const std::vector<std::pair<int, int>>& BlazePoseEdges();
const std::vector<int>& BlazePoseSides();

/// A skeleton for keypoints named as OpenPose, COCO and HALPE name them (LShoulder, RElbow, Neck,
/// MidHip, LBigToe, …): the edges between the names present, and each keypoint's side (+1 for a
/// name starting with L, −1 with R, 0 otherwise). Names it does not know get no edge.
struct Skeleton {
  std::vector<std::pair<int, int>> edges;
  std::vector<int> sides;
};
Skeleton SkeletonOfNames(const std::vector<std::string>& names);

}  // namespace acro::pose
