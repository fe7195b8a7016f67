#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Reads a TRC marker file (Motion Analysis / OpenSim / Pose2Sim conventions): tab- or
/// space-separated, header keys on line 2 and values on line 3, marker names on line 4 (one name
/// every three columns), coordinates by row. Empty cells and NaN are gaps. The header's NumFrames
/// and NumMarkers are checked against the data: the data win and a warning says so. Frames follow
/// the row order (frame numbers are kept only for the first frame). Throws acro::InputError naming
/// the file, line and column at fault.
Trial ReadTrc(const std::filesystem::path& path);
Trial ReadTrcFromString(std::string_view text, const std::string& name);

struct TrcWriteOptions {
  /// Length unit of the coordinates written: "mm" (OpenSim's usual) or "m".
  std::string units = "mm";
  /// Significant digits after the decimal point (in `units`).
  int decimals = 6;
};

/// Writes the trial's markers (PointType::kMarker only) as an OpenSim-compatible TRC, gaps as
/// "NaN" cells (as OpenSim 4 writes them), atomically (temporary file, then rename).
void WriteTrc(const Trial& trial,
              const std::filesystem::path& path,
              const TrcWriteOptions& options = {});
std::string WriteTrcToString(const Trial& trial,
                             const std::string& file_name,
                             const TrcWriteOptions& options = {});

/// Metres per unit for a length unit name ("mm", "cm", "m", "in"); 0 when unknown.
double LengthUnitToMetres(std::string_view unit);

}  // namespace acro::capture
