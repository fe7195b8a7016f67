// One pipeline for every door (docs/design.md, "One pipeline"): the same Y-up trial with no athlete
// file opened by the pipeline (what analyze, overlay, compare and reconstruct call), by the
// studio's session and by library add gives the same body, the same orientation and the same
// reconstructed angles; with the sample's video and `--sync auto`, the pipeline's steps (what
// analyze runs) and the studio's session find the same offset, each opening the video once and
// building its background once; the provenance is the hash of the bytes analysed.

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/base/content_hash.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trc.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/library/add_trial.h"
#include "acro/library/library.h"
#include "acro/pipeline/detect.h"
#include "acro/pipeline/monocular_input.h"
#include "acro/pipeline/steps.h"
#include "acro/studio/session.h"
#include "acro/vision/silhouette.h"
#include "pose_model_cache.h"
#include "refdata.h"

namespace acro {
namespace {

namespace fs = std::filesystem;

fs::path Sample(const std::string& relative) {
  return testing::SourceDir() / "samples" / relative;
}

// The sample routine written as a Y-up TRC (OpenSim's convention): (x, y, z) → (y, z, x), a
// rotation, so every length and angle is kept.
fs::path YUpTrial() {
  static const fs::path path = [] {
    capture::Trial trial =
        capture::ReadTrial(Sample("trials/trampoline_routine/trampoline_routine.c3d"));
    for (Eigen::Index k = 0; k < trial.positions.cols(); ++k) {
      const Eigen::Vector3d p = trial.positions.col(k);
      trial.positions.col(k) = Eigen::Vector3d(p.y(), p.z(), p.x());
    }
    const fs::path out = testing::TempDir() / "routine_y_up.trc";
    capture::WriteTrc(trial, out, {.units = "mm", .decimals = 6});
    return out;
  }();
  return path;
}

TEST(Doors, EveryDoorOpensAndAnalysesTheYUpTrialTheSame) {
  // The pipeline, as analyze, overlay, compare and reconstruct call it.
  pipeline::TrialRequest request;
  request.trial = YUpTrial();
  const pipeline::TrialInput input = pipeline::OpenTrial(request);
  EXPECT_TRUE(input.up.found);
  EXPECT_EQ(input.up.axis, 1);  // y
  EXPECT_DOUBLE_EQ(input.athlete.body.height_m, pipeline::kDefaultHeightM);
  EXPECT_FALSE(input.athlete.warning.empty());
  const analysis::TrialAnalysis analysed = pipeline::Analyze(input);

  // The studio's session: the same body, the same turn, the same angles.
  studio::SessionFiles files;
  files.trial = YUpTrial().string();
  const std::unique_ptr<studio::Session> session = studio::Session::Open(files);
  EXPECT_DOUBLE_EQ(session->body().height_m, input.athlete.body.height_m);
  EXPECT_DOUBLE_EQ(session->body().total.mass_kg, input.athlete.body.total.mass_kg);
  const auto& a = session->trial().positions.array();
  const auto& b = input.trial.positions.array();
  ASSERT_EQ(a.cols(), b.cols());
  EXPECT_TRUE((a == b || (a.isNaN() && b.isNaN())).all());  // turned the same way, to the bit
  const Eigen::MatrixXd& q = analysed.reconstruction.motion.q;
  const Eigen::MatrixXd& q_studio = session->analysis().reconstruction.motion.q;
  ASSERT_EQ(q.rows(), q_studio.rows());
  ASSERT_EQ(q.cols(), q_studio.cols());
  EXPECT_LE((q - q_studio).cwiseAbs().maxCoeff(), 1e-12);

  // library add (a profile required there: a season is an athlete's) against the pipeline with the
  // same profile: the same jumps stored as analyze writes them.
  const fs::path dir = testing::ScratchDir("doors_library");
  library::Library lib(dir / "season.sqlite", library::Library::Mode::kReadWrite);
  library::AddRequest add;
  add.trial = YUpTrial();
  add.athlete_profile = Sample("athletes/sample_athlete.yaml");
  add.session_date = "2026-12-05";
  const library::AddResult added = library::AddTrial(lib, add);
  pipeline::TrialRequest with_profile = request;
  with_profile.athlete.profile = add.athlete_profile;
  const pipeline::TrialInput profiled = pipeline::OpenTrial(with_profile);
  EXPECT_EQ(added.sha256, profiled.sha256);
  const std::string jumps = analysis::FormatJumpsJson(pipeline::Analyze(profiled));
  const nlohmann::json stored = nlohmann::json::parse(jumps);  // one object per jump
  ASSERT_TRUE(stored.is_array());
  EXPECT_GT(stored.size(), 0u);
  EXPECT_EQ(added.num_jumps, static_cast<int>(stored.size()));
}

TEST(Doors, AutoSyncIsTheSameEverywhereAndTheVideoIsOpenedOnce) {
  pipeline::TrialRequest request;
  request.trial = Sample("trials/trampoline_routine/trampoline_routine.c3d");
  request.athlete.profile = Sample("athletes/sample_athlete.yaml");
  const pipeline::TrialInput input = pipeline::OpenTrial(request);
  analysis::TrialAnalysis analysed = pipeline::Analyze(input);

  // analyze's steps: the video opened once, its background built once for the sync, the
  // silhouettes and the overlay's mismatch.
  const long long opened = capture::VideoReader::OpenedCount();
  const long long built = vision::BackgroundModel::BuiltCount();
  pipeline::VideoRequest v;
  v.video = Sample("trials/trampoline_routine/side_camera.mp4");
  v.calibration = Sample("trials/trampoline_routine/side_camera.toml");
  v.sync.kind = pipeline::SyncRequest::Kind::kAuto;
  pipeline::VideoInput video(v);
  const pipeline::VideoCheck check = pipeline::AttachVideo(video, input, &analysed);
  video.Background();  // what the overlay's mismatch takes
  EXPECT_EQ(capture::VideoReader::OpenedCount() - opened, 1);
  EXPECT_EQ(vision::BackgroundModel::BuiltCount() - built, 1);
  // The refined sync: the video starts 0.575 s after the trial (video_truth.json), to a sample.
  EXPECT_NEAR(check.sync.sync.offset_s, -0.575, 1.0 / 120 + 1e-9);
  EXPECT_GT(check.silhouettes.median_iou, 0.85);

  // The studio's session: the same offset, the video opened once, one background.
  studio::SessionFiles files;
  files.trial = request.trial.string();
  files.athlete = request.athlete.profile.string();
  files.videos.push_back({v.video.string(), v.calibration.string(), "", std::nullopt});
  const long long opened_studio = capture::VideoReader::OpenedCount();
  const long long built_studio = vision::BackgroundModel::BuiltCount();
  const std::unique_ptr<studio::Session> session = studio::Session::Open(files);
  EXPECT_EQ(capture::VideoReader::OpenedCount() - opened_studio, 1);
  EXPECT_EQ(vision::BackgroundModel::BuiltCount() - built_studio, 1);
  EXPECT_DOUBLE_EQ(session->sync().offset_s, check.sync.sync.offset_s);
}

TEST(Doors, TheProvenanceIsTheHashOfTheBytesAnalysed) {
  const fs::path dir = testing::ScratchDir("doors_provenance");
  const fs::path trial = dir / "jump.c3d";
  fs::copy_file(Sample("trials/trampoline_routine/trampoline_routine.c3d"), trial);
  const std::vector<std::uint8_t> before = ReadFileBytes(trial);
  pipeline::TrialRequest request;
  request.trial = trial;
  const pipeline::TrialInput input = pipeline::OpenTrial(request);
  // The file changes while the analysis runs: the provenance keeps the content analysed.
  std::ofstream(trial, std::ios::app) << "changed";
  const nlohmann::json provenance =
      nlohmann::json::parse(pipeline::FormatAnalysisProvenance(input));
  EXPECT_EQ(
      provenance["trial_sha256"],
      Sha256Hex(std::string_view(reinterpret_cast<const char*>(before.data()), before.size())));
  EXPECT_NE(provenance["trial_sha256"], Sha256OfFile(trial));
}

// One video analysed alone (docs/one-camera.md): the studio's session and `analyze --video V
// --detect-bed` (the pipeline's OpenMonocular, UseOneCamera, Analyze) give the same flights, the
// same codes and the same angles; the session shows the video on its own clock (frame k is sample
// k); a cancel during the detection stops the opening and a second opening resumes the detection;
// a session file of one video (no trial, no calibration) reads back as it was written.
TEST(Doors, OneVideoAloneIsAnalysedAsAnalyzeDoes) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path dir = testing::ScratchDir("doors_one_video");
  const fs::path video = dir / "side_camera.mp4";
  fs::copy_file(Sample("trials/trampoline_routine/side_camera.mp4"), video);
  studio::SessionFiles files;
  files.athlete = Sample("athletes/sample_athlete.yaml").string();
  files.videos.push_back({video.string(), "", "", std::nullopt});
  ASSERT_TRUE(studio::OneVideoAlone(files));

