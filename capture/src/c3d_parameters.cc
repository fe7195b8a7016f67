// Decoding of the C3D parameters that describe points, analog channels, events and force
// platforms (C3D manual, "The POINT group", "The ANALOG group", "The EVENT group", "The
// FORCE_PLATFORM group"). Used by the reader, and by the writer to check that the Trial still
// matches the parameters it carries.

#include <algorithm>
#include <cctype>
#include <cmath>

#include "c3d_internal.h"

namespace acro::capture::internal {
namespace {

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string Trim(const std::string& s) {
  std::size_t b = 0;
  std::size_t e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\0')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
  return s.substr(b, e - b);
}

// The entries of a list parameter, or of a scalar character parameter (one string).
std::vector<std::string> StringList(const Parameter& p) {
  return p.AsStrings();
}

}  // namespace

const char* ProcessorName(Processor processor) {
  switch (processor) {
    case Processor::kIntel:
      return "Intel";
    case Processor::kDec:
      return "DEC";
    case Processor::kMips:
      return "MIPS";
  }
  return "";
}

std::vector<std::string> ConcatStrings(const ParameterSet& parameters,
                                       std::string_view group,
                                       std::string_view name) {
  std::vector<std::string> out;
  const Parameter* first = parameters.Find(group, name);
  if (first == nullptr) return out;
  out = StringList(*first);
  // Continuations NAME2, NAME3, … hold entries beyond the 255 that one parameter can index.
  for (int k = 2; k < 100; ++k) {
    const Parameter* more = parameters.Find(group, std::string(name) + std::to_string(k));
    if (more == nullptr) break;
    std::vector<std::string> extra = StringList(*more);
    out.insert(out.end(), extra.begin(), extra.end());
  }
  return out;
}

std::vector<double> ConcatDoubles(const ParameterSet& parameters,
                                  std::string_view group,
                                  std::string_view name) {
  std::vector<double> out;
  const Parameter* first = parameters.Find(group, name);
  if (first == nullptr) return out;
  out = first->AsDoubles();
  for (int k = 2; k < 100; ++k) {
    const Parameter* more = parameters.Find(group, std::string(name) + std::to_string(k));
    if (more == nullptr) break;
    std::vector<double> extra = more->AsDoubles();
    out.insert(out.end(), extra.begin(), extra.end());
  }
  return out;
}

double LengthUnitToMetres(std::string unit) {
  unit = Lower(Trim(unit));
  if (unit == "mm" || unit.rfind("millim", 0) == 0) return 1e-3;
  if (unit == "cm" || unit.rfind("centim", 0) == 0) return 1e-2;
  if (unit == "dm") return 1e-1;
  // "m", and "meters"/"metres" including the 4-character truncation "mete" (c3d.org sample 15).
  if (unit == "m" || unit.rfind("met", 0) == 0) return 1.0;
  if (unit == "in" || unit.rfind("inch", 0) == 0) return 0.0254;
  if (unit == "ft" || unit == "feet" || unit == "foot") return 0.3048;
  return 0.0;
}

std::vector<PointInfo> DecodePoints(const ParameterSet& parameters, int count, const Warner& warn) {
  std::vector<PointInfo> points(static_cast<std::size_t>(std::max(count, 0)));
  const std::vector<std::string> labels = ConcatStrings(parameters, "POINT", "LABELS");
  const std::vector<std::string> descriptions = ConcatStrings(parameters, "POINT", "DESCRIPTIONS");
  if (count > 0 && static_cast<int>(labels.size()) < count) {
    warn("POINT:LABELS",
         std::to_string(labels.size()) + " labels for " + std::to_string(count) +
             " points; the others are named uname*N");
  }
  int blank = 0;
  for (int i = 0; i < count; ++i) {
    PointInfo& info = points[i];
    info.label = i < static_cast<int>(labels.size()) ? labels[i] : "uname*" + std::to_string(i + 1);
    if (i < static_cast<int>(descriptions.size())) info.description = descriptions[i];
    info.unit = "m";
    if (info.label.empty()) ++blank;
  }
  if (blank > 0) {
    warn("POINT:LABELS", std::to_string(blank) + " blank point labels (kept blank)");
  }
  // Duplicate labels: reported, kept (FindPoint returns the first).
  {
    std::vector<std::string> sorted;
    for (const PointInfo& p : points) {
      if (!p.label.empty()) sorted.push_back(p.label);
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i) {
      if (sorted[i] == sorted[i - 1] && (i == 1 || sorted[i] != sorted[i - 2])) {
        warn("POINT:LABELS", "duplicate point label '" + sorted[i] + "'");
      }
    }
  }
  // Model outputs stored as points (Vicon Plug-in Gait): POINT:ANGLES, FORCES, MOMENTS, POWERS,
  // SCALARS, REACTIONS list the labels of each kind; their units are POINT:<KIND>_UNITS.
  struct Kind {
    const char* list;
    const char* unit_parameter;
    const char* default_unit;
    PointType type;
  };
  static constexpr Kind kKinds[] = {
      {"ANGLES", "ANGLE_UNITS", "deg", PointType::kAngle},
      {"FORCES", "FORCE_UNITS", "N", PointType::kForce},
      {"MOMENTS", "MOMENT_UNITS", "Nmm", PointType::kMoment},
      {"POWERS", "POWER_UNITS", "W", PointType::kPower},
      {"SCALARS", "SCALAR_UNITS", "", PointType::kScalar},
      {"REACTIONS", "REACTION_UNITS", "", PointType::kReaction},
  };
  for (const Kind& kind : kKinds) {
    const std::vector<std::string> members = ConcatStrings(parameters, "POINT", kind.list);
    if (members.empty()) continue;
    const std::string unit =
        parameters.FindString("POINT", kind.unit_parameter).value_or(kind.default_unit);
    for (const std::string& member : members) {
      if (member.empty()) continue;
      for (PointInfo& p : points) {
        if (p.label == member && p.type == PointType::kMarker) {
          p.type = kind.type;
          p.unit = unit;
        }
      }
    }
  }
  return points;
}

std::vector<AnalogChannel> DecodeAnalogChannels(const ParameterSet& parameters,
                                                int count,
                                                AnalogConversion* conversion,
                                                const Warner& warn) {
  const std::size_t n = static_cast<std::size_t>(std::max(count, 0));
  std::vector<AnalogChannel> channels(n);
  const std::vector<std::string> labels = ConcatStrings(parameters, "ANALOG", "LABELS");
  const std::vector<std::string> descriptions = ConcatStrings(parameters, "ANALOG", "DESCRIPTIONS");
  const std::vector<std::string> units = ConcatStrings(parameters, "ANALOG", "UNITS");
  const std::vector<double> scales = ConcatDoubles(parameters, "ANALOG", "SCALE");
  const std::vector<double> gains = ConcatDoubles(parameters, "ANALOG", "GAIN");
  // ANALOG:FORMAT "UNSIGNED" means raw samples and OFFSET are unsigned 16-bit (C3D manual,
  // "ANALOG:FORMAT"); OFFSET is then read as unsigned too.
  const std::string format = Lower(parameters.FindString("ANALOG", "FORMAT").value_or("SIGNED"));
  const bool is_unsigned = format.rfind("unsigned", 0) == 0;
  std::vector<double> offsets;
  if (const Parameter* p = parameters.Find("ANALOG", "OFFSET")) {
    if (is_unsigned && p->type == ParameterType::kInt16) {
      for (std::uint32_t v : p->AsUnsigned()) offsets.push_back(v);
      for (int k = 2; k < 100; ++k) {
        const Parameter* more = parameters.Find("ANALOG", "OFFSET" + std::to_string(k));
        if (more == nullptr) break;
        for (std::uint32_t v : more->AsUnsigned()) offsets.push_back(v);
      }
    } else {
      offsets = ConcatDoubles(parameters, "ANALOG", "OFFSET");
    }
  }
  double gen_scale = parameters.FindDouble("ANALOG", "GEN_SCALE").value_or(1.0);
  if (n > 0 && parameters.Find("ANALOG", "GEN_SCALE") == nullptr) {
    warn("ANALOG:GEN_SCALE", "missing; 1.0 assumed");
  }
  if (n > 0 && labels.size() < n) {
    warn("ANALOG:LABELS",
         std::to_string(labels.size()) + " labels for " + std::to_string(n) +
             " channels; the others are named Channel N");
  }
  if (n > 0 && scales.size() < n) {
    warn("ANALOG:SCALE",
         std::to_string(scales.size()) + " values for " + std::to_string(n) +
             " channels; 1.0 assumed for the others");
  }
  if (n > 0 && offsets.size() < n) {
    warn("ANALOG:OFFSET",
         std::to_string(offsets.size()) + " values for " + std::to_string(n) +
             " channels; 0 assumed for the others");
  }
  if (conversion != nullptr) {
    conversion->offset.assign(n, 0.0);
    conversion->coefficient.assign(n, 1.0);
    conversion->unsigned_format = is_unsigned;
  }
  for (std::size_t i = 0; i < n; ++i) {
    AnalogChannel& c = channels[i];
    c.label = i < labels.size() ? labels[i] : "Channel " + std::to_string(i + 1);
    if (i < descriptions.size()) c.description = descriptions[i];
    if (i < units.size()) c.unit = units[i];
    c.scale = i < scales.size() ? scales[i] : 1.0;
    c.offset = i < offsets.size() ? offsets[i] : 0.0;
    c.gain_code = i < gains.size() ? gains[i] : 0.0;
    if (conversion != nullptr) {
      conversion->offset[i] = c.offset;
      conversion->coefficient[i] = c.scale * gen_scale;
    }
  }
  return channels;
}

std::vector<Event> DecodeEventGroup(const ParameterSet& parameters, const Warner& warn) {
  std::vector<Event> events;
  // The group is EVENT (C3D manual); BKIN Technologies writes EVENTS (c3d.org sample 22).
  std::string group = "EVENT";
  std::optional<double> used = parameters.FindDouble(group, "USED");
  if (!used || *used <= 0) {
    group = "EVENTS";
    used = parameters.FindDouble(group, "USED");
  }
  if (!used || *used <= 0) return events;
  const std::vector<double> times = ConcatDoubles(parameters, group, "TIMES");
  std::size_t n = static_cast<std::size_t>(*used);
  // TIMES is [2, n]: minutes then seconds of each event.
  if (times.size() / 2 < n) {
    warn(group + ":TIMES",
         std::to_string(times.size() / 2) + " times for EVENT:USED = " + std::to_string(n) +
             "; only those events are read");
    n = times.size() / 2;
  }
  const std::vector<std::string> labels = ConcatStrings(parameters, group, "LABELS");
  const std::vector<std::string> contexts = ConcatStrings(parameters, group, "CONTEXTS");
  const std::vector<std::string> descriptions = ConcatStrings(parameters, group, "DESCRIPTIONS");
  const std::vector<std::string> subjects = ConcatStrings(parameters, group, "SUBJECTS");
  const std::vector<double> icons = ConcatDoubles(parameters, group, "ICON_IDS");
  const std::vector<double> flags = ConcatDoubles(parameters, group, "GENERIC_FLAGS");
  events.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Event& e = events[i];
    e.time_s = 60.0 * times[2 * i] + times[2 * i + 1];
    if (i < labels.size()) e.label = labels[i];
    if (i < contexts.size()) e.context = contexts[i];
    if (i < descriptions.size()) e.description = descriptions[i];
    if (i < subjects.size()) e.subject = subjects[i];
    if (i < icons.size()) e.icon_id = static_cast<int>(icons[i]);
    if (i < flags.size()) e.generic_flag = static_cast<int>(flags[i]);
  }
  return events;
}

