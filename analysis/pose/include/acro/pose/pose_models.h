#pragma once

/// \file
/// Where the pose networks are (docs/pose.md, "The models"). scripts/install-models.sh fetches
/// MediaPipe's BlazePose package with `npm pack` at a pinned version, checks it, converts its TFLite
/// networks to ONNX (tools/pose_model_conversion.h) and keeps them in a cache outside the
/// repository, with a MANIFEST of their sizes and SHA-256. Nothing is downloaded at run time: a
/// command that needs a missing model says in one line what to run.

#include <cstdint>
#include <filesystem>
#include <string>

namespace acro::pose {

/// BlazePose GHUM's three landmark networks: lite (2.8 MB of weights), full (6.4 MB), heavy
/// (27.7 MB) — slower and closer to the truth in that order (docs/pose.md).
enum class LandmarkModel { kLite, kFull, kHeavy };

/// "lite", "full", "heavy".
const char* LandmarkModelName(LandmarkModel model);
/// Parses "lite", "full" or "heavy"; acro::InputError (where "--model") otherwise.
LandmarkModel ParseLandmarkModel(const std::string& name);

/// The npm package the networks come from, pinned (install-models.sh checks its integrity).
inline constexpr const char* kPosePackage = "@mediapipe/pose";
inline constexpr const char* kPosePackageVersion = "0.5.1675469404";

/// The cache: $ACRO_MODELS when set, else $XDG_CACHE_HOME/acrolab/models, else
/// $HOME/.cache/acrolab/models; the networks are in its folder "mediapipe-pose-<version>".
std::filesystem::path DefaultModelDirectory();

struct PoseModelFiles {
  std::filesystem::path detector;   ///< pose_detection.onnx
  std::filesystem::path landmarks;  ///< pose_landmark_<model>.onnx
};

/// The two networks a detection needs, checked against the cache's MANIFEST (present, the size and
/// SHA-256 the conversion gave). Throws acro::InputError with one line naming the file at fault and the
/// command that installs the models ("scripts/install-models.sh") when one is missing, of another
/// size or content (another version, or damaged), or when the cache has no MANIFEST.
PoseModelFiles FindPoseModels(LandmarkModel model,
                              const std::filesystem::path& directory = DefaultModelDirectory());

}  // namespace acro::pose
