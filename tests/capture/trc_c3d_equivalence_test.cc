// BTK's Gait pair: the same 33 trajectories exported as C3D (DEC integer) and as Motion Analysis
// TRC. BTK asserts x/y/z equal within 1e-4 (mm) for frames 1..49; the importers must agree.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "acro/capture/c3d.h"
#include "acro/capture/trc.h"
#include "refdata.h"

namespace acro::capture {
namespace {

TEST(TrcC3dEquivalence, BtkGaitPairAgreesWhereItsDataAgree) {
  const auto c3d_path = acro::testing::RefdataFile("BTKData/Input/C3DSamples/others/Gait.c3d");
  const auto trc_path = acro::testing::RefdataFile("BTKData/Input/TRCSamples/Gait.trc");
  ACRO_REQUIRE_REFDATA_FILE(c3d_path);
  ACRO_REQUIRE_REFDATA_FILE(trc_path);
  const Trial c3d = ReadC3d(c3d_path);
  const Trial trc = ReadTrc(trc_path);
  EXPECT_EQ(c3d.point_rate_hz, trc.point_rate_hz);
  EXPECT_EQ(c3d.num_frames, trc.num_frames);
  ASSERT_GE(c3d.num_points(), 33);
  ASSERT_EQ(trc.num_points(), 33);
  // What BTK asserts: frames 1..49, every point, equal within 1e-4 mm. In both files every marker
  // is a gap in those frames (BTK compares zeros with zeros), so what can be checked there is that
  // both importers agree on visibility.
  for (int p = 0; p < 33; ++p) {
    for (int f = 0; f < 49; ++f) {
      EXPECT_FALSE(c3d.valid(f, p)) << trc.points[p].label << " frame " << f;
      EXPECT_FALSE(trc.valid(f, p)) << trc.points[p].label << " frame " << f;
    }
  }
  // Beyond frame 49 the two files hold different reconstructions of the same walk: the C3D has data
  // in frames 133-326, the TRC in 159-438, and where both have data they differ by 1.15 mm on
  // average (7.6 mm at most). They are the same trial on the same time base: the mean distance is
  // smallest at zero lag, one frame of lag adds ~14 mm (walking speed × 10 ms). Points pair by
  // index, as in BTK (the exports spell labels differently: RSHO / R.Shoulder).
  auto mean_distance = [&](int lag) {
    double sum = 0;
    int n = 0;
    for (int p = 0; p < 33; ++p) {
      for (int f = std::max(0, -lag); f < c3d.num_frames && f + lag < trc.num_frames; ++f) {
        if (c3d.valid(f, p) && trc.valid(f + lag, p)) {
          sum += (c3d.position(f, p) - trc.position(f + lag, p)).norm();
          ++n;
        }
      }
    }
    return sum / n;
  };
  const double at_zero = mean_distance(0);
  EXPECT_LT(at_zero, 2e-3);
  EXPECT_GT(mean_distance(-1), at_zero + 10e-3);
  EXPECT_GT(mean_distance(+1), at_zero + 10e-3);
}

TEST(TrcC3dEquivalence, C3dToTrcToC3dKeepsEveryMarkerSampleToStorageRounding) {
  for (const char* rel : {"c3dio-c3d_org_samples/sample_01/Eb015pr.c3d",
                          "BTKData/Input/C3DSamples/others/Gait.c3d"}) {
    SCOPED_TRACE(rel);
    const auto path = acro::testing::RefdataFile(rel);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial c3d = ReadC3d(path);
    const Trial trc =
        ReadTrcFromString(WriteTrcToString(c3d, "x.trc", {.units = "mm", .decimals = 6}), "x.trc");
    const Trial back = ReadC3dFromMemory(WriteC3dToMemory(trc), "x.c3d");
    ASSERT_EQ(back.num_frames, c3d.num_frames);
    ASSERT_EQ(back.num_points(), c3d.num_points());
    // Per coordinate: TRC rounding to 6 decimals of mm (5e-7 mm), then float32 rounding in the C3D
    // (half an ulp, |x|·2⁻²⁴ — 1.2e-4 mm at 2 m, so "1e-4 mm" holds within 1.6 m of the origin).
    double worst_excess = -1;
    for (int f = 0; f < c3d.num_frames; ++f) {
      for (int p = 0; p < c3d.num_points(); ++p) {
        ASSERT_EQ(back.valid(f, p), c3d.valid(f, p));
        if (!c3d.valid(f, p)) continue;
        for (int k = 0; k < 3; ++k) {
          const double x = c3d.position(f, p)[k];
          const double bound = 5e-7 * 1e-3 + std::abs(x) * std::ldexp(1.0, -24) * 1.0001;
          worst_excess = std::max(worst_excess, std::abs(back.position(f, p)[k] - x) - bound);
        }
      }
    }
    EXPECT_LE(worst_excess, 0.0);
  }
}

}  // namespace
}  // namespace acro::capture
