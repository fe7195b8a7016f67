// A designed skill as a ghost (`acrolab overlay --ghost DIR`): optimize's folder is read back as
// the motion the optimisation made (every sample of motion.mot against the design evaluated
// directly), and the ghost stands at each flight's take-off of the sample routine, then follows
// its own take-off parabola — its centre of mass rises as v_z τ − g τ²/2 from there.

#include "acro/scene/skill_ghost.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/design/skill_optimization.h"
#include "acro/dynamics/configuration.h"
#include "acro/report/skill_report.h"
#include "acro/scene/compare_scene.h"
#include "acro/scene/trial_scene.h"
#include "analysed_sample.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

struct Design {
  std::filesystem::path dir;
  Skill skill;
  SkillOptimizationResult result;
};

// The sample back tuck optimised (Model 2) and written as `acrolab optimize` writes it.
const Design& TheBackTuck() {
  static const Design back_tuck = [] {
    Design d;
    d.skill = ReadSkill(acro::testing::SourceDir() / "samples/skills/back_tuck.yaml");
    const SkillDesign design(d.skill);
    d.result = OptimizeSkill(design, SkillOptimizationOptions{});
    d.dir = acro::testing::ScratchDir("designed_skill");
    ui::WriteSkillOutputs(d.dir, design, d.result, nullptr);
    return d;
  }();
  return back_tuck;
}

using testing::TheSample;

// The largest differences between a motion read or made from a design and the design evaluated
// directly at the motion's times: root position (m), root orientation (rad), joint angles (rad).
struct Worst {
  double position = 0, angle = 0, joint = 0;
};
Worst AgainstTheDesign(const Motion& m,
                       const SkillDesign& design,
                       const SkillTrajectory& trajectory) {
  Worst w;
  for (int f = 0; f < m.num_frames(); ++f) {
    const SkillMotionState s = CalcSkillMotion(design, trajectory, m.time_s(f));
    w.position = std::max(w.position, (m.q.col(f).head<3>() - s.q.head<3>()).norm());
    w.angle = std::max(
        w.angle,
        dynamics::GetRootQuaternion(m.q.col(f)).angularDistance(dynamics::GetRootQuaternion(s.q)));
    w.joint = std::max(
        w.joint,
        (m.q.col(f).tail(m.nq() - dynamics::kRootNq) - s.q.tail(m.nq() - dynamics::kRootNq))
            .cwiseAbs()
            .maxCoeff());
  }
  return w;
}

TEST(SkillGhost, ReadsOptimizesFolderBackAsTheOptimisedMotion) {
  const Design& d = TheBackTuck();
  const SkillDesign design(d.skill);
  const SkillGhost read = ReadSkillGhost(d.dir, design.model());
  EXPECT_EQ(read.name, "back tuck");
  EXPECT_EQ(read.fig_code, "40o");
  EXPECT_DOUBLE_EQ(read.flight_time_s, design.flight_time_s());
  ASSERT_EQ(read.keyframe_times_s.size(), size_t(design.num_keyframes()));
  for (int i = 0; i < design.num_keyframes(); ++i)
    EXPECT_NEAR(read.keyframe_times_s[size_t(i)], d.result.optimized.times_s(i), 1e-12);
  const Motion& m = read.motion;
  ASSERT_GT(m.num_frames(), 100);  // 100 Hz over ~1.4 s
  EXPECT_NEAR(m.time_s(m.num_frames() - 1), design.flight_time_s(), 1e-9);
  const Worst worst = AgainstTheDesign(m, design, d.result.optimized);
  EXPECT_LT(worst.position, 1e-9);
  EXPECT_LT(worst.angle, 1e-9);
  EXPECT_LT(worst.joint, 1e-9);
  // The folder, its result.json or its motion.mot name the same design.
  EXPECT_EQ(ReadSkillGhost(d.dir / "motion.mot", design.model()).motion.q, m.q);
}

