#pragma once

// Readers that take a path (calibrations, detections, video) get the fuzz input through a file of
// this process's own under the temporary directory: the fuzzer and the corpus replay exercise the
// same code a user's file does.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace acro::fuzz {

/// The directory of this process's fuzz files (created on first use).
inline const std::filesystem::path& FuzzDirectory() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("acro_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes the bytes to FuzzDirectory()/name and returns the path.
inline std::filesystem::path WriteFuzzFile(const std::string& name,
                                           const std::uint8_t* data,
                                           std::size_t size) {
  const std::filesystem::path path = FuzzDirectory() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace acro::fuzz
