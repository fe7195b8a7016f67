#pragma once

// The place around the athlete: the trampoline (from the bed the trial shows, or placed by hand,
// with the FIG apparatus' dimensions) and the cameras (as frusta), in the lab frame W.

#include <Eigen/Core>

#include "acro/assess/trial_analysis.h"
#include "acro/scene/scene.h"
#include "acro/vision/calibration.h"
#include "acro/vision/camera.h"

namespace acro::analysis {

/// The FIG trampoline's dimensions (FIG Apparatus Norms, trampoline): the woven bed 4.28 m ×
/// 2.14 m, the frame 5.05 m × 2.91 m outside, the bed 1.155 m above the floor; the frame pads are
/// drawn this wide and the springs this many per long and short side.
struct TrampolineDimensions {
  double frame_length_m = fig::kFrameLength_m;
  double frame_width_m = fig::kFrameWidth_m;
  double height_m = fig::kBedHeight_m;
  int springs_long_side = 40;
  int springs_short_side = 20;
};

struct TrampolineScene {
  SceneMesh bed;       ///< the woven bed at rest: a rectangle, two triangles
  SceneMesh frame;     ///< the frame and its pads: the ring between the bed and the frame's outside
  SceneLines springs;  ///< from the bed's edge to the frame's inner edge
  SceneLines legs;     ///< the frame's corners down to the floor
  SceneLines cross;    ///< the bed's centre cross (where the athlete should land)
};

/// The trampoline of `bed` (its centre, long axis and size from the trial's BED markers, FindBed,
/// or given), its frame and legs from `dimensions`. Z up.
TrampolineScene MakeTrampolineScene(const BedGeometry& bed,
                                    const TrampolineDimensions& dimensions = {});

/// A camera as a frustum: its centre, and the four image corners' rays (distortion removed) cut
/// `depth_m` in front of it along its optical axis; 8 segments (4 edges from the centre, the far
/// rectangle).
SceneLines MakeCameraFrustum(const vision::Camera& camera, double depth_m);

}  // namespace acro::analysis
