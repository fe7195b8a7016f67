#include "acro/design/skill_file.h"

#include <fstream>
#include <numbers>

#include <gtest/gtest.h>

#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/model.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kEps = std::numeric_limits<double>::epsilon();

std::filesystem::path Samples() {
  return acro::testing::SourceDir() / "samples";
}

std::string ErrorOf(const std::string& text) {
  try {
    SkillFromYaml(ParseYaml(text, "bad.yaml"), Samples() / "skills");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kHead =
    "name: test\n"
    "athlete: ../athletes/sample_athlete.yaml\n"
    "takeoff:\n"
    "  flight_time_s: 1.5\n"
    "keyframes:\n";

TEST(SkillFile, ReadsThePapersExample) {
  const Skill s = ReadSkill(Samples() / "skills/front_1_3_4_half_twist.yaml");
  ASSERT_EQ(s.keyframes.size(), 12u);
  EXPECT_EQ(s.takeoff_com_velocity_mps, Eigen::Vector3d(0, 0.015, 7.8));
  EXPECT_NEAR(s.flight_time_s, 2 * 7.8 / 9.81, 4 * kEps);
  EXPECT_EQ(s.athlete.name, "Sample Athlete");
  const SkillKeyframe& tuck = s.keyframes[2];
  EXPECT_EQ(tuck.name, "tuck");
  EXPECT_NEAR(tuck.somersault_rad, 140 * kDeg, 4 * kEps);
  // Unsided joints set both sides; the mirror keeps flexion (about y).
  EXPECT_NEAR(tuck.joint_angles_rad[StandardJointDofIndex("r_thigh", 0)], -140 * kDeg, 4 * kEps);
  EXPECT_NEAR(tuck.joint_angles_rad[StandardJointDofIndex("l_thigh", 0)], -140 * kDeg, 4 * kEps);
  EXPECT_NEAR(tuck.joint_angles_rad[StandardJointDofIndex("r_shank", 0)], 145 * kDeg, 4 * kEps);
  EXPECT_NEAR(tuck.tolerance_angle_rad, 5 * kDeg, 4 * kEps);
}

// Every sample skill reads.
TEST(SkillFile, EverySampleReads) {
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(Samples() / "skills")) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(ReadSkill(e.path())) << e.path();
    ++count;
  }
  EXPECT_GE(count, 6);
}

// The joint angle indices agree with the model's coordinates.
TEST(SkillFile, JointIndicesFollowTheModel) {
  const Skill s = ReadSkill(Samples() / "skills/back_tuck.yaml");
  const dynamics::Model<double> m = MakeStandardHumanModel(MakeAthleteBody(s.athlete));
  EXPECT_EQ(m.num_joint_dofs(), StandardJointDofCount());
  for (const StandardJoint& j : kStandardJoints) {
    if (j.axis_sequence.empty()) continue;
    const int seg = m.FindSegment(std::string(j.segment));
    EXPECT_EQ(StandardJointDofIndex(j.segment, 0), m.segment(seg).q_start - 7) << j.segment;
  }
}

// Mirroring an unsided joint negates the angles about x and z on the left.
TEST(SkillFile, MirrorsAbductionAndRotation) {
  const Skill s =
      SkillFromYaml(ParseYaml(std::string(kHead) +
                                  "  - name: a\n    joints_deg:\n      upper_arm: [-30, 10, -40]\n"
                                  "  - name: b\n  - name: c\n",
                              "m.yaml"),
                    Samples() / "skills");
  const Eigen::VectorXd& q = s.keyframes[0].joint_angles_rad;
  EXPECT_NEAR(q[StandardJointDofIndex("r_upper_arm", 1)], 10 * kDeg, 4 * kEps);
  EXPECT_NEAR(q[StandardJointDofIndex("l_upper_arm", 0)], -30 * kDeg, 4 * kEps);
  EXPECT_NEAR(q[StandardJointDofIndex("l_upper_arm", 1)], -10 * kDeg, 4 * kEps);
  EXPECT_NEAR(q[StandardJointDofIndex("l_upper_arm", 2)], 40 * kDeg, 4 * kEps);
  EXPECT_NEAR(s.takeoff_com_velocity_mps.z(), 0.5 * 9.81 * 1.5, 8 * kEps);
}

