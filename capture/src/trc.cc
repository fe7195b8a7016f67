#include "acro/capture/trc.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "acro/base/file_io.h"
#include "internal/text.h"

namespace acro::capture {
namespace {

using internal::LineCursor;
using internal::ParseCell;
using internal::Trim;

std::string Where(int line, int column = 0) {
  std::string where = "line " + std::to_string(line);
  if (column > 0) where += ", column " + std::to_string(column);
  return where;
}

// Splits a TRC line: on tabs when the file uses tabs (empty cells are meaningful), otherwise on
// runs of blanks.
void SplitTrc(std::string_view line, bool tabs, std::vector<std::string_view>* fields) {
  if (tabs) {
    internal::Split(line, '\t', fields);
  } else {
    internal::SplitWhitespace(line, fields);
  }
}

bool LooksNumeric(std::string_view cell) {
  double value;
  cell = Trim(cell);
  return !cell.empty() && ParseCell(cell, &value) && !std::isnan(value);
}

}  // namespace

double LengthUnitToMetres(std::string_view unit) {
  std::string u(Trim(unit));
  for (char& c : u) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (u == "mm" || u == "millimeters" || u == "millimetres") return 1e-3;
  if (u == "cm" || u == "centimeters" || u == "centimetres") return 1e-2;
  if (u == "dm") return 1e-1;
  if (u == "m" || u == "meters" || u == "metres" || u == "meter" || u == "metre") return 1.0;
  if (u == "in" || u == "inch" || u == "inches") return 0.0254;
  return 0.0;
}

Trial ReadTrc(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path);
  return ReadTrcFromString(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

Trial ReadTrcFromString(std::string_view text, const std::string& name) {
  Trial trial;
  trial.source.path = name;
  trial.source.format = "TRC";
  if (text.empty()) throw InputError(name, "", "empty file: not a TRC file");
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 BOM

  LineCursor lines(text);
  std::string_view line;
  std::vector<std::string_view> fields;

  // Line 1: "PathFileType 4 (X/Y/Z) <file name>".
  lines.Next(&line);
  if (Trim(line).substr(0, 12) != "PathFileType") {
    throw InputError(name,
                     Where(1),
                     "not a TRC file: expected 'PathFileType', found '" +
                         std::string(Trim(line).substr(0, 40)) + "'");
  }

  // Lines 2 and 3: header keys and their values.
  std::string_view keys_line, values_line;
  if (!lines.Next(&keys_line) || !lines.Next(&values_line)) {
    throw InputError(name,
                     Where(lines.line_number() + 1),
                     "unexpected end of file: the header ends before its values line");
  }
  const bool tabs = keys_line.find('\t') != std::string_view::npos;
  std::vector<std::string_view> keys, values;
  SplitTrc(keys_line, tabs, &keys);
  SplitTrc(values_line, tabs, &values);
  std::map<std::string, std::string> header;
  for (std::size_t i = 0; i < keys.size() && i < values.size(); ++i) {
    const std::string key(Trim(keys[i]));
    if (!key.empty()) header[key] = std::string(Trim(values[i]));
  }
  auto header_number = [&](const std::string& key) -> double {
    auto it = header.find(key);
    if (it == header.end() || it->second.empty()) return std::numeric_limits<double>::quiet_NaN();
    double value;
    if (!ParseCell(it->second, &value)) {
      throw InputError(name, Where(3) + " (" + key + ")", "'" + it->second + "' is not a number");
    }
    return value;
  };

  // Line 4: "Frame# Time name1 (2 blanks) name2 ...": a name every three columns.
  std::string_view names_line;
  if (!lines.Next(&names_line)) {
    throw InputError(name, Where(4), "unexpected end of file: no marker-name line");
  }
  SplitTrc(names_line, tabs, &fields);
  if (fields.empty() || Trim(fields[0]).substr(0, 5) != "Frame") {
    throw InputError(name,
                     Where(4),
                     "expected 'Frame#' at the start of the marker-name line, found '" +
                         std::string(fields.empty() ? "" : Trim(fields[0])) + "'");
  }
  std::vector<std::string> names;
  if (tabs) {
    // Trailing empty cells do not make markers.
    std::size_t last = fields.size();
    while (last > 2 && Trim(fields[last - 1]).empty()) --last;
    for (std::size_t column = 2; column < last; column += 3)
      names.emplace_back(Trim(fields[column]));
  } else {
    for (std::size_t column = 2; column < fields.size(); ++column)
      names.emplace_back(Trim(fields[column]));
  }

  // Data rows, after the optional X1 Y1 Z1 line and blank lines: parsed once into a flat buffer.
  std::vector<double> cells;  // row-major, `row_width` doubles per row after the frame number
  std::vector<std::size_t> row_offsets;
  std::vector<int> row_lines;
  std::size_t max_columns = 0;  // coordinate columns holding a value, over all rows
  std::int64_t first_frame_number = 1;
  std::vector<double> times;
  while (lines.Next(&line)) {
    if (Trim(line).empty()) continue;
    SplitTrc(line, tabs, &fields);
    if (!LooksNumeric(fields[0])) {
      // The coordinate-name line ("X1 Y1 Z1 ...", starting with blank cells) may precede the data.
      if (row_offsets.empty() && (Trim(fields[0]).empty() || Trim(fields[0])[0] == 'X')) continue;
      throw InputError(
          name,
          Where(lines.line_number(), 1),
          "expected a frame number, found '" + std::string(Trim(fields[0]).substr(0, 40)) + "'");
    }
    double frame_number = 0, time = 0;
    ParseCell(fields[0], &frame_number);
    if (fields.size() < 2 || !ParseCell(fields[1], &time)) {
      throw InputError(name, Where(lines.line_number(), 2), "missing or non-numeric time");
    }
    if (row_offsets.empty())
      first_frame_number = static_cast<std::int64_t>(std::llround(frame_number));
    row_offsets.push_back(cells.size());
    row_lines.push_back(lines.line_number());
    times.push_back(time);
    std::size_t last_value = 0;
    for (std::size_t column = 2; column < fields.size(); ++column) {
      double value;
      if (!ParseCell(fields[column], &value)) {
        throw InputError(
            name,
            Where(lines.line_number(), static_cast<int>(column) + 1),
            "'" + std::string(Trim(fields[column]).substr(0, 40)) + "' is not a number");
      }
      cells.push_back(value);
      if (!Trim(fields[column]).empty()) last_value = column - 1;
    }
    max_columns = std::max(max_columns, last_value);
  }
  row_offsets.push_back(cells.size());
  const int num_rows = static_cast<int>(times.size());

  // Header counts against what the data hold: the data win.
  const double header_frames = header_number("NumFrames");
  const double header_markers = header_number("NumMarkers");
  if (num_rows == 0 && !std::isnan(header_frames) && header_frames > 0) {
    throw InputError(name,
                     Where(lines.line_number() + 1),
                     "unexpected end of file: the header announces " +
                         std::to_string(static_cast<long long>(header_frames)) +
                         " frames and there are none");
  }
  if (names.empty()) {
    const std::size_t count = (max_columns + 2) / 3;
    for (std::size_t i = 0; i < count; ++i) names.push_back("Unlabel#" + std::to_string(i + 1));
  } else {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i].empty()) names[i] = "Unlabel#" + std::to_string(i + 1);
    }
    if (max_columns > 3 * names.size()) {
      trial.warnings.push_back(name + ": data rows hold " + std::to_string(max_columns) +
                               " coordinate columns but only " + std::to_string(names.size()) +
                               " markers are named; the unnamed columns were ignored");
    }
  }
  const int num_markers = static_cast<int>(names.size());
  if (!std::isnan(header_frames) && static_cast<long long>(header_frames) != num_rows) {
    trial.warnings.push_back(
        name + ": header NumFrames = " + std::to_string(static_cast<long long>(header_frames)) +
        " but the file has " + std::to_string(num_rows) + " data rows; the rows were read");
  }
  if (!std::isnan(header_markers) && static_cast<long long>(header_markers) != num_markers) {
    trial.warnings.push_back(
        name + ": header NumMarkers = " + std::to_string(static_cast<long long>(header_markers)) +
        " but " + std::to_string(num_markers) + " markers were found; the data were read");
  }

  // Units and rate.
  auto units_it = header.find("Units");
  trial.source.point_units = units_it == header.end() ? "" : units_it->second;
  double to_m = LengthUnitToMetres(trial.source.point_units);
  if (to_m == 0.0) {
    trial.warnings.push_back(name + ": header Units = '" + trial.source.point_units +
                             "' is not a known length unit; millimetres assumed");
    to_m = 1e-3;
  }
  trial.source.point_units_to_m = to_m;
  double rate = header_number("DataRate");
  if (std::isnan(rate) || rate <= 0) {
    if (num_rows >= 2 && times[1] > times[0]) {
      rate = (num_rows - 1) / (times.back() - times.front());
      trial.warnings.push_back(name + ": header DataRate missing or not positive; " +
                               std::to_string(rate) + " Hz taken from the time column");
    } else {
      throw InputError(name,
                       Where(3) + " (DataRate)",
                       "missing or not positive, and no time column to derive it from");
    }
  }
  trial.point_rate_hz = rate;
  trial.first_frame = first_frame_number;
  trial.num_frames = num_rows;

  // Assemble frame-major positions in metres.
  trial.points.resize(num_markers);
  for (int m = 0; m < num_markers; ++m) {
    trial.points[m].label = names[m];
    trial.points[m].type = PointType::kMarker;
    trial.points[m].unit = "m";
  }
  trial.positions.setConstant(
      3, std::int64_t(num_rows) * num_markers, std::numeric_limits<double>::quiet_NaN());
  trial.residuals.setConstant(num_markers, num_rows, -1.0f);
  trial.camera_masks.setZero(num_markers, num_rows);
  for (int f = 0; f < num_rows; ++f) {
    const std::size_t begin = row_offsets[f];
    const std::size_t count = row_offsets[f + 1] - begin;
    for (int m = 0; m < num_markers; ++m) {
      if (3 * std::size_t(m) + 2 >= count) break;
      const double* xyz = &cells[begin + 3 * m];
      if (std::isnan(xyz[0]) || std::isnan(xyz[1]) || std::isnan(xyz[2])) continue;
      trial.position(f, m) = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * to_m;
      trial.residuals(m, f) = 0.0f;
    }
  }
  return trial;
}

