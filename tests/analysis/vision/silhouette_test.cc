// Silhouettes: a projected sphere against the analytic disc, the intersection over union against
// its definition, and the background model cutting a moving shape out of noisy frames.

#include "acro/vision/silhouette.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace acro::vision {
namespace {

// A UV sphere of `rings` × `sectors` around `c`.
void MakeSphere(const Eigen::Vector3d& c,
                double r,
                int rings,
                int sectors,
                Eigen::Matrix3Xd* v,
                Eigen::Matrix3Xi* t) {
  v->resize(3, (rings + 1) * sectors);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      v->col(i * sectors + j) =
          c + r * Eigen::Vector3d(
                      std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  t->resize(3, 2 * rings * sectors);
  int k = 0;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const int a = i * sectors + j, b = i * sectors + (j + 1) % sectors;
      t->col(k++) << a, a + sectors, b;
      t->col(k++) << b, a + sectors, b + sectors;
    }
}

Camera Pinhole() {
  Camera c;
  c.name = "pinhole";
  c.width_px = 640;
  c.height_px = 480;
  c.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  return c;
}

// A sphere of radius r at distance d on the optical axis images as a disc of radius
// f r / √(d² − r²) (the cone of rays tangent to it).
TEST(Silhouette, ProjectedSphereIsTheAnalyticDisc) {
  Eigen::Matrix3Xd v;
  Eigen::Matrix3Xi t;
  const double r = 0.5, d = 3.0;
  MakeSphere(Eigen::Vector3d(0, 0, d), r, 96, 192, &v, &t);
  const Mask m = RenderSilhouette(Pinhole(), v, t);
  const double radius = 500.0 * r / std::sqrt(d * d - r * r);
  const double area = M_PI * radius * radius;
  RecordProperty("pixels", m.CountInside());
  RecordProperty("disc_area", std::to_string(area));
  EXPECT_NEAR(m.CountInside(), area, 0.003 * area);  // pixel-centre sampling: no rim
  // The disc's centre pixel is inside, a pixel just beyond its rim outside.
  EXPECT_EQ(m.pixels[240 * 640 + 320], 255);
  EXPECT_EQ(m.pixels[240 * 640 + 320 + int(radius) + 3], 0);
  // Behind the camera: nothing.
  MakeSphere(Eigen::Vector3d(0, 0, -d), r, 16, 32, &v, &t);
  EXPECT_EQ(RenderSilhouette(Pinhole(), v, t).CountInside(), 0);
}

TEST(Silhouette, IntersectionOverUnionOfTwoDiscs) {
  Eigen::Matrix3Xd v;
  Eigen::Matrix3Xi t;
  MakeSphere(Eigen::Vector3d(0, 0, 3), 0.5, 64, 128, &v, &t);
  const Mask a = RenderSilhouette(Pinhole(), v, t);
  EXPECT_DOUBLE_EQ(IntersectionOverUnion(a, a), 1.0);
  // The disc moved sideways by its radius R: two discs a distance R apart,
  // IoU = (2π/3 − √3/2) / (4π/3 + √3/2) = 0.2430.
  const int R = int(std::lround(500.0 * 0.5 / std::sqrt(9.0 - 0.25)));
  Mask b = a;
  std::fill(b.pixels.begin(), b.pixels.end(), 0);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x + R < a.width; ++x)
      b.pixels[size_t(y) * a.width + x + R] = a.pixels[size_t(y) * a.width + x];
  const double expected = (2 * M_PI / 3 - std::sqrt(3.0) / 2) / (4 * M_PI / 3 + std::sqrt(3.0) / 2);
  EXPECT_NEAR(IntersectionOverUnion(a, b), expected, 0.005);
  Mask other;
  other.width = 10;
  other.height = 10;
  other.pixels.assign(100, 0);
  EXPECT_THROW(IntersectionOverUnion(a, other), std::invalid_argument);
}

// Twenty noisy grey frames of a static scene with a bright square crossing it: the median is the
// background, and the square is cut out of a frame with IoU ≥ 0.95 against the truth.
TEST(Silhouette, BackgroundModelCutsOutTheMovingShape) {
  const int w = 160, h = 120;
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, 4.0);
  auto frame_at = [&](int k, Mask* truth) {
    capture::VideoFrame f;
    f.width = w;
    f.height = h;
    f.channels = 1;
    f.pixels.resize(size_t(w) * h);
    if (truth) {
      truth->width = w;
      truth->height = h;
      truth->pixels.assign(size_t(w) * h, 0);
    }
    const int x0 = 5 + 7 * k, y0 = 40;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool inside = x >= x0 && x < x0 + 30 && y >= y0 && y < y0 + 40;
        const double base = 60 + 0.5 * x + 0.3 * y;  // a gradient wall
        f.pixels[size_t(y) * w + x] =
            std::uint8_t(std::clamp((inside ? 200.0 : base) + noise(rng), 0.0, 255.0));
        if (truth && inside) truth->pixels[size_t(y) * w + x] = 255;
      }
    return f;
  };
  std::vector<capture::VideoFrame> frames;
  for (int k = 0; k < 20; ++k) frames.push_back(frame_at(k, nullptr));
  const BackgroundModel background(frames);
  Mask truth;
  const capture::VideoFrame f = frame_at(9, &truth);
  const Mask cut = background.Foreground(f);
  EXPECT_GE(IntersectionOverUnion(cut, truth), 0.95);
}

}  // namespace
}  // namespace acro::vision
