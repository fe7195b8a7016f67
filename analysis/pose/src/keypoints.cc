#include "acro/pose/keypoints.h"

#include <algorithm>
#include <cctype>

namespace acro::pose {

const std::vector<std::string>& BlazePoseNames() {
  static const std::vector<std::string> names = {
      "nose",           "left_eye_inner", "left_eye",     "left_eye_outer",  "right_eye_inner",
      "right_eye",      "right_eye_outer", "left_ear",    "right_ear",       "mouth_left",
      "mouth_right",    "left_shoulder",  "right_shoulder", "left_elbow",    "right_elbow",
      "left_wrist",     "right_wrist",    "left_pinky",   "right_pinky",     "left_index",
      "right_index",    "left_thumb",     "right_thumb",  "left_hip",        "right_hip",
      "left_knee",      "right_knee",     "left_ankle",   "right_ankle",     "left_heel",
      "right_heel",     "left_foot_index", "right_foot_index"};
  return names;
}

const std::vector<std::pair<int, int>>& BlazePoseLeftRightPairs() {
  static const std::vector<std::pair<int, int>> pairs = {
      {1, 4},   {2, 5},   {3, 6},   {7, 8},   {9, 10},  {11, 12}, {13, 14}, {15, 16},
      {17, 18}, {19, 20}, {21, 22}, {23, 24}, {25, 26}, {27, 28}, {29, 30}, {31, 32}};
  return pairs;
}

const std::vector<std::pair<int, int>>& BlazePoseEdges() {
  static const std::vector<std::pair<int, int>> edges = {
      {0, 2},   {0, 5},   {2, 7},   {5, 8},   {9, 10},  {11, 12}, {11, 13}, {13, 15}, {15, 17},
      {15, 19}, {15, 21}, {12, 14}, {14, 16}, {16, 18}, {16, 20}, {16, 22}, {11, 23}, {12, 24},
      {23, 24}, {23, 25}, {25, 27}, {27, 29}, {27, 31}, {29, 31}, {24, 26}, {26, 28}, {28, 30},
      {28, 32}, {30, 32}};
  return edges;
}

const std::vector<int>& BlazePoseSides() {
  static const std::vector<int> sides = [] {
    std::vector<int> s(33, 0);
    for (const auto& [l, r] : BlazePoseLeftRightPairs()) {
      s[l] = 1;
      s[r] = -1;
    }
    return s;
  }();
  return sides;
}

Skeleton SkeletonOfNames(const std::vector<std::string>& names) {
  // The bones by name, each side's spelled with its L/R prefix.
  static const std::vector<std::pair<std::string, std::string>> kBones = {
      {"Nose", "Neck"},      {"Neck", "MidHip"},     {"Nose", "LEye"},        {"Nose", "REye"},
      {"LEye", "LEar"},      {"REye", "REar"},       {"Neck", "LShoulder"},   {"Neck", "RShoulder"},
      {"Head", "Nose"},      {"LShoulder", "RShoulder"}, {"LHip", "RHip"},    {"MidHip", "LHip"},
      {"MidHip", "RHip"},    {"LShoulder", "LHip"},  {"RShoulder", "RHip"}};
  static const std::vector<std::pair<std::string, std::string>> kSideBones = {
      {"Shoulder", "Elbow"}, {"Elbow", "Wrist"}, {"Hip", "Knee"},      {"Knee", "Ankle"},
      {"Ankle", "Heel"},     {"Ankle", "BigToe"}, {"BigToe", "SmallToe"}, {"Heel", "BigToe"}};
  Skeleton skeleton;
  auto index = [&](const std::string& name) {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return static_cast<int>(k);
    return -1;
  };
  auto add = [&](const std::string& a, const std::string& b) {
    const int i = index(a), j = index(b);
    if (i >= 0 && j >= 0) skeleton.edges.emplace_back(i, j);
  };
  for (const auto& [a, b] : kBones) add(a, b);
  for (const char* side : {"L", "R"})
    for (const auto& [a, b] : kSideBones) add(side + a, side + b);
  for (const std::string& name : names)
    skeleton.sides.push_back(name.size() > 1 && name[0] == 'L' && std::isupper(static_cast<unsigned char>(name[1])) ? 1
                             : name.size() > 1 && name[0] == 'R' && std::isupper(static_cast<unsigned char>(name[1])) ? -1
                                                                                                                     : 0);
  // The shoulders' and hips' cross bars belong to neither side.
  return skeleton;
}

capture::DetectedPerson Body25bFromBlazePose(const capture::DetectedPerson& bp) {
  // BODY_25B index ← BlazePose index (−1: made below or absent).
  static constexpr int kFrom[25] = {0,  2,  5,  7,  8,  11, 12, 13, 14, 15, 16, 23, 24,
                                    25, 26, 27, 28, -1, -1, 31, -1, 29, 32, -1, 30};
  capture::DetectedPerson out = capture::DetectedPerson::Zero(3, 25);
  for (int k = 0; k < 25; ++k)
    if (kFrom[k] >= 0) out.col(k) = bp.col(kFrom[k]);
  // OpenPose's hips, from BlazePose's: moved towards the shoulders by 8 % of the torso (the hips'
  // centre to the shoulders' centre). Measured on the Pose2Sim balancing trial (4 phones × 100
  // frames; docs/pose.md): OpenPose BODY_25B's hips sit 6–11 % of the torso above BlazePose's along
  // the torso, and not consistently to either side.
  const Eigen::Vector2d torso = 0.5 * (bp.block<2, 1>(0, 11) + bp.block<2, 1>(0, 12)) -
                                0.5 * (bp.block<2, 1>(0, 23) + bp.block<2, 1>(0, 24));
  out.block<2, 1>(0, 11) += kBody25bHipShift * torso;
  out.block<2, 1>(0, 12) += kBody25bHipShift * torso;
  // Neck: the shoulders' mid-point.
  out.block<2, 1>(0, 17) = 0.5 * (bp.block<2, 1>(0, 11) + bp.block<2, 1>(0, 12));
  out(2, 17) = std::min(bp(2, 11), bp(2, 12));
  return out;
}

}  // namespace acro::pose