std::string WriteTrcToString(const Trial& trial,
                             const std::string& file_name,
                             const TrcWriteOptions& options) {
  const double from_m = LengthUnitToMetres(options.units);
  if (from_m == 0.0)
    throw InputError(file_name, "units", "unknown length unit '" + options.units + "'");
  std::vector<int> markers;
  for (int p = 0; p < trial.num_points(); ++p) {
    if (trial.points[p].type == PointType::kMarker) markers.push_back(p);
  }
  std::string out;
  out.reserve(64 + std::size_t(trial.num_frames) * (16 + markers.size() * 3 * 14));
  const std::string rate = std::to_string(trial.point_rate_hz);
  out += "PathFileType\t4\t(X/Y/Z)\t" + file_name + "\n";
  out +=
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNu"
      "mFrames\n";
  out += rate + "\t" + rate + "\t" + std::to_string(trial.num_frames) + "\t" +
         std::to_string(markers.size()) + "\t" + options.units + "\t" + rate + "\t" +
         std::to_string(trial.first_frame) + "\t" + std::to_string(trial.num_frames) + "\n";
  out += "Frame#\tTime";
  for (int p : markers) out += "\t" + trial.points[p].label + "\t\t";
  out += "\n\t";
  for (std::size_t i = 1; i <= markers.size(); ++i) {
    const std::string k = std::to_string(i);
    out += "\tX" + k + "\tY" + k + "\tZ" + k;
  }
  out += "\n\n";
  for (int f = 0; f < trial.num_frames; ++f) {
    out += std::to_string(trial.first_frame + f);
    out += '\t';
    internal::AppendFixed(f / trial.point_rate_hz, 6, &out);
    for (int p : markers) {
      const auto xyz = trial.position(f, p);
      for (int k = 0; k < 3; ++k) {
        out += '\t';
        if (std::isnan(xyz[k])) {
          out += "NaN";
        } else {
          internal::AppendFixed(xyz[k] / from_m, options.decimals, &out);
        }
      }
    }
    out += '\n';
  }
  return out;
}

void WriteTrc(const Trial& trial,
              const std::filesystem::path& path,
              const TrcWriteOptions& options) {
  WriteFileAtomically(path, WriteTrcToString(trial, path.filename().string(), options));
}

}  // namespace acro::capture
