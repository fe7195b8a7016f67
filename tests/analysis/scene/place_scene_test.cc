// The trampoline and the cameras as the scene draws them.

#include "acro/scene/place_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "acro/capture/trial_io.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

// The sample routine's bed markers give the bed; the frame is FIG's around it.
TEST(PlaceScene, TrampolineOfTheSampleRoutine) {
  const capture::Trial trial = capture::ReadTrial(
      acro::testing::SourceDir() / "samples/trials/trampoline_routine/trampoline_routine.c3d");
  const std::optional<BedGeometry> bed = FindBed(trial);
  ASSERT_TRUE(bed.has_value());
  const TrampolineScene t = MakeTrampolineScene(*bed);
  ASSERT_EQ(t.bed.vertices_W.cols(), 4);
  // The bed's corners are the markers' (to their noise), 4.28 m × 2.14 m apart.
  const Eigen::Vector3d c1 = t.bed.vertices_W.col(0), c2 = t.bed.vertices_W.col(1),
                        c3 = t.bed.vertices_W.col(2);
  EXPECT_NEAR((c1 - c2).norm(), bed->length_m, 1e-9);
  EXPECT_NEAR((c2 - c3).norm(), bed->width_m, 1e-9);
  EXPECT_NEAR(bed->length_m, 4.28, 0.01);
  EXPECT_NEAR(bed->width_m, 2.14, 0.01);
  // Triangles face up (counter-clockwise seen from above), bed and frame alike.
  for (const SceneMesh* m : {&t.bed, &t.frame}) {
    for (Eigen::Index k = 0; k < m->triangles.cols(); ++k) {
      const Eigen::Vector3d a = m->vertices_W.col(m->triangles(0, k)),
                            b = m->vertices_W.col(m->triangles(1, k)),
                            c = m->vertices_W.col(m->triangles(2, k));
      EXPECT_GT((b - a).cross(c - a).z(), 0.0) << m->name << " triangle " << k;
    }
  }
  // The frame's area is its outside less the bed; the legs reach the floor 1.155 m below.
  double area = 0.0;
  for (Eigen::Index k = 0; k < t.frame.triangles.cols(); ++k) {
    const Eigen::Vector3d a = t.frame.vertices_W.col(t.frame.triangles(0, k)),
                          b = t.frame.vertices_W.col(t.frame.triangles(1, k)),
                          c = t.frame.vertices_W.col(t.frame.triangles(2, k));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  EXPECT_NEAR(area, 5.05 * 2.91 - bed->length_m * bed->width_m, 1e-9);
  EXPECT_EQ(t.legs.num_segments(), 4);
  EXPECT_NEAR(t.legs.points_W(2, 0) - t.legs.points_W(2, 1), 1.155, 1e-12);
  EXPECT_EQ(t.springs.num_segments(), 2 * 40 + 2 * 20);
}

// The frustum's far corners project back onto the image's corners (the camera model's own
// projection: the frustum is the camera, distortion and all).
TEST(PlaceScene, CameraFrustumCornersProjectOntoTheImageCorners) {
  vision::Camera c;
  c.name = "cam";
  c.width_px = 1080;
  c.height_px = 1920;
  c.K << 1680, 0, 533, 0, 1681, 948, 0, 0, 1;
  c.distortion = {-0.046, 0.14, 0.0006, 0.0007, 0.0};
  c.R_KW = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  c.t_KW = Eigen::Vector3d(0.5, -0.2, 4.0);
  const SceneLines f = MakeCameraFrustum(c, 3.0);
  ASSERT_EQ(f.num_segments(), 8);
  const Eigen::Vector2d corners[4] = {{0, 0}, {1080, 0}, {1080, 1920}, {0, 1920}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((f.points_W.col(2 * k) - c.CentreInWorld()).norm(), 1e-12);
    const Eigen::Vector3d far = f.points_W.col(2 * k + 1);
    EXPECT_NEAR((c.R_KW * far + c.t_KW).z(), 3.0, 1e-9);  // 3 m along the optical axis
    const auto uv = c.Project(far);
    ASSERT_TRUE(uv.has_value());
    EXPECT_LT((*uv - corners[k]).norm(), 1e-6) << k;
  }
}

}  // namespace
}  // namespace acro::analysis
