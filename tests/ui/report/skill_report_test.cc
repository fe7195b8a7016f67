#include "acro/report/skill_report.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "acro/capture/c3d.h"
#include "acro/capture/storage.h"
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
  TimingOptimizationOptions o;
  o.quadrature_intervals = 20;
  const TimingOptimizationResult r = OptimizeSkillTiming(d, o);
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
  const std::string json = Slurp(dir / "result.json");
  for (const char* key : {"\"keyframe_names\"",
                          "\"keyframe_times_initial_s\"",
                          "\"keyframe_times_s\"",
                          "\"objective_initial\"",
                          "\"objective\"",
                          "\"angular_momentum_variation\"",
                          "\"angular_momentum_variation_initial\"",
                          "\"model\": 2",
                          "\"keyframes_within_tolerance\": true",
                          "\"solver\"",
                          "\"simulation\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  EXPECT_EQ(Slurp(dir / "timing.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  const capture::Trial c3d = capture::ReadC3d(dir / "motion.c3d");
  EXPECT_EQ(c3d.num_points(), d.model().num_points());
  EXPECT_EQ(c3d.point_rate_hz, 100.0);
  EXPECT_NEAR(c3d.duration_s(), d.flight_time_s() + 0.01, 0.011);  // frames at 0, 10 ms, …, and T
  const capture::Storage mot = capture::ReadStorage(dir / "motion.mot");
  const int knee = mot.FindColumn("r_shank:y");
  ASSERT_GE(knee, 0);
  // Landing: knee 10° (the back tuck's last keyframe); single precision of the text: 1e-4.
  EXPECT_NEAR(mot.data(mot.data.rows() - 1, knee), 10.0, 1e-4);
}

}  // namespace
}  // namespace acro::ui
