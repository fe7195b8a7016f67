#include "acro/capture/trc.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
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

// ---- ReadTrcFromString's steps ----

// The header keys (line 2) and their values (line 3), and whether the file separates its cells
// by tabs (decided on the keys line).
struct TrcHeader {
  bool tabs = false;
  std::map<std::string, std::string> values;
};

// Lines 1 to 3: "PathFileType 4 (X/Y/Z) <file name>", then the header keys and their values.
TrcHeader ReadTrcHeader(LineCursor& lines, const std::string& name) {
  // Line 1.
  std::string_view line;
  lines.Next(&line);
  if (Trim(line).substr(0, 12) != "PathFileType") {
    throw InputError(name,
                     Where(1),
                     "not a TRC file: expected 'PathFileType', found '" +
                         std::string(Trim(line).substr(0, 40)) + "'");
  }
  // Lines 2 and 3.
  std::string_view keys_line, values_line;
  if (!lines.Next(&keys_line) || !lines.Next(&values_line)) {
    throw InputError(name,
                     Where(lines.line_number() + 1),
                     "unexpected end of file: the header ends before its values line");
  }
  TrcHeader header;
  header.tabs = keys_line.find('\t') != std::string_view::npos;
  std::vector<std::string_view> keys, values;
  SplitTrc(keys_line, header.tabs, &keys);
  SplitTrc(values_line, header.tabs, &values);
  for (std::size_t i = 0; i < keys.size() && i < values.size(); ++i) {
    const std::string key(Trim(keys[i]));
    if (!key.empty()) header.values[key] = std::string(Trim(values[i]));
  }
  return header;
}

// The header's number under `key`; NaN when absent or empty.
double HeaderNumber(const TrcHeader& header, const std::string& key, const std::string& name) {
  auto it = header.values.find(key);
  if (it == header.values.end() || it->second.empty())
    return std::numeric_limits<double>::quiet_NaN();
  double value;
  if (!ParseCell(it->second, &value)) {
    throw InputError(name, Where(3) + " (" + key + ")", "'" + it->second + "' is not a number");
  }
  return value;
}

// Line 4: "Frame# Time name1 (2 blanks) name2 ...": a name every three columns.
std::vector<std::string> ReadMarkerNames(LineCursor& lines, bool tabs, const std::string& name) {
  std::string_view names_line;
  if (!lines.Next(&names_line)) {
    throw InputError(name, Where(4), "unexpected end of file: no marker-name line");
  }
  std::vector<std::string_view> fields;
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
  return names;
}

// The data rows parsed once into a flat buffer.
struct TrcRows {
  std::vector<double> cells;             // row-major, the cells after the frame number and time
  std::vector<std::size_t> row_offsets;  // where each row starts in `cells`, then the end
  std::size_t max_columns = 0;           // coordinate columns holding a value, over all rows
  std::int64_t first_frame_number = 1;
  std::vector<double> times;
  std::vector<int> lines;             // each row's line in the file
  int first_line = 0, last_line = 0;  // of the data rows
};

// Data rows, after the optional X1 Y1 Z1 line and blank lines.
TrcRows ReadDataRows(LineCursor& lines, bool tabs, const std::string& name) {
  TrcRows rows;
  std::string_view line;
  std::vector<std::string_view> fields;
  while (lines.Next(&line)) {
    if (Trim(line).empty()) continue;
    SplitTrc(line, tabs, &fields);
    if (!LooksNumeric(fields[0])) {
      // The coordinate-name line ("X1 Y1 Z1 ...", starting with blank cells) may precede the data.
      if (rows.row_offsets.empty() && (Trim(fields[0]).empty() || Trim(fields[0])[0] == 'X'))
        continue;
      throw InputError(
          name,
          Where(lines.line_number(), 1),
          "expected a frame number, found '" + std::string(Trim(fields[0]).substr(0, 40)) + "'");
    }
    // Frame number and time.
    double frame_number = 0, time = 0;
    ParseCell(fields[0], &frame_number);
    if (fields.size() < 2 || !ParseCell(fields[1], &time)) {
      throw InputError(name, Where(lines.line_number(), 2), "missing or non-numeric time");
    }
    if (rows.row_offsets.empty())
      rows.first_frame_number = static_cast<std::int64_t>(std::llround(frame_number));
    // Time runs forward: a row at or before its predecessor is a spliced or sorted-wrong file.
    if (!rows.times.empty() && !(time > rows.times.back())) {
      throw InputError(name,
                       Where(lines.line_number(), 2),
                       "time " + std::to_string(time) + " s is not after the previous row's " +
                           std::to_string(rows.times.back()) + " s");
    }
    if (rows.row_offsets.empty()) rows.first_line = lines.line_number();
    rows.last_line = lines.line_number();
    rows.row_offsets.push_back(rows.cells.size());
    rows.times.push_back(time);
    rows.lines.push_back(lines.line_number());
    // The coordinates (empty cells are NaN).
    std::size_t last_value = 0;
    for (std::size_t column = 2; column < fields.size(); ++column) {
      double value;
      if (!ParseCell(fields[column], &value)) {
        throw InputError(
            name,
            Where(lines.line_number(), static_cast<int>(column) + 1),
            "'" + std::string(Trim(fields[column]).substr(0, 40)) + "' is not a number");
      }
      rows.cells.push_back(value);
      if (!Trim(fields[column]).empty()) last_value = column - 1;
    }
    rows.max_columns = std::max(rows.max_columns, last_value);
  }
  rows.row_offsets.push_back(rows.cells.size());
  return rows;
}

