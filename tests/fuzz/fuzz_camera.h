#pragma once

// The camera-side readers' fuzz entry point: the bytes as a calibration file in each format
// (Pose2Sim TOML, Qualisys QCA, OpenCV FileStorage YAML/XML/JSON) and as 2D detections (a
// detections CSV, one OpenPose JSON frame). Each read accepts the file or rejects it with
// acro::InputError; anything else is a bug. Used by the libFuzzer target (camera_fuzz.cc) and by
// the corpus replay in the suite (tests/analysis/vision/camera_corpus_test.cc).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/vision/camera.h"
#include "fuzz_accepts.h"
#include "fuzz_files.h"

namespace acro::fuzz {

/// Number of readers that accepted the input (0–7); the rejections' messages go to `errors`.
inline int FeedCameraReaders(const std::uint8_t* data,
                             std::size_t size,
                             std::vector<std::string>* errors = nullptr) {
  int accepted = 0;
  for (const char* name : {"calib.toml", "calib.qca", "calib.yml", "calib.xml", "calib.json"})
    accepted += Accepts(errors, [&] { vision::ReadCameras(WriteFuzzFile(name, data, size)); });
  accepted += Accepts(
      errors, [&] { capture::ReadDetectionsCsv(WriteFuzzFile("detections.csv", data, size)); });
  // One OpenPose frame, alone in its directory, under OpenPose's own name. (Written, not copied:
  // copy_file's sendfile is not retried when libFuzzer's timer interrupts it, writes are.)
  const std::filesystem::path json_dir = FuzzDirectory() / "openpose";
  std::filesystem::create_directories(json_dir);
  WriteFuzzFile("openpose/cam01_000000000003_keypoints.json", data, size);
  accepted += Accepts(errors, [&] { capture::ReadOpenPoseJson(json_dir, "body25"); });
  return accepted;
}

}  // namespace acro::fuzz
