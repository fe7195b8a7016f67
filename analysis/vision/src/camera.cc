#include "acro/vision/camera.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>
#include <Eigen/Geometry>
#include <pugixml.hpp>

#include "acro/base/nesting.h"

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::vision {

namespace {

// The distortion of normalised coordinates (x, y), as Project applies it.
Eigen::Vector2d Distort(const std::vector<double>& distortion, double x, double y) {
  const auto d = [&](size_t i) { return i < distortion.size() ? distortion[i] : 0.0; };
  const double r2 = x * x + y * y;
  const double radial = 1.0 + d(0) * r2 + d(1) * r2 * r2 + d(4) * r2 * r2 * r2;
  return {x * radial + 2.0 * d(2) * x * y + d(3) * (r2 + 2.0 * x * x),
          y * radial + d(2) * (r2 + 2.0 * y * y) + 2.0 * d(3) * x * y};
}

}  // namespace

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d p = R_KW * p_W + t_KW;
  if (!(p.z() > 0.0)) return std::nullopt;
  // Brown–Conrady distortion on normalised coordinates, as OpenCV's projectPoints applies it
  // (OpenCV documentation, "Camera Calibration and 3D Reconstruction"):
  //   x' = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2 x²), y' likewise with p1 ↔ p2.
  const Eigen::Vector2d xd = Distort(distortion, p.x() / p.z(), p.y() / p.z());
  return Eigen::Vector2d(K(0, 0) * xd.x() + K(0, 1) * xd.y() + K(0, 2), K(1, 1) * xd.y() + K(1, 2));
}

Eigen::Vector2d Camera::Undistort(const Eigen::Vector2d& uv_px) const {
  // Distorted normalised coordinates, then x ← x_d − (distort(x) − x) until it stops moving.
  const double yd = (uv_px.y() - K(1, 2)) / K(1, 1);
  const double xd = (uv_px.x() - K(0, 2) - K(0, 1) * yd) / K(0, 0);
  Eigen::Vector2d x(xd, yd);
  for (int i = 0; i < 100 && !distortion.empty(); ++i) {
    const Eigen::Vector2d step = Eigen::Vector2d(xd, yd) - (Distort(distortion, x.x(), x.y()) - x);
    const bool done = (step - x).norm() < 1e-12;
    x = step;
    if (done) break;
  }
  return {K(0, 0) * x.x() + K(0, 1) * x.y() + K(0, 2), K(1, 1) * x.y() + K(1, 2)};
}

Eigen::Vector3d Camera::RayInWorld(const Eigen::Vector2d& uv_px) const {
  const Eigen::Vector2d u = Undistort(uv_px);
  const double y = (u.y() - K(1, 2)) / K(1, 1);
  const double x = (u.x() - K(0, 2) - K(0, 1) * y) / K(0, 0);
  return (R_KW.transpose() * Eigen::Vector3d(x, y, 1.0)).normalized();
}

