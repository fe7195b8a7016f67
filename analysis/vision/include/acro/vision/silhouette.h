#pragma once

// Silhouettes (issue "virtual against real"): the athlete's, cut out of a video by a background
// model, and a virtual body's, by projecting its mesh with the camera model and filling the
// triangles (no renderer needed); their intersection over union says how well the two agree — a
// wrong sync or calibration shows as a drop.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/video.h"
#include "acro/vision/camera.h"

namespace acro::vision {

/// A binary image, rows top to bottom, one byte per pixel: 255 inside, 0 outside.
struct Mask {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;

  int CountInside() const;
};

/// A rectangle of pixels, [x0, x1) × [y0, y1); empty when x1 ≤ x0 or y1 ≤ y0.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

/// The silhouette of a triangle mesh (vertices in W, 3 × V; triangles 3 × T) in the camera's
/// image: every triangle with all three vertices in front of the camera, its vertices projected
/// (distortion applied) and the triangle filled. Triangles crossing the camera plane are left out.
/// `drawn`, when given, gets the smallest rectangle holding every pixel set (empty: none).
Mask RenderSilhouette(const Camera& camera,
                      const Eigen::Matrix3Xd& vertices_W,
                      const Eigen::Matrix3Xi& triangles,
                      PixelRect* drawn = nullptr);

/// |A ∩ B| / |A ∪ B| of two masks of one size (1 when both are empty). Throws
/// std::invalid_argument for masks of different sizes.
double IntersectionOverUnion(const Mask& a, const Mask& b);

struct BackgroundOptions {
  /// A grey pixel is foreground where it differs from the background by more than this (of 255).
  int threshold = 25;
  /// A colour pixel is foreground where its channel that differs most from the background differs
  /// by more than this. Higher than the grey threshold: the largest of three channels' noises is
  /// larger than the noise of their weighted mean, grey (about 1.6× for independent channels), and
  /// a pixel half covered by a strongly coloured athlete still passes. On the sample video the
  /// median flight IoU is 0.866 with 25 and 0.894 with 40 (docs/overlay.md).
  int colour_threshold = 40;
  /// Morphological opening then closing with a square of this side (px) removes speckle and fills
  /// small holes; 0 leaves the raw difference.
  int clean_px = 5;
};

/// The static background of a fixed camera: the per-pixel median of frames spread over the video
/// (where the athlete moves, every pixel shows the background in most of them), grey or colour as
/// the frames are. Colour separates what grey confuses (skin on a grey wall).
class BackgroundModel {
 public:
  /// Reads `num_samples` frames spread evenly over the video (an RGB reader for a colour model, a
  /// grey one for speed). Throws acro::InputError when the video has fewer than 3 frames.
  BackgroundModel(capture::VideoReader& video, int num_samples = 25);
  /// The background from frames given directly (all grey or all RGB, one size).
  explicit BackgroundModel(const std::vector<capture::VideoFrame>& frames);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  /// How many models this process has built from a video: for the tests that hold a door to one.
  static long long BuiltCount();
  const std::vector<std::uint8_t>& grey() const { return grey_; }

  /// The foreground of one frame (the background's size): by colour when both are RGB, else by
  /// grey level.
  Mask Foreground(const capture::VideoFrame& frame, const BackgroundOptions& options = {}) const;
  /// The same inside `region` only (clipped to the frame), every pixel outside it 0: inside, each
  /// pixel equals Foreground(frame, options)'s (the cleaning sees the pixels around the region it
  /// reaches). For a check that looks at the athlete's box alone: a 1080p frame's foreground costs
  /// ~5 ms, the athlete's box a tenth of it.
  Mask Foreground(const capture::VideoFrame& frame,
                  const BackgroundOptions& options,
                  const PixelRect& region) const;

 private:
  int width_ = 0;
  int height_ = 0;
  int channels_ = 1;
  std::vector<std::uint8_t> median_;  ///< per pixel and channel
  std::vector<std::uint8_t> grey_;
};

}  // namespace acro::vision
