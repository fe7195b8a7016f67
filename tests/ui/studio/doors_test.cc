// One pipeline for every door (docs/design.md, "One pipeline"): the same Y-up trial with no athlete
// file opened by the pipeline (what analyze, overlay, compare and reconstruct call), by the
// studio's session and by library add gives the same body, the same orientation and the same
// reconstructed angles; with the sample's video and `--sync auto`, the pipeline's steps (what
// analyze runs) and the studio's session find the same offset, each opening the video once and
// building its background once; the provenance is the hash of the bytes analysed.

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/base/content_hash.h"
#include "acro/base/file_io.h"
#include "acro/capture/trc.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/library/add_trial.h"
#include "acro/library/library.h"
#include "acro/pipeline/steps.h"
#include "acro/studio/session.h"
#include "acro/vision/silhouette.h"
#include "refdata.h"

namespace acro {
namespace {

namespace fs = std::filesystem;

fs::path Sample(const std::string& relative) { return testing::SourceDir() / "samples" / relative; }

// The sample routine written as a Y-up TRC (OpenSim's convention): (x, y, z) → (y, z, x), a
// rotation, so every length and angle is kept.
fs::path YUpTrial() {
  static const fs::path path = [] {
    capture::Trial trial = capture::ReadTrial(Sample("trials/trampoline_routine/trampoline_routine.c3d"));
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
  const nlohmann::json provenance = nlohmann::json::parse(pipeline::FormatAnalysisProvenance(input));
  EXPECT_EQ(provenance["trial_sha256"], Sha256Hex(std::string_view(reinterpret_cast<const char*>(before.data()), before.size())));
  EXPECT_NE(provenance["trial_sha256"], Sha256OfFile(trial));
}

}  // namespace
}  // namespace acro
