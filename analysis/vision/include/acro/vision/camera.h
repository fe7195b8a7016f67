#pragma once

// A calibrated camera (docs/formats/calibration.md): image size, intrinsic matrix K, OpenCV's
// distortion (k1 k2 p1 p2 [k3]), and the pose world → camera, p_K = R_KW p_W + t_KW with the
// camera looking along +z, x right and y down in the image (OpenCV's convention). Projection and
// the Pose2Sim/Anipose TOML format; no OpenCV type in this header.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::vision {

struct Camera {
  std::string name;
  int width_px = 0;
  int height_px = 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  /// k1 k2 p1 p2, optionally k3 (OpenCV's order); empty: no distortion.
  std::vector<double> distortion;
  Eigen::Matrix3d R_KW = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_KW = Eigen::Vector3d::Zero();

  /// The pixel of world point p_W (distortion applied), or nothing when the point is not in front
  /// of the camera.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_W) const;
  /// The inverse of the distortion: the pixel a distortion-free camera with the same K would
  /// show for what this camera shows at `uv_px` (OpenCV's undistortPoints with P = K). Solved by
  /// fixed-point iteration on the normalised coordinates to 1e-12, as OpenCV does, at most 100
  /// steps.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& uv_px) const;
  /// The unit direction, in the world, of the ray through pixel `uv_px` (distortion removed).
  Eigen::Vector3d RayInWorld(const Eigen::Vector2d& uv_px) const;
  /// The camera centre in the world.
  Eigen::Vector3d CentreInWorld() const { return -R_KW.transpose() * t_KW; }
  /// True when K, the distortion and the pose make a camera (R_KW orthonormal with det +1 to 1e-6,
  /// positive focal lengths, positive size); else false with the reason in *why.
  bool IsValid(std::string* why) const;
};

/// Sets the pose of `camera` to stand at `centre` (world, Z up) and look at `target`, the image's x
/// axis level (a camera on a tripod, not rolled). `target` must not be straight above or below.
void AimCamera(Camera* camera, const Eigen::Vector3d& centre, const Eigen::Vector3d& target);

/// The one image-size policy of every command that puts a camera on a video (docs/limits.md,
/// "Cameras"): a video of the calibrated size, or within 16 px of it (a calibration at the coded
/// size, 1088 rows, for a 1080-row video), takes the camera as it is, its pixels from the top-left
/// corner; a scaled copy (both sides scaled alike, to 1 %) takes the camera scaled to it, said in
/// `*note`; any other size is refused: acro::InputError naming `video`, both sizes.
Camera FitCameraToVideo(
    const Camera& camera, int width, int height, const std::string& video, std::string* note);

/// Reads a Pose2Sim/Anipose calibration: one table per camera with `name`, `size` [w, h],
/// `matrix` (3 × 3), `distortions` [k1 k2 p1 p2], `rotation` (Rodrigues vector, rad) and
/// `translation` (m), world → camera; a `[metadata]` table is skipped. Throws acro::InputError
/// naming the file, the camera and the key for anything missing or malformed, and for a camera
/// that is not valid.
std::vector<Camera> ReadPose2SimToml(const std::filesystem::path& path);

/// Reads a Qualisys Track Manager calibration (.qca, XML), one camera per `<camera>` named by its
/// `serial`: the `<transform>` r11..r33 (row by row) maps the lab into Qualisys' camera axes (x
/// right, y up, z backwards), so R_KW = diag(1, −1, −1) r; its x y z are the camera centre in mm;
/// the `<intrinsic>` centre and focal lengths are in sensor sub-pixels (÷ 64 for pixels), its
/// distortion coefficients radial 1–3 and tangential 1–2 are OpenCV's k1 k2 k3 p1 p2. The image
/// size is `fov_video`'s. Throws acro::InputError naming the file, the camera and the attribute.
std::vector<Camera> ReadQualisysQca(const std::filesystem::path& path);

/// Reads an OpenCV FileStorage file (YAML, XML or JSON) in either layout in use:
/// - one camera, as OpenCV's calibration sample writes it: `image_width`, `image_height`,
///   `camera_matrix`, `distortion_coefficients`, and optionally a pose `rvec` (Rodrigues) or `R`
///   (3 × 3) with `tvec` or `T`; the camera is named after the file;
/// - several, as EasyMocap's intri.yml/extri.yml: `names` (a sequence), then per name N `K_N`,
///   `dist_N` (or `D_N`), `W_N`/`H_N` (size), `Rot_N` (3 × 3) or `R_N` (Rodrigues) and `T_N`. A
///   file named intri.* is read with the extri.* beside it when there is one.
/// A camera without a pose gets the identity. Throws acro::InputError naming the file, the camera
/// and the key.
std::vector<Camera> ReadOpenCvStorage(const std::filesystem::path& path);

/// Any of the formats above, by extension and content: .toml (Pose2Sim), .qca or a `<calibration>`
/// XML document (Qualisys), .yml/.yaml/.xml/.json (OpenCV).
std::vector<Camera> ReadCameras(const std::filesystem::path& path);

/// The camera named `name` of a list, or (empty name) the only one. Throws acro::InputError
/// (file, where "--camera") naming the cameras there are.
const Camera& FindCamera(const std::vector<Camera>& cameras,
                         const std::string& name,
                         const std::string& file);

/// Writes cameras in the Pose2Sim/Anipose TOML format, atomically.
void WritePose2SimToml(const std::vector<Camera>& cameras, const std::filesystem::path& path);

/// The rotation of a Rodrigues vector (angle = its norm, about its direction), and back.
Eigen::Matrix3d RotationFromRodrigues(const Eigen::Vector3d& r);
Eigen::Vector3d RodriguesFromRotation(const Eigen::Matrix3d& R);

}  // namespace acro::vision
