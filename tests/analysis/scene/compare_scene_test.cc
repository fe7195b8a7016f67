// Two jumps aligned at take-off (`acrolab compare`): the sample routine's back tuck (jump 2) and
// back pike (jump 3). At τ = 0 both athletes are at take-off at the same place — their centres of
// mass together and their pelvises facing the same way — and the curves under the views start at
// zero and count one backward somersault each.

#include "acro/scene/compare_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/dynamics/configuration.h"
#include "acro/scene/trial_scene.h"
#include "analysed_sample.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

using Sample = testing::AnalysedSample;
using testing::TheSample;

CompareJump Jump(int index) {
  const Sample& s = TheSample();
  return {&s.trial,
          &s.analysis,
          &s.body,
          MakeEllipsoidBodyMesh(s.body, OverlayBodyMeshOptions()),
          index,
          "jump " + std::to_string(index)};
}

TEST(CompareScene, BothAthletesStartAtTheSameTakeoff) {
  const Sample& s = TheSample();
  ASSERT_EQ(s.analysis.jumps.at(1).fig_code, "40o");
  ASSERT_EQ(s.analysis.jumps.at(2).fig_code, "40<");
  CompareScene scene(Jump(2), Jump(3));
  EXPECT_EQ(scene.start_s(), 0.0);
  CompareFrame f;
  scene.Frame(0.0, &f);
  EXPECT_TRUE(f.a_in_flight);
  EXPECT_TRUE(f.b_in_flight);
  // The take-offs are 0.5 m apart on the bed, yet here the two athletes are one.
  const TakeoffPlacement pa = FindTakeoff(s.analysis, 2), pb = FindTakeoff(s.analysis, 3);
  std::printf("take-off feet %.3f m apart in the trial; B moved %.3f m\n",
              (pa.feet_W - pb.feet_W).norm(),
              scene.b_to_a().translation().norm());
  EXPECT_LT((scene.b_to_a() * pb.feet_W - pa.feet_W).norm(), 1e-9);
  EXPECT_LT((f.a.com_W - f.b.com_W).head<2>().norm(), 0.05)
      << f.a.com_W.transpose() << " / " << f.b.com_W.transpose();
  EXPECT_LT(std::abs(f.a.com_W.z() - f.b.com_W.z()), 0.05);
  // They face the same way: each foot (ankle to toe) points the same way in both.
  for (const char* name : {"r_foot", "l_foot"}) {
    int g = -1;
    for (size_t k = 0; k < s.body.segments.size(); ++k)
      if (s.body.segments[k].name == name) g = int(k);
    ASSERT_GE(g, 0) << name;
    const Eigen::Vector3d da =
        f.a.skeleton.points_W.col(2 * g + 1) - f.a.skeleton.points_W.col(2 * g);
    const Eigen::Vector3d db =
        f.b.skeleton.points_W.col(2 * g + 1) - f.b.skeleton.points_W.col(2 * g);
    EXPECT_GT(da.normalized().dot(db.normalized()), std::cos(10.0 * M_PI / 180)) << name;
  }
  // Later in the flight the two skills part: the pike's body differs from the tuck's.
  scene.Frame(0.6, &f);
  EXPECT_GT((f.a.mesh.vertices_W - f.b.mesh.vertices_W).colwise().norm().maxCoeff(), 0.2);
}

TEST(CompareScene, CurvesStartAtZeroAndCountOneBackSomersault) {
  CompareScene scene(Jump(2), Jump(3));
  for (const JumpCurves& c : {scene.CurvesA(), scene.CurvesB()}) {
    ASSERT_GT(c.tau_s.size(), 100u);
    EXPECT_NEAR(c.tau_s.front(), 0.0, 0.01);
    EXPECT_EQ(c.somersault_deg.front(), 0.0);
    EXPECT_EQ(c.twist_deg.front(), 0.0);
    // The in-air rotation of a single somersault from feet to feet: about ¾ to 1 turn, backward.
    EXPECT_LT(c.somersault_deg.back(), -250.0);
    EXPECT_GT(c.somersault_deg.back(), -400.0);
    EXPECT_LT(std::abs(c.twist_deg.back()), 30.0);
  }
  // Both in A's frame: the COM heights start together.
  EXPECT_NEAR(scene.CurvesA().com_height_m.front(), scene.CurvesB().com_height_m.front(), 0.05);
}

