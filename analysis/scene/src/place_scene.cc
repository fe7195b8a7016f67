#include "acro/scene/place_scene.h"

#include <Eigen/Geometry>

namespace acro::analysis {

namespace {

// Appends segment a → b.
void AddSegment(SceneLines* lines, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Index n = lines->points_W.cols();
  lines->points_W.conservativeResize(3, n + 2);
  lines->points_W.col(n) = a;
  lines->points_W.col(n + 1) = b;
}

}  // namespace

TrampolineScene MakeTrampolineScene(const BedGeometry& bed, const TrampolineDimensions& d) {
  const Eigen::Vector3d x =
      Eigen::Vector3d(bed.long_axis_W.x(), bed.long_axis_W.y(), 0.0).normalized();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d y = z.cross(x);
  const Eigen::Vector3d c = bed.centre_W;
  // Rectangle corners in the order (+x, +y), (−x, +y), (−x, −y), (+x, −y): the BED_C order.
  auto corners = [&](double length, double width) {
    Eigen::Matrix<double, 3, 4> out;
    const double sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
    for (int k = 0; k < 4; ++k) out.col(k) = c + 0.5 * sx[k] * length * x + 0.5 * sy[k] * width * y;
    return out;
  };
  const Eigen::Matrix<double, 3, 4> in = corners(bed.length_m, bed.width_m);
  const Eigen::Matrix<double, 3, 4> out = corners(d.frame_length_m, d.frame_width_m);

  TrampolineScene t;
  t.bed.name = "bed";
  t.bed.colour = {0.12f, 0.12f, 0.14f, 1.0f};
  t.bed.vertices_W = in;
  t.bed.triangles.resize(3, 2);
  t.bed.triangles << 0, 0, 1, 2, 2, 3;  // (0 1 2) and (0 2 3), counter-clockwise seen from above

  t.frame.name = "frame";
  t.frame.colour = {0.15f, 0.35f, 0.75f, 1.0f};
  t.frame.vertices_W.resize(3, 8);
  t.frame.vertices_W << in, out;
  t.frame.triangles.resize(3, 8);
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    // The quad in_k, out_k, out_n, in_n, counter-clockwise seen from above.
    t.frame.triangles.col(2 * k) << k, 4 + k, 4 + n;
    t.frame.triangles.col(2 * k + 1) << k, 4 + n, n;
  }

  t.springs.name = "springs";
  t.springs.colour = {0.75f, 0.75f, 0.78f, 1.0f};
  t.springs.width_px = 1.0;
  // The springs reach 60 % of the way to the frame's outside (the frame tube, under its pad).
  const double gap_x = 0.5 * (d.frame_length_m - bed.length_m) * 0.6;
  const double gap_y = 0.5 * (d.frame_width_m - bed.width_m) * 0.6;
  for (int side = 0; side < 4; ++side) {
    const Eigen::Vector3d a = in.col(side), b = in.col((side + 1) % 4);
    const bool long_side = side % 2 == 0;  // sides 0 and 2 run along x
    const int n = long_side ? d.springs_long_side : d.springs_short_side;
    const Eigen::Vector3d outward = side == 0   ? Eigen::Vector3d(y * gap_y)
                                    : side == 1 ? Eigen::Vector3d(-x * gap_x)
                                    : side == 2 ? Eigen::Vector3d(-y * gap_y)
                                                : Eigen::Vector3d(x * gap_x);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d p = a + (b - a) * ((i + 0.5) / n);
      AddSegment(&t.springs, p, p + outward);
    }
  }

  t.legs.name = "legs";
  t.legs.colour = {0.4f, 0.4f, 0.45f, 1.0f};
  for (int k = 0; k < 4; ++k) AddSegment(&t.legs, out.col(k), out.col(k) - d.height_m * z);

  t.cross.name = "cross";
  t.cross.colour = {0.9f, 0.2f, 0.2f, 1.0f};
  AddSegment(&t.cross, c - 0.3 * x, c + 0.3 * x);
  AddSegment(&t.cross, c - 0.3 * y, c + 0.3 * y);
  return t;
}

SceneLines MakeCameraFrustum(const vision::Camera& camera, double depth_m) {
  SceneLines f;
  f.name = "camera " + camera.name;
  f.colour = {0.95f, 0.75f, 0.1f, 1.0f};
  const Eigen::Vector3d centre = camera.CentreInWorld();
  const Eigen::Vector3d axis = camera.R_KW.row(2).transpose();  // the optical axis in W
  const Eigen::Vector2d pixels[4] = {{0.0, 0.0},
                                     {double(camera.width_px), 0.0},
                                     {double(camera.width_px), double(camera.height_px)},
                                     {0.0, double(camera.height_px)}};
  Eigen::Vector3d far[4];
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d ray = camera.RayInWorld(pixels[k]);
    far[k] = centre + ray * (depth_m / ray.dot(axis));
    AddSegment(&f, centre, far[k]);
  }
  for (int k = 0; k < 4; ++k) AddSegment(&f, far[k], far[(k + 1) % 4]);
  return f;
}

}  // namespace acro::analysis
