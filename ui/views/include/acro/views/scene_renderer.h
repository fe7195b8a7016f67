#pragma once

// Draws a scene (analysis/scene's meshes, lines and points) with VTK into an image, offscreen:
// actors are built once and updated per frame in place (no allocation after the first frame).
// Two ways to look: a free viewpoint (orbit, follow, side/front/top), or through a calibrated
// camera's pinhole — its K as an explicit OpenGL projection matrix (fx ≠ fy, an off-centre
// principal point and skew are kept exactly; docs/overlay.md derives the matrix), its pose as the
// view. Distortion is not a matrix: CameraComposite (camera_composite.h) warps the pinhole render
// by it onto the video frame.
//
// A SceneRenderer needs an X display (display.h): make an XDisplay first.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/scene/scene.h"
#include "acro/vision/camera.h"

namespace acro::ui {

/// A rectangle of pixels [x0, x1) × [y0, y1), y down.
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

/// An RGBA image, rows top to bottom, colours premultiplied by alpha (what OpenGL blending over a
/// transparent background leaves): composite as out = rgb + (1 − a) · under. It is the part of
/// the view at (x0, y0) (all of it unless a region was read).
struct RenderImage {
  int x0 = 0;
  int y0 = 0;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

/// A free viewpoint: the eye, where it looks, which way is up, and the vertical view angle.
struct FreeViewpoint {
  Eigen::Vector3d eye_W = Eigen::Vector3d(0, -8, 1.5);
  Eigen::Vector3d target_W = Eigen::Vector3d(0, 0, 1.5);
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();
  double view_angle_deg = 30.0;
  /// > 0: a parallel projection showing this many metres above and below the target (no
  /// perspective: sizes compare across the picture).
  double parallel_scale_m = 0.0;
};

/// The presets of the 3D view, named as a coach names them for a trampoline (the bed's long axis
/// along x): from the side (looking along +y, across the bed), from the front (along −x, down the
/// bed's long axis) and from the top.
enum class ViewPreset { kSide, kFront, kTop };

/// `preset` looking at `target_W` from `distance_m`, for an athlete facing `heading_W`
/// (horizontal): the side view from the athlete's right, the front view from ahead, the top view
/// from above with the athlete's left up the picture. The default heading is +x (the side view from
/// −y).
FreeViewpoint PresetViewpoint(ViewPreset preset,
                              const Eigen::Vector3d& target_W,
                              double distance_m,
                              const Eigen::Vector3d& heading_W = Eigen::Vector3d::UnitX());

/// `view` following the athlete: its target moved onto `target_W` (the athlete's centre of mass)
/// and its eye by the same translation — the same direction, distance and view angle, the scene
/// sliding past behind.
FreeViewpoint FollowViewpoint(const FreeViewpoint& view, const Eigen::Vector3d& target_W);

/// The viewpoint rotated about the vertical through its target by `azimuth_deg` and raised by
/// `elevation_deg` (orbit).
FreeViewpoint OrbitViewpoint(const FreeViewpoint& view, double azimuth_deg, double elevation_deg);

/// The OpenGL projection matrix (clip = P · eye, eye looking down −z, y up) whose pixels are the
/// pinhole camera K's: pixel centre (u, v) of an image `width` × `height` (v down, OpenCV's
/// convention) is the clip-space point that OpenGL rasterises at window coordinates
/// (u + ½, height − v − ½). Depth from `near_m` to `far_m`.
Eigen::Matrix4d PinholeProjectionMatrix(
    const Eigen::Matrix3d& K, int width, int height, double near_m, double far_m);

/// A line of text (FreeType, monospace) on a translucent dark box with a margin of a quarter of
/// its height: the heads-up line over video. No X display needed, a fraction of a millisecond: it
/// is drawn on the frame, not rendered by OpenGL. `out` is reused.
void RenderTextLine(const std::string& text, int size_px, analysis::Rgba colour, RenderImage* out);

class SceneRenderer {
 public:
  /// An offscreen view of `width` × `height` pixels; `multisamples` > 0 smooths edges, for stills
  /// (on Mesa's software rasteriser, 4× multisampling adds 66 ms to a 1080p frame, FXAA 53 ms,
  /// against 4.5 ms for the frame without: video overlays go without).
  SceneRenderer(int width, int height, int multisamples = 0);
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  int width() const;
  int height() const;

  /// Adds a triangle mesh (its triangles are fixed; its vertices move with UpdateMesh). Returns
  /// the actor's id.
  int AddMesh(const analysis::SceneMesh& mesh);
  void UpdateMesh(int id, const Eigen::Matrix3Xd& vertices_W);
  /// Adds line segments drawn as shaded tubes of `lines.width_px` pixels (capsules when joints
  /// are drawn as points too).
  int AddLines(const analysis::SceneLines& lines);
  /// Updates the segments (their number may change: a growing trail).
  void UpdateLines(int id, const Eigen::Matrix3Xd& points_W);
  /// Adds points drawn as spheres of `radius_m` (true meshes: exact under any projection, unlike
  /// point sprites, which Mesa places half a pixel off).
  int AddPoints(const Eigen::Matrix3Xd& points_W, double radius_m, analysis::Rgba colour);
  /// Updates the points (their number may change; memory grows only, by doubling).
  void UpdatePoints(int id, const Eigen::Matrix3Xd& points_W);
  void SetVisible(int id, bool visible);
  void SetColour(int id, analysis::Rgba colour);
  /// Shaded by the lights (the default), or flat in its colour (for measuring what is drawn).
  void SetLit(int id, bool lit);

  /// Lights fixed in the scene (a hall's ceiling lights) instead of VTK's single headlight, which
  /// leaves surfaces parallel to the view (a floor seen from the side) black: `direction_W` is
  /// where each light shines to; a dimmer headlight stays. Call once, before rendering.
  void SetSceneLights(const std::vector<Eigen::Vector3d>& directions_W,
                      double intensity,
                      double headlight_intensity);

  /// The background; alpha 0 (the default) for renders composited over video.
  void SetBackground(analysis::Rgba colour);

  /// Looks through the camera's pinhole (K and pose; its distortion is ignored here). The camera's
  /// image size must be this renderer's.
  void LookThrough(const vision::Camera& pinhole);
  void LookFrom(const FreeViewpoint& view);

  /// Renders and reads the image back: all of it, or only `region` (clipped to the view), which is
  /// all a composite over video needs when the scene covers a part of the frame.
  void Render(RenderImage* out);
  void Render(const PixelBox& region, RenderImage* out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::ui