bool Camera::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (width_px <= 0 || height_px <= 0)
    return fail(fmt::format("size {} x {} px is not positive", width_px, height_px));
  if (name.size() > 200)
    return fail(fmt::format("a camera name of {} bytes (at most 200)", name.size()));
  for (const char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return fail("the camera name holds a control character");
  if (!(K(0, 0) > 0 && K(1, 1) > 0) || !K.allFinite())
    return fail("the focal lengths of the matrix are not positive");
  // Physical ranges (docs/limits.md, "Cameras"): a pinhole matrix's last row is (0, 0, 1) and its
  // (1, 0) entry 0; a focal length from 0.05 to 100 image sides spans fields of view from 169° to
  // 0.6° (every lens from a fisheye's centre to a telephoto); the principal point lies within an
  // image side of the image.
  if (K(2, 0) != 0 || K(2, 1) != 0 || std::abs(K(2, 2) - 1) > 1e-9 || K(1, 0) != 0)
    return fail(
        fmt::format("the matrix's last row is ({:g}, {:g}, {:g}) and its (1, 0) entry {:g}: "
                    "a camera matrix has (0, 0, 1) and 0",
                    K(2, 0),
                    K(2, 1),
                    K(2, 2),
                    K(1, 0)));
  const double side = std::max(width_px, height_px);
  for (const double f : {K(0, 0), K(1, 1)})
    if (!(f >= 0.05 * side && f <= 100 * side))
      return fail(
          fmt::format("focal length {:g} px is outside {:g} … {:g} px (0.05 to 100 times the "
                      "image's {} px side)",
                      f,
                      0.05 * side,
                      100 * side,
                      side));
  if (std::abs(K(0, 1)) > K(0, 0))
    return fail(fmt::format("skew {:g} exceeds the focal length {:g}", K(0, 1), K(0, 0)));
  if (!(K(0, 2) >= -width_px && K(0, 2) <= 2.0 * width_px && K(1, 2) >= -height_px &&
        K(1, 2) <= 2.0 * height_px))
    return fail(
        fmt::format("principal point ({:g}, {:g}) px is more than an image side outside "
                    "the {} x {} image",
                    K(0, 2),
                    K(1, 2),
                    width_px,
                    height_px));
  if (!R_KW.allFinite() || (R_KW * R_KW.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      std::abs(R_KW.determinant() - 1.0) > 1e-6)
    return fail("the rotation is not orthonormal with determinant +1");
  if (!t_KW.allFinite()) return fail("the translation is not finite");
  if (t_KW.norm() > 1e4)
    return fail(
        fmt::format("the camera is {:.3g} m from the origin (a hall is not 10 km wide; "
                    "translations are in metres)",
                    t_KW.norm()));
  for (double k : distortion)
    if (!std::isfinite(k)) return fail("a distortion coefficient is not finite");
  for (double k : distortion)
    if (std::abs(k) > 1000)
      return fail(fmt::format("distortion coefficient {:g} is beyond ±1000", k));
  if (distortion.size() != 0 && distortion.size() != 4 && distortion.size() != 5)
    return fail(
        fmt::format("{} distortion coefficients (4 or 5: k1 k2 p1 p2 [k3])", distortion.size()));
  return true;
}

void AimCamera(Camera* camera, const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  camera->R_KW.row(0) = x.transpose();
  camera->R_KW.row(1) = z.cross(x).transpose();
  camera->R_KW.row(2) = z.transpose();
  camera->t_KW = -camera->R_KW * centre;
}

Camera FitCameraToVideo(
    const Camera& camera, int width, int height, const std::string& video, std::string* note) {
  Camera fitted = camera;
  fitted.width_px = width;
  fitted.height_px = height;
  if (std::abs(width - camera.width_px) <= 16 && std::abs(height - camera.height_px) <= 16)
    return fitted;
  const double sx = double(width) / camera.width_px, sy = double(height) / camera.height_px;
  if (width <= 0 || height <= 0 || std::abs(sx / sy - 1.0) > 0.01) {
    throw InputError(
        video,
        "",
        fmt::format("is {} x {} px, camera {} was calibrated at {} x {}: neither that "
                    "size nor a scaled copy of it (aspect {:.3f} against {:.3f}); give "
                    "the calibration of this video",
                    width,
                    height,
                    camera.name,
                    camera.width_px,
                    camera.height_px,
                    double(width) / std::max(1, height),
                    double(camera.width_px) / camera.height_px));
  }
  // Pixel centres: x_new + ½ = s (x_old + ½).
  fitted.K.row(0) *= sx;
  fitted.K.row(1) *= sy;
  fitted.K(0, 2) = (camera.K(0, 2) + 0.5) * sx - 0.5;
  fitted.K(1, 2) = (camera.K(1, 2) + 0.5) * sy - 0.5;
  if (note)
    *note = fmt::format(
        "{} is {} x {} px, camera {} was calibrated at {} x {}: the camera is "
        "scaled by {:.4g} to it",
        video,
        width,
        height,
        camera.name,
        camera.width_px,
        camera.height_px,
        sx);
  return fitted;
}

Eigen::Matrix3d RotationFromRodrigues(const Eigen::Vector3d& r) {
  const double angle = r.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
}

Eigen::Vector3d RodriguesFromRotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd a(R);
  return a.angle() * a.axis();
}

