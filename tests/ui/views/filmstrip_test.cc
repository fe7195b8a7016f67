// Filmstrips (`optimize`'s initial against optimised timing, `analyze`'s per jump): rows one above
// the other share one scale and one height reference — the same pose in two rows is the same
// picture one band lower — and the video fills the strip in as the flight goes, with the number of
// frames its clock says.

#include "acro/views/filmstrip.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/capture/video.h"
#include "acro/design/skill_optimization.h"
#include "acro/scene/trial_scene.h"
#include "refdata.h"

namespace acro::ui {
namespace {

struct BackTuck {
  analysis::Skill skill;
  analysis::AthleteBody body;
  analysis::Motion initial, optimised;
};

const BackTuck& TheBackTuck() {
  static const BackTuck tuck = [] {
    BackTuck t;
    t.skill = analysis::ReadSkill(acro::testing::SourceDir() / "samples/skills/back_tuck.yaml");
    t.body = analysis::MakeAthleteBody(t.skill.athlete);
    const analysis::SkillDesign design(t.skill);
    const analysis::SkillOptimizationResult r =
        analysis::OptimizeSkill(design, analysis::SkillOptimizationOptions{});
    t.initial = analysis::SampleSkillMotion(design, r.initial);
    t.optimised = analysis::SampleSkillMotion(design, r.optimized);
    return t;
  }();
  return tuck;
}

// Pixels of the band (0-based) of an RGB strip that differ from `other`'s band by more than 40 in
// a channel, over columns [x0, x1); and the non-white pixels there.
std::pair<int, int> CompareBands(const std::vector<std::uint8_t>& rgb,
                                 const FilmstripOptions& o,
                                 int band,
                                 int other,
                                 int x0,
                                 int x1) {
  int differ = 0, ink = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = x0; x < x1; ++x) {
      const std::uint8_t* a = &rgb[(size_t(band * o.height + y) * size_t(o.width) + size_t(x)) * 3];
      const std::uint8_t* b =
          &rgb[(size_t(other * o.height + y) * size_t(o.width) + size_t(x)) * 3];
      bool d = false, i = false;
      for (int c = 0; c < 3; ++c) {
        d = d || std::abs(int(a[c]) - int(b[c])) > 40;
        i = i || a[c] < 200;
      }
      differ += d ? 1 : 0;
      ink += i ? 1 : 0;
    }
  return {differ, ink};
}

TEST(Filmstrip, RowsShareOneScaleAndOneHeight) {
  const BackTuck& t = TheBackTuck();
  const analysis::BodyMesh mesh =
      analysis::MakeEllipsoidBodyMesh(t.body, analysis::OverlayBodyMeshOptions());
  analysis::AthleteScene a(t.body, mesh, t.initial), b(t.body, mesh, t.optimised);
  const std::vector<int> frames = EvenlySpacedFrames(0, t.initial.num_frames() - 1, 8);
  ASSERT_EQ(t.optimised.num_frames(), t.initial.num_frames());
  FilmstripOptions o;
  o.spacing_m = 1.5;
  const Eigen::Vector3d heading = Eigen::Vector3d::UnitX();

  // The same row twice: the bottom band is the top band.
  const std::vector<std::uint8_t> same =
      RenderFilmstrips({{&a, frames, t.initial.rate_hz, "", o.colour},
                        {&a, frames, t.initial.rate_hz, "", o.colour}},
                       heading,
                       o);
  ASSERT_EQ(same.size(), size_t(o.width) * size_t(2 * o.height) * 3);
  const auto [differ_same, ink_same] = CompareBands(same, o, 0, 1, 0, o.width);
  EXPECT_GT(ink_same, 5000);  // eight athletes drawn
  EXPECT_LE(differ_same, ink_same / 100);

  // Initial against optimised timing: both take off in the same pose (t = 0, the first keyframe)
  // and land in the same pose (t = T, the last), so the first and last poses are the same pictures
  // one band apart; in between the timings differ and so do the pictures.
  const std::vector<std::uint8_t> pair =
      RenderFilmstrips({{&a, frames, t.initial.rate_hz, "", o.colour},
                        {&b, frames, t.optimised.rate_hz, "", o.colour}},
                       heading,
                       o);
  // Columns of the first pose, the middle and the last: the strip's non-white columns, split.
  int first_x = o.width, last_x = -1;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      if (pair[(size_t(y) * size_t(o.width) + size_t(x)) * 3] < 200) {
        first_x = std::min(first_x, x);
        last_x = std::max(last_x, x);
      }
  ASSERT_LT(first_x, last_x);
  const int pose_px = (last_x - first_x) / 12;  // narrower than one pose's spacing
  const auto [differ_first, ink_first] = CompareBands(pair, o, 0, 1, first_x, first_x + pose_px);
  const auto [differ_last, ink_last] = CompareBands(pair, o, 0, 1, last_x - pose_px, last_x + 1);
  const auto [differ_mid, ink_mid] =
      CompareBands(pair, o, 0, 1, first_x + 2 * pose_px, last_x - 2 * pose_px);
  EXPECT_GT(ink_first, 300);
  EXPECT_GT(ink_last, 300);
  EXPECT_LE(differ_first, ink_first / 50);
  EXPECT_LE(differ_last, ink_last / 50);
  EXPECT_GT(differ_mid, ink_mid / 5);  // other poses at the same instants
}

TEST(Filmstrip, TheVideoFillsTheStripInAsTheFlightGoes) {
  const BackTuck& t = TheBackTuck();
  analysis::AthleteScene a(
      t.body,
      analysis::MakeEllipsoidBodyMesh(t.body, analysis::OverlayBodyMeshOptions()),
      t.initial);
  const std::vector<int> frames = EvenlySpacedFrames(0, t.initial.num_frames() - 1, 8);
  FilmstripOptions o;
  o.width = 600;
  o.height = 160;
  FilmstripVideoOptions v;
  v.slow = 1;
  v.hold_s = 0.5;
  const std::filesystem::path out = acro::testing::ScratchDir("filmstrip_video") / "strip.mp4";
  const int written = WriteFilmstripVideo(
      {{&a, frames, t.initial.rate_hz, "initial", o.colour}}, Eigen::Vector3d::UnitX(), out, o, v);
  // The flight's T at 30 frames a second, its first and last instants included, then the hold.
  const double T = t.initial.time_s(t.initial.num_frames() - 1);
  EXPECT_EQ(written, int(std::floor(T * 30 + 1e-9)) + 1 + 15);
  capture::VideoReader video(out);
  EXPECT_EQ(video.info().num_frames, written);
  EXPECT_EQ(video.info().width, 600);
  // The first frame: one athlete at the strip's left end; the last: the whole strip.
  capture::VideoFrame first, last;
  ASSERT_TRUE(video.ReadNext(&first));
  for (int i = 1; i < written; ++i) ASSERT_TRUE(video.ReadNext(&last));
  const auto extent = [&](const capture::VideoFrame& f) {
    int lo = o.width, hi = -1;
    for (int y = 40; y < o.height; ++y)  // below the label
      for (int x = 0; x < o.width; ++x)
        if (f.pixels[(size_t(y) * size_t(o.width) + size_t(x)) * 3 + 1] < 180) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
    return std::pair<int, int>(lo, hi);
  };
  const auto [first_lo, first_hi] = extent(first);
  const auto [last_lo, last_hi] = extent(last);
  EXPECT_NEAR(first_lo, last_lo, 3);
  EXPECT_LT(first_hi - first_lo, (last_hi - last_lo) / 4);
}

}  // namespace
}  // namespace acro::ui
