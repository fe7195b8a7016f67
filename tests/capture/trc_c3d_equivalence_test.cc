// BTK's Gait pair: the same 33 trajectories exported as C3D (DEC integer) and as Motion Analysis TRC.
// BTK asserts x/y/z equal within 1e-4 (mm) for frames 1..49; the importers must agree.
#include <gtest/gtest.h>

#include "acro/capture/c3d.h"
#include "acro/capture/trc.h"
#include "refdata.h"

namespace acro::capture {
namespace {

TEST(TrcC3dEquivalence, BtkGaitPairAgreesTo1e4Millimetre) {
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
  int compared = 0;
  for (int p = 0; p < 33; ++p) {
    const int q = c3d.FindPoint(trc.points[p].label);
    ASSERT_GE(q, 0) << trc.points[p].label;
    for (int f = 0; f < c3d.num_frames; ++f) {
      ASSERT_EQ(c3d.valid(f, q), trc.valid(f, p)) << trc.points[p].label << " frame " << f;
      if (!trc.valid(f, p)) continue;
      EXPECT_LT((c3d.position(f, q) - trc.position(f, p)).cwiseAbs().maxCoeff(), 1e-4 * 1e-3)
          << trc.points[p].label << " frame " << f;
      ++compared;
    }
  }
  EXPECT_GT(compared, 33 * 49 / 2);
}

TEST(TrcC3dEquivalence, C3dToTrcToC3dKeepsEveryMarkerSample) {
  const auto path = acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial c3d = ReadC3d(path);
  const Trial trc = ReadTrcFromString(WriteTrcToString(c3d, "x.trc", {.units = "mm", .decimals = 6}), "x.trc");
  const Trial back = ReadC3dFromMemory(WriteC3dToMemory(trc), "x.c3d");
  ASSERT_EQ(back.num_frames, c3d.num_frames);
  ASSERT_EQ(back.num_points(), c3d.num_points());
  for (int f = 0; f < c3d.num_frames; ++f) {
    for (int p = 0; p < c3d.num_points(); ++p) {
      ASSERT_EQ(back.valid(f, p), c3d.valid(f, p));
      // 6 decimals of mm in the TRC, then float32 in the C3D (7 significant digits of ~1000 mm).
      if (c3d.valid(f, p)) ASSERT_LT((back.position(f, p) - c3d.position(f, p)).cwiseAbs().maxCoeff(), 1e-7);
    }
  }
}

}  // namespace
}  // namespace acro::capture