// Names for unnamed markers ("Unlabel#i"), and as many as the data's columns when the file names
// none; a warning when the data hold more columns than the names.
void NameMarkers(std::size_t max_columns,
                 const std::string& name,
                 std::vector<std::string>& names,
                 std::vector<std::string>& warnings) {
  if (names.empty()) {
    const std::size_t count = (max_columns + 2) / 3;
    for (std::size_t i = 0; i < count; ++i) names.push_back("Unlabel#" + std::to_string(i + 1));
    return;
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) names[i] = "Unlabel#" + std::to_string(i + 1);
  }
  if (max_columns > 3 * names.size()) {
    warnings.push_back(name + ": data rows hold " + std::to_string(max_columns) +
                       " coordinate columns but only " + std::to_string(names.size()) +
                       " markers are named; the unnamed columns were ignored");
  }
}

// Units (millimetres when unknown) and rate (from the time column when the header has none).
void ReadUnitsAndRate(const TrcHeader& header,
                      const std::vector<double>& times,
                      int first_line,
                      int last_line,
                      const std::string& name,
                      Trial& trial) {
  auto units_it = header.values.find("Units");
  trial.source.point_units = units_it == header.values.end() ? "" : units_it->second;
  double to_m = LengthUnitToMetres(trial.source.point_units);
  if (to_m == 0.0) {
    trial.warnings.push_back(name + ": header Units = '" + trial.source.point_units +
                             "' is not a known length unit; millimetres assumed");
    to_m = 1e-3;
  }
  trial.source.point_units_to_m = to_m;
  const int num_rows = static_cast<int>(times.size());
  if (num_rows > 0 && std::isfinite(times.front())) trial.source.first_time_s = times.front();
  double rate = HeaderNumber(header, "DataRate", name);
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
  // The time column against the rate: over the whole file, so that times rounded to a millisecond
  // do not count; a difference of more than 1 % is said (the header's rate is used).
  if (num_rows >= 3) {
    const double from_times = (num_rows - 1) / (times.back() - times.front());
    if (std::abs(from_times - rate) > 0.01 * rate) {
      trial.warnings.push_back(name + ": lines " + std::to_string(first_line) + "–" +
                               std::to_string(last_line) + ": the time column runs at " +
                               std::to_string(from_times) + " Hz but the header's DataRate is " +
                               std::to_string(rate) + " Hz; the header's rate is used");
    }
  }
}