// The studio's designer saves an edited skill: every sample written and read back is the same
// skill (every number within 1e-12: twelve significant digits), and an edit survives.
TEST(SkillFile, WrittenAndReadBackIsTheSameSkill) {
  const std::filesystem::path dir = acro::testing::ScratchDir("skill_write");
  for (const auto& entry : std::filesystem::directory_iterator(Samples() / "skills")) {
    Skill skill = ReadSkill(entry.path());
    const std::string name = entry.path().filename().string();
    skill.keyframes[1].time_s = 0.25;  // a time guess given in the designer
    skill.keyframes[1].joint_angles_rad(StandardJointDofIndex("l_shank", 0)) = 1.25;  // an edit
    WriteSkill(dir / name, skill);
    const Skill back = ReadSkill(dir / name);
    EXPECT_EQ(back.name, skill.name) << name;
    EXPECT_EQ(back.fig_code, skill.fig_code) << name;
    EXPECT_EQ(back.athlete.name, skill.athlete.name) << name;
    EXPECT_EQ(std::filesystem::weakly_canonical(back.athlete_path),
              std::filesystem::weakly_canonical(skill.athlete_path))
        << name;
    EXPECT_LT((back.takeoff_com_velocity_mps - skill.takeoff_com_velocity_mps).norm(), 1e-12);
    ASSERT_EQ(back.keyframes.size(), skill.keyframes.size()) << name;
    for (size_t i = 0; i < skill.keyframes.size(); ++i) {
      const SkillKeyframe& a = skill.keyframes[i];
      const SkillKeyframe& b = back.keyframes[i];
      EXPECT_EQ(a.name, b.name);
      EXPECT_NEAR(a.somersault_rad, b.somersault_rad, 1e-12) << name << " " << a.name;
      EXPECT_NEAR(a.tilt_rad, b.tilt_rad, 1e-12) << name << " " << a.name;
      EXPECT_NEAR(a.twist_rad, b.twist_rad, 1e-12) << name << " " << a.name;
      EXPECT_LT((a.joint_angles_rad - b.joint_angles_rad).cwiseAbs().maxCoeff(), 1e-12)
          << name << " " << a.name;
      EXPECT_EQ(a.time_s.has_value(), b.time_s.has_value());
      if (a.time_s && b.time_s) {
        EXPECT_NEAR(*a.time_s, *b.time_s, 1e-12);
      }
      EXPECT_NEAR(a.tolerance_angle_rad, b.tolerance_angle_rad, 1e-12);
      EXPECT_NEAR(a.tolerance_position_m, b.tolerance_position_m, 1e-12);
    }
    EXPECT_NEAR(
        back.keyframes[1].joint_angles_rad(StandardJointDofIndex("l_shank", 0)), 1.25, 1e-12);
  }
  EXPECT_THROW(WriteSkill(dir / "no_such_folder/x.yaml", ReadSkill(Samples() / "skills/full.yaml")),
               InputError);
}

TEST(SkillFile, ErrorsNameFileLineAndKey) {
  EXPECT_NE(ErrorOf(std::string(kHead) +
                    "  - name: a\n    joints_deg:\n      r_wing: [1]\n  - name: b\n  - name: c\n")
                .find("bad.yaml: line 8: r_wing: unknown joint"),
            std::string::npos)
      << ErrorOf(std::string(kHead) +
                 "  - name: a\n    joints_deg:\n      r_wing: [1]\n  - name: b\n  - name: c\n");
  EXPECT_NE(
      ErrorOf(std::string(kHead) +
              "  - name: a\n    joints_deg:\n      r_shank: [1, 2]\n  - name: b\n  - name: c\n")
          .find("r_shank: joint r_shank has 1 axes"),
      std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kHead) + "  - name: a\n  - name: b\n").find("at least 3 keyframes"),
            std::string::npos);
  // A root angle that changes by more than 170° between keyframes, as written (−40° then −250°
  // would otherwise be the 150° turn the other way), and two that stay below it each but turn
  // the orientation by 172° together.
  EXPECT_NE(ErrorOf(std::string(kHead) +
                    "  - name: a\n  - name: b\n    somersault_deg: 175\n  - name: c\n")
                .find("bad.yaml: line 7: somersault_deg changes by 175.0°"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kHead) + "  - name: a\n  - name: b\n    somersault_deg: -40\n"
                                         "  - name: c\n    somersault_deg: -250\n")
                .find("somersault_deg changes by -210.0°"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kHead) + "  - name: a\n  - name: b\n    somersault_deg: 150\n"
                                         "    tilt_deg: 150\n  - name: c\n")
                .find("bad.yaml: line 7: orientation turns 172."),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(std::string(kHead) + "  - name: a\n    twsit_deg: 3\n  - name: b\n  - name: c\n")
          .find("twsit_deg"),
      std::string::npos);
  EXPECT_NE(
      ErrorOf(
          std::string(kHead) +
          "  - name: a\n  - name: b\n    time_s: 1.0\n  - name: c\n    time_s: 0.5\n  - name: d\n")
          .find("keyframe times must increase"),
      std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
