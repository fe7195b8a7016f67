#include "acro/capture/detections.h"

#include <algorithm>
#include <cctype>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::capture {

const std::vector<std::string>& KeypointSetNames(const std::string& set) {
  // OpenPose's output formats (openpose doc/02_output.md; BODY_25B from its experimental models
  // page) and HALPE's 26 keypoints (Fang et al., AlphaPose, 2022); COCO's 17 are HALPE's first.
  static const std::map<std::string, std::vector<std::string>> sets = {
      {"body25",
       {"Nose",      "Neck",      "RShoulder", "RElbow",  "RWrist",   "LShoulder", "LElbow",
        "LWrist",    "MidHip",    "RHip",      "RKnee",   "RAnkle",   "LHip",      "LKnee",
        "LAnkle",    "REye",      "LEye",      "REar",    "LEar",     "LBigToe",   "LSmallToe",
        "LHeel",     "RBigToe",   "RSmallToe", "RHeel"}},
      {"body25b",
       {"Nose",      "LEye",      "REye",      "LEar",    "REar",     "LShoulder", "RShoulder",
        "LElbow",    "RElbow",    "LWrist",    "RWrist",  "LHip",     "RHip",      "LKnee",
        "RKnee",     "LAnkle",    "RAnkle",    "Neck",    "Head",     "LBigToe",   "LSmallToe",
        "LHeel",     "RBigToe",   "RSmallToe", "RHeel"}},
      {"coco17",
       {"Nose", "LEye", "REye", "LEar", "REar", "LShoulder", "RShoulder", "LElbow", "RElbow",
        "LWrist", "RWrist", "LHip", "RHip", "LKnee", "RKnee", "LAnkle", "RAnkle"}},
      {"halpe26",
       {"Nose",    "LEye",    "REye",      "LEar",      "REar",   "LShoulder", "RShoulder",
        "LElbow",  "RElbow",  "LWrist",    "RWrist",    "LHip",   "RHip",      "LKnee",
        "RKnee",   "LAnkle",  "RAnkle",    "Head",      "Neck",   "Hip",       "LBigToe",
        "RBigToe", "LSmallToe", "RSmallToe", "LHeel",   "RHeel"}}};
  const auto it = sets.find(set);
  if (it == sets.end())
    throw InputError(
        "", "--keypoints", "unknown keypoint set '" + set + "' (body25, body25b, coco17, halpe26)");
  return it->second;
}

namespace {

// The last run of digits in a file name's stem, or -1.
long long LastNumber(const std::string& stem) {
  long long value = -1;
  size_t i = stem.size();
  while (i > 0 && !std::isdigit(static_cast<unsigned char>(stem[i - 1]))) --i;
  if (i == 0) return -1;
  size_t begin = i;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
  if (i - begin > 9) return -1;
  value = std::stoll(stem.substr(begin, i - begin));
  return value;
}

}  // namespace

KeypointDetections ReadOpenPoseJson(const std::filesystem::path& directory,
                                    const std::string& keypoint_set) {
  KeypointDetections out;
  out.source = directory.string();
  out.names = KeypointSetNames(keypoint_set);
  const size_t K = out.names.size();
  std::error_code ec;
  if (!std::filesystem::is_directory(directory, ec))
    throw InputError(directory.string(), "", "not a directory of OpenPose JSON files");
  std::vector<std::pair<long long, std::filesystem::path>> files;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    if (!entry.is_regular_file() || LowerExtension(entry.path()) != "json") continue;
    const long long frame = LastNumber(entry.path().stem().string());
    if (frame < 0 || frame >= 1000000) {
      throw InputError(
          entry.path().string(), "", "no frame number (0 to 999999) at the end of the name");
    }
    files.emplace_back(frame, entry.path());
  }
  if (files.empty()) throw InputError(directory.string(), "", "no .json file");
  std::sort(files.begin(), files.end());
  for (size_t i = 1; i < files.size(); ++i) {
    if (files[i].first == files[i - 1].first)
      throw InputError(files[i].second.string(),
                       "",
                       fmt::format("frame {} also comes from {}",
                                   files[i].first,
                                   files[i - 1].second.filename().string()));
  }
  out.frames.resize(static_cast<size_t>(files.back().first + 1));
  for (const auto& [frame, path] : files) {
    const std::string file = path.string();
    const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(64) << 20);
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(bytes.begin(), bytes.end());
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(file, AtByte(static_cast<long long>(e.byte)), "not JSON");
    }
    if (!doc.is_object() || !doc.contains("people") || !doc["people"].is_array())
      throw InputError(file, "people", "missing or not an array");
    std::vector<DetectedPerson>& people = out.frames[static_cast<size_t>(frame)];
    for (size_t i = 0; i < doc["people"].size(); ++i) {
      const nlohmann::json& k = doc["people"][i]["pose_keypoints_2d"];
      const std::string where = fmt::format("people[{}].pose_keypoints_2d", i);
      if (!k.is_array())
        throw InputError(file, where, "missing or not an array");
      if (k.empty()) continue;  // OpenPose writes an empty list for a person it dropped
      if (k.size() != 3 * K) {
        throw InputError(file,
                         where,
                         fmt::format("{} numbers, but the {} set has {} keypoints × 3",
                                     k.size(),
                                     keypoint_set,
                                     K));
      }
      DetectedPerson person(3, static_cast<Eigen::Index>(K));
      for (size_t j = 0; j < 3 * K; ++j) {
        if (!k[j].is_number())
          throw InputError(file, fmt::format("{}[{}]", where, j), "not a number");
        person(static_cast<Eigen::Index>(j % 3), static_cast<Eigen::Index>(j / 3)) =
            k[j].get<double>();
      }
      people.push_back(std::move(person));
    }
  }
  return out;
}

}  // namespace acro::capture