namespace {

// Reads `count` numbers of an array value `key` of `table`, naming file, camera and key on error.
std::vector<double> Numbers(const toml::table& table,
                            std::string_view key,
                            size_t count,
                            const std::string& file,
                            const std::string& camera) {
  const toml::array* array = table[key].as_array();
  if (array == nullptr)
    throw InputError(file, camera, std::string(key) + ": missing or not an array");
  std::vector<double> out;
  for (const toml::node& n : *array) {
    if (const toml::array* row = n.as_array()) {
      for (const toml::node& m : *row) {
        const std::optional<double> v = m.value<double>();
        if (!v) throw InputError(file, camera, std::string(key) + ": an entry is not a number");
        out.push_back(*v);
      }
    } else {
      const std::optional<double> v = n.value<double>();
      if (!v) throw InputError(file, camera, std::string(key) + ": an entry is not a number");
      out.push_back(*v);
    }
  }
  if (count != 0 && out.size() != count) {
    throw InputError(
        file, camera, fmt::format("{}: {} numbers, expected {}", key, out.size(), count));
  }
  return out;
}

// An image width or height read as a number: 1 to 100 000 px (the cast of anything else to int
// would be undefined).
int ImageSide(double v, const std::string& file, const std::string& where, const char* what) {
  if (!(v >= 1 && v <= 100000))
    throw InputError(
        file, where, fmt::format("{}: {} px is not an image size (1–100000)", what, v));
  if (v != std::floor(v))
    throw InputError(
        file, where, fmt::format("{}: {} px is not a whole number of pixels", what, v));
  return static_cast<int>(std::lround(v));
}

}  // namespace

std::vector<Camera> ReadPose2SimToml(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(16) << 20);
  DemandNestingAtMost(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                      64,
                      path.string());
  toml::table root;
  try {
    root = toml::parse(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                       file);
  } catch (const toml::parse_error& e) {
    throw InputError(
        file, fmt::format("line {}", e.source().begin.line), std::string(e.description()));
  }
  std::vector<Camera> cameras;
  for (const auto& [key, node] : root) {
    const toml::table* t = node.as_table();
    if (t == nullptr || key.str() == "metadata") continue;
    const std::string where = fmt::format("[{}]", key.str());
    Camera c;
    c.name = (*t)["name"].value_or(std::string(key.str()));
    const std::vector<double> size = Numbers(*t, "size", 2, file, where);
    c.width_px = ImageSide(size[0], file, where, "size");
    c.height_px = ImageSide(size[1], file, where, "size");
    const std::vector<double> k = Numbers(*t, "matrix", 9, file, where);
    c.K = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(k.data());
    c.distortion = Numbers(*t, "distortions", 0, file, where);
    if (c.distortion.empty())  // written by mistake: a lens without distortion has four zeros
      throw InputError(file, where, "distortions: empty; give k1 k2 p1 p2 (four zeros for none)");
    const std::vector<double> r = Numbers(*t, "rotation", 0, file, where);
    if (r.size() == 3) {
      c.R_KW = RotationFromRodrigues(Eigen::Vector3d(r[0], r[1], r[2]));
    } else if (r.size() == 9) {
      c.R_KW = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.data());
    } else {
      throw InputError(
          file, where, fmt::format("rotation: {} numbers (3: Rodrigues, or 9)", r.size()));
    }
    const std::vector<double> tr = Numbers(*t, "translation", 3, file, where);
    c.t_KW = Eigen::Vector3d(tr[0], tr[1], tr[2]);
    if ((*t)["fisheye"].value_or(false))
      throw InputError(file, where, "fisheye cameras are not supported");
    std::string why;
    if (!c.IsValid(&why)) throw InputError(file, where, why);
    cameras.push_back(std::move(c));
  }
  if (cameras.empty()) throw InputError(file, "", "no camera in the file");
  return cameras;
}

