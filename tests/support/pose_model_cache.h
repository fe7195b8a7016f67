#pragma once

// The installed pose networks for tests: skipped when absent, failed when ACRO_REQUIRE_MODELS=1
// (.ci/run sets it, as scripts/test.sh installs them first).

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "acro/pose/pose_models.h"

namespace acro::testing {

inline bool ModelsRequired() {
  const char* env = std::getenv("ACRO_REQUIRE_MODELS");
  return env && std::string(env) == "1";
}

/// The cache folder when its MANIFEST is there, else empty.
inline std::filesystem::path InstalledModelDir() {
  const auto dir = pose::DefaultModelDirectory();
  return std::filesystem::exists(dir / "MANIFEST") ? dir : std::filesystem::path();
}

}  // namespace acro::testing

/// Skips the test when the pose models are not installed, or fails it when ACRO_REQUIRE_MODELS=1.
#define ACRO_REQUIRE_POSE_MODELS()                                                             \
  do {                                                                                         \
    if (::acro::testing::InstalledModelDir().empty()) {                                        \
      if (::acro::testing::ModelsRequired()) {                                                 \
        FAIL() << "pose models missing in " << ::acro::pose::DefaultModelDirectory()           \
               << " (ACRO_REQUIRE_MODELS=1): run scripts/install-models.sh";                  \
      }                                                                                        \
      GTEST_SKIP() << "pose models not installed (scripts/install-models.sh)";                 \
    }                                                                                          \
  } while (0)
