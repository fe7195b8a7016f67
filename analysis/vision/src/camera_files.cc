// OpenCV FileStorage calibrations, and reading any calibration format by its extension.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/nesting.h"
#include "acro/vision/camera.h"

namespace acro::vision {

namespace {

// One FileStorage, with errors that name the file and the key.
class Storage {
 public:
  explicit Storage(const std::filesystem::path& path) : file_(path.string()) {
    if (!IsRegularFile(path)) throw InputError(file_, "", "no such file");
    // Refuse huge files before OpenCV reads them whole.
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(file_, "", "cannot read: " + ec.message());
    if (size > (std::uintmax_t(16) << 20))
      throw InputError(file_, "", "larger than 16 MiB: not a calibration");
    // OpenCV's parsers recurse per level: a file nested 100,000 deep overflowed the stack.
    const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(16) << 20);
    DemandNestingAtMost(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), 64, file_);
    try {
      fs_.open(file_, cv::FileStorage::READ);
    } catch (const cv::Exception& e) {
      // OpenCV's message spans lines and names its own source; keep what it says about ours.
      std::string what = e.err.empty() ? e.what() : e.err;
      for (char& c : what)
        if (c == '\n') c = ' ';
      throw InputError(file_, "", "not an OpenCV FileStorage file: " + what);
    }
    if (!fs_.isOpened()) throw InputError(file_, "", "not an OpenCV FileStorage file");
  }

  const std::string& file() const { return file_; }
  bool Has(const std::string& key) const { return !fs_[key].empty(); }

  // A matrix of `rows` × `cols` doubles (either orientation of a vector), or nothing if absent.
  std::optional<cv::Mat> Matrix(const std::string& key,
                                int rows,
                                int cols,
                                const std::string& camera) const {
    const cv::FileNode node = fs_[key];
    if (node.empty()) return std::nullopt;
    cv::Mat m = ReadMat(node, key, camera);
    if (cols == 1 && m.rows == 1) m = m.t();
    if (m.rows != rows || m.cols != cols) {
      throw InputError(
          file_,
          camera,
          fmt::format("{}: {} × {}, expected {} × {}", key, m.rows, m.cols, rows, cols));
    }
    return m;
  }

  // An !!opencv-matrix, or a plain sequence of numbers (a row), as a one-channel CV_64F matrix.
  cv::Mat ReadMat(const cv::FileNode& node,
                  const std::string& key,
                  const std::string& camera) const {
    cv::Mat m;
    try {
      if (node.isSeq()) {
        std::vector<double> values;
        for (const cv::FileNode& item : node) {
          if (!item.isReal() && !item.isInt())
            throw InputError(file_, camera, key + ": not a matrix (a sequence of numbers)");
          values.push_back(static_cast<double>(item));
        }
        m = cv::Mat(values, true).t();
      } else {
        // An !!opencv-matrix allocates rows × cols before it reads its data: a calibration's
        // matrices are at most 3 × 3 or 1 × 14, so anything past 16 × 16 is refused first.
        if (node.isMap()) {
          const cv::FileNode rows = node["rows"], cols = node["cols"];
          const double r = rows.isInt() || rows.isReal() ? static_cast<double>(rows) : -1.0;
          const double c = cols.isInt() || cols.isReal() ? static_cast<double>(cols) : -1.0;
          if (!(r >= 1 && r <= 16 && c >= 1 && c <= 16)) {
            throw InputError(
                file_, camera, fmt::format("{}: {} × {} is not a calibration matrix", key, r, c));
          }
        }
        node >> m;
      }
    } catch (const cv::Exception&) {
      throw InputError(file_, camera, key + ": not a matrix");
    }
    if (m.empty() || m.channels() != 1) throw InputError(file_, camera, key + ": not a matrix");
    m.convertTo(m, CV_64F);
    return m;
  }

