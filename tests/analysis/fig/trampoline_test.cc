// The horizontal-displacement zones and a landing's zone and margin: the zone lines belong to the
// zone they bound, the worst contact point decides, and the margin found by the directional search
// equals the distance to the nearest line that changes the deduction, worked out by hand.
#include "acro/fig/trampoline.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace acro::fig {
namespace {

TEST(HdZones, DefaultZonesAndTheirLines) {
  const HdZones z = HdZones::Default();
  std::string why;
  ASSERT_TRUE(z.IsValid(&why)) << why;
  std::string name;
  EXPECT_DOUBLE_EQ(z.DeductionAt({0, 0}, &name), 0.0);
  EXPECT_EQ(name, "A");
  // On zone A's line: inside ("the lines belong to the marked areas").
  EXPECT_DOUBLE_EQ(z.DeductionAt({1.075, 0.54}, &name), 0.0);
  EXPECT_EQ(name, "A");
  EXPECT_DOUBLE_EQ(z.DeductionAt({1.08, 0.0}, &name), 0.1);
  EXPECT_EQ(name, "B");
  EXPECT_DOUBLE_EQ(z.DeductionAt({0.0, -0.6}, &name), 0.2);
  EXPECT_EQ(name, "C");
  EXPECT_DOUBLE_EQ(z.DeductionAt({2.2, 0.0}, &name), 0.3);
  EXPECT_EQ(name, "off the bed");
  EXPECT_DOUBLE_EQ(kZoneALength_m, 2.15);
  EXPECT_DOUBLE_EQ(kZoneAWidth_m, 1.08);
}

TEST(HdZones, ImpossibleZonesAreRefusedByName) {
  HdZones z = HdZones::Default();
  z.zones[1].deduction = 2.0;
  std::string why;
  EXPECT_FALSE(z.IsValid(&why));
  EXPECT_NE(why.find("zone B"), std::string::npos) << why;
  z = HdZones::Default();
  z.zones[0].x_min = 3.0;
  EXPECT_FALSE(z.IsValid(&why));
  EXPECT_NE(why.find("zone A is empty"), std::string::npos) << why;
}

// A foot-sized box (0.24 m × 0.09 m) centred at c: its four corners.
std::vector<Eigen::Vector2d> Foot(const Eigen::Vector2d& c) {
  return {c + Eigen::Vector2d(0.12, 0.045),
          c + Eigen::Vector2d(0.12, -0.045),
          c + Eigen::Vector2d(-0.12, 0.045),
          c + Eigen::Vector2d(-0.12, -0.045)};
}

TEST(ClassifyLanding, AFootNearZoneALineIsACloseCall) {
  const HdZones z = HdZones::Default();
  // Toe 12 cm inside A's end line: zone A, margin 12 cm, not a close call at 3 cm.
  HdLanding l = ClassifyLanding(z, Foot({0.835, 0.0}), 0.03);
  EXPECT_EQ(l.zone, "A");
  EXPECT_DOUBLE_EQ(l.deduction, 0.0);
  EXPECT_NEAR(l.margin_m, 0.12, 0.0011);
  EXPECT_FALSE(l.uncertain);
  l = ClassifyLanding(z, Foot({0.935, 0.0}), 0.03);
  EXPECT_NEAR(l.margin_m, 0.02, 0.0011);  // toe at 1.055: 2 cm from the line
  EXPECT_TRUE(l.uncertain);
  // Toe 2 cm over the line: zone B by "any part of a foot"; back into A takes 2 cm.
  l = ClassifyLanding(z, Foot({0.975, 0.0}), 0.03);
  EXPECT_EQ(l.zone, "B");
  EXPECT_DOUBLE_EQ(l.deduction, 0.1);
  EXPECT_NEAR(l.margin_m, 0.02, 0.0011);
  EXPECT_TRUE(l.uncertain);
}

// For one point the margin is the distance to the nearest line that changes its deduction, which
// for the default zones can be written down: a second way to the same number.
double HandMargin(const Eigen::Vector2d& p) {
  const double x = std::abs(p.x()), y = std::abs(p.y());
  const double ax = 1.075, ay = 0.54, bx = 2.14, by = 1.07;
  auto dist_to_box = [](double px, double py, double hx, double hy) {  // outside distance
    const double dx = std::max(px - hx, 0.0), dy = std::max(py - hy, 0.0);
    return std::hypot(dx, dy);
  };
  if (x <= ax && y <= ay) return std::min(ax - x, ay - y);            // in A: leave it
  if (x <= bx && y <= ay) return std::min({x - ax, ay - y, bx - x});  // in B: into A, into C, off
  if (x <= bx && y <= by) return std::min({dist_to_box(x, y, bx, ay), by - y, bx - x});  // in C
  return dist_to_box(x, y, bx, by);  // off: back onto the bed
}

TEST(ClassifyLanding, MarginOfOnePointMatchesTheDistanceWorkedOutByHand) {
  const HdZones z = HdZones::Default();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-1.4, 1.4);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const double hand = HandMargin(p);
    if (hand > 2.9) continue;  // the search reaches 3 m
    const HdLanding l = ClassifyLanding(z, {p}, 0.0);
    // Lines inside their zone: a point exactly on a line is found on the move across it, within
    // the 1 mm of the search's resolution.
    EXPECT_NEAR(l.margin_m, hand, 0.0012) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 250);
}

}  // namespace
}  // namespace acro::fig
