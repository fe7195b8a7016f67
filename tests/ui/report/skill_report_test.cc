#include "acro/report/skill_report.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/capture/c3d.h"
#include "acro/capture/storage.h"
#include "json_keys.h"
#include "refdata.h"

namespace acro::ui {

using namespace acro::analysis;  // NOLINT(build/namespaces)

namespace {

std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The CLI's outputs for the back tuck: every file, the JSON keys the issue names, a C3D that reads
// back with the model's points at the motion's rate, a .mot whose last row is the landing pose.
TEST(SkillReport, WritesEveryOutput) {
  const SkillDesign d(ReadSkill(acro::testing::SourceDir() / "samples/skills/back_tuck.yaml"));
  SkillOptimizationOptions o;
  o.quadrature_intervals = 20;
  const SkillOptimizationResult r = OptimizeSkill(d, o);
  const SkillSimulationResult sim = SimulateSkill(d, r.optimized);
  const auto dir = acro::testing::TempDir() / "skill_report";
  const std::vector<std::string> files = WriteSkillOutputs(dir, d, r, &sim);
  for (const char* f : {"result.json",
                        "timing.csv",
                        "timing.svg",
                        "timing.png",
                        "angular_momentum.svg",
                        "angular_momentum.png",
                        "motion.c3d",
                        "motion.mot",
                        "report.html"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
    EXPECT_NE(std::find(files.begin(), files.end(), f), files.end()) << f;
  }
  // result.json parsed and compared with the result it reports (JSON numbers round-trip exactly).
  // Not const: [] on a missing key then gives null rather than undefined behaviour.
  nlohmann::ordered_json json = nlohmann::ordered_json::parse(Slurp(dir / "result.json"));
  EXPECT_EQ(acro::testing::JsonKeys(json),
            (std::vector<std::string>{"skill",
                                      "fig_code",
                                      "athlete",
                                      "model",
                                      "flight_time_s",
                                      "keyframe_names",
                                      "keyframe_times_initial_s",
                                      "keyframe_times_s",
                                      "objective_initial",
                                      "objective",
                                      "objective_ratio",
                                      "angular_momentum_variation_initial",
                                      "angular_momentum_variation",
                                      "max_joint_deviation_deg",
                                      "max_orientation_deviation_deg",
                                      "keyframes_within_tolerance",
                                      "solver",
                                      "simulation"}));
  EXPECT_EQ(json["skill"], d.skill().name);
  EXPECT_EQ(json["fig_code"], d.skill().fig_code);
  EXPECT_TRUE(json["model"].is_number_integer());
  EXPECT_EQ(json["model"], 2);
  EXPECT_EQ(json["flight_time_s"].get<double>(), d.flight_time_s());
  ASSERT_EQ(json["keyframe_names"].size(), static_cast<size_t>(d.num_keyframes()));
  ASSERT_EQ(json["keyframe_times_initial_s"].size(), static_cast<size_t>(d.num_keyframes()));
  ASSERT_EQ(json["keyframe_times_s"].size(), static_cast<size_t>(d.num_keyframes()));
  for (int i = 0; i < d.num_keyframes(); ++i) {
    EXPECT_EQ(json["keyframe_names"][i], d.skill().keyframes[static_cast<size_t>(i)].name);
    EXPECT_EQ(json["keyframe_times_initial_s"][i].get<double>(), r.times_initial_s[i]);
    EXPECT_EQ(json["keyframe_times_s"][i].get<double>(), r.optimized.times_s[i]);
  }
  EXPECT_EQ(json["objective_initial"].get<double>(), r.objective_initial);
  EXPECT_EQ(json["objective"].get<double>(), r.objective);
  EXPECT_EQ(json["angular_momentum_variation_initial"].get<double>(),
            r.angular_momentum_variation_initial);
  EXPECT_EQ(json["angular_momentum_variation"].get<double>(), r.angular_momentum_variation);
  EXPECT_EQ(json["keyframes_within_tolerance"], true);
  // One entry per solver stage, counts as integers.
  ASSERT_EQ(json["solver"].size(), r.stages.size());
  ASSERT_FALSE(r.stages.empty());
  EXPECT_EQ(json["solver"][0]["stage"], "model 2");
  EXPECT_EQ(json["solver"][0]["success"], r.stages[0].success);
  EXPECT_TRUE(json["solver"][0]["iterations"].is_number_integer());
  EXPECT_EQ(json["solver"][0]["iterations"], r.stages[0].iterations);
  EXPECT_EQ(json["solver"][0]["message"], r.stages[0].message);
  // The simulation.
  nlohmann::ordered_json& simulation = json["simulation"];
  ASSERT_TRUE(simulation.is_object());
  EXPECT_EQ(simulation["H_Scm_W_kgm2ps"],
            (nlohmann::ordered_json{sim.H_Scm_W.x(), sim.H_Scm_W.y(), sim.H_Scm_W.z()}));
  EXPECT_EQ(simulation["somersault_turns"].get<double>(), sim.somersault_turns);
  EXPECT_EQ(simulation["twist_turns"].get<double>(), sim.twist_turns);
  EXPECT_EQ(simulation["warnings"], nlohmann::ordered_json(sim.warnings));
  EXPECT_EQ(simulation["final_somersault_tilt_twist_deg"].size(), 3u);
  EXPECT_EQ(simulation["status"], sim.flight.summary.BriefReport());
  EXPECT_EQ(Slurp(dir / "timing.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  const capture::Trial c3d = capture::ReadC3d(dir / "motion.c3d");
  EXPECT_EQ(c3d.num_points(), d.model().num_points());
  EXPECT_EQ(c3d.point_rate_hz, 100.0);
  EXPECT_NEAR(c3d.duration_s(), d.flight_time_s() + 0.01, 0.011);  // frames at 0, 10 ms, …, and T
  const capture::Storage mot = capture::ReadStorage(dir / "motion.mot");
  const int knee = mot.FindColumn("r_knee_flexion");
  ASSERT_GE(knee, 0);
  // Landing: knee 10° (the back tuck's last keyframe); single precision of the text: 1e-4.
  EXPECT_NEAR(mot.data(mot.data.rows() - 1, knee), 10.0, 1e-4);
}

}  // namespace
}  // namespace acro::ui