std::vector<Camera> ReadQualisysQca(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(16) << 20);
  DemandNestingAtMost(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                      64,
                      path.string());
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(bytes.data(), bytes.size());
  if (!parsed) {
    throw InputError(file, fmt::format("byte {}", parsed.offset), parsed.description());
  }
  // A required numeric attribute of `node`, naming file, camera and attribute when absent.
  auto number = [&](const pugi::xml_node& node, const char* name, const std::string& camera) {
    const pugi::xml_attribute a = node.attribute(name);
    char* end = nullptr;
    const double v = a ? std::strtod(a.value(), &end) : 0.0;
    if (!a || end == a.value() || !std::isfinite(v)) {
      throw InputError(
          file, camera, fmt::format("{}.{}: missing or not a number", node.name(), name));
    }
    return v;
  };
  std::vector<Camera> cameras;
  for (const pugi::xml_node cam : doc.child("calibration").child("cameras").children("camera")) {
    Camera c;
    c.name = cam.attribute("serial").value();
    const std::string where = "camera '" + c.name + "'";
    // QTM's flag of a camera in use: read although unused here, so that a damaged one is said.
    if (const pugi::xml_attribute active = cam.attribute("active");
        active && std::string_view(active.value()) != "0" &&
        std::string_view(active.value()) != "1")
      throw InputError(file, where, fmt::format("active: '{}' is not 0 or 1", active.value()));
    const pugi::xml_node transform = cam.child("transform");
    const pugi::xml_node intrinsic = cam.child("intrinsic");
    const pugi::xml_node fov = cam.child("fov_video");
    if (!transform || !intrinsic || !fov)
      throw InputError(file, where, "needs <transform>, <intrinsic> and <fov_video>");
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r(i, j) = number(transform, fmt::format("r{}{}", i + 1, j + 1).c_str(), where);
    c.R_KW = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal() * r;
    const Eigen::Vector3d centre_m(number(transform, "x", where) / 1000.0,
                                   number(transform, "y", where) / 1000.0,
                                   number(transform, "z", where) / 1000.0);
    c.t_KW = -c.R_KW * centre_m;
    c.width_px = ImageSide(
        number(fov, "right", where) - number(fov, "left", where) + 1, file, where, "fov_video");
    c.height_px = ImageSide(
        number(fov, "bottom", where) - number(fov, "top", where) + 1, file, where, "fov_video");
    c.K << number(intrinsic, "focalLengthU", where) / 64.0, 0.0,
        number(intrinsic, "centerPointU", where) / 64.0, 0.0,
        number(intrinsic, "focalLengthV", where) / 64.0,
        number(intrinsic, "centerPointV", where) / 64.0, 0.0, 0.0, 1.0;
    c.distortion = {number(intrinsic, "radialDistortion1", where),
                    number(intrinsic, "radialDistortion2", where),
                    number(intrinsic, "tangentalDistortion1", where),
                    number(intrinsic, "tangentalDistortion2", where),
                    number(intrinsic, "radialDistortion3", where)};
    std::string why;
    if (!c.IsValid(&why)) throw InputError(file, where, why);
    cameras.push_back(std::move(c));
  }
  if (cameras.empty()) throw InputError(file, "", "no <camera> under <calibration><cameras>");
  return cameras;
}

void WritePose2SimToml(const std::vector<Camera>& cameras, const std::filesystem::path& path) {
  std::ostringstream out;
  out.precision(17);
  for (const Camera& c : cameras) {
    const Eigen::Vector3d r = RodriguesFromRotation(c.R_KW);
    out << "[" << c.name << "]\n"
        << "name = \"" << c.name << "\"\n"
        << "size = [ " << double(c.width_px) << ", " << double(c.height_px) << "]\n"
        << "matrix = [ [ " << c.K(0, 0) << ", " << c.K(0, 1) << ", " << c.K(0, 2) << "], [ "
        << c.K(1, 0) << ", " << c.K(1, 1) << ", " << c.K(1, 2) << "], [ " << c.K(2, 0) << ", "
        << c.K(2, 1) << ", " << c.K(2, 2) << "]]\n"
        << "distortions = [";
    for (size_t i = 0; i < c.distortion.size(); ++i) out << (i ? ", " : " ") << c.distortion[i];
    out << "]\n"
        << "rotation = [ " << r.x() << ", " << r.y() << ", " << r.z() << "]\n"
        << "translation = [ " << c.t_KW.x() << ", " << c.t_KW.y() << ", " << c.t_KW.z() << "]\n"
        << "fisheye = false\n\n";
  }
  WriteFileAtomically(path, out.str());
}

}  // namespace acro::vision
