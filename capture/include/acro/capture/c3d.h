#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "acro/capture/trial.h"

namespace acro::capture {

struct C3dReadOptions {
  /// Compute the ground reaction of every TYPE 1–4 force platform per analog sample.
  bool compute_force_plates = true;
  /// Largest file accepted, as a guard against lying headers (bytes).
  std::int64_t max_file_bytes = std::int64_t(4) << 30;
};

/// Reads a C3D file (Intel, DEC or MIPS; integer or float storage) into a Trial in SI units.
/// Throws acro::InputError naming the file, the byte offset or parameter, and the problem.
Trial ReadC3d(const std::filesystem::path& path, const C3dReadOptions& options = {});

/// The same from bytes in memory; `name` is used in error messages.
Trial ReadC3dFromMemory(std::span<const std::uint8_t> bytes,
                        const std::string& name,
                        const C3dReadOptions& options = {});

/// Writes Intel-float C3D keeping points, analog, labels, rates, events, force plates and every
/// parameter. Written to a temporary name beside `path` and renamed when complete.
void WriteC3d(const Trial& trial, const std::filesystem::path& path);

/// The bytes WriteC3d would write.
std::vector<std::uint8_t> WriteC3dToMemory(const Trial& trial);

}  // namespace acro::capture
