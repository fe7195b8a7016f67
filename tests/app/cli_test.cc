// The acrolab command line as a user meets it: real processes, real files, exit codes and output.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/capture/trial_io.h"
#include "body25b.h"
#include "refdata.h"
#include "run_command.h"

namespace {

using acro::testing::Execute;
using acro::testing::ProcessResult;
using acro::testing::Quote;

const std::filesystem::path& SampleC3d() {
  static const std::filesystem::path path = [] {
    auto p = acro::testing::TempDir() / "sample_jump.c3d";
    Execute(std::string(MAKE_SAMPLE_EXE) + " " + Quote(p));
    return p;
  }();
  return path;
}

TEST(Cli, InfoJsonHasTheDocumentedKeys) {
  const ProcessResult run =
      Execute(std::string(ACROLAB_EXE) + " info --json " + Quote(SampleC3d()));
  ASSERT_EQ(run.status, 0) << run.err;
  // Parsed (a malformed output fails here), then checked value by value. Not const: [] on a
  // missing key then gives null rather than undefined behaviour.
  nlohmann::json info = nlohmann::json::parse(run.out);
  EXPECT_EQ(info["format"], "C3D") << run.out;
  EXPECT_EQ(info["processor"], "Intel");
  EXPECT_TRUE(info["frames"].is_number_integer());
  EXPECT_GT(info["frames"].get<int>(), 0);
  EXPECT_EQ(info["point_rate_hz"], 200);
  EXPECT_TRUE(info["markers"].is_number_integer());
  EXPECT_EQ(info["markers"], 16);
  ASSERT_TRUE(info["marker_labels"].is_array());
  EXPECT_EQ(info["marker_labels"].size(), 16u);
  EXPECT_EQ(info["missing_marker_frames_total"], 12);
  ASSERT_TRUE(info["gaps"].is_array());
  ASSERT_EQ(info["gaps"].size(), 16u);
  for (nlohmann::json& gap : info["gaps"]) {  // RWRI holds all 12 missing frames, in one gap
    const int missing = gap["label"] == "RWRI" ? 12 : 0;
    EXPECT_EQ(gap["missing_frames"], missing) << gap;
    EXPECT_EQ(gap["longest_gap_frames"], missing) << gap;
    EXPECT_EQ(gap["gap_count"], missing > 0 ? 1 : 0) << gap;
  }
  ASSERT_TRUE(info["analog_channels"].is_array());
  ASSERT_FALSE(info["analog_channels"].empty());
  EXPECT_EQ(info["analog_channels"][0]["label"], "BedFz");
  EXPECT_EQ(info["analog_channels"][0]["unit"], "N");
  EXPECT_EQ(info["analog_rate_hz"], 2000);
  EXPECT_EQ(info["force_plates"], nlohmann::json::array());
  ASSERT_TRUE(info["events"].is_array());
  ASSERT_EQ(info["events"].size(), 2u);
  EXPECT_EQ(info["events"][0]["label"], "Take-off");
  EXPECT_EQ(info["events"][1]["label"], "Landing");
  EXPECT_EQ(info["warnings"], nlohmann::json::array());
}

TEST(Cli, InfoTextNamesGapsEventsAndChannels) {
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " info " + Quote(SampleC3d()));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("RWRI  missing 12 frames in 1 gap, longest 12"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("BedFz [N]"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Take-off"), std::string::npos) << run.out;
}

TEST(Cli, BrokenFileGivesOneLineNamingTheFileAndExitStatus1) {
  const auto bad = acro::testing::TempDir() / "not a capture.c3d";
  std::ofstream(bad) << "this is not a C3D file at all";
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " info " + Quote(bad));
  EXPECT_EQ(run.status, 1);
  EXPECT_TRUE(run.out.empty());
  EXPECT_NE(run.err.find(bad.string()), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
}

TEST(Cli, EveryBrokenReferenceFileFailsCleanlyOrLoads) {
  const auto empty = acro::testing::RefdataFile("BTKData/Input/C3DSamples/others/Empty.c3d");
  ACRO_REQUIRE_REFDATA_FILE(empty);
  for (const char* rel : {"BTKData/Input/C3DSamples/others/Empty.c3d",
                          "BTKData/Input/TRCSamples/Truncated.trc",
                          "BTKData/Input/TRCSamples/Empty.trc",
                          "c3dio-c3d_org_samples/sample_18/bad_parameter_section.c3d"}) {
    const auto path = acro::testing::RefdataFile(rel);
    const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " info " + Quote(path));
    // Each is refused (tests/capture: empty, truncated, a broken parameter section): status 1,
    // nothing on stdout, one line on stderr naming the file.
    EXPECT_EQ(run.status, 1) << rel << ": status " << run.status << " " << run.err;
    EXPECT_TRUE(run.out.empty()) << rel << ": " << run.out;
    EXPECT_NE(run.err.find(path.filename().string()), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

TEST(Cli, ConvertC3dToTrcAndCsvKeepsTheMarkers) {
  const auto dir = acro::testing::TempDir();
  const auto trc = dir / "converted.trc";
  const auto csv = dir / "converted.csv";
  ASSERT_EQ(Execute(std::string(ACROLAB_EXE) + " convert " + Quote(SampleC3d()) + " " + Quote(trc))
                .status,
            0);
  ASSERT_EQ(Execute(std::string(ACROLAB_EXE) + " convert " + Quote(trc) + " " + Quote(csv)).status,
            0);
  const auto a = acro::capture::ReadTrial(SampleC3d());
  const auto b = acro::capture::ReadTrial(csv);
  ASSERT_EQ(a.num_frames, b.num_frames);
  ASSERT_EQ(a.num_points(), b.num_points());
  EXPECT_NEAR(a.point_rate_hz, b.point_rate_hz, 1e-9);
  for (int f = 0; f < a.num_frames; ++f) {
    for (int p = 0; p < a.num_points(); ++p) {
      ASSERT_EQ(a.valid(f, p), b.valid(f, p));
      // TRC keeps 6 decimals of millimetres.
      if (a.valid(f, p)) {
        ASSERT_LT((a.position(f, p) - b.position(f, p)).cwiseAbs().maxCoeff(), 1e-9);
      }
    }
  }
}

TEST(Cli, FailedConvertLeavesNoOutputBehind) {
  const auto dir = acro::testing::TempDir() / "failed_convert";
  std::filesystem::create_directories(dir);
  const auto out = dir / "out.c3d";
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " convert " +
                                    Quote(dir / "missing.trc") + " " + Quote(out));
  EXPECT_EQ(run.status, 1);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(Cli, BadCommandLinesExitWith2) {
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE)).status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " frobnicate").status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " info").status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " info a.c3d --bogus").status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " convert onlyone.c3d").status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " --help").status, 0);
}

// --- acrolab analyze ---

std::string Slurp(const std::filesystem::path& path);

std::filesystem::path RepoFile(const std::string& relative) {
  return acro::testing::SourceDir() / relative;
}

std::string AnalyzeSample(const std::filesystem::path& out, const std::string& extra = "") {
  return std::string(ACROLAB_EXE) + " analyze " +
         Quote(RepoFile("samples/trials/trampoline_routine/trampoline_routine.c3d")) +
         " --athlete " + Quote(RepoFile("samples/athletes/sample_athlete.yaml")) + " -o " +
         Quote(out) + " " + extra;
}

bool HasFile(const std::filesystem::path& p) {
  return std::filesystem::exists(p);
}

