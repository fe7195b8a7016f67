#include "acro/capture/detections.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/nesting.h"
#include "acro/base/text.h"
#include "acro/capture/trc.h"

namespace acro::capture {

const std::vector<std::string>& KeypointSetNames(const std::string& set) {
  // OpenPose's output formats (openpose doc/02_output.md; BODY_25B from its experimental models
  // page) and HALPE's 26 keypoints (Fang et al., AlphaPose, 2022); COCO's 17 are HALPE's first.
  static const std::map<std::string, std::vector<std::string>> sets = {
      {"body25", {"Nose",   "Neck",    "RShoulder", "RElbow", "RWrist", "LShoulder", "LElbow",
                  "LWrist", "MidHip",  "RHip",      "RKnee",  "RAnkle", "LHip",      "LKnee",
                  "LAnkle", "REye",    "LEye",      "REar",   "LEar",   "LBigToe",   "LSmallToe",
                  "LHeel",  "RBigToe", "RSmallToe", "RHeel"}},
      {"body25b", {"Nose",   "LEye",    "REye",      "LEar",   "REar", "LShoulder", "RShoulder",
                   "LElbow", "RElbow",  "LWrist",    "RWrist", "LHip", "RHip",      "LKnee",
                   "RKnee",  "LAnkle",  "RAnkle",    "Neck",   "Head", "LBigToe",   "LSmallToe",
                   "LHeel",  "RBigToe", "RSmallToe", "RHeel"}},
      {"coco17",
       {"Nose",
        "LEye",
        "REye",
        "LEar",
        "REar",
        "LShoulder",
        "RShoulder",
        "LElbow",
        "RElbow",
        "LWrist",
        "RWrist",
        "LHip",
        "RHip",
        "LKnee",
        "RKnee",
        "LAnkle",
        "RAnkle"}},
      {"halpe26", {"Nose",    "LEye",      "REye",      "LEar",   "REar", "LShoulder", "RShoulder",
                   "LElbow",  "RElbow",    "LWrist",    "RWrist", "LHip", "RHip",      "LKnee",
                   "RKnee",   "LAnkle",    "RAnkle",    "Head",   "Neck", "Hip",       "LBigToe",
                   "RBigToe", "LSmallToe", "RSmallToe", "LHeel",  "RHeel"}}};
  const auto it = sets.find(set);
  if (it == sets.end())
    throw InputError(
        "", "--keypoints", "unknown keypoint set '" + set + "' (body25, body25b, coco17, halpe26)");
  return it->second;
}

namespace {

// The last run of digits in a file name's stem (OpenPose pads to 12: 000000000042), or -1 when
// there is none or it has more than 9 significant digits.
long long LastNumber(const std::string& stem) {
  size_t i = stem.size();
  while (i > 0 && !std::isdigit(static_cast<unsigned char>(stem[i - 1]))) --i;
  if (i == 0) return -1;
  size_t begin = i;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
  while (begin + 1 < i && stem[begin] == '0') ++begin;  // leading zeros
  if (i - begin > 9) return -1;
  return std::stoll(stem.substr(begin, i - begin));
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
  // Without exceptions: a link loop or an unreadable entry is the folder's fault, said in one line.
  std::filesystem::directory_iterator it(directory, ec);
  if (ec) throw InputError(directory.string(), "", "cannot list: " + ec.message());
  for (; it != std::filesystem::directory_iterator(); it.increment(ec)) {
    if (ec) throw InputError(directory.string(), "", "cannot list: " + ec.message());
    const std::filesystem::directory_entry& entry = *it;
    if (LowerExtension(entry.path()) != "json") continue;
    std::error_code kind;
    const bool regular = entry.is_regular_file(kind);
    if (kind) throw InputError(entry.path().string(), "", "cannot be read: " + kind.message());
    if (!regular) continue;
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
    DemandNestingAtMost(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), 64, file);
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(bytes.begin(), bytes.end());
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(file, AtByte(static_cast<long long>(e.byte)), "not JSON");
    } catch (const nlohmann::json::exception& e) {  // a number beyond double, say
      throw InputError(file, "", fmt::format("not JSON: {}", e.what()));
    }
    if (!doc.is_object() || !doc.contains("people") || !doc["people"].is_array())
      throw InputError(file, "people", "missing or not an array");
    std::vector<DetectedPerson>& people = out.frames[static_cast<size_t>(frame)];
    const nlohmann::json& all = doc["people"];
    for (size_t i = 0; i < all.size(); ++i) {
      const std::string where = fmt::format("people[{}].pose_keypoints_2d", i);
      if (!all[i].is_object() || !all[i].contains("pose_keypoints_2d"))
        throw InputError(
            file, fmt::format("people[{}]", i), "not an object with pose_keypoints_2d");
      const nlohmann::json& k = all[i]["pose_keypoints_2d"];
      if (!k.is_array()) throw InputError(file, where, "missing or not an array");
      if (k.empty()) continue;  // OpenPose writes an empty list for a person it dropped
      if (k.size() != 3 * K) {
        throw InputError(
            file,
            where,
            fmt::format(
                "{} numbers, but the {} set has {} keypoints × 3", k.size(), keypoint_set, K));
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

KeypointDetections ReadDetectionsCsv(const std::filesystem::path& path, const std::string& camera) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(1) << 30);
  LineCursor lines(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  std::string_view line;
  std::vector<std::string_view> f;
  if (!lines.Next(&line)) throw InputError(file, "", "empty file");
  Split(Trim(line), ',', &f);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < f.size(); ++i) column[std::string(Trim(f[i]))] = i;
  const auto find = [&](std::initializer_list<const char*> names, bool required) -> long {
    for (const char* n : names)
      if (const auto it = column.find(n); it != column.end()) return static_cast<long>(it->second);
    if (required) {
      throw InputError(
          file,
          "line 1",
          fmt::format("no '{}' column in the header (frame, marker, u_px, v_px)", *names.begin()));
    }
    return -1;
  };
  const long c_frame = find({"frame"}, true), c_name = find({"marker", "keypoint"}, true),
             c_u = find({"u_px"}, true), c_v = find({"v_px"}, true),
             c_conf = find({"confidence"}, false), c_camera = find({"camera"}, false);
  KeypointDetections out;
  out.source = file;
  std::map<std::string, int> index;
  struct Row {
    long frame;
    int keypoint;
    Eigen::Vector3d value;
  };
  std::vector<Row> rows;
  long last_frame = -1;
  while (lines.Next(&line)) {
    if (Trim(line).empty()) continue;
    Split(Trim(line), ',', &f);
    const std::string where = fmt::format("line {}", lines.line_number());
    if (f.size() != column.size())
      throw InputError(
          file, where, fmt::format("{} fields, the header has {}", f.size(), column.size()));
    if (c_camera >= 0 && !camera.empty() && Trim(f[size_t(c_camera)]) != camera) continue;
    auto number = [&](long c) {
      const std::string text(Trim(f[size_t(c)]));
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
        throw InputError(file, where, fmt::format("'{}' is not a number", text));
      return v;
    };
    const double frame = number(c_frame);
    if (frame < 0 || frame >= 1000000 || frame != std::floor(frame))
      throw InputError(
          file, where, fmt::format("frame {} is not a frame number (0 to 999999)", frame));
    const std::string name(Trim(f[size_t(c_name)]));
    const auto [it, added] = index.emplace(name, static_cast<int>(out.names.size()));
    if (added) out.names.push_back(name);
    rows.push_back({static_cast<long>(frame),
                    it->second,
                    {number(c_u), number(c_v), c_conf >= 0 ? number(c_conf) : 1.0}});
    last_frame = std::max(last_frame, rows.back().frame);
  }
  if (rows.empty())
    throw InputError(file, "", camera.empty() ? "no rows" : "no rows of camera " + camera);
  out.frames.resize(static_cast<size_t>(last_frame + 1));
  const Eigen::Index K = static_cast<Eigen::Index>(out.names.size());
  for (const Row& r : rows) {
    std::vector<DetectedPerson>& people = out.frames[static_cast<size_t>(r.frame)];
    if (people.empty()) {
      // Keypoints not in a frame's rows are absent: confidence 0.
      people.emplace_back(DetectedPerson::Zero(3, K));
    }
    people.front().col(r.keypoint) = r.value;
  }
  for (std::vector<DetectedPerson>& people : out.frames)
    for (DetectedPerson& p : people)
      if (p.cols() < K) p.conservativeResizeLike(DetectedPerson::Zero(3, K));
  return out;
}

KeypointDetections ReadDetectionsTrc(const std::filesystem::path& path) {
  const Trial trial = ReadTrc(path);
  const std::string file = path.string();
  if (trial.num_frames == 0 || trial.num_points() == 0) throw InputError(file, "", "no frame");
  // The file's own numbers (the reader scaled them to metres by the header's unit).
  const double scale = 1.0 / trial.source.point_units_to_m;
  bool legacy = true;
  for (int f = 0; f < trial.num_frames; ++f) {
    for (int p = 0; p < trial.num_points(); ++p) {
      if (!trial.valid(f, p)) continue;
      const Eigen::Vector3d x = trial.position(f, p) * scale;
      if (x.z() != 0.0) {
        throw InputError(file,
                         fmt::format("frame {}", trial.first_frame + f),
                         fmt::format("{}: Z = {} is not 0: a 3D file, not 2D detections",
                                     trial.points[static_cast<size_t>(p)].label,
                                     x.z()));
      }
      if (std::abs(x.x()) > 10.0 || std::abs(x.y()) > 10.0 || x.y() > 0.0) legacy = false;
    }
  }
  KeypointDetections out;
  out.source = file;
  for (const PointInfo& p : trial.points) out.names.push_back(p.label);
  const double t0 = trial.source.first_time_s;
  const double first = std::round(t0 * trial.point_rate_hz);
  if (!(first >= 0 && first < 1000000))
    throw InputError(file, "time", fmt::format("first time {} s is not a video time", t0));
  out.frames.resize(static_cast<size_t>(first) + static_cast<size_t>(trial.num_frames));
  const Eigen::Index K = trial.num_points();
  for (int f = 0; f < trial.num_frames; ++f) {
    DetectedPerson person = DetectedPerson::Zero(3, K);
    for (int p = 0; p < trial.num_points(); ++p) {
      if (!trial.valid(f, p)) continue;
      const Eigen::Vector3d x = trial.position(f, p) * scale;
      if (x.x() == 0.0 && x.y() == 0.0) continue;
      person.col(p) = legacy ? Eigen::Vector3d(1000.0 * x.x(), -1000.0 * x.y(), 1.0)
                             : Eigen::Vector3d(x.x(), x.y(), 1.0);
    }
    out.frames[static_cast<size_t>(first) + static_cast<size_t>(f)].push_back(std::move(person));
  }
  out.warnings = trial.warnings;
  out.warnings.push_back(
      legacy ? file + ": 2D TRC read as Sports2D before 0.5 wrote it: pixels ÷ 1000, y up"
             : file + ": 2D TRC read as pixels, x right and y down");
  return out;
}

KeypointDetections ReadDetections(const std::filesystem::path& path,
                                  const std::string& keypoint_set,
                                  const std::string& camera) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return ReadOpenPoseJson(path, keypoint_set);
  if (LowerExtension(path) == "csv") return ReadDetectionsCsv(path, camera);
  if (LowerExtension(path) == "trc") return ReadDetectionsTrc(path);
  throw InputError(
      path.string(), "", "detections are a directory of OpenPose JSON files, a .csv or a 2D .trc");
}

}  // namespace acro::capture
