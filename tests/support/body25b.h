#pragma once

// OpenPose BODY_25B index of each keypoint name of the Pose2Sim demo's TRC
// (../shared/refdata/pose2sim-demo/README.md), for tests that compare projections with detections.

#include <map>
#include <string>

namespace acro::testing {

inline const std::map<std::string, int>& Body25bIndex() {
  static const std::map<std::string, int> index = {
      {"Nose", 0},     {"LShoulder", 5},  {"RShoulder", 6}, {"LElbow", 7},   {"RElbow", 8},
      {"LWrist", 9},   {"RWrist", 10},    {"LHip", 11},     {"RHip", 12},    {"LKnee", 13},
      {"RKnee", 14},   {"LAnkle", 15},    {"RAnkle", 16},   {"Neck", 17},    {"Head", 18},
      {"LBigToe", 19}, {"LSmallToe", 20}, {"LHeel", 21},    {"RBigToe", 22}, {"RSmallToe", 23},
      {"RHeel", 24}};
  return index;
}

}  // namespace acro::testing