// The overlay's ghost: jump 2 (the back tuck) in every other flight, placed at that flight's
// take-off: at the back pike's take-off the two are together; not in its own flight; not in
// contact.
TEST(TrialScene, TheGhostJumpStartsAtEachFlightsTakeoff) {
  const Sample& s = TheSample();
  TrialScene scene(
      s.trial, s.analysis, s.body, MakeEllipsoidBodyMesh(s.body, OverlayBodyMeshOptions()));
  scene.SetGhostJump(2);
  TrialFrame f;
  const Flight& pike = s.analysis.phases.flights.at(2);
  scene.Frame(pike.takeoff_frame, &f);
  ASSERT_TRUE(f.ghost_shown);
  EXPECT_LT((f.ghost.com_W - f.athlete.com_W).norm(), 0.06)
      << f.ghost.com_W.transpose() << " / " << f.athlete.com_W.transpose();
  scene.Frame((pike.takeoff_frame + pike.landing_frame) / 2, &f);
  EXPECT_TRUE(f.ghost_shown);
  EXPECT_GT((f.ghost.mesh.vertices_W - f.athlete.mesh.vertices_W).colwise().norm().maxCoeff(), 0.2);
  const Flight& tuck = s.analysis.phases.flights.at(1);
  scene.Frame((tuck.takeoff_frame + tuck.landing_frame) / 2, &f);
  EXPECT_FALSE(f.ghost_shown);  // its own flight
  scene.Frame(tuck.landing_frame + 5, &f);
  EXPECT_FALSE(f.ghost_shown);  // in contact
  EXPECT_THROW(scene.SetGhostJump(7), InputError);
}

// A ghost from another trial (the studio's compare mode across trials): the same routine read and
// analysed a second time stands for it. Its jump 2 is shown in every flight — its own number is
// another trial's — and in this trial's flight 2 it is the athlete exactly (the same motion placed
// at its own take-off); at the back pike's take-off it is where this trial's own ghost jump 2 is.
TEST(TrialScene, AGhostFromAnotherTrialIsShownInEveryFlight) {
  const Sample& s = TheSample();
  const capture::Trial other_trial = capture::ReadTrial(
      acro::testing::SourceDir() / "samples/trials/trampoline_routine/trampoline_routine.c3d");
  const TrialAnalysis other = AnalyzeTrial(other_trial, nullptr, s.body);
  const BodyMesh mesh = MakeEllipsoidBodyMesh(s.body, OverlayBodyMeshOptions());
  TrialScene scene(s.trial, s.analysis, s.body, mesh);
  TrialScene own(s.trial, s.analysis, s.body, mesh);
  scene.SetGhostJump(other, s.body, mesh, 2, "jump 2 of the other trial");
  own.SetGhostJump(2);
  TrialFrame f, g;
  const Flight& tuck = s.analysis.phases.flights.at(1);
  for (const int sample : {tuck.takeoff_frame, (tuck.takeoff_frame + tuck.landing_frame) / 2}) {
    scene.Frame(sample, &f);
    ASSERT_TRUE(f.ghost_shown) << sample;
    EXPECT_LT((f.ghost.com_W - f.athlete.com_W).norm(), 1e-9) << sample;
    EXPECT_LT((f.ghost.mesh.vertices_W - f.athlete.mesh.vertices_W).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_NE(f.heads_up.find("ghost: jump 2 of the other trial"), std::string::npos) << f.heads_up;
  const Flight& pike = s.analysis.phases.flights.at(2);
  scene.Frame(pike.takeoff_frame + 20, &f);
  own.Frame(pike.takeoff_frame + 20, &g);
  ASSERT_TRUE(f.ghost_shown && g.ghost_shown);
  EXPECT_LT((f.ghost.com_W - g.ghost.com_W).norm(), 1e-9);
  EXPECT_THROW(scene.SetGhostJump(other, s.body, mesh, 7, "jump 7"), InputError);
}

TEST(CompareScene, AJumpThatDoesNotExistIsNamed) {
  try {
    CompareScene scene(Jump(2), Jump(9));
    ADD_FAILURE() << "jump 9 of a six-jump trial";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("9 is not a jump of this trial (it has 6)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace acro::analysis
