// `acrolab detect` as a user meets it (docs/pose.md): its outputs read back by the OpenPose reader
// Pose2Sim-style tools use, a resumed run, an interrupted run resumed, a video with nobody in it,
// and every refusal in one line, exit 1 or 2, nothing written.

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/capture/detections.h"
#include "acro/capture/video.h"
#include "acro/pose/pose_models.h"
#include "pose_model_cache.h"
#include "refdata.h"
#include "run_command.h"

namespace {

namespace fs = std::filesystem;
using acro::testing::Execute;
using acro::testing::Quote;

const fs::path kSample = acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";

std::string Acrolab() { return ACROLAB_EXE; }

int JsonFiles(const fs::path& dir) {
  int n = 0;
  if (!fs::exists(dir)) return 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ".json";
  return n;
}

TEST(DetectCli, WritesOpenPoseJsonThatReadsBackAndResumes) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path out = acro::testing::ScratchDir("detect_resume");
  const auto first = Execute(Acrolab() + " detect " + Quote(kSample) + " --model lite --frames 0:12 --quiet -o " + Quote(out));
  ASSERT_EQ(first.status, 0) << first.err;
  const fs::path dir = out / "side_camera";
  for (const char* f : {"keypoints_2d.trc", "blazepose_2d.csv", "detect.json", "contact_sheet.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  // Pose2Sim's reader (BODY_25B) takes the files: 12 frames, the athlete in each.
  const acro::capture::KeypointDetections read = acro::capture::ReadOpenPoseJson(dir / "json", "body25b");
  ASSERT_EQ(read.num_frames(), 12);
  int with_person = 0;
  for (const auto& people : read.frames) with_person += people.size() == 1;
  EXPECT_GE(with_person, 10);
  // A longer run over the same frames takes the first 12 from the files.
  const auto second = Execute(Acrolab() + " detect " + Quote(kSample) + " --model lite --frames 0:20 --json --quiet -o " + Quote(out));
  ASSERT_EQ(second.status, 0) << second.err;
  const nlohmann::json summary = nlohmann::json::parse(second.out);
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_EQ(summary[0]["frames"], 20);
  EXPECT_EQ(summary[0]["frames_resumed"], 12);
  for (const char* key : {"video", "model", "frames_with_pose", "median_confidence", "ms_per_frame",
                          "decode_ms_per_frame", "crop_ms_per_frame", "network_ms_per_frame", "post_ms_per_frame"})
    EXPECT_TRUE(summary[0].contains(key)) << key;
  EXPECT_EQ(JsonFiles(dir / "json"), 20);
  // The detections drawn over the video: every frame written, the first 20 with a skeleton.
  const fs::path drawn = out / "drawn.mp4";
  const auto overlay = Execute(Acrolab() + " overlay --video " + Quote(kSample) + " --detections " + Quote(dir) + " -o " + Quote(drawn));
  ASSERT_EQ(overlay.status, 0) << overlay.err;
  acro::capture::VideoReader written(drawn);
  EXPECT_EQ(written.num_frames(), 299);
  acro::capture::VideoReader original(kSample);
  EXPECT_NE(acro::capture::HashFrame(written.Frame(5)), acro::capture::HashFrame(original.Frame(5)));
  // With no trial, --calib is not taken.
  EXPECT_EQ(Execute(Acrolab() + " overlay --video " + Quote(kSample) + " --calib x.toml --detections " + Quote(dir) + " -o " + Quote(drawn)).status, 2);
}

TEST(DetectCli, AnInterruptedRunIsResumedWhereItStopped) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path out = acro::testing::ScratchDir("detect_interrupted");
  const fs::path json = out / "side_camera" / "json";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl(ACROLAB_EXE, ACROLAB_EXE, "detect", kSample.c_str(), "--model", "lite", "--frames", "0:60", "--quiet", "-o",
          out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // SIGTERM once a few frames are written (at most 120 s, a loaded machine included).
  const auto start = std::chrono::steady_clock::now();
  while (JsonFiles(json) < 5 && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(child, SIGTERM);
  int status = 0;
  waitpid(child, &status, 0);
  const int written = JsonFiles(json);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) GTEST_SKIP() << "the run ended before the signal";
  EXPECT_EQ(WEXITSTATUS(status), 143);
  ASSERT_GE(written, 5);
  const auto again = Execute(Acrolab() + " detect " + Quote(kSample) + " --model lite --frames 0:60 --json --quiet -o " + Quote(out));
  ASSERT_EQ(again.status, 0) << again.err;
  const nlohmann::json summary = nlohmann::json::parse(again.out);
  EXPECT_EQ(summary[0]["frames"], 60);
  EXPECT_GE(summary[0]["frames_resumed"].get<int>(), written - 1);  // the frame being written may be lost
  EXPECT_EQ(JsonFiles(json), 60);
}

TEST(DetectCli, AVideoWithNobodyGivesEmptyFramesAndAWarning) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path dir = acro::testing::ScratchDir("detect_nobody");
  // A moving test pattern and nobody in it.
  const fs::path video = dir / "empty.mp4";
  ASSERT_EQ(Execute("ffmpeg -v error -y -f lavfi -i testsrc2=size=640x360:rate=30 -t 1 -pix_fmt yuv420p " + Quote(video)).status, 0);
  const auto r = Execute(Acrolab() + " detect " + Quote(video) + " --model lite --quiet -o " + Quote(dir / "out"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nobody found"), std::string::npos) << r.err;
  const acro::capture::KeypointDetections read = acro::capture::ReadOpenPoseJson(dir / "out/empty/json", "body25b");
  EXPECT_EQ(read.num_frames(), 30);
  for (const auto& people : read.frames) EXPECT_TRUE(people.empty());
}

// One line on stderr naming `what`, the status, and no output folder.
void ExpectRefused(const std::string& args, const fs::path& out, int status, const std::string& what,
                   const std::string& env = "") {
  const auto r = Execute(env + Acrolab() + " detect " + args + " --quiet -o " + Quote(out));
  EXPECT_EQ(r.status, status) << args << "\n" << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << args << "\n" << r.err;
  EXPECT_FALSE(fs::exists(out)) << args;
}

TEST(DetectCli, BadInputIsOneLineAndNothingIsWritten) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path dir = acro::testing::ScratchDir("detect_bad");
  const fs::path out = dir / "out";
  // An unreadable video.
  const fs::path text = dir / "notes.mp4";
  std::ofstream(text) << "not a video\n";
  ExpectRefused(Quote(text), out, 1, "notes.mp4");
  // Frames outside the video, and a range that is not one.
  ExpectRefused(Quote(kSample) + " --frames 500:600", out, 1, "outside the video's 299 frames");
  ExpectRefused(Quote(kSample) + " --frames 5:3", out, 2, "5:3");
  ExpectRefused(Quote(kSample) + " --frames x", out, 2, "--frames x");
  // A box outside the frame, and an unknown model.
  ExpectRefused(Quote(kSample) + " --roi 1800,1000,400,400", out, 1, "is not inside the 1920×1080 frame");
  ExpectRefused(Quote(kSample) + " --model huge", out, 2, "huge");
}

TEST(DetectCli, MissingOrDamagedModelsSayWhatToRun) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path dir = acro::testing::ScratchDir("detect_models");
  const fs::path out = dir / "out";
  // No models at all.
  ExpectRefused(Quote(kSample), out, 1, "scripts/install-models.sh", "ACRO_MODELS=" + Quote(dir / "nothing") + " ");
  // A copy of the cache whose lite network is damaged in the middle (same size), then cut short.
  const fs::path copy = dir / "models" / acro::pose::DefaultModelDirectory().filename();
  fs::create_directories(copy);
  for (const char* f : {"MANIFEST", "pose_detection.onnx", "pose_landmark_lite.onnx"})
    fs::copy_file(acro::pose::DefaultModelDirectory() / f, copy / f);
  const std::string env = "ACRO_MODELS=" + Quote(dir / "models") + " ";
  {
    std::fstream f(copy / "pose_landmark_lite.onnx", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(2'000'000);
    f.write("damaged!", 8);
  }
  ExpectRefused(Quote(kSample) + " --model lite", out, 1, "its SHA-256 is not the installed model's", env);
  fs::resize_file(copy / "pose_landmark_lite.onnx", 1000);
  ExpectRefused(Quote(kSample) + " --model lite", out, 1, "1000 bytes, the installed model has", env);
  // The heavy network is not in this copy at all.
  ExpectRefused(Quote(kSample), out, 1, "pose_landmark_heavy.onnx", env);
}

}  // namespace
