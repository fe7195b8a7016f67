#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Acrolab's marker CSV: one row per frame, columns
/// `frame,time_s,<label>_x_m,<label>_y_m,<label>_z_m,…` (metres, lab frame W; a gap is an empty
/// cell). Labels holding a comma or quote are quoted as in RFC 4180. Spreadsheet- and
/// pandas-friendly; docs/formats/csv.md.
void WriteMarkerCsv(const Trial& trial, const std::filesystem::path& path);
std::string WriteMarkerCsvToString(const Trial& trial);

/// Reads the CSV that WriteMarkerCsv writes (the rate comes from the time column).
Trial ReadMarkerCsv(const std::filesystem::path& path);
Trial ReadMarkerCsvFromString(std::string_view text, const std::string& name);

}  // namespace acro::capture
