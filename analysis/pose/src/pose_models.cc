#include "acro/pose/pose_models.h"

#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "acro/base/content_hash.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::pose {

const char* LandmarkModelName(LandmarkModel model) {
  switch (model) {
    case LandmarkModel::kLite: return "lite";
    case LandmarkModel::kFull: return "full";
    case LandmarkModel::kHeavy: return "heavy";
  }
  return "?";
}

LandmarkModel ParseLandmarkModel(const std::string& name) {
  if (name == "lite") return LandmarkModel::kLite;
  if (name == "full") return LandmarkModel::kFull;
  if (name == "heavy") return LandmarkModel::kHeavy;
  throw InputError("", "--model", fmt::format("'{}': expected lite, full or heavy", name));
}

std::filesystem::path DefaultModelDirectory() {
  std::filesystem::path root;
  if (const char* models = std::getenv("ACRO_MODELS"); models != nullptr && *models != '\0')
    root = models;
  else if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    root = std::filesystem::path(cache) / "acrolab" / "models";
  else if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    root = std::filesystem::path(home) / ".cache" / "acrolab" / "models";
  else
    root = std::filesystem::path(".cache") / "acrolab" / "models";
  return root / (std::string("mediapipe-pose-") + kPosePackageVersion);
}

namespace {

constexpr const char* kInstall =
    "run scripts/install-models.sh (it fetches @mediapipe/pose 0.5.1675469404 with npm and converts it)";

// MANIFEST: one line per file, "<sha256>  <bytes>  <name>", written by install-models.sh.
struct ManifestEntry {
  std::string sha256;
  std::uintmax_t bytes = 0;
};

std::map<std::string, ManifestEntry> ReadManifest(const std::filesystem::path& directory) {
  const std::filesystem::path path = directory / "MANIFEST";
  if (!IsRegularFile(path))
    throw InputError(path.string(), "", fmt::format("pose models not installed: {}", kInstall));
  std::ifstream in(path);
  std::map<std::string, ManifestEntry> entries;
  std::string line;
  for (int number = 1; std::getline(in, line) && number <= 64; ++number) {
    std::istringstream fields(line);
    std::string sha, name;
    std::uintmax_t bytes = 0;
    if (!(fields >> sha >> bytes >> name) || sha.size() != 64)
      throw InputError(path.string(), fmt::format("line {}", number),
                       fmt::format("not '<sha256> <bytes> <name>': {}", kInstall));
    entries[name] = {sha, bytes};
  }
  return entries;
}

std::filesystem::path CheckedFile(const std::filesystem::path& directory,
                                  const std::map<std::string, ManifestEntry>& manifest,
                                  const std::string& name) {
  const std::filesystem::path path = directory / name;
  const auto it = manifest.find(name);
  if (it == manifest.end())
    throw InputError((directory / "MANIFEST").string(), "", fmt::format("no entry for {}: {}", name, kInstall));
  if (!IsRegularFile(path))
    throw InputError(path.string(), "", fmt::format("missing: {}", kInstall));
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error || size != it->second.bytes)
    throw InputError(path.string(), "",
                     fmt::format("{} bytes, the installed model has {} (another version, or damaged): {}",
                                 error ? 0 : size, it->second.bytes, kInstall));
  // The whole content against the hash the installation pinned (0.1–0.2 s for the heavy network),
  // once per file, size and modification time in a process (several videos load it each).
  static std::mutex mutex;
  static std::set<std::string> checked;
  const auto mtime = std::filesystem::last_write_time(path, error).time_since_epoch().count();
  const std::string key = fmt::format("{}|{}|{}|{}", path.string(), size, mtime, it->second.sha256);
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (checked.count(key)) return path;
  }
  if (Sha256OfFile(path) != it->second.sha256)
    throw InputError(path.string(), "",
                     fmt::format("its SHA-256 is not the installed model's (damaged, or another version): {}", kInstall));
  std::lock_guard<std::mutex> lock(mutex);
  checked.insert(key);
  return path;
}

}  // namespace

PoseModelFiles FindPoseModels(LandmarkModel model, const std::filesystem::path& directory) {
  const auto manifest = ReadManifest(directory);
  PoseModelFiles files;
  files.detector = CheckedFile(directory, manifest, "pose_detection.onnx");
  files.landmarks = CheckedFile(directory, manifest, fmt::format("pose_landmark_{}.onnx", LandmarkModelName(model)));
  return files;
}

}  // namespace acro::pose