// The studio's designer hands the optimisation's result to the ghost without writing it: the same
// design as the folder read back.
TEST(SkillGhost, MadeFromTheResultItIsTheFolderReadBack) {
  const Design& d = TheBackTuck();
  const SkillDesign design(d.skill);
  const SkillGhost read = ReadSkillGhost(d.dir, design.model());
  const SkillGhost made = MakeSkillGhost(design, d.result);
  EXPECT_EQ(made.name, read.name);
  EXPECT_EQ(made.fig_code, read.fig_code);
  EXPECT_DOUBLE_EQ(made.flight_time_s, read.flight_time_s);
  EXPECT_EQ(made.keyframe_names, read.keyframe_names);
  ASSERT_EQ(made.keyframe_times_s.size(), read.keyframe_times_s.size());
  for (size_t i = 0; i < made.keyframe_times_s.size(); ++i) {
    EXPECT_NEAR(made.keyframe_times_s[i], read.keyframe_times_s[i], 1e-12);
    EXPECT_NEAR(made.keyframe_times_initial_s[i], read.keyframe_times_initial_s[i], 1e-12);
  }
  // The same motion, sampled evenly (motion.mot's samples are 10 ms apart with the last at T).
  const Motion& m = made.motion;
  ASSERT_GE(m.num_frames(), read.motion.num_frames());
  EXPECT_EQ(m.coordinate_names, read.motion.coordinate_names);
  EXPECT_EQ(m.time_s(0), 0.0);
  EXPECT_NEAR(m.time_s(m.num_frames() - 1), design.flight_time_s(), 1e-12);
  const Worst worst = AgainstTheDesign(m, design, d.result.optimized);
  EXPECT_LT(worst.position, 1e-9);
  EXPECT_LT(worst.angle, 1e-9);
}

// Compare mode with a design as B (the studio): the sample's back tuck (jump 2) against the
// designed back tuck. At τ = 0 the design stands on the jump's take-off feet; B's curves end at the
// somersault the skill file's keyframes ask for (the design passes through them: Model 2 keeps the
// poses), and B's COM follows the design's take-off parabola.
TEST(SkillGhost, ComparedWithAJump) {
  const Design& d = TheBackTuck();
  const auto& [trial, body, analysis] = TheSample();
  const SkillGhost design = ReadSkillGhost(d.dir, MakeStandardHumanModel(body));
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body, OverlayBodyMeshOptions());
  CompareJump a{&trial, &analysis, &body, mesh, 2, "jump 2"};
  CompareJump b;
  b.body = &body;
  b.mesh = mesh;
  b.design = &design;
  b.label = "back tuck (design)";
  CompareScene scene(a, b);
  const TakeoffPlacement pa = FindTakeoff(analysis, 2);
  const TakeoffPlacement pb = FindDesignTakeoff(design, MakeStandardHumanModel(body));
  EXPECT_LT((scene.b_to_a() * pb.feet_W - pa.feet_W).norm(), 1e-9);
  EXPECT_NEAR(
      scene.end_s(), std::max(pa.landing_s - pa.takeoff_s, design.flight_time_s) + 0.25, 1e-9);
  const JumpCurves c = scene.CurvesB();
  ASSERT_GT(c.tau_s.size(), 100u);
  EXPECT_NEAR(c.tau_s.back(), design.flight_time_s, 0.006);
  const auto& k = d.skill.keyframes;
  const double asked_deg = (k.back().somersault_rad - k.front().somersault_rad) * 180 / M_PI;
  std::printf(
      "design somersault %.1f deg, keyframes %.1f deg\n", c.somersault_deg.back(), asked_deg);
  EXPECT_NEAR(c.somersault_deg.back(), asked_deg, 1.0);
  const double vz = d.skill.takeoff_com_velocity_mps.z();
  const double g = MakeStandardHumanModel(body).gravity_W().norm();
  for (size_t i = 0; i < c.tau_s.size(); i += 20) {
    const double t = c.tau_s[i];
    EXPECT_NEAR(c.com_height_m[i] - c.com_height_m[0], vz * t - 0.5 * g * t * t, 1e-6) << t;
  }
  CompareFrame f;
  scene.Frame(0.0, &f);
  EXPECT_TRUE(f.b_in_flight);
  // The design's COM starts at (0, 0, 1) m (CalcSkillMotion's default), moved onto A's take-off.
  EXPECT_LT((f.b.com_W - scene.b_to_a() * Eigen::Vector3d(0, 0, 1)).norm(), 1e-9);
}