  // Cancelled in the detection: nothing opened, the frames done kept for the next run.
  int reports = 0;
  EXPECT_THROW(studio::Session::Open(files,
                                     [&](const std::string& step, int done, int) {
                                       ++reports;
                                       return !(step == "detect" && done >= 20);
                                     }),
               Cancelled);
  EXPECT_GT(reports, 20);
  const pose::VideoPoses poses =
      pipeline::DetectPosesInCache(video, pose::LandmarkModel::kHeavy);  // the rest
  EXPECT_GE(poses.frames_resumed, 20);

  // The studio, then analyze's steps: the same detections (the cache), the same analysis.
  std::vector<std::string> steps;
  const std::unique_ptr<studio::Session> session =
      studio::Session::Open(files, [&](const std::string& step, int, int) {
        if (steps.empty() || steps.back() != step) steps.push_back(step);
        return true;
      });
  EXPECT_NE(std::find(steps.begin(), steps.end(), "detect"), steps.end());
  pipeline::MonocularRequest request;
  request.video = video;
  request.detect_bed = true;
  request.athlete.profile = files.athlete;
  const pipeline::MonocularInput mono = pipeline::OpenMonocular(request);
  analysis::TrialAnalysisOptions options;
  pipeline::UseOneCamera(mono, request, &options);
  const analysis::TrialAnalysis analysed = pipeline::Analyze(mono.input, options);

