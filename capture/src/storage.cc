#include "acro/capture/storage.h"

#include <algorithm>
#include <cmath>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "internal/text.h"

namespace acro::capture {

int Storage::FindColumn(std::string_view label) const {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] == label) return static_cast<int>(i);
  }
  return -1;
}

std::string WriteStorageToString(const Storage& table, StorageFlavor flavor) {
  if (table.data.rows() != table.time_s.size() ||
      table.data.cols() != std::int64_t(table.labels.size())) {
    throw InputError(table.name,
                     "table",
                     "data are " + std::to_string(table.data.rows()) + "×" +
                         std::to_string(table.data.cols()) + " for " +
                         std::to_string(table.time_s.size()) + " times and " +
                         std::to_string(table.labels.size()) + " labels");
  }
  std::string out;
  out += (table.name.empty() ? "Acrolab" : table.name) + "\n";
  out += "version=1\n";
  if (flavor == StorageFlavor::kMot) {
    out += "nRows=" + std::to_string(table.time_s.size()) + "\n";
    out += "nColumns=" + std::to_string(table.labels.size() + 1) + "\n";
  } else {
    out += "OpenSimVersion=4.0\n";
  }
  out += std::string("inDegrees=") + (table.in_degrees ? "yes" : "no") + "\n";
  for (const auto& [key, value] : table.metadata) {
    if (key == "version" || key == "nRows" || key == "nColumns" || key == "inDegrees" ||
        key == "OpenSimVersion")
      continue;
    out += key + "=" + value + "\n";
  }
  if (flavor == StorageFlavor::kSto &&
      std::none_of(table.metadata.begin(), table.metadata.end(), [](const auto& kv) {
        return kv.first == "DataType";
      })) {
    out += "DataType=double\n";
  }
  out += "endheader\ntime";
  for (const std::string& label : table.labels) out += "\t" + label;
  out += "\n";
  for (std::int64_t r = 0; r < table.time_s.size(); ++r) {
    internal::AppendNumber(table.time_s[r], &out);
    for (std::int64_t c = 0; c < table.data.cols(); ++c) {
      out += '\t';
      if (std::isnan(table.data(r, c))) {
        out += "NaN";
      } else {
        internal::AppendNumber(table.data(r, c), &out);
      }
    }
    out += '\n';
  }
  return out;
}

void WriteStorage(const Storage& table, const std::filesystem::path& path, StorageFlavor flavor) {
  WriteFileAtomically(path, WriteStorageToString(table, flavor));
}

Storage ReadStorage(const std::filesystem::path& path) {
  const auto bytes = ReadFileBytes(path);
  return ReadStorageFromString(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

Storage ReadStorageFromString(std::string_view text, const std::string& name) {
  using internal::Trim;
  Storage table;
  internal::LineCursor lines(text);
  std::string_view line;
  bool first = true;
  bool ended = false;
  // Header: a name line, key=value lines, then "endheader".
  while (lines.Next(&line)) {
    const std::string_view trimmed = Trim(line);
    if (trimmed == "endheader") {
      ended = true;
      break;
    }
    const std::size_t eq = trimmed.find('=');
    if (eq != std::string_view::npos) {
      const std::string key(Trim(trimmed.substr(0, eq)));
      const std::string value(Trim(trimmed.substr(eq + 1)));
      if (key == "inDegrees")
        table.in_degrees = (value == "yes" || value == "Yes" || value == "true");
      table.metadata.emplace_back(key, value);
    } else if (first) {
      table.name = std::string(trimmed);
    }
    first = false;
  }
  if (!ended)
    throw InputError(name,
                     "line " + std::to_string(lines.line_number()),
                     "no 'endheader' line: not an OpenSim storage file");
  // Column labels, then numbers.
  std::vector<std::string_view> fields;
  do {
    if (!lines.Next(&line))
      throw InputError(name,
                       "line " + std::to_string(lines.line_number() + 1),
                       "no column-label line after 'endheader'");
  } while (Trim(line).empty());
  const bool tabs = line.find('\t') != std::string_view::npos;
  if (tabs)
    internal::Split(Trim(line), '\t', &fields);
  else
    internal::SplitWhitespace(line, &fields);
  if (fields.empty() || Trim(fields[0]) != "time") {
    throw InputError(name,
                     "line " + std::to_string(lines.line_number()),
                     "first column must be 'time', found '" +
                         std::string(fields.empty() ? "" : Trim(fields[0])) + "'");
  }
  for (std::size_t i = 1; i < fields.size(); ++i) table.labels.emplace_back(Trim(fields[i]));
  const std::size_t columns = fields.size();
  std::vector<double> values;
  while (lines.Next(&line)) {
    if (Trim(line).empty()) continue;
    if (tabs)
      internal::Split(Trim(line), '\t', &fields);
    else
      internal::SplitWhitespace(line, &fields);
    if (fields.size() != columns) {
      throw InputError(name,
                       "line " + std::to_string(lines.line_number()),
                       std::to_string(fields.size()) + " columns where the labels name " +
                           std::to_string(columns));
    }
    for (std::size_t c = 0; c < columns; ++c) {
      double value;
      if (!internal::ParseCell(fields[c], &value)) {
        throw InputError(
            name,
            "line " + std::to_string(lines.line_number()) + ", column " + std::to_string(c + 1),
            "'" + std::string(Trim(fields[c]).substr(0, 40)) + "' is not a number");
      }
      // NaN is a gap (as written for one); an infinity or a time that is not a number is no value
      // any table holds.
      if (std::isinf(value) || (c == 0 && !std::isfinite(value))) {
        throw InputError(
            name,
            "line " + std::to_string(lines.line_number()) + ", column " + std::to_string(c + 1) +
                " (" + (c == 0 ? std::string("time") : table.labels[c - 1]) + ")",
            "'" + std::string(Trim(fields[c]).substr(0, 40)) + "' is not a finite number");
      }
      values.push_back(value);
    }
  }
  const std::int64_t rows = static_cast<std::int64_t>(values.size() / columns);
  table.time_s.resize(rows);
  table.data.resize(rows, static_cast<std::int64_t>(columns) - 1);
  for (std::int64_t r = 0; r < rows; ++r) {
    table.time_s[r] = values[r * columns];
    for (std::size_t c = 1; c < columns; ++c) table.data(r, c - 1) = values[r * columns + c];
  }
  return table;
}

}  // namespace acro::capture