TEST(SkillGhost, AMotionForAnotherModelIsNamed) {
  const Design& d = TheBackTuck();
  const std::filesystem::path dir = acro::testing::ScratchDir("designed_skill_bad");
  std::filesystem::copy_file(d.dir / "result.json", dir / "result.json");
  // motion.mot without its knee columns.
  std::ifstream in(d.dir / "motion.mot");
  std::ofstream out(dir / "motion.mot");
  for (std::string line; std::getline(in, line);) out << line << "\n";
  out.close();
  {
    std::string text;
    std::ifstream again(dir / "motion.mot");
    text.assign(std::istreambuf_iterator<char>(again), {});
    const size_t at = text.find("r_knee_flexion");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 14, "r_knee_bending");
    std::ofstream(dir / "motion.mot") << text;
  }
  const SkillDesign design(d.skill);
  try {
    ReadSkillGhost(dir, design.model());
    ADD_FAILURE() << "a motion without r_knee_flexion was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("motion.mot"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("r_knee_flexion"), std::string::npos) << e.what();
  }
  std::filesystem::remove(dir / "result.json");
  EXPECT_THROW(ReadSkillGhost(dir, design.model()), InputError);
  // A folder that is not there is named as given.
  try {
    ReadSkillGhost(dir / "no_such_design", design.model());
    ADD_FAILURE() << "a folder that is not there was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_design"), std::string::npos) << e.what();
  }
}

TEST(SkillGhost, TheGhostTakesOffWithEachFlightAndFliesItsOwnParabola) {
  const Design& d = TheBackTuck();
  const auto& [trial, body, analysis] = TheSample();
  const dynamics::Model<double> model = MakeStandardHumanModel(body);
  const SkillGhost design = ReadSkillGhost(d.dir, model);
  TrialScene scene(trial, analysis, body, MakeEllipsoidBodyMesh(body, OverlayBodyMeshOptions()));
  scene.SetGhostDesign(design, body);

  const double vz = d.skill.takeoff_com_velocity_mps.z();
  const double g = model.gravity_W().norm();
  const TakeoffPlacement own = FindDesignTakeoff(design, model);
  TrialFrame f;
  for (const JumpMetrics& j : analysis.jumps) {
    if (j.partial()) continue;
    const Flight& flight = j.flight;
    scene.Frame(flight.takeoff_frame, &f);
    ASSERT_TRUE(f.ghost_shown) << "flight " << j.index;
    EXPECT_NE(f.heads_up.find("ghost: back tuck (design)"), std::string::npos) << f.heads_up;
    // At the take-off frame the ghost stands on the flight's take-off feet as the design stands
    // on its own: its COM (on the design's parabola from (0, 0, 1) m) as high above them and as
    // far from them horizontally.
    const double tau0 = flight.takeoff_frame / trial.point_rate_hz - flight.takeoff_s;
    const double t_0 = design.motion.time_s(FrameNearestTime(design.motion, std::max(tau0, 0.0)));
    const Eigen::Vector3d design_com = Eigen::Vector3d(0, 0, 1) +
                                       d.skill.takeoff_com_velocity_mps * t_0 -
                                       Eigen::Vector3d(0, 0, 0.5 * g * t_0 * t_0);
    const Eigen::Vector3d above = f.ghost.com_W - j.takeoff_feet_W;
    const Eigen::Vector3d own_above = design_com - own.feet_W;
    EXPECT_NEAR(above.z(), own_above.z(), 1e-6) << "flight " << j.index;
    EXPECT_NEAR(above.head<2>().norm(), own_above.head<2>().norm(), 1e-6) << "flight " << j.index;
    const double com0 = f.ghost.com_W.z();
    // Half-way through the flight: the ghost's COM has risen as the design's parabola says.
    const int mid = (flight.takeoff_frame + flight.landing_frame) / 2;
    scene.Frame(mid, &f);
    ASSERT_TRUE(f.ghost_shown);
    const double tau = mid / trial.point_rate_hz - flight.takeoff_s;
    const double t_mid = design.motion.time_s(FrameNearestTime(design.motion, tau));
    const double rise = (vz * t_mid - 0.5 * g * t_mid * t_mid) - (vz * t_0 - 0.5 * g * t_0 * t_0);
    EXPECT_NEAR(f.ghost.com_W.z() - com0, rise, 1e-6) << "flight " << j.index;
  }
  // Not in contact.
  scene.Frame(analysis.phases.flights.at(1).landing_frame + 5, &f);
  EXPECT_FALSE(f.ghost_shown);
}

}  // namespace
}  // namespace acro::analysis
