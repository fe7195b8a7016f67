#include "acro/capture/csv.h"

#include <cmath>
#include <limits>
#include <vector>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "internal/text.h"

namespace acro::capture {
namespace {

void AppendCsvField(const std::string& field, std::string* out) {
  if (field.find_first_of(",\"\n") == std::string::npos) {
    *out += field;
    return;
  }
  *out += '"';
  for (char c : field) {
    if (c == '"') *out += '"';
    *out += c;
  }
  *out += '"';
}

// Splits one CSV record (RFC 4180 quoting, no embedded line breaks).
std::vector<std::string> SplitCsv(std::string_view line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

std::string WriteMarkerCsvToString(const Trial& trial) {
  std::vector<int> markers;
  for (int p = 0; p < trial.num_points(); ++p) {
    if (trial.points[p].type == PointType::kMarker) markers.push_back(p);
  }
  std::string out = "frame,time_s";
  static const char* kAxes[3] = {"_x_m", "_y_m", "_z_m"};
  for (int p : markers) {
    for (const char* axis : kAxes) {
      out += ',';
      std::string column = trial.points[p].label;
      column.append(axis);
      AppendCsvField(column, &out);
    }
  }
  out += '\n';
  for (int f = 0; f < trial.num_frames; ++f) {
    out += std::to_string(trial.first_frame + f);
    out += ',';
    internal::AppendNumber(f / trial.point_rate_hz, &out);
    for (int p : markers) {
      const auto xyz = trial.position(f, p);
      for (int k = 0; k < 3; ++k) {
        out += ',';
        if (!std::isnan(xyz[k])) internal::AppendNumber(xyz[k], &out);
      }
    }
    out += '\n';
  }
  return out;
}

void WriteMarkerCsv(const Trial& trial, const std::filesystem::path& path) {
  WriteFileAtomically(path, WriteMarkerCsvToString(trial));
}

Trial ReadMarkerCsv(const std::filesystem::path& path) {
  const auto bytes = ReadFileBytes(path);
  return ReadMarkerCsvFromString(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

Trial ReadMarkerCsvFromString(std::string_view text, const std::string& name) {
  Trial trial;
  trial.source.path = name;
  trial.source.format = "CSV";
  trial.source.point_units = "m";
  trial.source.point_units_to_m = 1.0;
  internal::LineCursor lines(text);
  std::string_view line;
  if (!lines.Next(&line)) throw InputError(name, "", "empty file: not an Acrolab marker CSV");
  const std::vector<std::string> header = SplitCsv(line);
  if (header.size() < 2 || header[0] != "frame" || header[1] != "time_s" ||
      (header.size() - 2) % 3 != 0) {
    throw InputError(
        name, "line 1", "expected 'frame,time_s' followed by x, y, z columns per marker");
  }
  const int num_markers = static_cast<int>((header.size() - 2) / 3);
  for (int m = 0; m < num_markers; ++m) {
    const std::string& x = header[2 + 3 * m];
    if (x.size() < 4 || x.compare(x.size() - 4, 4, "_x_m") != 0) {
      throw InputError(name,
                       "line 1, column " + std::to_string(3 + 3 * m),
                       "expected '<label>_x_m', found '" + x + "'");
    }
    PointInfo info;
    info.label = x.substr(0, x.size() - 4);
    info.unit = "m";
    trial.points.push_back(info);
  }
  std::vector<double> values;
  std::vector<double> times;
  while (lines.Next(&line)) {
    if (internal::Trim(line).empty()) continue;
    const std::vector<std::string> fields = SplitCsv(line);
    if (fields.size() != header.size()) {
      throw InputError(name,
                       "line " + std::to_string(lines.line_number()),
                       std::to_string(fields.size()) + " fields where the header has " +
                           std::to_string(header.size()));
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double value;
      if (!internal::ParseCell(fields[c], &value) || (c < 2 && std::isnan(value))) {
        throw InputError(
            name,
            "line " + std::to_string(lines.line_number()) + ", column " + std::to_string(c + 1),
            "'" + fields[c].substr(0, 40) + "' is not a number");
      }
      if (c == 0 && times.empty())
        trial.first_frame = static_cast<std::int64_t>(std::llround(value));
      if (c == 1)
        times.push_back(value);
      else if (c >= 2)
        values.push_back(value);
    }
  }
  trial.num_frames = static_cast<int>(times.size());
  if (trial.num_frames >= 2 && times.back() > times.front()) {
    trial.point_rate_hz = (trial.num_frames - 1) / (times.back() - times.front());
  } else {
    throw InputError(
        name, "time_s", "at least two frames with increasing times are needed to know the rate");
  }
  trial.positions =
      Eigen::Map<Eigen::Matrix3Xd>(values.data(), 3, std::int64_t(trial.num_frames) * num_markers);
  trial.residuals.setZero(num_markers, trial.num_frames);
  trial.camera_masks.setZero(num_markers, trial.num_frames);
  for (int f = 0; f < trial.num_frames; ++f) {
    for (int m = 0; m < num_markers; ++m) {
      if (trial.position(f, m).hasNaN()) {
        trial.position(f, m).setConstant(std::numeric_limits<double>::quiet_NaN());
        trial.residuals(m, f) = -1.0f;
      }
    }
  }
  return trial;
}

}  // namespace acro::capture
