#include "acro/capture/csv.h"

#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <fmt/format.h>

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

namespace {

// The header's markers: '<label>_x_m', then its y and z, in that order (swapped columns would be
// read as another motion).
std::vector<PointInfo> ReadCsvHeader(const std::vector<std::string>& header, const std::string& name) {
  if (header.size() < 2 || header[0] != "frame" || header[1] != "time_s" || (header.size() - 2) % 3 != 0) {
    throw InputError(name, "line 1", "expected 'frame,time_s' followed by x, y, z columns per marker");
  }
  const int num_markers = static_cast<int>((header.size() - 2) / 3);
  std::vector<PointInfo> points;
  for (int m = 0; m < num_markers; ++m) {
    const std::string& x = header[2 + 3 * m];
    if (x.size() < 4 || x.compare(x.size() - 4, 4, "_x_m") != 0) {
      throw InputError(name, "line 1, column " + std::to_string(3 + 3 * m), "expected '<label>_x_m', found '" + x + "'");
    }
    PointInfo info;
    info.label = x.substr(0, x.size() - 4);
    info.unit = "m";
    for (int axis = 1; axis < 3; ++axis) {
      const std::string expected = info.label + (axis == 1 ? "_y_m" : "_z_m");
      const std::string& found = header[2 + 3 * m + axis];
      if (found != expected)
        throw InputError(name,
                         "line 1, column " + std::to_string(3 + 3 * m + axis),
                         "expected '" + expected + "', found '" + found.substr(0, 80) + "'");
    }
    points.push_back(info);
  }
  return points;
}

// A label given twice would make two markers one: the second gets a suffix, said (the first
// ten, then a count).
void RenameRepeatedLabels(const std::string& name, Trial* trial) {
  std::unordered_map<std::string, int> first;
  std::unordered_set<std::string> taken;
  for (const PointInfo& p : trial->points) taken.insert(p.label);
  int repeats = 0;
  for (int m = 0; m < trial->num_points(); ++m) {
    std::string& label = trial->points[m].label;
    const auto [at, is_first] = first.emplace(label, m);
    if (is_first) continue;
    int k = 2;
    std::string renamed = label + "_" + std::to_string(k);
    while (taken.count(renamed) > 0) renamed = label + "_" + std::to_string(++k);
    if (++repeats <= 10)
      trial->warnings.push_back(name + ": line 1: marker label '" + label + "' repeats (markers " +
                                std::to_string(at->second + 1) + " and " + std::to_string(m + 1) +
                                "); the second is read as '" + renamed + "'");
    taken.insert(renamed);
    label = renamed;
  }
  if (repeats > 10)
    trial->warnings.push_back(name + ": line 1: " + std::to_string(repeats - 10) +
                              " more repeated marker labels, each read with a suffix");
}

struct CsvRows {
  std::vector<double> values;  // x, y, z per marker per row
  std::vector<double> times;
  std::vector<int> time_lines;
  std::int64_t first_frame = 0;
};

// The rows after the header: as many fields as the header, numbers (blank coordinates are gaps),
// the time running forward.
CsvRows ReadCsvRows(internal::LineCursor* lines, std::size_t num_fields, const std::string& name) {
  CsvRows rows;
  std::string_view line;
  while (lines->Next(&line)) {
    if (internal::Trim(line).empty()) continue;
    const std::vector<std::string> fields = SplitCsv(line);
    const std::string at = "line " + std::to_string(lines->line_number());
    if (fields.size() != num_fields) {
      throw InputError(name, at,
                       std::to_string(fields.size()) + " fields where the header has " + std::to_string(num_fields));
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double value;
      if (!internal::ParseCell(fields[c], &value) || (c < 2 && std::isnan(value))) {
        throw InputError(name, at + ", column " + std::to_string(c + 1),
                         "'" + fields[c].substr(0, 40) + "' is not a number");
      }
      if (c == 0 && rows.times.empty()) rows.first_frame = static_cast<std::int64_t>(std::llround(value));
      // Time runs forward: a row at or before its predecessor is a spliced or sorted-wrong file.
      if (c == 1 && !rows.times.empty() && !(value > rows.times.back()))
        throw InputError(name, at + ", column 2",
                         "time " + std::to_string(value) + " s is not after the previous row's " +
                             std::to_string(rows.times.back()) + " s");
      if (c == 1) {
        rows.times.push_back(value);
        rows.time_lines.push_back(lines->line_number());
      } else if (c >= 2) {
        rows.values.push_back(value);
      }
    }
  }
  return rows;
}

// The rate comes from the first and last times; rows off that even grid by more than 1 % of a
// frame are said (dropped or duplicated frames, another rate spliced in).
void WarnRowsOffTheGrid(const CsvRows& rows, const std::string& name, Trial* trial) {
  const std::vector<double>& times = rows.times;
  const double dt = 1.0 / trial->point_rate_hz;
  int off = 0;
  std::string lines_off;
  for (int f = 0; f < trial->num_frames; ++f) {
    if (std::abs(times[f] - times.front() - f * dt) <= 0.01 * dt) continue;
    if (++off <= 5) lines_off += (lines_off.empty() ? "" : ", ") + std::to_string(rows.time_lines[f]);
  }
  if (off > 0)
    trial->warnings.push_back(
        name + ": line" + (off > 1 ? "s " : " ") + lines_off +
        (off > 5 ? " and " + std::to_string(off - 5) + " more rows" : "") +
        ": time_s off the even grid of " + fmt::format("{:g}", trial->point_rate_hz) +
        " Hz (from the first and last times) by more than 1 % of a frame; frames are taken as "
        "evenly spaced");
}

}  // namespace

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
  trial.points = ReadCsvHeader(header, name);
  const int num_markers = trial.num_points();
  RenameRepeatedLabels(name, &trial);
  CsvRows rows = ReadCsvRows(&lines, header.size(), name);
  trial.first_frame = rows.first_frame;
  const std::vector<double>& times = rows.times;
  trial.num_frames = static_cast<int>(times.size());
  if (trial.num_frames >= 2 && times.back() > times.front()) {
    trial.point_rate_hz = (trial.num_frames - 1) / (times.back() - times.front());
  } else {
    throw InputError(name, "time_s", "at least two frames with increasing times are needed to know the rate");
  }
  WarnRowsOffTheGrid(rows, name, &trial);
  trial.positions = Eigen::Map<Eigen::Matrix3Xd>(rows.values.data(), 3, std::int64_t(trial.num_frames) * num_markers);
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
  GapImpossiblePositions(&trial, name);
  return trial;
}

}  // namespace acro::capture