  const analysis::TrialAnalysis& ours = session->analysis();
  ASSERT_EQ(ours.jumps.size(), analysed.jumps.size());
  ASSERT_GE(ours.jumps.size(), 5u);
  for (size_t j = 0; j < ours.jumps.size(); ++j) {
    EXPECT_EQ(ours.jumps[j].fig_code, analysed.jumps[j].fig_code) << j;
    EXPECT_DOUBLE_EQ(ours.jumps[j].flight.takeoff_s, analysed.jumps[j].flight.takeoff_s) << j;
    EXPECT_DOUBLE_EQ(ours.jumps[j].flight.landing_s, analysed.jumps[j].flight.landing_s) << j;
  }
  EXPECT_LE((ours.reconstruction.motion.q - analysed.reconstruction.motion.q).cwiseAbs().maxCoeff(),
            1e-12);
  ASSERT_TRUE(ours.bed.has_value());  // the FIG bed the camera was posed on
  EXPECT_NE(ours.bed->source.find("posed on"), std::string::npos) << ours.bed->source;
  // The one camera's execution rule (docs/scoring.md): its centre known to the assistant.
  EXPECT_TRUE(ours.execution_options.single_camera_centre_W.has_value());
  ASSERT_EQ(session->num_videos(), 1);
  EXPECT_NEAR(session->rate_hz(), session->video().info().nominal_fps, 1e-6);
  for (int k : {0, session->num_samples() / 2, session->num_samples() - 1}) {
    EXPECT_EQ(session->VideoFrameOf(k), k);
    EXPECT_EQ(session->SampleOf(k), k);
  }

  // The session file: no trial, one video without a calibration, as written.
  const fs::path saved = dir / "one.acrolab";
  studio::WriteSessionFile(saved, session->files(), {});
  const auto [read, view] = studio::ReadSessionFile(saved);
  EXPECT_TRUE(read.trial.empty());
  ASSERT_EQ(read.videos.size(), 1u);
  EXPECT_TRUE(read.videos[0].calibration.empty());
  EXPECT_EQ(fs::weakly_canonical(read.videos[0].video), fs::weakly_canonical(video));
  // Two videos with no trial: refused, one line.
  studio::SessionFiles two = files;
  two.videos.push_back(files.videos[0]);
  EXPECT_THROW(studio::Session::Open(two), InputError);
}

}  // namespace
}  // namespace acro
