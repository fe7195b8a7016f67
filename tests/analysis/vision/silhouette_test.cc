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

// Colour frames: a textured wall, noise, and blobs that move; the background of 15 of them.
std::vector<capture::VideoFrame> ColourFrames(int w, int h, int count) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 9.0);
  std::vector<capture::VideoFrame> frames;
  for (int k = 0; k < count; ++k) {
    capture::VideoFrame f;
    f.width = w;
    f.height = h;
    f.channels = 3;
    f.pixels.resize(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool blob = std::hypot(x - (20 + 9 * k), y - 0.5 * h) < 18 ||
                          (x < 12 && y > h - 15 && k % 2 == 0) ||  // at the frame's corner
                          (std::abs(x - (w - 25 - 4 * k)) < 3 && y > 10 && y < 60);  // thin
        for (int c = 0; c < 3; ++c) {
          const double wall = 80 + 40 * std::sin(0.11 * x + c) + 30 * std::cos(0.07 * y);
          const double v = blob ? (c == 0 ? 210 : 70) : wall;
          f.pixels[(size_t(y) * w + x) * 3 + c] =
              std::uint8_t(std::clamp(v + noise(rng), 0.0, 255.0));
        }
      }
    frames.push_back(std::move(f));
  }
  return frames;
}

// The foreground worked out in a region is, inside it, the whole frame's, pixel for pixel — the
// cleaning's reach included, at the frame's edges too — and 0 outside; by colour and by grey.
TEST(Silhouette, ForegroundInARegionIsTheWholeFramesThere) {
  const int w = 200, h = 150;
  const std::vector<capture::VideoFrame> frames = ColourFrames(w, h, 16);
  const BackgroundModel colour(std::vector<capture::VideoFrame>(frames.begin(), frames.end() - 1));
  std::vector<capture::VideoFrame> greys;
  for (const capture::VideoFrame& f : frames) {
    capture::VideoFrame g;
    g.width = w;
    g.height = h;
    g.channels = 1;
    for (size_t i = 0; i < size_t(w) * h; ++i)
      g.pixels.push_back(
          std::uint8_t((int(f.pixels[3 * i]) + f.pixels[3 * i + 1] + f.pixels[3 * i + 2]) / 3));
    greys.push_back(std::move(g));
  }
  const BackgroundModel grey(std::vector<capture::VideoFrame>(greys.begin(), greys.end() - 1));
  // (the last frame's disc is centred at (155, 75), radius 18; its bar at x 113–117, y 11–59)
  const std::vector<PixelRect> regions = {{145, 65, 160, 80},
                                          {130, 50, 158, 78},
                                          {100, 30, 116, 45},
                                          {40, 30, 90, 100},
                                          {0, 0, 30, 25},
                                          {150, 100, 200, 150},
                                          {-20, -5, 500, 400},
                                          {60, 60, 61, 61},
                                          {70, 20, 70, 80},
                                          {300, 300, 320, 320}};
  for (const BackgroundOptions& options :
       {BackgroundOptions{}, BackgroundOptions{.clean_px = 0}, BackgroundOptions{.clean_px = 4}}) {
    using Case = std::pair<const BackgroundModel*, const capture::VideoFrame*>;
    for (const auto& [model, frame] : {Case{&colour, &frames.back()}, Case{&grey, &greys.back()}}) {
      const Mask whole = model->Foreground(*frame, options);
      ASSERT_GT(whole.CountInside(), 500);
      for (const PixelRect& r : regions) {
        const Mask part = model->Foreground(*frame, options, r);
        ASSERT_EQ(part.width, w);
        ASSERT_EQ(part.height, h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const bool in = x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
            const size_t i = size_t(y) * w + x;
            ASSERT_EQ(part.pixels[i], in ? whole.pixels[i] : 0)
                << "region " << r.x0 << "," << r.y0 << "–" << r.x1 << "," << r.y1 << " pixel " << x
                << "," << y << " channels " << frame->channels << " clean " << options.clean_px;
          }
      }
    }
  }
  // Uncleaned, by colour, it is the definition: the largest channel's difference from the
  // background's median over the threshold (the median from the frames, worked out here).
  const BackgroundOptions raw{.clean_px = 0};
  const Mask cut = colour.Foreground(frames.back(), raw);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    int d = 0;
    for (int c = 0; c < 3; ++c) {
      std::vector<int> v;
      for (size_t k = 0; k + 1 < frames.size(); ++k) v.push_back(frames[k].pixels[3 * i + c]);
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      d = std::max(d, std::abs(int(frames.back().pixels[3 * i + c]) - v[v.size() / 2]));
    }
    ASSERT_EQ(cut.pixels[i], d > raw.colour_threshold ? 255 : 0) << "pixel " << i;
  }
}

// The rectangle RenderSilhouette says it drew holds every pixel set, and no smaller one does.
TEST(Silhouette, RenderSaysTheBoxItDrew) {
  Eigen::Matrix3Xd v;
  Eigen::Matrix3Xi t;
  MakeSphere(Eigen::Vector3d(0.3, -0.2, 4.0), 0.5, 16, 24, &v, &t);
  PixelRect drawn;
  const Mask m = RenderSilhouette(Pinhole(), v, t, &drawn);
  PixelRect scanned{m.width, m.height, 0, 0};
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      if (m.pixels[size_t(y) * m.width + x]) {
        scanned.x0 = std::min(scanned.x0, x);
        scanned.y0 = std::min(scanned.y0, y);
        scanned.x1 = std::max(scanned.x1, x + 1);
        scanned.y1 = std::max(scanned.y1, y + 1);
      }
  ASSERT_FALSE(drawn.empty());
  EXPECT_EQ(drawn.x0, scanned.x0);
  EXPECT_EQ(drawn.y0, scanned.y0);
  EXPECT_EQ(drawn.x1, scanned.x1);
  EXPECT_EQ(drawn.y1, scanned.y1);
  // Behind the camera: nothing drawn, an empty box.
  MakeSphere(Eigen::Vector3d(0, 0, -4.0), 0.5, 8, 12, &v, &t);
  RenderSilhouette(Pinhole(), v, t, &drawn);
  EXPECT_TRUE(drawn.empty());
}

}  // namespace
}  // namespace acro::vision