  std::vector<double> Distortion(const std::string& key, const std::string& camera) const {
    const cv::Mat m = ReadMat(fs_[key], key, camera);
    if (m.total() != 4 && m.total() != 5 && m.total() != 8) {
      throw InputError(
          file_,
          camera,
          fmt::format("{}: {} coefficients (4, 5 or 8: k1 k2 p1 p2 [k3 …])", key, m.total()));
    }
    std::vector<double> d(m.begin<double>(), m.end<double>());
    if (d.size() == 8) {
      // The rational model's k4 k5 k6 are not in the camera model: refuse them unless zero.
      for (size_t i = 5; i < 8; ++i)
        if (d[i] != 0.0)
          throw InputError(file_, camera, key + ": the rational model (k4–k6) is not supported");
      d.resize(5);
    }
    return d;
  }

  int Integer(const std::string& key, const std::string& camera) const {
    const cv::FileNode node = fs_[key];
    if (node.empty() || (!node.isReal() && !node.isInt()))
      throw InputError(file_, camera, key + ": missing or not a number");
    const double v = static_cast<double>(node);
    if (!(v >= -1e9 && v <= 1e9) || v != std::floor(v))
      throw InputError(file_, camera, fmt::format("{}: {} is not an integer", key, v));
    return static_cast<int>(v);
  }

  std::vector<std::string> Names() const {
    std::vector<std::string> names;
    const cv::FileNode node = fs_["names"];
    if (!node.isSeq()) throw InputError(file_, "names", "not a sequence of camera names");
    for (const cv::FileNode& n : node) {
      if (!n.isString()) throw InputError(file_, "names", "an entry is not a string");
      names.push_back(static_cast<std::string>(n));
    }
    return names;
  }

 private:
  std::string file_;
  cv::FileStorage fs_;
};

Eigen::Matrix3d ToEigen3(const cv::Mat& m) {
  Eigen::Matrix3d e;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) e(i, j) = m.at<double>(i, j);
  return e;
}

Eigen::Vector3d ToEigenVector(const cv::Mat& m) {
  return Eigen::Vector3d(m.at<double>(0), m.at<double>(1), m.at<double>(2));
}

// The pose from a Rodrigues key or a matrix key and a translation key; identity when all absent.
void ReadPose(const Storage& s,
              const std::string& rodrigues_key,
              const std::string& matrix_key,
              const std::string& translation_key,
              const std::string& where,
              const Storage* fallback,
              Camera* c) {
  for (const Storage* st : {&s, fallback}) {
    if (st == nullptr) continue;
    const std::optional<cv::Mat> R = st->Matrix(matrix_key, 3, 3, where);
    const std::optional<cv::Mat> r = R ? std::nullopt : st->Matrix(rodrigues_key, 3, 1, where);
    const std::optional<cv::Mat> t = st->Matrix(translation_key, 3, 1, where);
    if (!R && !r && !t) continue;
    if (!t) throw InputError(st->file(), where, translation_key + ": missing beside the rotation");
    if (!R && !r)
      throw InputError(st->file(),
                       where,
                       rodrigues_key + " or " + matrix_key + ": missing beside the translation");
    c->R_KW = R ? ToEigen3(*R) : RotationFromRodrigues(ToEigenVector(*r));
    c->t_KW = ToEigenVector(*t);
    return;
  }
}