TEST(Cli, AnalyzeWritesTheReportAndTablesAndSaysWhere) {
  const auto out = acro::testing::TempDir() / "analyze_sample";
  std::filesystem::remove_all(out);
  const ProcessResult run = Execute(AnalyzeSample(out));
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* f : {"report.html", "jumps.json", "angles.mot", "torques.sto", "residuals.csv"})
    EXPECT_TRUE(HasFile(out / f)) << f;
  EXPECT_NE(run.out.find("routine: 6 skills, DD 3.5"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("physical check: pass"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("report: " + (out / "report.html").string()), std::string::npos);
  // Progress on stderr, one line per step.
  for (const char* step : {"reconstruct:", "phases:", "check:", "metrics:", "report:"})
    EXPECT_NE(run.err.find(step), std::string::npos) << step << "\n" << run.err;
  const std::string html = Slurp(out / "report.html");
  for (const char* code : {"00", "40o", "40&lt;", "41/", "42/", "800o"})
    EXPECT_NE(html.find("<b>" + std::string(code) + "</b>"), std::string::npos) << code;
  // The plots, as PNG for the page and SVG for papers.
  for (const char* f : {"com_height",
                        "residual_force",
                        "residual_moment",
                        "angular_momentum",
                        "joint_angle",
                        "joint_torque"}) {
    EXPECT_TRUE(HasFile(out / (std::string(f) + ".png"))) << f;
    EXPECT_TRUE(HasFile(out / (std::string(f) + ".svg"))) << f;
  }
  EXPECT_NE(html.find("<img src=\"angular_momentum.png\""), std::string::npos);
}

// Every number and text of `actual` equals `expected` (numbers to 1e-9), naming the first
// difference by its JSON path.
void ExpectSameJson(const nlohmann::json& expected,
                    const nlohmann::json& actual,
                    const std::string& path) {
  if (expected.is_number() && actual.is_number()) {
    EXPECT_NEAR(actual.get<double>(), expected.get<double>(), 1e-9) << path;
    return;
  }
  ASSERT_EQ(expected.type(), actual.type()) << path;
  if (expected.is_object()) {
    ASSERT_EQ(expected.size(), actual.size()) << path;
    for (const auto& [key, value] : expected.items()) {
      ASSERT_TRUE(actual.contains(key)) << path << "." << key;
      ExpectSameJson(value, actual[key], path + "." + key);
    }
  } else if (expected.is_array()) {
    ASSERT_EQ(expected.size(), actual.size()) << path;
    for (std::size_t i = 0; i < expected.size(); ++i)
      ExpectSameJson(expected[i], actual[i], path + "[" + std::to_string(i) + "]");
  } else {
    EXPECT_EQ(expected, actual) << path;
  }
}

TEST(Cli, AnalyzeWithoutAnyDisplayWritesTheMilestoneOneNumbersAndTheCharts) {
  const auto out = acro::testing::TempDir() / "analyze_no_display";
  std::filesystem::remove_all(out);
  // No display and nothing on PATH (no xvfb-run): the charts need neither.
  const ProcessResult run =
      Execute("env -u DISPLAY PATH=/nonexistent " + AnalyzeSample(out, "--quiet"));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string html = Slurp(out / "report.html");
  EXPECT_EQ(html.find("No plots in this report"), std::string::npos);
#ifdef ACRO_HAVE_VIEWS
  // The filmstrips need the 3D views, which need Xvfb here: the page says why there are none.
  EXPECT_NE(html.find("no filmstrips: 3D views: no X display"), std::string::npos);
#endif
  EXPECT_TRUE(HasFile(out / "com_height.png"));
  EXPECT_TRUE(HasFile(out / "com_height.svg"));
  // jumps.json as milestone 1 wrote it (tests/data, made by the milestone-1 build on this sample).
  const nlohmann::json expected =
      nlohmann::json::parse(Slurp(std::filesystem::path(ACRO_DEFAULT_SOURCE_DIR) /
                                  "tests/data/sample_routine_jumps_milestone1.json"));
  nlohmann::json actual = nlohmann::json::parse(Slurp(out / "jumps.json"));
  ASSERT_EQ(expected.size(), 6u);
  // Milestone 2 added keys: the silhouette IoU, null without a video, why the shape (the FIG
  // body positions held: the same shapes as milestone 1's on this sample, checked below), where
  // the surface's height comes from (here the bed's corner markers) and the twist's direction;
  // milestone 3 the score sheet's line.
  for (nlohmann::json& jump : actual) {
    EXPECT_TRUE(jump["silhouette_iou"].is_null());
    jump.erase("silhouette_iou");
    EXPECT_EQ(jump["surface"], "bed at rest 1.155 m from markers BED_C1–BED_C4");
    jump.erase("surface");
    // The judged (windowed) residuals and what the trial's noise alone gives them: with markers
    // of 1 mm noise the floor raises no limit (the verdicts are milestone 1's).
    if (jump["check"].is_object()) {
      EXPECT_FALSE(jump["check"]["noise_floor"]["judged_against_noise"].get<bool>());
      for (const char* key : {"window_force_bw", "window_moment_bwh", "noise_floor"})
        jump["check"].erase(key);
    }
    const std::string shape = jump["shape"].get<std::string>();
    EXPECT_EQ(jump["shape_reason"].get<std::string>().rfind(shape + ":", 0), 0u)
        << jump["shape_reason"];
    EXPECT_EQ(jump["shape_hold_fraction"].get<double>() >= 0.15, shape != "straight");
    jump.erase("shape_reason");
    jump.erase("shape_hold_fraction");
    // No shape of this sample is a close call (its holds are far from 135°).
    EXPECT_TRUE(jump["shape_alternative"].is_null()) << jump["shape_alternative"];
    jump.erase("shape_alternative");
    // Which way it twists: the barani and the full to the left, as the simulator made them.
    const std::string code = jump["fig_code"].get<std::string>();
    EXPECT_EQ(jump["twist_direction"], code == "41/" || code == "42/" ? "left" : "none") << code;
    jump.erase("twist_direction");
    // Milestone 3: the jump's line on the score sheet (the straight in-bounce is no element).
    EXPECT_EQ(jump["score"].is_null(), code == "00") << code;
    if (!jump["score"].is_null()) {
      EXPECT_EQ(jump["score"]["code"], code);
    }
    jump.erase("score");
  }
  ExpectSameJson(expected, actual, "jumps");
}

TEST(Cli, AnalyzeRefusesBadInputBeforeWritingAnything) {
  const auto out = acro::testing::TempDir() / "analyze_bad";
  std::filesystem::remove_all(out);
  // A joint that does not exist: exit 2, nothing written.
  ProcessResult run = Execute(AnalyzeSample(out, "--joint r_elbow_twist --no-images"));
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("r_elbow_twist"), std::string::npos) << run.err;
  EXPECT_FALSE(HasFile(out));
  // A missing athlete file: one line naming it, exit 1, nothing written.
  run = Execute(std::string(ACROLAB_EXE) + " analyze " +
                Quote(RepoFile("samples/trials/trampoline_routine/trampoline_routine.c3d")) +
                " --athlete /nonexistent/athlete.yaml -o " + Quote(out));
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("/nonexistent/athlete.yaml"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(HasFile(out));
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " analyze").status, 2);
  EXPECT_EQ(Execute(std::string(ACROLAB_EXE) + " analyze a.c3d").status, 2);  // no -o
}

// Video keypoints (17 COCO) with no athlete file: a default athlete, with a warning.
TEST(Cli, AnalyzeTakesACocoKeypointTrcWithoutAthlete) {
  const auto trc = acro::testing::RefdataFile(
      "s2mLab-EKF_multicamera-trampoline/inputs/trc/1_partie_0429_002.trc");
  ACRO_REQUIRE_REFDATA_FILE(trc);
  const auto out = acro::testing::TempDir() / "analyze_keypoints";
  std::filesystem::remove_all(out);
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(trc) +
                                    " --height 1.70 --mass 60 --surface-height 1.155 --quiet "
                                    "--no-images -o " +
                                    Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("warning: no --athlete file"), std::string::npos) << run.err;
  EXPECT_NE(run.out.find("routine: 5 skills"), std::string::npos) << run.out;
  EXPECT_TRUE(HasFile(out / "jumps.json"));
}