// The markers' descriptions and their frame-major positions in metres (NaN and residual −1 where
// a row has no complete coordinates).
void AssemblePositions(const TrcRows& rows,
                       const std::vector<std::string>& names,
                       double to_m,
                       Trial& trial) {
  const int num_rows = static_cast<int>(rows.times.size());
  const int num_markers = static_cast<int>(names.size());
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
    const std::size_t begin = rows.row_offsets[f];
    const std::size_t count = rows.row_offsets[f + 1] - begin;
    for (int m = 0; m < num_markers; ++m) {
      if (3 * std::size_t(m) + 2 >= count) break;
      const double* xyz = &rows.cells[begin + 3 * m];
      if (std::isnan(xyz[0]) || std::isnan(xyz[1]) || std::isnan(xyz[2])) continue;
      trial.position(f, m) = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * to_m;
      trial.residuals(m, f) = 0.0f;
    }
  }
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

  // Header (lines 1–3), marker names (line 4), data rows.
  LineCursor lines(text);
  const TrcHeader header = ReadTrcHeader(lines, name);
  std::vector<std::string> names = ReadMarkerNames(lines, header.tabs, name);
  const TrcRows rows = ReadDataRows(lines, header.tabs, name);
  const int num_rows = static_cast<int>(rows.times.size());

  // Header counts against what the data hold: the data win.
  const double header_frames = HeaderNumber(header, "NumFrames", name);
  const double header_markers = HeaderNumber(header, "NumMarkers", name);
  if (num_rows == 0 && !std::isnan(header_frames) && header_frames > 0) {
    throw InputError(name,
                     Where(lines.line_number() + 1),
                     "unexpected end of file: the header announces " +
                         std::to_string(static_cast<long long>(header_frames)) +
                         " frames and there are none");
  }
  NameMarkers(rows.max_columns, name, names, trial.warnings);
  // A name given twice would make two markers one; the second gets a suffix, said (the first ten,
  // then a count). Hash sets and a suffix counter per name, not pairwise comparison: a line of
  // 300,000 equal names must not take minutes.
  {
    std::unordered_set<std::string> taken(names.begin(), names.end());
    std::unordered_map<std::string, std::size_t> first;  // name → its first marker
    std::unordered_map<std::string, int> next_suffix;
    std::size_t repeats = 0;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto [at, is_first] = first.emplace(names[i], i);
      if (is_first) continue;
      int& k = next_suffix.try_emplace(names[i], 2).first->second;
      std::string renamed = names[i] + "_" + std::to_string(k);
      while (taken.count(renamed) > 0) renamed = names[i] + "_" + std::to_string(++k);
      ++k;
      if (++repeats <= 10)
        trial.warnings.push_back(name + ": " + Where(4) + ": marker name '" + names[i] +
                                 "' repeats (markers " + std::to_string(at->second + 1) + " and " +
                                 std::to_string(i + 1) + "); the second is read as '" + renamed +
                                 "'");
      taken.insert(renamed);
      names[i] = renamed;
    }
    if (repeats > 10)
      trial.warnings.push_back(name + ": " + Where(4) + ": " + std::to_string(repeats - 10) +
                               " more repeated marker names, each read with a suffix");
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

  // Rows shorter than the markers' columns: their missing markers are read as gaps, and said (the
  // first five lines, then a count).
  {
    const std::size_t columns = 3 * static_cast<std::size_t>(num_markers);
    std::string first;
    int short_rows = 0;
    for (int f = 0; f < num_rows; ++f) {
      if (rows.row_offsets[f + 1] - rows.row_offsets[f] >= columns) continue;
      if (++short_rows <= 5) first += (first.empty() ? "" : ", ") + std::to_string(rows.lines[f]);
    }
    if (short_rows > 0)
      trial.warnings.push_back(
          name + ": line" + (short_rows > 1 ? "s " : " ") + first +
          (short_rows > 5 ? " and " + std::to_string(short_rows - 5) + " more rows" : "") +
          (short_rows > 1 ? " hold" : " holds") + " fewer than the " + std::to_string(columns) +
          " coordinate columns of " + std::to_string(num_markers) +
          " markers; the markers past a row's end are read as gaps");
  }

  // Units and rate; frames.
  ReadUnitsAndRate(header, rows.times, rows.first_line, rows.last_line, name, trial);
  trial.first_frame = rows.first_frame_number;
  trial.num_frames = num_rows;

  // The grid of positions is sized from what the file holds, never from what it declares: each
  // coordinate of a row takes at least its separator, so rows × markers × 3 cells larger than the
  // file's bytes cannot come from it (a header naming 100,000 markers over 400 rows of 3
  // coordinates asked for 1 GB).
  const double cells = 3.0 * num_markers * num_rows;
  if (cells > static_cast<double>(text.size())) {
    throw InputError(name,
                     Where(4),
                     fmt::format("names {} markers over {} rows, {:.3g} coordinates, but the file "
                                 "holds only {} bytes (the rows hold at most {} columns)",
                                 num_markers, num_rows, cells, text.size(), rows.max_columns));
  }

  // Assemble frame-major positions in metres.
  AssemblePositions(rows, names, trial.source.point_units_to_m, trial);
  GapImpossiblePositions(&trial, name);
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
