#include "acro/views/filmstrip.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"

namespace acro::ui {

std::vector<int> EvenlySpacedFrames(int first, int last, int count) {
  std::vector<int> frames;
  if (count <= 0 || last < first) return frames;
  if (count == 1) return {first};
  for (int k = 0; k < count; ++k)
    frames.push_back(first +
                     static_cast<int>(std::lround(double(k) * (last - first) / (count - 1))));
  return frames;
}

std::vector<std::uint8_t> RenderFilmstrip(analysis::AthleteScene& scene,
                                          const std::vector<int>& frames,
                                          const Eigen::Vector3d& heading_W,
                                          const FilmstripOptions& options) {
  if (frames.empty()) throw std::invalid_argument("RenderFilmstrip: no frame");
  for (const int f : frames)
    if (f < 0 || f >= scene.num_frames())
      throw std::invalid_argument("RenderFilmstrip: frame " + std::to_string(f) + " of " +
                                  std::to_string(scene.num_frames()));
  Eigen::Vector3d forward(heading_W.x(), heading_W.y(), 0.0);
  forward =
      forward.norm() > 1e-9 ? Eigen::Vector3d(forward.normalized()) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward);
  // Seen from the athlete's left, the picture's right is the athlete's back (−forward): the strip
  // runs that way, so time goes left to right.
  const Eigen::Vector3d along = -forward;
  const XDisplay display;
  SceneRenderer renderer(options.width, options.height, 4);
  renderer.SetBackground({1, 1, 1, 1});
  renderer.SetSceneLights({{0.3, 0.5, -1}, {-0.4, 0.2, -1}}, 0.5, 0.5);
  analysis::AthletePose pose;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  const double n = static_cast<double>(frames.size());
  Eigen::Vector3d first_com = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < frames.size(); ++k) {
    scene.Pose(frames[k], &pose);
    if (k == 0) first_com = pose.com_W;
    // Along the strip, k spacings from the middle (about the first pose's COM); the height as it
    // was, so the flight's rise and fall show.
    const Eigen::Vector3d place = first_com + (double(k) - (n - 1) / 2) * options.spacing_m * along;
    Eigen::Vector3d shift = place - pose.com_W;
    shift.z() = 0.0;
    analysis::SceneMesh mesh = pose.mesh;
    mesh.vertices_W.colwise() += shift;
    mesh.colour = options.colour;
    renderer.AddMesh(mesh);
    lo = lo.cwiseMin(mesh.vertices_W.rowwise().minCoeff());
    hi = hi.cwiseMax(mesh.vertices_W.rowwise().maxCoeff());
  }
  FreeViewpoint view;
  view.target_W = (lo + hi) / 2;
  view.eye_W = view.target_W + 20.0 * left;
  // Parallel projection fitting every pose with a margin.
  const double half_w = 0.5 * (hi - lo).cwiseAbs().dot(along.cwiseAbs()) + 0.3;
  const double half_h = 0.5 * (hi.z() - lo.z()) + 0.3;
  view.parallel_scale_m = std::max(half_h, half_w * options.height / options.width);
  renderer.LookFrom(view);
  RenderImage image;
  renderer.Render(&image);
  std::vector<std::uint8_t> rgb(size_t(options.width) * size_t(options.height) * 3);
  for (size_t i = 0, n_px = size_t(options.width) * size_t(options.height); i < n_px; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = image.rgba[4 * i + size_t(c)];
  return rgb;
}

}  // namespace acro::ui