std::vector<ForcePlate> DecodeForcePlates(const ParameterSet& parameters,
                                          double length_to_m,
                                          int num_analog_channels,
                                          const Warner& warn) {
  std::vector<ForcePlate> plates;
  if (parameters.FindGroup("FORCE_PLATFORM") == nullptr) return plates;
  const std::vector<double> types = ConcatDoubles(parameters, "FORCE_PLATFORM", "TYPE");
  std::optional<double> used = parameters.FindDouble("FORCE_PLATFORM", "USED");
  if (!used) {
    if (types.empty()) return plates;
    warn("FORCE_PLATFORM:USED",
         "missing; " + std::to_string(types.size()) + " plates assumed from FORCE_PLATFORM:TYPE");
    used = static_cast<double>(types.size());
  }
  if (*used <= 0) return plates;
  std::size_t n = static_cast<std::size_t>(*used);
  if (types.size() < n) {
    warn("FORCE_PLATFORM:TYPE",
         std::to_string(types.size()) + " types for FORCE_PLATFORM:USED = " + std::to_string(n) +
             "; only those plates are read");
    n = types.size();
  }
  const Parameter* corners_p = parameters.Find("FORCE_PLATFORM", "CORNERS");
  const Parameter* origin_p = parameters.Find("FORCE_PLATFORM", "ORIGIN");
  const Parameter* channel_p = parameters.Find("FORCE_PLATFORM", "CHANNEL");
  const Parameter* cal_p = parameters.Find("FORCE_PLATFORM", "CAL_MATRIX");
  const std::vector<double> corners = corners_p ? corners_p->AsDoubles() : std::vector<double>{};
  const std::vector<double> origins = origin_p ? origin_p->AsDoubles() : std::vector<double>{};
  const std::vector<double> channel = channel_p ? channel_p->AsDoubles() : std::vector<double>{};
  const std::vector<double> cal = cal_p ? cal_p->AsDoubles() : std::vector<double>{};
  const std::vector<double> zero = ConcatDoubles(parameters, "FORCE_PLATFORM", "ZERO");
  // CHANNEL is [channels per plate, plates].
  std::size_t per_plate = 0;
  if (channel_p != nullptr) {
    per_plate = channel_p->dimensions.empty() ? channel.size() : channel_p->dimensions[0];
  }
  for (std::size_t i = 0; i < n; ++i) {
    ForcePlate plate;
    plate.type = static_cast<int>(types[i]);
    const std::string tag = "FORCE_PLATFORM plate " + std::to_string(i + 1);
    // CORNERS [3, 4, n] and ORIGIN [3, n], in POINT:UNITS.
    if (corners.size() >= 12 * (i + 1)) {
      for (int c = 0; c < 4; ++c) {
        for (int k = 0; k < 3; ++k)
          plate.corners_W_m(k, c) = corners[12 * i + 3 * c + k] * length_to_m;
      }
    } else {
      warn(tag, "FORCE_PLATFORM:CORNERS has no entry for this plate (zeros used)");
    }
    if (origins.size() >= 3 * (i + 1)) {
      for (int k = 0; k < 3; ++k) plate.origin_F_m(k) = origins[3 * i + k] * length_to_m;
    } else {
      warn(tag, "FORCE_PLATFORM:ORIGIN has no entry for this plate (zeros used)");
    }
    const int wanted = plate.type == 3 ? 8 : 6;
    if (per_plate * (i + 1) <= channel.size()) {
      for (std::size_t k = 0; k < per_plate && k < static_cast<std::size_t>(wanted); ++k) {
        plate.channels.push_back(static_cast<int>(channel[per_plate * i + k]) - 1);
      }
    }
    if (plate.type >= 1 && plate.type <= 4 && static_cast<int>(plate.channels.size()) < wanted) {
      warn(tag,
           "FORCE_PLATFORM:CHANNEL gives " + std::to_string(plate.channels.size()) +
               " channels for a TYPE " + std::to_string(plate.type) + " plate, which needs " +
               std::to_string(wanted) + " (no ground reaction computed)");
    }
    for (int ch : plate.channels) {
      if (ch < 0 || ch >= num_analog_channels) {
        warn(tag,
             "FORCE_PLATFORM:CHANNEL refers to analog channel " + std::to_string(ch + 1) + " of " +
                 std::to_string(num_analog_channels) + " (no ground reaction computed)");
        break;
      }
    }
    // CAL_MATRIX [rows, columns, n], first index fastest: element (r, c) at r + rows·c.
    if (cal_p != nullptr && cal_p->dimensions.size() == 3 && cal_p->dimensions[2] > i) {
      const int rows = cal_p->dimensions[0];
      const int cols = cal_p->dimensions[1];
      const std::size_t base = static_cast<std::size_t>(rows) * cols * i;
      if (rows > 0 && cols > 0 && cal.size() >= base + static_cast<std::size_t>(rows) * cols) {
        plate.cal_matrix.resize(rows, cols);
        for (int c = 0; c < cols; ++c) {
          for (int r = 0; r < rows; ++r) plate.cal_matrix(r, c) = cal[base + r + rows * c];
        }
      }
    }
    if (zero.size() >= 2) plate.zero = {static_cast<int>(zero[0]), static_cast<int>(zero[1])};
    plates.push_back(std::move(plate));
  }
  return plates;
}

}  // namespace acro::capture::internal