// Issue "real-data fidelity", acceptance: the Pose2Sim balancing trial (BODY_25B keypoints, Y up)
// and the s2mLab routine (COCO-17, no bed markers), each with no option at all. The balancing
// trial holds no jump: since issue "Rules, not examples" (a trial whose markers never leave the
// floor is one line, exit 1, nothing written) `analyze` refuses it after saying what it found,
// and `reconstruct` gives its joint angles.
TEST(Cli, AnalyzeTakesKeypointTrialsWithNoOptions) {
  const auto balancing = acro::testing::RefdataFile(
      "pose2sim-demo/balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  ACRO_REQUIRE_REFDATA_FILE(balancing);
  const auto out = acro::testing::TempDir() / "analyze_no_options";
  std::filesystem::remove_all(out);
  ProcessResult run = Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(balancing) +
                              " --no-images -o " + Quote(out));
  ASSERT_EQ(run.status, 1) << run.err;
  // The up axis and the keypoint set found, the fit error said, then the missing flight.
  EXPECT_NE(run.err.find("+Y up (detected"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("turned to Z up"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("the body25b keypoints"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("reconstruct: marker RMS median"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("no flight in its 100 frames"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << "analyze wrote outputs for a trial with no jump";
  run =
      Execute(std::string(ACROLAB_EXE) + " reconstruct " + Quote(balancing) + " -o " + Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_FALSE(std::filesystem::is_empty(out));

  const auto s2m = acro::testing::RefdataFile(
      "s2mLab-EKF_multicamera-trampoline/inputs/trc/1_partie_0429_002.trc");
  ACRO_REQUIRE_REFDATA_FILE(s2m);
  std::filesystem::remove_all(out);
  run = Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(s2m) + " --no-images -o " +
                Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  // The bed's level estimated and said with its spread; judged against the trial's noise.
  EXPECT_NE(run.out.find("surface: bed at rest "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find(" m (spread "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("estimated from the soles and the COM"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("routine: 5 skills"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("its noise (≈ "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("mm per coordinate, video keypoints)"), std::string::npos) << run.out;
}

}  // namespace

namespace {

std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Samples, CommittedSampleTrialIsWhatTheGeneratorMakes) {
  // samples/ holds only what the project makes itself: regenerating gives the same bytes.
  const auto committed =
      acro::testing::SourceDir() / "samples/trials/straight_jump/straight_jump.c3d";
  ASSERT_TRUE(std::filesystem::exists(committed));
  EXPECT_EQ(Slurp(committed), Slurp(SampleC3d()))
      << "regenerate with: build/bin/make_sample_trial "
         "samples/trials/straight_jump/straight_jump.c3d";
}

}  // namespace

namespace {

// The balancing trial through `acrolab project --csv`, against the OpenPose detections of the same
// video frames (../shared/refdata/pose2sim-demo/expected.md: medians 11.3, 7.7, 17.2, 8.5 px for an
// independent projection; the TRC is Y-up, the lab's axes are its (z, x, y)).
TEST(Cli, ProjectCsvLandsOnTheDetectionsAsExpected) {
  const auto root = acro::testing::RefdataFile("pose2sim-demo");
  const auto trc = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  ACRO_REQUIRE_REFDATA_FILE(trc);
  const auto csv = acro::testing::TempDir() / "projection.csv";
  const ProcessResult run =
      Execute(std::string(ACROLAB_EXE) + " project " + Quote(trc) + " --calib " +
              Quote(root / "calibration/Calib_qualisys.toml") + " --axes zxy --csv " + Quote(csv));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::map<std::string, int>& body25b = acro::testing::Body25bIndex();
  std::map<std::string, std::vector<double>> errors;
  std::map<std::string, nlohmann::json> detections;  // "cam_01/7" -> people
  std::istringstream rows(Slurp(csv));
  std::string line;
  std::getline(rows, line);
  ASSERT_EQ(line, "camera,frame,time_s,marker,u_px,v_px");
  while (std::getline(rows, line)) {
    std::istringstream fields(line);
    std::string camera, frame, time, marker, u, v;
    std::getline(fields, camera, ',');
    std::getline(fields, frame, ',');
    std::getline(fields, time, ',');
    std::getline(fields, marker, ',');
    std::getline(fields, u, ',');
    std::getline(fields, v, ',');
    const int cam = std::stoi(camera.substr(4)), f = std::stoi(frame);
    const std::string key = camera + "/" + frame;
    if (!detections.count(key)) {
      char name[64];
      std::snprintf(name, sizeof name, "cam%02d_json/cam%02d.%04d.json", cam, cam, f);
      detections[key] =
          nlohmann::json::parse(Slurp(root / "balancing-trial/pose" / name))["people"];
    }
    const size_t i = 3 * static_cast<size_t>(body25b.at(marker));
    double best = 1e300;
    for (const nlohmann::json& person : detections[key]) {
      const nlohmann::json& k = person["pose_keypoints_2d"];
      if (k[i + 2].get<double>() <= 0.5) continue;
      best = std::min(
          best,
          std::hypot(k[i].get<double>() - std::stod(u), k[i + 1].get<double>() - std::stod(v)));
    }
    if (best < 1e300) errors[camera].push_back(best);
  }
  const std::map<std::string, double> expected = {
      {"cam_01", 11.3}, {"cam_02", 7.7}, {"cam_03", 17.2}, {"cam_04", 8.5}};
  for (const auto& [camera, median] : expected) {
    std::vector<double>& e = errors[camera];
    ASSERT_GT(e.size(), 1000u) << camera;
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    EXPECT_NEAR(e[e.size() / 2], median, 0.5) << camera;
  }
}

// `reconstruct --detections`: Pose2Sim's four cameras' OpenPose detections to the 3D keypoints
// (within 10 mm median of Pose2Sim's own TRC, distortion modelled) and the joint angles; and the
// mistakes a user makes with several cameras, one line each, nothing written.
TEST(Cli, ReconstructFromSeveralCamerasDetections) {
  const auto root = acro::testing::RefdataFile("pose2sim-demo");
  const auto theirs_path = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  ACRO_REQUIRE_REFDATA_FILE(theirs_path);
  const auto calib = root / "calibration/Calib_qualisys.toml";
  auto source = [&](int c) {
    return " --detections cam_0" + std::to_string(c) + "=" +
           Quote(root / "balancing-trial/pose" / ("cam0" + std::to_string(c) + "_json"));
  };
  const std::string four = source(1) + source(2) + source(3) + source(4);
  const auto out = acro::testing::ScratchDir("reconstruct_views");
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " reconstruct" + four + " --calib " +
                                    Quote(calib) + " --rate 60 --quiet -o " + Quote(out / "a"));
  ASSERT_EQ(run.status, 0) << run.err;
  // The balancing trial hardly moves: the offsets cannot be told, and the user is told so.
  EXPECT_NE(run.err.find("do not tell its offset"), std::string::npos) << run.err;
  for (const char* f : {"triangulated.trc",
                        "triangulated_triangulation.txt",
                        "triangulated.mot",
                        "triangulated_angles.csv",
                        "triangulated_summary.txt"})
    EXPECT_TRUE(std::filesystem::exists(out / "a" / f)) << f;
  const acro::capture::Trial ours = acro::capture::ReadTrial(out / "a/triangulated.trc");
  const acro::capture::Trial theirs = acro::capture::ReadTrial(theirs_path);
  ASSERT_EQ(ours.num_frames, 100);
  std::vector<double> d;
  for (int j = 0; j < theirs.num_points(); ++j) {
    int o = -1;
    for (int i = 0; i < ours.num_points(); ++i)
      if (ours.points[i].label == theirs.points[j].label) o = i;
    ASSERT_GE(o, 0) << theirs.points[j].label;
    for (int k = 0; k < 100; ++k) {
      if (!theirs.valid(k, j) || !ours.valid(k, o)) continue;
      const Eigen::Vector3d p = theirs.position(k, j);
      d.push_back((ours.position(k, o) - Eigen::Vector3d(p.z(), p.x(), p.y())).norm());
    }
  }
  ASSERT_GT(d.size(), 1500u);
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  EXPECT_LT(d[d.size() / 2], 0.010);

  const std::string exe = std::string(ACROLAB_EXE) + " reconstruct";
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {source(1) + " --detections cam_09=" + Quote(root / "balancing-trial/pose/cam02_json") +
           " --calib " + Quote(calib) + " --rate 60",
       "cam_09"},
      {source(1) + source(1) + " --calib " + Quote(calib) + " --rate 60", "given twice"},
      {source(1) + " --calib " + Quote(calib) + " --rate 60", "at least 2"},
      {four + " --calib " + Quote(calib), "--rate"},
      {four + " --rate 60", "--calib"},
      {four + " --calib " + Quote(calib) + " --rate 60 --keypoints coco17", "cam01"},
      {four + " --calib " + Quote(calib) + " --rate 60 --offset cam_07=3", "cam_07"},
      {four + " --calib " + Quote(calib) + " --rate 60 --offset cam_02=x", "CAM=FRAMES"},
      {" --detections cam_01 --calib " + Quote(calib) + " --rate 60", "CAMERA=PATH"},
  };
  for (const Case& c : cases) {
    const auto dir = out / "bad";
    const ProcessResult bad = Execute(exe + c.args + " --quiet -o " + Quote(dir));
    EXPECT_TRUE(bad.status == 1 || bad.status == 2) << c.args << "\n" << bad.err;  // input, usage
    EXPECT_NE(bad.err.find(c.message), std::string::npos) << c.args << "\n" << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir)) << c.args;
  }
}

// `calibrate intrinsics` on one phone's photos: the photo without a board is named and skipped,
// the reprojection error printed, and the camera written where `project` reads it.
TEST(Cli, CalibrateIntrinsicsReportsEachPhotoAndWritesTheCamera) {
  const auto dir = acro::testing::RefdataFile("pose2sim-demo/calibration/intrinsics/cam02");
  ACRO_REQUIRE_REFDATA_FILE(dir);
  const auto out = acro::testing::TempDir() / "cam02_intrinsics.toml";
  const ProcessResult run =
      Execute(std::string(ACROLAB_EXE) + " calibrate intrinsics --board checkerboard:4x7:60mm " +
              Quote(dir) + "/*.jpg --name cam02 -o " + Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("cam02_06_int.jpg: skipped, no board found"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("cam02: 1088 x 1920 px, fx 1675."), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("reprojection RMS 0.2"), std::string::npos) << run.out;
  EXPECT_NE(Slurp(out).find("[cam02]"), std::string::npos);
  // Extrinsics from points: four corners of a 2 m square on the floor, seen by this camera as the
  // test places them (3 m in front of it), come back with a tiny error.
  const auto p3 = acro::testing::TempDir() / "p3.csv";
  const auto p2 = acro::testing::TempDir() / "p2.csv";
  std::ofstream(p3) << "name,x_m,y_m,z_m\nA,-1,-1,0\nB,1,-1,0\nC,1,1,0\nD,-1,1,0\nE,0,0,0.5\n";
  // Camera at (0, 0, 3) looking down (R_KW = diag(1, −1, −1)): u = cx + f x / (3 − z),
  // v = cy − f y / (3 − z), with no distortion for this check.
  std::ofstream(acro::testing::TempDir() / "pin.toml")
      << "[pin]\nsize = [ 1000.0, 1000.0]\nmatrix = [ [ 800.0, 0.0, 500.0], [ 0.0, 800.0, "
         "500.0], [ 0.0, 0.0, 1.0]]\ndistortions = [ 0.0, 0.0, 0.0, 0.0]\nrotation = [ 0.0, "
         "0.0, 0.0]\ntranslation = [ 0.0, 0.0, 0.0]\n";
  std::ofstream(p2) << "name,u_px,v_px\nA,233.333,766.667\nB,766.667,766.667\nC,766.667,233.333\n"
                       "D,233.333,233.333\nE,500,500\n";
  const ProcessResult ex = Execute(std::string(ACROLAB_EXE) + " calibrate extrinsics --points3d " +
                                   Quote(p3) + " --points2d " + Quote(p2) + " --intrinsics " +
                                   Quote(acro::testing::TempDir() / "pin.toml") + " -o " +
                                   Quote(acro::testing::TempDir() / "posed.toml"));
  ASSERT_EQ(ex.status, 0) << ex.err;
  EXPECT_NE(ex.out.find("0000, 3.0000) m, reprojection RMS 0.000 px over 5 points"),
            std::string::npos)
      << ex.out;
}

// Extrinsics from the bed found in a frame: the sample's side camera from its video and the trial's
// BED_C1…C4, the corners written for checking, the camera within 10 cm of the truth (0.4, −9.7,
// 3.4) m; a picture with no bed, or both kinds of 2D input, is one line and status 1.
TEST(Cli, CalibrateExtrinsicsFromTheDetectedBed) {
  const std::string sample = "samples/trials/trampoline_routine/";
  const auto dir = acro::testing::ScratchDir("calibrate_bed");
  const std::string common = std::string(ACROLAB_EXE) + " calibrate extrinsics --points3d " +
                             Quote(RepoFile(sample + "trampoline_routine.c3d")) + " --intrinsics " +
                             Quote(RepoFile(sample + "side_camera.toml"));
  const ProcessResult run =
      Execute(common + " --detect-bed " + Quote(RepoFile(sample + "side_camera.mp4")) +
              " --frame 100 --corners-csv " + Quote(dir / "corners.csv") + " -o " +
              Quote(dir / "side.toml"));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string corners = Slurp(dir / "corners.csv");
  for (const char* name : {"BED_C1", "BED_C2", "BED_C3", "BED_C4"})
    EXPECT_NE(corners.find(name), std::string::npos) << corners;
  EXPECT_NE(Slurp(dir / "side.toml").find("[side]"), std::string::npos);
  const size_t at = run.out.find("side: centre (");
  ASSERT_NE(at, std::string::npos) << run.out;
  double x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(run.out.c_str() + at, "side: centre (%lf, %lf, %lf)", &x, &y, &z), 3);
  EXPECT_LT(std::hypot(x - 0.4, y + 9.7, z - 3.4), 0.10) << run.out;
  EXPECT_NE(run.out.find("the other naming: centre"), std::string::npos) << run.out;

  std::ofstream(dir / "plain.pgm", std::ios::binary) << "P5\n64 48\n255\n"
                                                     << std::string(64 * 48, char(200));
  const ProcessResult none = Execute(common + " --detect-bed " + Quote(dir / "plain.pgm") + " -o " +
                                     Quote(dir / "x.toml"));
  EXPECT_EQ(none.status, 1);
  EXPECT_NE(none.err.find("plain.pgm: bed: no trampoline bed found"), std::string::npos)
      << none.err;
  EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
  const ProcessResult both =
      Execute(common + " --detect-bed " + Quote(dir / "plain.pgm") + " --points2d " +
              Quote(dir / "corners.csv") + " -o " + Quote(dir / "x.toml"));
  EXPECT_EQ(both.status, 1);
  EXPECT_NE(both.err.find("either --points2d or --detect-bed"), std::string::npos) << both.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.toml"));
}

// The acceptance's bad inputs: one line on stderr naming the file and what is wrong, status 1.
TEST(Cli, BadVideosAndCalibrationsAreOneLineAndStatus1) {
  const auto dir = acro::testing::TempDir() / "bad_inputs";
  std::filesystem::create_directories(dir);
  auto expect_one_line = [](const ProcessResult& run, const std::string& needle) {
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  };
  std::ofstream(dir / "notes.mp4") << "this is a text file\n";
  expect_one_line(Execute(std::string(ACROLAB_EXE) + " video info " + Quote(dir / "notes.mp4")),
                  "notes.mp4");
  // A zero-frame MP4: a video stream with no packet (ffmpeg's command line writes it).
  const ProcessResult made = Execute(
      "ffmpeg -v error -y -f lavfi -i color=c=black:s=64x64:r=25 "
      "-frames:v 0 -c:v libx264 " +
      Quote(dir / "empty.mp4"));
  if (made.status == 0 && std::filesystem::exists(dir / "empty.mp4")) {
    expect_one_line(Execute(std::string(ACROLAB_EXE) + " video info " + Quote(dir / "empty.mp4")),
                    "empty.mp4");
  }
  const auto video = acro::testing::RefdataFile("pose2sim-demo/videos/cam01.mp4");
  if (std::filesystem::exists(video)) {
    const std::string bytes = Slurp(video);
    std::ofstream(dir / "cut.mp4", std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 3));
    const ProcessResult cut =
        Execute(std::string(ACROLAB_EXE) + " video frame " + Quote(dir / "cut.mp4") +
                " --frame 99 -o " + Quote(dir / "f.png"));
    expect_one_line(cut, "cut.mp4");
    EXPECT_FALSE(std::filesystem::exists(dir / "f.png"));
  }
  const auto calib = acro::testing::RefdataFile("pose2sim-demo/calibration/Calib_qualisys.toml");
  const auto trc = acro::testing::RefdataFile(
      "pose2sim-demo/balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  if (std::filesystem::exists(calib)) {
    expect_one_line(Execute(std::string(ACROLAB_EXE) + " project " + Quote(trc) + " --calib " +
                            Quote(calib) + " --camera cam_07 --axes zxy"),
                    "Calib_qualisys.toml: --camera: no camera named 'cam_07' (there are cam_01");
  }
  std::ofstream(dir / "skewed.toml")
      << "[cam_a]\nsize = [ 640.0, 480.0]\nmatrix = [ [ 500.0, 0.0, 320.0], [ 0.0, 500.0, "
         "240.0], [ 0.0, 0.0, 1.0]]\ndistortions = [ 0.0, 0.0, 0.0, 0.0]\nrotation = [ 1.0, "
         "0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0, 1.0]\ntranslation = [ 0.0, 0.0, 1.0]\n";
  expect_one_line(Execute(std::string(ACROLAB_EXE) + " project " + Quote(SampleC3d()) +
                          " --calib " + Quote(dir / "skewed.toml")),
                  "skewed.toml: [cam_a]: the rotation is not orthonormal");
}

// `sync` from the four cameras' OpenPose detections: the balancing trial as recorded is in sync.
TEST(Cli, SyncFromDetectionsFindsTheRecordedTrialInSync) {
  const auto root = acro::testing::RefdataFile("pose2sim-demo");
  const auto trc = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  ACRO_REQUIRE_REFDATA_FILE(trc);
  std::string command = std::string(ACROLAB_EXE) + " sync " + Quote(trc) + " --calib " +
                        Quote(root / "calibration/Calib_qualisys.toml") +
                        " --axes zxy --fps 60 --search-s -0.5:0.5";
  for (int cam = 1; cam <= 4; ++cam)
    command += " --detections cam_0" + std::to_string(cam) + "=" +
               Quote(root / "balancing-trial/pose" / ("cam0" + std::to_string(cam) + "_json"));
  const ProcessResult run = Execute(command);
  ASSERT_EQ(run.status, 0) << run.err;
  const size_t at = run.out.find("use: --offset-s ");
  ASSERT_NE(at, std::string::npos) << run.out;
  EXPECT_NEAR(std::stod(run.out.substr(at + 16)) * 60.0, 0.0, 1.0 / 3.0) << run.out;
}

// SIGTERM in the middle of an overlay: exit 143, one line saying so, and neither the output nor
// its staging directory left behind.
TEST(Cli, TerminatedOverlayLeavesNothingBehind) {
  const auto root = acro::testing::RefdataFile("pose2sim-demo");
  const auto trc = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  ACRO_REQUIRE_REFDATA_FILE(trc);
  const auto dir = acro::testing::TempDir() / "terminated";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto out = dir / "frames";
  const std::string command = std::string(ACROLAB_EXE) + " project " + Quote(trc) + " --calib " +
                              Quote(root / "calibration/Calib_qualisys.toml") +
                              " --camera cam_02 --axes zxy --video " +
                              Quote(root / "videos/cam02.mp4") + " -o " + Quote(out);
  // Start it, wait until its staging directory holds a frame, then SIGTERM it.
  std::ofstream(dir / "run.sh") << command << " 2>" << Quote(dir / "err.txt")
                                << " >/dev/null &\npid=$!\nfor i in $(seq 400); do\n  ls "
                                << Quote(dir) << "/frames.tmp-*/frame_000002.png >/dev/null 2>&1"
                                << " && break\n  sleep 0.05\ndone\nkill -TERM $pid\nwait $pid\n"
                                << "echo status=$?\n";
  const ProcessResult run = Execute("bash " + Quote(dir / "run.sh"));
  EXPECT_NE(run.out.find("status=143"), std::string::npos) << run.out << run.err;
  const std::string err = Slurp(dir / "err.txt");
  EXPECT_NE(err.find("acrolab: interrupted (SIGTERM); 1 unfinished output removed"),
            std::string::npos)
      << err;
  EXPECT_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find("frames.tmp-"), std::string::npos) << e.path();
}

// An output directory that cannot be one is refused before any work, in one line, exit 1.
TEST(Cli, UnusableOutputDirectoryIsRefusedFirst) {
  const auto file = acro::testing::TempDir() / "not_a_dir";
  std::ofstream(file) << "x";
  for (const std::string command : {"analyze", "reconstruct"}) {
    const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " " + command + " " +
                                      Quote(SampleC3d()) + " -o " + Quote(file) + " --quiet");
    EXPECT_EQ(run.status, 1) << command << ": " << run.err;
    EXPECT_NE(run.err.find("not_a_dir: is a file, not a directory for the outputs"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(run.err.find("reconstruct:"), std::string::npos) << "work was done: " << run.err;
  }
  const ProcessResult proc = Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(SampleC3d()) +
                                     " -o /proc/acrolab_cannot_be_here --quiet");
  EXPECT_EQ(proc.status, 1) << proc.err;
  EXPECT_NE(proc.err.find("cannot create the output directory"), std::string::npos) << proc.err;
}

// Image-motion sync from the command line: the sample routine's markers drawn by `project` on a
// noise video 0.37 s late, then `sync` finds the offset within a frame.
TEST(Cli, SyncFromImageMotionFindsALateVideo) {
  const auto dir = acro::testing::TempDir() / "sync_motion";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const ProcessResult noise = Execute(
      "ffmpeg -v error -y -f lavfi -i "
      "'color=c=0x6e6e6e:s=480x360:r=30:d=10.2,noise=alls=12:allf=t' -c:v libx264 "
      "-preset ultrafast -pix_fmt yuv420p " +
      Quote(dir / "grey.mp4"));
  if (noise.status != 0) GTEST_SKIP() << "the ffmpeg command is not installed";
  const std::string trial =
      Quote(RepoFile("samples/trials/trampoline_routine/trampoline_routine.c3d"));
  const std::string calib = Quote(RepoFile("tests/data/sample_routine_side_camera.toml"));
  const ProcessResult drawn = Execute(std::string(ACROLAB_EXE) + " project " + trial + " --calib " +
                                      calib + " --offset-s -0.37 --video " +
                                      Quote(dir / "grey.mp4") + " -o " + Quote(dir / "late.mp4"));
  ASSERT_EQ(drawn.status, 0) << drawn.err;
  const ProcessResult run =
      Execute(std::string(ACROLAB_EXE) + " sync " + trial + " --calib " + calib + " --video " +
              Quote(dir / "late.mp4") + " --plot " + Quote(dir / "cost.svg"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("sync from image motion"), std::string::npos) << run.out;
  const size_t at = run.out.find("use: --offset-s ");
  ASSERT_NE(at, std::string::npos) << run.out;
  EXPECT_NEAR(std::stod(run.out.substr(at + 16)), -0.37, 1.0 / 30.0) << run.out;
  EXPECT_NE(Slurp(dir / "cost.svg").find("<svg"), std::string::npos);
}

// `video flights` on a video with no bed in its first frame and no line given: one line naming the
// video and what to give, no detection run, nothing written.
TEST(Cli, VideoFlightsWithoutABedSaysSoBeforeAnyWork) {
  const auto dir = acro::testing::TempDir() / "flights_no_bed";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const ProcessResult grey = Execute(
      "ffmpeg -v error -y -f lavfi -i 'color=c=0xb4b4b4:s=320x240:r=30:d=1' -c:v libx264 "
      "-preset ultrafast -pix_fmt yuv420p " +
      Quote(dir / "grey.mp4"));
  if (grey.status != 0) GTEST_SKIP() << "the ffmpeg command is not installed";
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " video flights " +
                                    Quote(dir / "grey.mp4") + " -o " + Quote(dir / "out"));
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("grey.mp4"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--bed-line"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("detect ["), std::string::npos) << "work was done: " << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "flights.json"));
  // A malformed line is the option's own error.
  const ProcessResult bad =
      Execute(std::string(ACROLAB_EXE) + " video flights " + Quote(dir / "grey.mp4") +
              " --bed-line 12 -o " + Quote(dir / "out"));
  EXPECT_EQ(bad.status, 2) << bad.err;  // the command line's mistake, not an internal error
  EXPECT_NE(bad.err.find("--bed-line: needs Y0,SLOPE"), std::string::npos) << bad.err;
}

// `analyze --video V --calib C` with one camera whose calibration's world is not Z up: one line
// naming the calibration and the camera before any detection, nothing written.
TEST(Cli, OneCameraWhoseWorldIsNotZUpIsRefusedFirst) {
  const auto dir = acro::testing::TempDir() / "one_camera_y_up";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream toml(dir / "y_up.toml");
    toml << "[side]\nname = \"side\"\nsize = [1920, 1080]\n"
            "matrix = [[1482, 0, 968.4], [0, 1478.5, 536.1], [0, 0, 1]]\n"
            "distortions = [0, 0, 0, 0]\nrotation = [0, 0, 0]\ntranslation = [0, 0, 10]\n"
            "fisheye = false\n";
  }
  const ProcessResult run =
      Execute(std::string(ACROLAB_EXE) + " analyze --video " +
              Quote(RepoFile("samples/trials/trampoline_routine/side_camera.mp4")) + " --calib " +
              Quote(dir / "y_up.toml") + " -o " + Quote(dir / "out"));
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("y_up.toml: camera side: "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("Z is up"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("detect ["), std::string::npos) << "work was done: " << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "report.html"));
}

#ifdef ACRO_HAVE_VIEWS
// `analyze --video`: the sample routine with its video (made from the true motion, 0.575 s after
// the mocap): the sync found from the image motion, a silhouette IoU per jump in jumps.json and on
// the page, the overlay video written and shown.
TEST(Cli, AnalyzeWithTheSampleVideoWritesTheOverlayAndTheSilhouettes) {
  const auto out = acro::testing::TempDir() / "analyze_video";
  std::filesystem::remove_all(out);
  const std::string dir = "samples/trials/trampoline_routine/";
  const ProcessResult run = Execute(
      "env -u DISPLAY " +
      AnalyzeSample(out,
                    "--quiet --video " + Quote(RepoFile(dir + "side_camera.mp4")) + " --calib " +
                        Quote(RepoFile(dir + "side_camera.toml")) + " --sync auto"));
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json jumps = nlohmann::json::parse(Slurp(out / "jumps.json"));
  ASSERT_EQ(jumps.size(), 6u);
  for (const nlohmann::json& j : jumps) {
    ASSERT_TRUE(j["silhouette_iou"].is_number()) << j.dump();
    EXPECT_GT(j["silhouette_iou"].get<double>(), 0.8) << j["fig_code"];
  }
  EXPECT_TRUE(HasFile(out / "overlay.mp4"));
  EXPECT_TRUE(HasFile(out / "silhouette_iou.png"));
  // A filmstrip per complete jump, on the page, and as a video linked under it.
  for (int k = 1; k <= 6; ++k) {
    const std::string file = "filmstrip_jump_" + std::to_string(k) + ".png";
    EXPECT_TRUE(HasFile(out / file)) << file;
    EXPECT_NE(Slurp(out / "report.html").find("src=\"" + file + "\""), std::string::npos) << file;
    const std::string video = "filmstrip_jump_" + std::to_string(k) + ".mp4";
    EXPECT_TRUE(HasFile(out / video)) << video;
    EXPECT_NE(Slurp(out / "report.html").find("href=\"" + video + "\""), std::string::npos)
        << video;
  }
  const std::string html = Slurp(out / "report.html");
  EXPECT_NE(html.find("<video controls"), std::string::npos);
  EXPECT_NE(html.find("src=\"overlay.mp4\""), std::string::npos);
  const ProcessResult info =
      Execute(std::string(ACROLAB_EXE) + " video info --json " + Quote(out / "overlay.mp4"));
  ASSERT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["frames"], 299);
}

// With no display and no Xvfb to start, the 3D views say what to install, in one line, and
// write nothing.
TEST(Cli, OverlayWithoutADisplayOrXvfbSaysWhatToInstall) {
  const auto out = acro::testing::TempDir() / "overlay_no_xvfb.mp4";
  std::filesystem::remove(out);
  const std::string dir = "samples/trials/trampoline_routine/";
  const ProcessResult run =
      Execute("env -u DISPLAY PATH=/nonexistent " + std::string(ACROLAB_EXE) + " overlay " +
              Quote(RepoFile(dir + "trampoline_routine.c3d")) + " --video " +
              Quote(RepoFile(dir + "side_camera.mp4")) + " --calib " +
              Quote(RepoFile(dir + "side_camera.toml")) + " --offset-s -0.575 -o " + Quote(out));
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("install the xvfb package"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// Runs the sample routine's overlay with no display (so it starts its own Xvfb) in `dir`, stderr
// to dir/err.txt; once its third frame is staged, prints "xvfb=PID" of its server, runs `then`
// (shell; $pid is acrolab's, $xvfb the server's), waits for acrolab, prints "status=N" and runs
// `after`.
ProcessResult OverlayOnItsOwnXvfbThen(const std::filesystem::path& dir,
                                      const std::string& then,
                                      const std::string& after = "") {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string sample = "samples/trials/trampoline_routine/";
  const std::string command = "env -u DISPLAY " + std::string(ACROLAB_EXE) + " overlay " +
                              Quote(RepoFile(sample + "trampoline_routine.c3d")) + " --video " +
                              Quote(RepoFile(sample + "side_camera.mp4")) + " --calib " +
                              Quote(RepoFile(sample + "side_camera.toml")) +
                              " --offset-s -0.575 -o " + Quote(dir / "frames");
  std::ofstream(dir / "run.sh") << command << " 2>" << Quote(dir / "err.txt")
                                << " >/dev/null &\npid=$!\nfor i in $(seq 400); do\n  ls "
                                << Quote(dir) << "/frames.tmp-*/frame_000003.png >/dev/null 2>&1"
                                << " && break\n  sleep 0.05\ndone\n"
                                << "xvfb=$(pgrep -P $pid Xvfb)\necho xvfb=$xvfb\n"
                                << then << "\nwait $pid\necho status=$?\n"
                                << after;
  return Execute("bash " + Quote(dir / "run.sh"));
}

// Neither the overlay's frames nor their staging directory are in `dir`.
void ExpectNoOverlayLeft(const std::filesystem::path& dir) {
  EXPECT_FALSE(std::filesystem::exists(dir / "frames"));
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find("frames.tmp-"), std::string::npos) << e.path();
}

// SIGTERM to an overlay that started its own Xvfb: exit 143, no output left, and the Xvfb server
// stopped with it (no re-exec under xvfb-run, which orphans the work).
TEST(Cli, TerminatedOverlayStopsItsXvfb) {
  const auto dir = acro::testing::TempDir() / "terminated_views";
  // Up to 5 s for the server to end (a zombie has ended).
  const ProcessResult run = OverlayOnItsOwnXvfbThen(
      dir,
      "kill -TERM $pid",
      "alive() { kill -0 $1 2>/dev/null && ! ps -o stat= -p $1 | grep -q Z; }\n"
      "for i in $(seq 50); do alive $xvfb || break; sleep 0.1; done\n"
      "if [ -n \"$xvfb\" ] && alive $xvfb; then echo xvfb-alive; fi\n");
  EXPECT_NE(run.out.find("status=143"), std::string::npos) << run.out << run.err;
  EXPECT_EQ(run.out.find("xvfb=\n"), std::string::npos) << "no Xvfb was started: " << run.out;
  EXPECT_EQ(run.out.find("xvfb-alive"), std::string::npos) << run.out;
  ExpectNoOverlayLeft(dir);
}

// The X server of an overlay's views gone under it (its Xvfb killed): one line naming the display,
// exit 1, and neither the output nor its staging directory left — not Xlib's bare exit, which
// left the staging directory behind.
TEST(Cli, OverlayWhoseXvfbDiesSaysSo) {
  const auto dir = acro::testing::TempDir() / "xvfb_gone";
  const ProcessResult run = OverlayOnItsOwnXvfbThen(dir, "kill -KILL $xvfb");
  EXPECT_EQ(run.out.find("xvfb=\n"), std::string::npos) << "no Xvfb was started: " << run.out;
  EXPECT_NE(run.out.find("status=1\n"), std::string::npos) << run.out << run.err;
  const std::string err = Slurp(dir / "err.txt");
  EXPECT_NE(err.find("acrolab: lost the connection to the X display :"), std::string::npos) << err;
  ExpectNoOverlayLeft(dir);
}

// `overlay --ghost DIR`: the back tuck designed by `acrolab optimize` drawn in the routine's
// flights; the heads-up names it. A folder that is not optimize's: one line naming its result.json.
TEST(Cli, OverlayDrawsADesignedSkillAsTheGhost) {
  const auto dir = acro::testing::ScratchDir("overlay_ghost");
  const ProcessResult design =
      Execute("env -u DISPLAY " + std::string(ACROLAB_EXE) + " optimize " +
              Quote(RepoFile("samples/skills/back_tuck.yaml")) + " -o " + Quote(dir / "design") +
              " --library " + Quote(dir / "library.sqlite"));
  ASSERT_EQ(design.status, 0) << design.err;
  // The design is kept in the season library too, under its athlete, with its code and DD.
  const ProcessResult designs =
      Execute(std::string(ACROLAB_EXE) + " library list --designs --library " +
              Quote(dir / "library.sqlite"));
  ASSERT_EQ(designs.status, 0) << designs.err;
  EXPECT_NE(designs.out.find("Sample Athlete     skill    40o        0.5"), std::string::npos)
      << designs.out;
  // optimize's filmstrip (initial and optimised timing, two bands) is on its page.
  EXPECT_TRUE(HasFile(dir / "design" / "filmstrip.png"));
  EXPECT_NE(Slurp(dir / "design" / "report.html").find("src=\"filmstrip.png\""), std::string::npos);
  const std::string sample = "samples/trials/trampoline_routine/";
  const std::string overlay = "env -u DISPLAY " + std::string(ACROLAB_EXE) + " overlay " +
                              Quote(RepoFile(sample + "trampoline_routine.c3d")) + " --video " +
                              Quote(RepoFile(sample + "side_camera.mp4")) + " --calib " +
                              Quote(RepoFile(sample + "side_camera.toml")) +
                              " --offset-s -0.575 --athlete " +
                              Quote(RepoFile("samples/athletes/sample_athlete.yaml"));
  const ProcessResult run = Execute(overlay + " --ghost " + Quote(dir / "design") +
                                    " --frames 100:102 -o " + Quote(dir / "frames"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err.find("warning"), std::string::npos) << run.err;  // designed for this athlete
  int pngs = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "frames"))
    pngs += e.path().extension() == ".png" && std::filesystem::file_size(e.path()) > 0 ? 1 : 0;
  EXPECT_EQ(pngs, 3);
  const ProcessResult bad =
      Execute(overlay + " --ghost " + Quote(dir) + " --frames 100:100 -o " + Quote(dir / "bad"));
  EXPECT_EQ(bad.status, 1) << bad.err;
  EXPECT_NE(bad.err.find("result.json"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

// `design CODE`: a barani from its code for the sample athlete, optimised by Model 1 by default;
// its skill.yaml is a skill file `optimize` takes; a code it cannot read is one line and no folder.
TEST(Cli, DesignABaraniFromItsCode) {
  const auto dir = acro::testing::ScratchDir("design_code");
  const std::string athlete = Quote(RepoFile("samples/athletes/sample_athlete.yaml"));
  const ProcessResult run =
      Execute("env -u DISPLAY " + std::string(ACROLAB_EXE) + " design 41/ --athlete " + athlete +
              " -o " + Quote(dir / "barani"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("barani (41/): DD 0.6"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("feasible for this athlete"), std::string::npos) << run.out;
  const nlohmann::json design = nlohmann::json::parse(Slurp(dir / "barani" / "design.json"));
  EXPECT_EQ(design["fig_code"], "41/");
  EXPECT_DOUBLE_EQ(design["difficulty"].get<double>(), 0.6);
  EXPECT_TRUE(design["feasible"].get<bool>());
  EXPECT_NEAR(design["air_twists"].get<double>(), 0.5, 1e-6);
  EXPECT_NEAR(design["air_somersaults"].get<double>(), 0.875, 1e-6);  // 15° + 30° on the bed
  const nlohmann::json result = nlohmann::json::parse(Slurp(dir / "barani" / "result.json"));
  EXPECT_EQ(result["model"], 1);
  EXPECT_LE(result["angular_momentum_variation"].get<double>(), 0.02);
  EXPECT_TRUE(result["keyframes_within_tolerance"].get<bool>());
  EXPECT_NE(Slurp(dir / "barani" / "report.html").find("Designed from its FIG code"),
            std::string::npos);
  // The keyframes as a skill file a person edits and `optimize` reads.
  const ProcessResult again =
      Execute(std::string(ACROLAB_EXE) + " optimize " + Quote(dir / "barani" / "skill.yaml") +
              " -o " + Quote(dir / "again"));
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find("barani (41/) (model 2)"), std::string::npos) << again.out;
  // A quadruple somersault in 1.2 s: designed, and said not feasible with its momentum.
  const ProcessResult quad =
      Execute(std::string(ACROLAB_EXE) + " design 160000o --no-simulate " +
              "--model 2 --flight-time 1.2 --athlete " + athlete + " -o " + Quote(dir / "quad"));
  ASSERT_EQ(quad.status, 0) << quad.err;
  EXPECT_NE(quad.out.find("not feasible: needs a somersault angular momentum of"),
            std::string::npos)
      << quad.out;
  const ProcessResult bad = Execute(std::string(ACROLAB_EXE) + " design 4x2 --athlete " + athlete +
                                    " -o " + Quote(dir / "bad"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("acrolab: FIG code '4x2': "), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

// `routine --codes`: the ten skills for the sample athlete, flown through the bed, then
// the routine's C3D (1 mm of marker noise) analysed by `analyze`: every time of flight back within
// 10 ms, every code (the twist-ins' shapes included: the analysis asks the tuck or pike held over
// 15 % of the flight) and the DD back. A repeated skill is refused.
TEST(Cli, RoutineOfTenSkillsRoundTripsThroughAnalyze) {
  const auto dir = acro::testing::ScratchDir("routine_codes");
  const std::string athlete = Quote(RepoFile("samples/athletes/sample_athlete.yaml"));
  const std::vector<std::string> codes = {
      "40o", "41/", "42/", "43/", "800o", "800<", "801<", "811o", "821o", "831<"};
  std::string list;
  for (const std::string& c : codes) list += (list.empty() ? "" : " ") + c;
  const ProcessResult run = Execute("env -u DISPLAY " + std::string(ACROLAB_EXE) +
                                    " routine --codes '" + list + "' --athlete " + athlete +
                                    " --marker-noise-mm 1 --video -o " + Quote(dir / "routine"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("10 skills, DD 10.6"), std::string::npos) << run.out;
  // Checked against the FIG senior rules: ten different elements, every difficulty counted.
  EXPECT_NE(run.out.find("FIG senior, individual trampoline: D 10.6, T "), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("; valid\n"), std::string::npos) << run.out;
  const nlohmann::json routine = nlohmann::json::parse(Slurp(dir / "routine" / "routine.json"));
  EXPECT_NEAR(routine["difficulty"].get<double>(), 10.6, 1e-9);  // the sum of the FIG values
  EXPECT_TRUE(routine["notes"].empty());
  ASSERT_EQ(routine["skills"].size(), codes.size());
  for (const char* f :
       {"report.html", "routine.c3d", "routine.mot", "height.svg", "skills/10.yaml"})
    EXPECT_TRUE(HasFile(dir / "routine" / f)) << f;
#ifdef ACRO_HAVE_VIEWS
  EXPECT_TRUE(HasFile(dir / "routine" / "filmstrip_10.png"));
  // The video: the whole routine in real time at 30 fps.
  const ProcessResult info = Execute(std::string(ACROLAB_EXE) + " video info --json " +
                                     Quote(dir / "routine" / "routine.mp4"));
  ASSERT_EQ(info.status, 0) << info.err;
  const int samples = routine["num_frames"].get<int>();
  EXPECT_EQ(nlohmann::json::parse(info.out)["frames"].get<int>(),
            static_cast<int>(std::floor((samples - 1) / 120.0 * 30.0)) + 1);
#endif

  const ProcessResult analyze =
      Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(dir / "routine" / "routine.c3d") +
              " --athlete " + athlete + " -o " + Quote(dir / "analysis"));
  ASSERT_EQ(analyze.status, 0) << analyze.err;
  const nlohmann::json jumps = nlohmann::json::parse(Slurp(dir / "analysis" / "jumps.json"));
  ASSERT_EQ(jumps.size(), codes.size());
  double dd_designed = 0, dd_analysed = 0;
  for (size_t i = 0; i < codes.size(); ++i) {
    const nlohmann::json& designed = routine["skills"][i];
    EXPECT_NEAR(jumps[i]["time_of_flight_s"].get<double>(),
                designed["time_of_flight_s"].get<double>(),
                0.010)
        << codes[i];
    EXPECT_EQ(jumps[i]["fig_code"].get<std::string>(), codes[i])
        << i << ": " << jumps[i]["shape_reason"].get<std::string>();
    // A designed flight is physical: our own check passes it (at most "within its noise"; the
    // twist-ins failed it when they entered their shape in 45° of somersault).
    EXPECT_EQ(jumps[i]["verdict"].get<std::string>().rfind("pass", 0), 0u)
        << codes[i] << ": " << jumps[i]["verdict"].get<std::string>();
    // The designer twists left in forward skills and right in backward ones (docs/skill-design.md),
    // and the analysis names each so: the two agree on which way is left.
    int halves = 0;
    for (const nlohmann::json& h : jumps[i]["twist_halves"]) halves += h.get<int>();
    const std::string way = halves == 0                          ? "none"
                            : jumps[i]["direction"] == "forward" ? "left"
                                                                 : "right";
    EXPECT_EQ(jumps[i]["twist_direction"].get<std::string>(), way) << codes[i];
    EXPECT_EQ(designed["twist_direction"].get<std::string>(), way) << codes[i];
    dd_designed += designed["difficulty"].get<double>();
    dd_analysed += jumps[i]["difficulty"].get<double>();
  }
  EXPECT_NEAR(dd_analysed, dd_designed, 1e-9);
  EXPECT_NEAR(dd_analysed, 10.6, 1e-9);
  // Its score sheet: ten elements, D 10.6, T the flights' sum truncated to 0.005, a zone per
  // landing.
  const nlohmann::json score = nlohmann::json::parse(Slurp(dir / "analysis" / "score.json"));
  EXPECT_EQ(score["elements_performed"], 10);
  EXPECT_FALSE(score["interrupted"].get<bool>());
  EXPECT_TRUE(score["valid"].get<bool>()) << score.dump(1);
  EXPECT_NEAR(score["D"].get<double>(), 10.6, 1e-9);
  double tof = 0;
  for (const nlohmann::json& j : jumps) tof += j["time_of_flight_s"].get<double>();
  EXPECT_NEAR(score["T"].get<double>(), std::floor(tof / 0.005 + 1e-9) * 0.005, 1e-9);
  for (const nlohmann::json& e : score["elements"]) EXPECT_TRUE(e["landing"]["zone"].is_string());
  EXPECT_NE(Slurp(dir / "analysis" / "report.html").find("<h2>Score sheet</h2>"),
            std::string::npos);
  // The same routine as an age group's first routine: no element to or from the front or back, so
  // those two requirements are missing, 1.0 each.
  const ProcessResult age = Execute(
      std::string(ACROLAB_EXE) + " analyze " + Quote(dir / "routine" / "routine.c3d") +
      " --athlete " + athlete + " --no-images --rules " +
      Quote(RepoFile("rules/fig-wagc-13-16-first-routine.yaml")) + " -o " + Quote(dir / "age"));
  ASSERT_EQ(age.status, 0) << age.err;
  const nlohmann::json age_score = nlohmann::json::parse(Slurp(dir / "age" / "score.json"));
  EXPECT_EQ(age_score["requirements_missing"],
            (nlohmann::json{"one element to front or back", "one element from front or back"}));
  EXPECT_NEAR(age_score["penalty"].get<double>(), 2.0, 1e-12);
  EXPECT_FALSE(age_score["valid"].get<bool>());
  EXPECT_NE(age.out.find("requirement not performed: one element to front or back"),
            std::string::npos)
      << age.out;
  // A rule file with a typo: one line naming it, nothing written.
  const auto typo = dir / "typo.yaml";
  std::ofstream(typo) << "name: club\nsource: our own\nroutine:\n  elementz: 10\n";
  const ProcessResult bad_rules =
      Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(dir / "routine" / "routine.c3d") +
              " --athlete " + athlete + " --rules " + Quote(typo) + " -o " + Quote(dir / "typo"));
  EXPECT_EQ(bad_rules.status, 1);
  EXPECT_NE(bad_rules.err.find("typo.yaml: line 4: unknown key 'elementz'"), std::string::npos)
      << bad_rules.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "typo"));

  // A skill twice: refused before any work, naming it.
  const ProcessResult again =
      Execute(std::string(ACROLAB_EXE) + " routine --codes '40o 41/ 40o' --athlete " + athlete +
              " -o " + Quote(dir / "again"));
  EXPECT_EQ(again.status, 1);
  EXPECT_NE(again.err.find("acrolab: skill 3 (40o): repeats skill 1 (40o)"), std::string::npos)
      << again.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "again"));
}

// `compare` of the sample's back tuck and back pike: an MP4 of the frames it says, at 30 fps.
TEST(Cli, CompareTwoJumpsOfTheSampleWritesTheVideo) {
  const auto out = acro::testing::TempDir() / "compare.mp4";
  std::filesystem::remove(out);
  const std::string trial =
      Quote(RepoFile("samples/trials/trampoline_routine/trampoline_routine.c3d"));
  const ProcessResult run =
      Execute("env -u DISPLAY " + std::string(ACROLAB_EXE) + " compare " +
              trial.substr(0, trial.size() - 1) + ":2' " + trial.substr(0, trial.size() - 1) +
              ":3' --athlete " + Quote(RepoFile("samples/athletes/sample_athlete.yaml")) + " -o " +
              Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("A: 40o back somersault (jump 2)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("B: 40< back somersault (jump 3)"), std::string::npos) << run.out;
  const size_t at = run.out.find("(", run.out.find("wrote "));
  ASSERT_NE(at, std::string::npos) << run.out;
  const int frames = std::stoi(run.out.substr(at + 1));
  const ProcessResult info = Execute(std::string(ACROLAB_EXE) + " video info --json " + Quote(out));
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["frames"], frames);
  EXPECT_EQ(j["width"], 1440);
  EXPECT_NEAR(j["average_fps"].get<double>(), 30.0, 1e-6);
  // A jump that is not there: one line, exit 1.
  const ProcessResult bad =
      Execute(std::string(ACROLAB_EXE) + " compare " + trial.substr(0, trial.size() - 1) + ":2' " +
              trial.substr(0, trial.size() - 1) + ":9' --athlete " +
              Quote(RepoFile("samples/athletes/sample_athlete.yaml")) + " -o " + Quote(out));
  EXPECT_EQ(bad.status, 1) << bad.err;
  EXPECT_NE(bad.err.find("jump: 9 is not a jump of this trial (it has 6)"), std::string::npos)
      << bad.err;
}
#endif

}  // namespace

// `acrolab synchro`: the sample beside itself is perfectly synchronised (S = 2 × its 5 elements
// by the default conversion), written as synchro.json; a rule file's synchronisation section with
// a typo is one line naming the file, and nothing is written.
TEST(Cli, SynchroOfTheSampleWithItself) {
  const auto out = acro::testing::TempDir() / "synchro_sample";
  std::filesystem::remove_all(out);
  const std::string trial =
      Quote(RepoFile("samples/trials/trampoline_routine/trampoline_routine.c3d"));
  const std::string athlete = Quote(RepoFile("samples/athletes/sample_athlete.yaml"));
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " synchro " + trial + " " + trial +
                                    " --athlete " + athlete + " -o " + Quote(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("S 10.000 over 5 elements"), std::string::npos) << run.out;
  std::ifstream in(out / "synchro.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_DOUBLE_EQ(j["S"].get<double>(), 10.0);
  EXPECT_TRUE(j["ended_at_element"].is_null());
  ASSERT_EQ(j["elements"].size(), 5u);
  EXPECT_EQ(j["elements"][3]["code_a"], "42/");
  EXPECT_NE(j["conversion_source"].get<std::string>().find("assumed"), std::string::npos);
  EXPECT_EQ(j["a"]["elements"].size(), 5u);

  const auto rules = acro::testing::TempDir() / "synchro_typo.yaml";
  std::ofstream(rules)
      << "name: club\nsource: our club\nsynchronisation:\n  points_per_element: 2\n"
         "  source: ours\n";
  const auto out2 = acro::testing::TempDir() / "synchro_typo";
  std::filesystem::remove_all(out2);
  const ProcessResult bad = Execute(std::string(ACROLAB_EXE) + " synchro " + trial + " " + trial +
                                    " --rules " + Quote(rules) + " -o " + Quote(out2));
  EXPECT_EQ(bad.status, 1) << bad.err;
  EXPECT_NE(bad.err.find("synchro_typo.yaml"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("points_per_element"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(out2));
}
