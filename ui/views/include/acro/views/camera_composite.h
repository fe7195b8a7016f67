#pragma once

// Renders of a calibrated camera put onto its video frames exactly where the camera model puts
// each point, distortion included. The scene is rendered through a distortion-free pinhole camera
// — the camera's K, shifted onto a canvas wide enough to hold every pixel of the frame once
// undistorted — and each frame pixel takes the render's colour at its undistorted position
// (bilinear). The video is left as filmed: a coach compares the athlete with what the camera saw,
// so the distortion is applied to the image we make rather than removed from the one we were
// given (which would also blur and crop the video). docs/overlay.md.

#include <cstdint>
#include <vector>

#include "acro/views/scene_renderer.h"
#include "acro/vision/camera.h"

namespace acro::ui {

/// Blends `image` (premultiplied RGBA) over `rgb` (`width` × `height`, 3 bytes per pixel) with its
/// top-left corner at (x0, y0), clipped to the frame; no warp (the heads-up line).
void BlendOver(const RenderImage& image,
               int x0,
               int y0,
               int width,
               int height,
               std::vector<std::uint8_t>* rgb);

class CameraComposite {
 public:
  /// Builds the pixel map of `camera` (a few milliseconds for 1080p: the undistortion is solved
  /// on a 4-pixel grid and interpolated, within 0.01 px for lens distortion). The canvas is at
  /// most `max_canvas_scale` times the image on each axis; frame pixels whose undistorted
  /// position falls outside it are left as filmed.
  explicit CameraComposite(const vision::Camera& camera, double max_canvas_scale = 2.0);

  /// The camera to render through (SceneRenderer::LookThrough): the same pose and focal lengths,
  /// no distortion, the canvas' size and principal point.
  const vision::Camera& render_camera() const { return render_camera_; }
  /// True when the camera has distortion (otherwise the render is the frame's own geometry).
  bool warps() const { return warps_; }

  /// Blends `render` (all or part of render_camera()'s view, premultiplied RGBA) over `rgb` (the
  /// camera's size, 3 bytes per pixel, rows top to bottom), in place; only the frame pixels in
  /// `frame_box` (default: all).
  void Composite(const RenderImage& render, std::vector<std::uint8_t>* rgb) const;
  void Composite(const RenderImage& render,
                 const PixelBox& frame_box,
                 std::vector<std::uint8_t>* rgb) const;

  /// The part of the render view that the frame pixels in `frame_box` take their colour from
  /// (what to render and read back for them).
  PixelBox RenderRegion(const PixelBox& frame_box) const;

 private:
  vision::Camera camera_;
  vision::Camera render_camera_;
  bool warps_ = false;
  /// Per frame pixel: the render pixel above-left of its undistorted position (x −1: outside the
  /// canvas) and the bilinear weights of the right and lower neighbours in 1/256.
  std::vector<std::int16_t> tap_x_, tap_y_;
  std::vector<std::uint8_t> weight_x_, weight_y_;
};

}  // namespace acro::ui