// ReadOpenCvStorage without the guard around OpenCV's parser.
std::vector<Camera> ReadStorageCameras(const std::filesystem::path& path) {
  const Storage s(path);
  std::vector<Camera> cameras;
  if (!s.Has("names")) {
    Camera c;
    c.name = path.stem().string();
    const std::string where = "camera '" + c.name + "'";
    const std::optional<cv::Mat> K = s.Matrix("camera_matrix", 3, 3, where);
    if (!K)
      throw InputError(s.file(), "camera_matrix", "missing (and no `names` of several cameras)");
    c.K = ToEigen3(*K);
    c.width_px = s.Integer("image_width", where);
    c.height_px = s.Integer("image_height", where);
    if (s.Has("distortion_coefficients"))
      c.distortion = s.Distortion("distortion_coefficients", where);
    ReadPose(s, "rvec", "R", s.Has("tvec") ? "tvec" : "T", where, nullptr, &c);
    std::string why;
    if (!c.IsValid(&why)) throw InputError(s.file(), where, why);
    cameras.push_back(std::move(c));
    return cameras;
  }
  // EasyMocap's pair: intri.yml holds K and the distortion, extri.yml beside it the poses.
  std::optional<Storage> extri;
  const std::string stem = path.stem().string();
  if (stem == "intri") {
    const std::filesystem::path other = path.parent_path() / ("extri" + path.extension().string());
    if (PathExists(other)) extri.emplace(other);
  }
  for (const std::string& name : s.Names()) {
    Camera c;
    c.name = name;
    const std::string where = "camera '" + name + "'";
    const std::optional<cv::Mat> K = s.Matrix("K_" + name, 3, 3, where);
    if (!K) throw InputError(s.file(), where, "K_" + name + ": missing");
    c.K = ToEigen3(*K);
    const std::string dist_key = s.Has("dist_" + name) ? "dist_" + name : "D_" + name;
    if (s.Has(dist_key)) c.distortion = s.Distortion(dist_key, where);
    c.width_px = s.Integer("W_" + name, where);
    c.height_px = s.Integer("H_" + name, where);
    ReadPose(s, "R_" + name, "Rot_" + name, "T_" + name, where, extri ? &*extri : nullptr, &c);
    std::string why;
    if (!c.IsValid(&why)) throw InputError(s.file(), where, why);
    cameras.push_back(std::move(c));
  }
  if (cameras.empty()) throw InputError(s.file(), "names", "no camera named");
  return cameras;
}

}  // namespace

std::vector<Camera> ReadOpenCvStorage(const std::filesystem::path& path) {
  // OpenCV's parser throws more than cv::Exception on a damaged file (std::length_error from a
  // string it sizes from the file: found by the camera fuzzer); each is the file's fault.
  try {
    return ReadStorageCameras(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path.string(), "", std::string("not an OpenCV FileStorage file: ") + e.what());
  }
}

namespace {

std::vector<Camera> ReadCamerasByFormat(const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  const std::string name = path.filename().string();
  if (ext == "toml") return ReadPose2SimToml(path);
  if (ext == "qca" || (name.size() > 8 && name.substr(name.size() - 8) == ".qca.txt"))
    return ReadQualisysQca(path);
  if (ext == "xml") {
    // Qualisys' export is XML too: tell by the root element.
    const std::vector<std::uint8_t> head = ReadFileBytes(path, std::int64_t(16) << 20);
    const std::string text(head.begin(), head.begin() + std::min<size_t>(head.size(), 4096));
    if (text.find("<calibration") != std::string::npos) return ReadQualisysQca(path);
    return ReadOpenCvStorage(path);
  }
  if (ext == "yml" || ext == "yaml" || ext == "json") return ReadOpenCvStorage(path);
  throw InputError(path.string(),
                   "",
                   "unknown calibration format " +
                       (ext.empty() ? std::string("(no extension)") : "'." + ext + "'") +
                       " (.toml Pose2Sim, .qca Qualisys, .yml/.yaml/.xml/.json OpenCV)");
}

}  // namespace

std::vector<Camera> ReadCameras(const std::filesystem::path& path) {
  std::vector<Camera> cameras = ReadCamerasByFormat(path);
  // Two cameras of one name would be one to --camera (it selected both).
  for (size_t i = 0; i < cameras.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (cameras[i].name == cameras[j].name)
        throw InputError(path.string(), "",
                         fmt::format("camera name '{}' is given twice (cameras {} and {})",
                                     cameras[i].name, j + 1, i + 1));
  return cameras;
}

const Camera& FindCamera(const std::vector<Camera>& cameras,
                         const std::string& name,
                         const std::string& file) {
  std::string names;
  for (const Camera& c : cameras) {
    if (c.name == name || (name.empty() && cameras.size() == 1)) return c;
    names += (names.empty() ? "" : ", ") + c.name;
  }
  if (name.empty())
    throw InputError(
        file, "--camera", fmt::format("{} cameras ({}): name one", cameras.size(), names));
  throw InputError(file, "--camera", "no camera named '" + name + "' (there are " + names + ")");
}

}  // namespace acro::vision
