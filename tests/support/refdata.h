#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

namespace acro::testing {

/// The public reference data folder: $ACRO_REFDATA, else ../shared/refdata beside the repository.
inline std::filesystem::path RefdataDir() {
  if (const char* env = std::getenv("ACRO_REFDATA"); env && *env) return env;
  const char* src = std::getenv("ACRO_SOURCE_DIR");
  std::filesystem::path root = src ? src : ACRO_DEFAULT_SOURCE_DIR;
  return root / ".." / "shared" / "refdata";
}

inline bool RefdataRequired() {
  const char* env = std::getenv("ACRO_REQUIRE_REFDATA");
  return env && std::string(env) == "1";
}

/// Path of a reference file; an empty path when it is absent (the caller skips).
inline std::filesystem::path RefdataFile(const std::string& relative) {
  return RefdataDir() / relative;
}

/// The directory with test outputs of this run.
inline std::filesystem::path TempDir() {
  auto dir = std::filesystem::path(::testing::TempDir()) / "acrolab_tests";
  std::filesystem::create_directories(dir);
  return dir;
}

/// A fresh, empty directory `<name>_<pid>` under TempDir() for one test's files.
inline std::filesystem::path ScratchDir(const std::string& name) {
  const auto dir = TempDir() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path SourceDir() {
  const char* src = std::getenv("ACRO_SOURCE_DIR");
  return src ? std::filesystem::path(src) : std::filesystem::path(ACRO_DEFAULT_SOURCE_DIR);
}

}  // namespace acro::testing

/// Skips the test when a reference file is absent, or fails it when ACRO_REQUIRE_REFDATA=1.
#define ACRO_REQUIRE_REFDATA_FILE(path)                                                \
  do {                                                                                 \
    if (!std::filesystem::exists(path)) {                                              \
      if (::acro::testing::RefdataRequired()) {                                        \
        FAIL() << "reference data missing: " << (path) << " (ACRO_REQUIRE_REFDATA=1)"; \
      }                                                                                \
      GTEST_SKIP() << "reference data absent: " << (path) << " (set ACRO_REFDATA)";    \
    }                                                                                  \
  } while (0)
