#include "acro/capture/trial_io.h"

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "acro/capture/csv.h"
#include "acro/capture/trc.h"

namespace acro::capture {

Trial ReadTrial(const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  if (ext == "c3d") return ReadC3d(path);
  if (ext == "trc") return ReadTrc(path);
  if (ext == "csv") return ReadMarkerCsv(path);
  throw InputError(path.string(),
                   "extension",
                   "'" + path.extension().string() +
                       "' is not a motion-capture format Acrolab reads (.c3d, .trc, .csv)");
}

Trial ReadTrialFromBytes(std::span<const std::uint8_t> bytes, const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (ext == "c3d") return ReadC3dFromMemory(bytes, path.string());
  if (ext == "trc") return ReadTrcFromString(text, path.string());
  if (ext == "csv") return ReadMarkerCsvFromString(text, path.string());
  throw InputError(path.string(),
                   "extension",
                   "'" + path.extension().string() +
                       "' is not a motion-capture format Acrolab reads (.c3d, .trc, .csv)");
}

void WriteTrial(const Trial& trial, const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  if (ext == "c3d") return WriteC3d(trial, path);
  if (ext == "trc") return WriteTrc(trial, path);
  if (ext == "csv") return WriteMarkerCsv(trial, path);
  throw InputError(path.string(),
                   "extension",
                   "'" + path.extension().string() +
                       "' is not a format Acrolab writes trials to (.c3d, .trc, .csv)");
}

}  // namespace acro::capture
