#pragma once

#include <filesystem>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Reads a trial by file extension: .c3d, .trc or .csv (Acrolab marker CSV), case-insensitive.
/// Throws acro::InputError for an unknown extension or a malformed file.
Trial ReadTrial(const std::filesystem::path& path);

/// Writes a trial by file extension (.c3d Intel float, .trc in mm, .csv in metres), atomically.
void WriteTrial(const Trial& trial, const std::filesystem::path& path);

}  // namespace acro::capture
