#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Reads a trial by file extension: .c3d, .trc or .csv (Acrolab marker CSV), case-insensitive.
/// Throws acro::InputError for an unknown extension or a malformed file.
Trial ReadTrial(const std::filesystem::path& path);

/// The same from the file's bytes, read already (the extension of `path` chooses the format; the
/// path names the trial in messages): a door that hashes what it analyses reads the file once.
Trial ReadTrialFromBytes(std::span<const std::uint8_t> bytes, const std::filesystem::path& path);

/// Writes a trial by file extension (.c3d Intel float, .trc in mm, .csv in metres), atomically.
void WriteTrial(const Trial& trial, const std::filesystem::path& path);

}  // namespace acro::capture
