// C3D writer: Intel processor, float storage (C3D manual, "The header section", "The parameter
// section", "The 3D point and analog data section"). The Trial's parameters are written back
// byte for byte, except those that describe the layout (POINT:USED, SCALE, DATA_START, FRAMES,
// ANALOG:USED, TRIAL:ACTUAL_*_FIELD) and those that no longer match the Trial (labels, rates,
// scales, force platforms, events, subject), which are rewritten from the Trial.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <system_error>
#include <type_traits>

#include "acro/base/demand.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "c3d_internal.h"

namespace acro::capture {
namespace {

using internal::Warner;

constexpr std::size_t kBlock = 512;

// Little-endian (Intel) stores.
void PutU16(std::vector<std::uint8_t>& out, std::size_t at, std::uint16_t v) {
  out[at] = static_cast<std::uint8_t>(v & 0xFF);
  out[at + 1] = static_cast<std::uint8_t>(v >> 8);
}
void PutF32(std::vector<std::uint8_t>& out, std::size_t at, float v) {
  std::memcpy(out.data() + at, &v, 4);
}
void AppendU16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}
void AppendF32(std::vector<std::uint8_t>& out, float v) {
  std::uint8_t b[4];
  std::memcpy(b, &v, 4);
  out.insert(out.end(), b, b + 4);
}

// Replaces NAME and its continuations NAME2, NAME3, … by `strings` split in chunks of 255 entries
// (C3D manual, "POINT:LABELS2").
void SetStringList(ParameterSet& params,
                   std::string_view group,
                   std::string_view name,
                   const std::vector<std::string>& strings) {
  ParameterGroup& g = params.GetOrAddGroup(group);
  for (int k = 2; k < 100; ++k) {
    const std::string continuation = std::string(name) + std::to_string(k);
    auto it = std::find_if(g.parameters.begin(), g.parameters.end(), [&](const Parameter& p) {
      return p.name == continuation;
    });
    if (it == g.parameters.end()) break;
    g.parameters.erase(it);
  }
  std::size_t chunk = 0;
  for (std::size_t begin = 0; begin < strings.size() || begin == 0; begin += 255, ++chunk) {
    const std::size_t end = std::min(strings.size(), begin + 255);
    std::vector<std::string> part(strings.begin() + begin, strings.begin() + end);
    std::string part_name = std::string(name) + (chunk == 0 ? "" : std::to_string(chunk + 1));
    params.Set(group, MakeStringsParameter(part_name, part));
    if (strings.empty()) break;
  }
}

// Replaces NAME and its continuations by `values` in parameters of up to 255 entries each (the
// continuation scheme of POINT:LABELS2, used by readers for ANALOG:SCALE2, OFFSET2, …). With
// `pairs`, entries are two-value columns ([2, n], as EVENT:TIMES).
template <class T>
void SetNumberList(ParameterSet& params,
                   std::string_view group,
                   std::string_view name,
                   const std::vector<T>& values,
                   bool pairs = false) {
  ParameterGroup& g = params.GetOrAddGroup(group);
  for (int k = 2; k < 100; ++k) {
    const std::string continuation = std::string(name) + std::to_string(k);
    auto it = std::find_if(g.parameters.begin(), g.parameters.end(), [&](const Parameter& p) {
      return p.name == continuation;
    });
    if (it == g.parameters.end()) break;
    g.parameters.erase(it);
  }
  const std::size_t width = pairs ? 2 : 1;
  const std::size_t entries = values.size() / width;
  std::size_t chunk = 0;
  for (std::size_t begin = 0; begin < entries || begin == 0; begin += 255, ++chunk) {
    const std::size_t end = std::min(entries, begin + 255);
    std::vector<T> part(values.begin() + begin * width, values.begin() + end * width);
    const std::string part_name = std::string(name) + (chunk == 0 ? "" : std::to_string(chunk + 1));
    std::vector<std::uint8_t> dims;
    if (pairs) dims.push_back(2);
    dims.push_back(static_cast<std::uint8_t>(end - begin));
    if constexpr (std::is_same_v<T, float>) {
      params.Set(group, MakeFloatParameter(part_name, std::move(part), dims));
    } else {
      params.Set(group, MakeInt16Parameter(part_name, std::move(part), dims));
    }
    if (entries == 0) break;
  }
}

std::string UnitName(double to_m) {
  if (to_m == 1e-3) return "mm";
  if (to_m == 1e-2) return "cm";
  if (to_m == 1.0) return "m";
  if (to_m == 0.0254) return "in";
  return "";
}

bool SameEvents(const std::vector<Event>& a, const std::vector<Event>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].label != b[i].label || a[i].context != b[i].context ||
        a[i].description != b[i].description || a[i].subject != b[i].subject ||
        a[i].time_s != b[i].time_s || a[i].icon_id != b[i].icon_id ||
        a[i].generic_flag != b[i].generic_flag) {
      return false;
    }
  }
  return true;
}

bool SamePlates(const std::vector<ForcePlate>& a, const std::vector<ForcePlate>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const ForcePlate& x = a[i];
    const ForcePlate& y = b[i];
    if (x.type != y.type || x.corners_W_m != y.corners_W_m || x.origin_F_m != y.origin_F_m ||
        x.channels != y.channels || x.zero != y.zero ||
        x.cal_matrix.rows() != y.cal_matrix.rows() || x.cal_matrix.cols() != y.cal_matrix.cols() ||
        (x.cal_matrix.size() > 0 && x.cal_matrix != y.cal_matrix)) {
      return false;
    }
  }
  return true;
}

// Events the header can hold exactly: at most 18, labels of up to 4 characters, nothing else.
bool HeaderCanHold(const std::vector<Event>& events) {
  if (events.size() > 18) return false;
  for (const Event& e : events) {
    if (e.label.size() > 4 || !e.context.empty() || !e.description.empty() || !e.subject.empty() ||
        e.icon_id != 0 || e.generic_flag != 0 ||
        static_cast<double>(static_cast<float>(e.time_s)) != e.time_s) {
      return false;
    }
  }
  return true;
}

struct Layout {
  int points = 0;
  int channels = 0;
  int per_frame = 0;  // analog samples per frame
  std::int64_t frames = 0;
  double abs_scale = 1.0;
  double to_m = 1e-3;  // marker unit written
};

// ---- SyncParameters' steps, in the order they set parameters (the order new ones are written)
// ----

// POINT:USED, POINT:SCALE (float storage, the trial's |scale| or 1) and POINT:FRAMES (int16 up to
// 65535 frames, unless the stored value already says so; float beyond). Returns |scale|.
double SyncPointLayout(const Trial& trial, ParameterSet& params) {
  const int P = trial.num_points();
  const std::int64_t F = trial.num_frames;
  double abs_scale = std::abs(trial.source.point_scale);
  if (!std::isfinite(abs_scale) || abs_scale == 0) abs_scale = 1.0;
  params.Set(
      "POINT",
      MakeInt16Parameter("USED", {static_cast<std::int16_t>(static_cast<std::uint16_t>(P))}, {}));
  params.Set("POINT", MakeFloatParameter("SCALE", {static_cast<float>(-abs_scale)}, {}));
  if (F <= 65535) {
    const Parameter* frames = params.Find("POINT", "FRAMES");
    const bool same =
        frames && ((frames->type == ParameterType::kFloat && !frames->floats.empty() &&
                    frames->floats[0] == static_cast<float>(F)) ||
                   (frames->type != ParameterType::kFloat && !frames->AsUnsigned().empty() &&
                    frames->AsUnsigned()[0] == F));
    if (!same) {
      params.Set("POINT",
                 MakeInt16Parameter(
                     "FRAMES", {static_cast<std::int16_t>(static_cast<std::uint16_t>(F))}, {}));
    }
  } else {
    params.Set("POINT", MakeFloatParameter("FRAMES", {static_cast<float>(F)}, {}));
  }
  return abs_scale;
}

// Rate: POINT:RATE when the file had one or the trial is new (the header carries it as well).
void SyncPointRate(const Trial& trial, bool scratch, ParameterSet& params) {
  if (const Parameter* rate = params.Find("POINT", "RATE")) {
    const std::vector<double> v = rate->AsDoubles();
    if (v.empty() || v[0] != trial.point_rate_hz) {
      params.Set("POINT",
                 MakeFloatParameter("RATE", {static_cast<float>(trial.point_rate_hz)}, {}));
    }
  } else if (scratch) {
    params.Set("POINT", MakeFloatParameter("RATE", {static_cast<float>(trial.point_rate_hz)}, {}));
  }
}

// Units of the marker coordinates as written: the trial's (millimetres when it has none or one
// without a name); POINT:UNITS rewritten when it says otherwise. Returns the factor to metres.
double SyncPointUnits(const Trial& trial, bool scratch, ParameterSet& params) {
  double to_m = trial.source.point_units_to_m > 0 ? trial.source.point_units_to_m : 1e-3;
  if (const std::optional<std::string> units = params.FindString("POINT", "UNITS")) {
    const double file_to_m = internal::LengthUnitToMetres(*units);
    if (file_to_m != to_m && !(file_to_m == 0 && to_m == 1e-3)) {
      if (UnitName(to_m).empty()) to_m = 1e-3;
      params.Set("POINT", MakeStringParameter("UNITS", UnitName(to_m)));
    }
  } else if (scratch || !trial.source.point_units.empty()) {
    if (UnitName(to_m).empty()) to_m = 1e-3;
    params.Set("POINT", MakeStringParameter("UNITS", UnitName(to_m)));
  }
  return to_m;
}

// The lists of points of each non-marker type (POINT:ANGLES, FORCES, …), written where they have
// members or already exist.
void SetPointTypeLists(const Trial& trial, ParameterSet& params) {
  const std::pair<PointType, const char*> kinds[] = {{PointType::kAngle, "ANGLES"},
                                                     {PointType::kForce, "FORCES"},
                                                     {PointType::kMoment, "MOMENTS"},
                                                     {PointType::kPower, "POWERS"},
                                                     {PointType::kScalar, "SCALARS"},
                                                     {PointType::kReaction, "REACTIONS"}};
  for (const auto& [type, list] : kinds) {
    std::vector<std::string> members;
    for (const PointInfo& p : trial.points) {
      if (p.type == type) members.push_back(p.label);
    }
    if (!members.empty() || params.Find("POINT", list))
      SetStringList(params, "POINT", list, members);
  }
}

// Labels, descriptions and point types, each rewritten when the parameters say otherwise (labels
// and descriptions always for a new trial).
void SyncPointDescriptions(const Trial& trial, bool scratch, ParameterSet& params) {
  const int P = trial.num_points();
  // What the parameters say now.
  const Warner quiet("", nullptr);
  const std::vector<PointInfo> decoded = internal::DecodePoints(params, P, quiet);
  bool labels_same = true;
  bool descriptions_same = true;
  bool types_same = true;
  for (int i = 0; i < P; ++i) {
    labels_same = labels_same && decoded[i].label == trial.points[i].label;
    descriptions_same = descriptions_same && decoded[i].description == trial.points[i].description;
    types_same = types_same && decoded[i].type == trial.points[i].type;
  }
  // What differs, rewritten.
  if (!labels_same || (scratch && P > 0)) {
    std::vector<std::string> labels;
    for (const PointInfo& p : trial.points) labels.push_back(p.label);
    SetStringList(params, "POINT", "LABELS", labels);
  }
  if (!descriptions_same || (scratch && P > 0)) {
    std::vector<std::string> descriptions;
    for (const PointInfo& p : trial.points) descriptions.push_back(p.description);
    SetStringList(params, "POINT", "DESCRIPTIONS", descriptions);
  }
  if (!types_same) SetPointTypeLists(trial, params);
}

// ANALOG:OFFSET from the trial's channels: int16 (read unsigned when ANALOG:FORMAT is UNSIGNED)
// when every offset is a whole number in range; floats otherwise.
void SetAnalogOffsets(const Trial& trial, ParameterSet& params) {
  bool integral = true;
  std::vector<std::int16_t> ints;
  std::vector<float> floats;
  for (const AnalogChannel& c : trial.analog_channels) {
    integral =
        integral && c.offset == std::round(c.offset) && c.offset >= -32768 && c.offset <= 65535;
    ints.push_back(
        static_cast<std::int16_t>(static_cast<std::uint16_t>(static_cast<std::int32_t>(c.offset))));
    floats.push_back(static_cast<float>(c.offset));
  }
  if (integral) {
    SetNumberList(params, "ANALOG", "OFFSET", ints);
  } else {
    SetNumberList(params, "ANALOG", "OFFSET", floats);
  }
}

// ANALOG:USED, then the channels' labels, descriptions, units, scales and offsets each rewritten
// when the parameters say otherwise (all for a new trial), then ANALOG:RATE when it differs.
void SyncAnalog(const Trial& trial, int per_frame, bool scratch, ParameterSet& params) {
  const int C = trial.num_analog_channels();
  params.Set(
      "ANALOG",
      MakeInt16Parameter("USED", {static_cast<std::int16_t>(static_cast<std::uint16_t>(C))}, {}));
  // What the parameters say now.
  const Warner quiet("", nullptr);
  internal::AnalogConversion conversion;
  const std::vector<AnalogChannel> decoded =
      internal::DecodeAnalogChannels(params, C, &conversion, quiet);
  bool labels = true, descriptions = true, units = true, scales = true, offsets = true;
  for (int i = 0; i < C; ++i) {
    const AnalogChannel& want = trial.analog_channels[i];
    labels = labels && decoded[i].label == want.label;
    descriptions = descriptions && decoded[i].description == want.description;
    units = units && decoded[i].unit == want.unit;
    scales = scales && decoded[i].scale == want.scale;
    offsets = offsets && decoded[i].offset == want.offset;
  }
  // What differs, rewritten.
  const bool all = scratch && C > 0;
  std::vector<std::string> text;
  if (!labels || all) {
    for (const AnalogChannel& c : trial.analog_channels) text.push_back(c.label);
    SetStringList(params, "ANALOG", "LABELS", text);
  }
  if (!descriptions || all) {
    text.clear();
    for (const AnalogChannel& c : trial.analog_channels) text.push_back(c.description);
    SetStringList(params, "ANALOG", "DESCRIPTIONS", text);
  }
  if (!units || all) {
    text.clear();
    for (const AnalogChannel& c : trial.analog_channels) text.push_back(c.unit);
    SetStringList(params, "ANALOG", "UNITS", text);
  }
  if (!scales || all) {
    std::vector<float> v;
    for (const AnalogChannel& c : trial.analog_channels) v.push_back(static_cast<float>(c.scale));
    SetNumberList(params, "ANALOG", "SCALE", v);
    if (!params.Find("ANALOG", "GEN_SCALE"))
      params.Set("ANALOG", MakeFloatParameter("GEN_SCALE", {1.0f}, {}));
  }
  if (!offsets || all) SetAnalogOffsets(trial, params);
  // The rate: ANALOG:RATE, else the point rate times the samples per frame.
  double analog_rate = trial.point_rate_hz * per_frame;
  if (const std::optional<double> r = params.FindDouble("ANALOG", "RATE");
      r && *r > 0 && std::isfinite(*r)) {
    analog_rate = *r;
  }
  if (C > 0 && (analog_rate != trial.analog_rate_hz || scratch)) {
    params.Set("ANALOG",
               MakeFloatParameter("RATE", {static_cast<float>(trial.analog_rate_hz)}, {}));
  }
}

// The FORCE_PLATFORM group from the trial's plates: USED, TYPE, CORNERS and ORIGIN (in the written
// unit, `to_m`), CHANNEL (1-based, as many rows as the plate with most channels, at least 6),
// CAL_MATRIX (when any plate has one) and ZERO.
void SetForcePlates(const std::vector<ForcePlate>& plates, double to_m, ParameterSet& params) {
  const std::size_t n = plates.size();
  // The sizes every plate is stored with.
  std::size_t per_plate = 6;
  int cal_rows = 0, cal_cols = 0;
  for (const ForcePlate& fp : plates) {
    per_plate = std::max(per_plate, fp.channels.size());
    cal_rows = std::max<int>(cal_rows, static_cast<int>(fp.cal_matrix.rows()));
    cal_cols = std::max<int>(cal_cols, static_cast<int>(fp.cal_matrix.cols()));
  }
  // Their values.
  std::vector<std::int16_t> types;
  std::vector<float> corners, origins;
  std::vector<std::int16_t> channels(per_plate * n, 0);
  std::vector<float> cal(static_cast<std::size_t>(cal_rows) * cal_cols * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const ForcePlate& fp = plates[i];
    types.push_back(static_cast<std::int16_t>(fp.type));
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < 3; ++k)
        corners.push_back(static_cast<float>(fp.corners_W_m(k, c) / to_m));
    }
    for (int k = 0; k < 3; ++k) origins.push_back(static_cast<float>(fp.origin_F_m(k) / to_m));
    for (std::size_t k = 0; k < fp.channels.size(); ++k)
      channels[per_plate * i + k] = static_cast<std::int16_t>(fp.channels[k] + 1);
    for (int c = 0; c < fp.cal_matrix.cols(); ++c) {
      for (int r = 0; r < fp.cal_matrix.rows(); ++r) {
        cal[static_cast<std::size_t>(cal_rows) * cal_cols * i + r + cal_rows * c] =
            static_cast<float>(fp.cal_matrix(r, c));
      }
    }
  }
  // The parameters.
  const std::uint8_t nn = static_cast<std::uint8_t>(n);
  params.Set("FORCE_PLATFORM", MakeInt16Parameter("USED", {static_cast<std::int16_t>(n)}, {}));
  params.Set("FORCE_PLATFORM", MakeInt16Parameter("TYPE", types, {nn}));
  params.Set("FORCE_PLATFORM", MakeFloatParameter("CORNERS", corners, {3, 4, nn}));
  params.Set("FORCE_PLATFORM", MakeFloatParameter("ORIGIN", origins, {3, nn}));
  params.Set("FORCE_PLATFORM",
             MakeInt16Parameter("CHANNEL", channels, {static_cast<std::uint8_t>(per_plate), nn}));
  if (cal_rows > 0 && cal_cols > 0) {
    params.Set("FORCE_PLATFORM",
               MakeFloatParameter(
                   "CAL_MATRIX",
                   cal,
                   {static_cast<std::uint8_t>(cal_rows), static_cast<std::uint8_t>(cal_cols), nn}));
  }
  const std::vector<int> zero =
      n > 0 && plates[0].zero.size() >= 2 ? plates[0].zero : std::vector<int>{0, 0};
  params.Set(
      "FORCE_PLATFORM",
      MakeInt16Parameter(
          "ZERO", {static_cast<std::int16_t>(zero[0]), static_cast<std::int16_t>(zero[1])}, {2}));
}

// The EVENT group from the trial's events: USED, TIMES (minutes and seconds), LABELS, CONTEXTS,
// DESCRIPTIONS, SUBJECTS, ICON_IDS and GENERIC_FLAGS.
void SetEventGroup(const std::vector<Event>& events, ParameterSet& params) {
  const std::size_t n = events.size();
  std::vector<std::string> labels, contexts, descriptions, subjects;
  std::vector<float> times;
  std::vector<std::int16_t> icons, flags;
  for (const Event& e : events) {
    labels.push_back(e.label);
    contexts.push_back(e.context);
    descriptions.push_back(e.description);
    subjects.push_back(e.subject);
    const double minutes = std::floor(e.time_s / 60.0);
    times.push_back(static_cast<float>(minutes));
    times.push_back(static_cast<float>(e.time_s - 60.0 * minutes));
    icons.push_back(static_cast<std::int16_t>(e.icon_id));
    flags.push_back(static_cast<std::int16_t>(e.generic_flag));
  }
  params.Set("EVENT", MakeInt16Parameter("USED", {static_cast<std::int16_t>(n)}, {}));
  SetNumberList(params, "EVENT", "TIMES", times, /*pairs=*/true);
  SetStringList(params, "EVENT", "LABELS", labels);
  SetStringList(params, "EVENT", "CONTEXTS", contexts);
  SetStringList(params, "EVENT", "DESCRIPTIONS", descriptions);
  SetStringList(params, "EVENT", "SUBJECTS", subjects);
  SetNumberList(params, "EVENT", "ICON_IDS", icons);
  SetNumberList(params, "EVENT", "GENERIC_FLAGS", flags);
}

// EVENT: kept when it already describes the events; else the header alone when it can hold
// them exactly and the file had no EVENT group; else rewritten.
void SyncEvents(const Trial& trial, ParameterSet& params) {
  const Warner quiet("", nullptr);
  const std::vector<Event> decoded = internal::DecodeEventGroup(params, quiet);
  const bool has_group = params.FindGroup("EVENT") != nullptr;
  if (SameEvents(decoded, trial.events)) return;
  if (trial.events.empty()) {
    params.Set("EVENT", MakeInt16Parameter("USED", {0}, {}));
  } else if (has_group || !HeaderCanHold(trial.events)) {
    SetEventGroup(trial.events, params);
  }
}

// TRIAL:ACTUAL_START_FIELD / ACTUAL_END_FIELD beyond 65535 frames (two 16-bit halves each), kept
// in step with the frames whenever present (a cropped trial must not carry the old range).
void SyncTrialFieldRange(const Trial& trial, ParameterSet& params) {
  const std::int64_t last = trial.first_frame + trial.num_frames - 1;
  if (!(last > 65535 || trial.first_frame > 65535 || params.Find("TRIAL", "ACTUAL_START_FIELD") ||
        params.Find("TRIAL", "ACTUAL_END_FIELD")))
    return;
  const auto halves = [](std::int64_t v) {
    return std::vector<std::int16_t>{
        static_cast<std::int16_t>(static_cast<std::uint16_t>(v & 0xFFFF)),
        static_cast<std::int16_t>(static_cast<std::uint16_t>((v >> 16) & 0xFFFF))};
  };
  // Rewritten only when the value differs, in the stored shape ([2] or [1, 2]).
  const auto sync = [&](const char* name, std::int64_t value) {
    const std::vector<std::int16_t> want = halves(value);
    const Parameter* have = params.Find("TRIAL", name);
    if (have && have->type == ParameterType::kInt16 && have->int16s == want) return;
    std::vector<std::uint8_t> dims = {2};
    if (have && have->ElementCount() == 2 && !have->dimensions.empty()) dims = have->dimensions;
    params.Set("TRIAL", MakeInt16Parameter(name, want, dims));
  };
  sync("ACTUAL_START_FIELD", trial.first_frame);
  sync("ACTUAL_END_FIELD", last);
}

// SUBJECTS:NAMES first entry.
void SyncSubject(const Trial& trial, ParameterSet& params) {
  std::vector<std::string> names = internal::ConcatStrings(params, "SUBJECTS", "NAMES");
  const std::string current = names.empty() ? std::string() : names.front();
  if (current != trial.subject_name) {
    if (names.empty()) names.push_back(trial.subject_name);
    names.front() = trial.subject_name;
    SetStringList(params, "SUBJECTS", "NAMES", names);
  }
}

// Brings the parameters in line with the Trial (see the file comment).
ParameterSet SyncParameters(const Trial& trial, Layout* layout) {
  ParameterSet params = trial.parameters;
  // A trial that did not come from a C3D file gets the full set of descriptive parameters.
  const bool scratch = trial.parameters.groups().empty() && trial.source.format != "C3D";
  const int C = trial.num_analog_channels();

  // POINT: layout, rate, units, then what describes the points.
  layout->abs_scale = SyncPointLayout(trial, params);
  SyncPointRate(trial, scratch, params);
  layout->to_m = SyncPointUnits(trial, scratch, params);
  SyncPointDescriptions(trial, scratch, params);

  // ANALOG.
  layout->channels = C;
  layout->per_frame = C > 0 ? trial.analog_samples_per_frame() : 0;
  if (C > 0 || params.FindGroup("ANALOG")) SyncAnalog(trial, layout->per_frame, scratch, params);

  // FORCE_PLATFORM: rewritten when the plates it describes are not the trial's.
  const Warner quiet("", nullptr);
  if (!SamePlates(internal::DecodeForcePlates(params, layout->to_m, C, quiet), trial.force_plates))
    SetForcePlates(trial.force_plates, layout->to_m, params);

  // EVENT, TRIAL's frame range, SUBJECTS.
  SyncEvents(trial, params);
  SyncTrialFieldRange(trial, params);
  SyncSubject(trial, params);

  layout->points = trial.num_points();
  layout->frames = trial.num_frames;
  // DATA_START is set by the caller once the parameter section size is known.
  params.Set("POINT", MakeInt16Parameter("DATA_START", {0}, {}));
  return params;
}

// One parameter section (C3D manual, "The parameter section"): records of groups then their
// parameters, the last record with offset 0, padded to whole blocks.
std::vector<std::uint8_t> SerializeParameters(const ParameterSet& params) {
  std::vector<std::uint8_t> out = {0x01, 0x50, 0x00, 84};
  // Group ids must be 1..127 and unique: renumber only when they are not.
  std::vector<int> ids;
  for (const ParameterGroup& g : params.groups()) ids.push_back(g.id);
  bool valid = true;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    valid =
        valid && ids[i] >= 1 && ids[i] <= 127 && std::count(ids.begin(), ids.end(), ids[i]) == 1;
  }
  if (!valid) {
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i) + 1;
  }
  ACRO_DEMAND(ids.size() <= 127);
  std::size_t last_offset_at = 0;
  const auto name_bytes = [](const std::string& name, bool locked, std::vector<std::uint8_t>& o) {
    const std::size_t n = std::min<std::size_t>(name.size(), 127);
    ACRO_DEMAND(n > 0);
    o.push_back(static_cast<std::uint8_t>(
        static_cast<std::int8_t>(locked ? -static_cast<int>(n) : static_cast<int>(n))));
    return n;
  };
  const auto description = [](const std::string& text, std::vector<std::uint8_t>& o) {
    const std::size_t n = std::min<std::size_t>(text.size(), 255);
    o.push_back(static_cast<std::uint8_t>(n));
    o.insert(o.end(), text.begin(), text.begin() + n);
  };
  for (std::size_t gi = 0; gi < params.groups().size(); ++gi) {
    const ParameterGroup& g = params.groups()[gi];
    const int id = ids[gi];
    {
      const std::size_t n = name_bytes(g.name, g.locked, out);
      out.push_back(static_cast<std::uint8_t>(static_cast<std::int8_t>(-id)));
      out.insert(out.end(), g.name.begin(), g.name.begin() + n);
      const std::size_t offset_at = out.size();
      AppendU16(out, 0);
      description(g.description, out);
      PutU16(out, offset_at, static_cast<std::uint16_t>(out.size() - offset_at));
      last_offset_at = offset_at;
    }
    for (const Parameter& p : g.parameters) {
      const std::size_t n = name_bytes(p.name, p.locked, out);
      out.push_back(static_cast<std::uint8_t>(id));
      out.insert(out.end(), p.name.begin(), p.name.begin() + n);
      const std::size_t offset_at = out.size();
      AppendU16(out, 0);
      out.push_back(static_cast<std::uint8_t>(static_cast<std::int8_t>(static_cast<int>(p.type))));
      out.push_back(static_cast<std::uint8_t>(p.dimensions.size()));
      out.insert(out.end(), p.dimensions.begin(), p.dimensions.end());
      const std::size_t count = p.ElementCount();
      switch (p.type) {
        case ParameterType::kChar:
          ACRO_DEMAND(p.chars.size() == count);
          out.insert(out.end(), p.chars.begin(), p.chars.end());
          break;
        case ParameterType::kByte:
          ACRO_DEMAND(p.bytes.size() == count);
          out.insert(out.end(), p.bytes.begin(), p.bytes.end());
          break;
        case ParameterType::kInt16:
          ACRO_DEMAND(p.int16s.size() == count);
          for (std::int16_t v : p.int16s) AppendU16(out, static_cast<std::uint16_t>(v));
          break;
        case ParameterType::kFloat:
          ACRO_DEMAND(p.floats.size() == count);
          for (float v : p.floats) AppendF32(out, v);
          break;
      }
      description(p.description, out);
      const std::size_t size = out.size() - offset_at;
      ACRO_DEMAND(size <= 0xFFFF);
      PutU16(out, offset_at, static_cast<std::uint16_t>(size));
      last_offset_at = offset_at;
    }
  }
  if (last_offset_at != 0) PutU16(out, last_offset_at, 0);
  // Terminator (a zero name length), then whole blocks.
  out.push_back(0);
  out.push_back(0);
  out.resize((out.size() + kBlock - 1) / kBlock * kBlock, 0);
  out[2] = static_cast<std::uint8_t>(std::min<std::size_t>(out.size() / kBlock, 255));
  return out;
}

// ---- WriteC3dToMemory's steps ----

// Analog samples per frame without analog frames (no channels, or no frames): from the rates, so
// that the analog rate survives the round trip.
void ChooseSamplesPerFrameWithoutAnalog(const Trial& trial, Layout& layout) {
  if ((layout.channels == 0 || trial.num_frames == 0) && trial.point_rate_hz > 0) {
    // The reader reports point rate × max(1, samples per frame) without channels: at least 1.
    const double ratio = std::round(trial.analog_rate_hz / trial.point_rate_hz);
    layout.per_frame =
        static_cast<int>(std::clamp(ratio, layout.channels == 0 ? 1.0 : 0.0, 65535.0));
  }
}

// The header (C3D manual, "The header section") into the first block of `out`.
void WriteHeader(const Trial& trial,
                 const Layout& layout,
                 std::size_t data_block,
                 std::vector<std::uint8_t>& out) {
  const int P = trial.num_points();
  const std::int64_t last = trial.first_frame + std::int64_t(trial.num_frames) - 1;
  out[0] = 2;
  out[1] = 0x50;
  PutU16(out, 2, static_cast<std::uint16_t>(std::min(P, 65535)));
  PutU16(out,
         4,
         static_cast<std::uint16_t>(
             std::min<std::int64_t>(std::int64_t(layout.channels) * layout.per_frame, 65535)));
  PutU16(out, 6, static_cast<std::uint16_t>(std::clamp<std::int64_t>(trial.first_frame, 0, 65535)));
  PutU16(out, 8, static_cast<std::uint16_t>(std::clamp<std::int64_t>(last, 0, 65535)));
  PutU16(out,
         10,
         static_cast<std::uint16_t>(std::clamp(trial.source.max_interpolation_gap, 0, 65535)));
  PutF32(out, 12, static_cast<float>(-layout.abs_scale));
  PutU16(out, 16, static_cast<std::uint16_t>(data_block));
  PutU16(out, 18, static_cast<std::uint16_t>(layout.per_frame));
  PutF32(out, 20, static_cast<float>(trial.point_rate_hz));
  // The event block: up to 18 events with 4-character labels.
  const std::size_t header_events = std::min<std::size_t>(trial.events.size(), 18);
  PutU16(out, 298, 12345);
  PutU16(out, 300, static_cast<std::uint16_t>(header_events));
  for (std::size_t i = 0; i < header_events; ++i) {
    const Event& e = trial.events[i];
    PutF32(out, 304 + 4 * i, static_cast<float>(e.time_s));
    out[376 + i] = e.displayed ? 1 : 0;
    for (std::size_t k = 0; k < 4; ++k)
      out[396 + 4 * i + k] = k < e.label.size() ? e.label[k] : ' ';
  }
}

// The data section, appended to `out`: per frame, points (x, y, z, residual word) then analog
// samples, all float; markers in the written unit, analog samples back to raw values through
// the parameters' conversion.
void WriteFrames(const Trial& trial,
                 const ParameterSet& params,
                 const Layout& layout,
                 std::size_t frame_floats,
                 std::vector<std::uint8_t>& out) {
  const int P = trial.num_points();
  const std::int64_t F = trial.num_frames;
  // The conversions.
  internal::AnalogConversion conversion;
  internal::DecodeAnalogChannels(params, layout.channels, &conversion, Warner("", nullptr));
  std::vector<double> point_factor(P, 1.0);
  for (int p = 0; p < P; ++p) {
    if (trial.points[p].type == PointType::kMarker) point_factor[p] = 1.0 / layout.to_m;
  }
  const std::size_t data_at = out.size();
  out.resize(data_at + frame_floats * 4 * F);
  std::uint8_t* dst = out.data() + data_at;
  const bool has_residuals = trial.residuals.size() > 0;
  const bool has_masks = trial.camera_masks.size() > 0;
  // Files in which every residual word is −1 although the coordinates are real (SIMI, c3d.org
  // sample 16) are written the same way, so they read back the same.
  const bool keep_invalid_words =
      has_residuals && trial.residuals.size() > 0 && (trial.residuals < 0).all();
  // Frame by frame.
  std::vector<float> frame(frame_floats);
  for (std::int64_t f = 0; f < F; ++f) {
    float* v = frame.data();
    for (int p = 0; p < P; ++p) {
      const auto x = trial.positions.col(f * P + p);
      const float residual = has_residuals ? trial.residuals(p, f) : 0.0f;
      if (std::isnan(x(0)) || std::isnan(x(1)) || std::isnan(x(2))) {
        v[0] = v[1] = v[2] = 0.0f;
        v[3] = -1.0f;
      } else {
        v[0] = static_cast<float>(x(0) * point_factor[p]);
        v[1] = static_cast<float>(x(1) * point_factor[p]);
        v[2] = static_cast<float>(x(2) * point_factor[p]);
        if (residual < 0 && keep_invalid_words) {
          v[3] = -1.0f;
        } else if (residual < 0) {
          // A coordinate where the residual says "invalid" was filled in by code (a gap filled):
          // written valid, residual 0 ("computed").
          v[3] = 0.0f;
        } else {
          const int r =
              std::clamp(static_cast<int>(std::lround(residual / layout.abs_scale)), 0, 255);
          const int mask = has_masks ? (trial.camera_masks(p, f) & 0x7F) : 0;
          v[3] = static_cast<float>((mask << 8) | r);
        }
      }
      v += 4;
    }
    for (int s = 0; s < layout.per_frame; ++s) {
      const std::int64_t column = f * layout.per_frame + s;
      for (int c = 0; c < layout.channels; ++c) {
        const double coefficient = conversion.coefficient[c];
        const double value = trial.analog(c, column);
        *v++ = static_cast<float>(coefficient != 0 ? value / coefficient + conversion.offset[c]
                                                   : conversion.offset[c]);
      }
    }
    // (A trial with no point and no analog channel has empty frames: memcpy is not called with
    // the null pointers they hold, undefined even for 0 bytes.)
    if (frame_floats > 0) std::memcpy(dst, frame.data(), frame_floats * 4);
    dst += frame_floats * 4;
  }
}

}  // namespace

std::vector<std::uint8_t> WriteC3dToMemory(const Trial& trial) {
  const int P = trial.num_points();
  const std::int64_t F = trial.num_frames;
  ACRO_DEMAND(F >= 0);
  ACRO_DEMAND(trial.positions.cols() == F * P);
  ACRO_DEMAND(trial.residuals.size() == 0 ||
              (trial.residuals.rows() == P && trial.residuals.cols() == F));
  ACRO_DEMAND(trial.camera_masks.size() == 0 ||
              (trial.camera_masks.rows() == P && trial.camera_masks.cols() == F));
  ACRO_DEMAND(trial.analog.rows() == trial.num_analog_channels());
  ACRO_DEMAND(F == 0 || trial.analog.cols() % F == 0);

  // The parameters in line with the trial, and the layout they give.
  Layout layout;
  ParameterSet params = SyncParameters(trial, &layout);
  ChooseSamplesPerFrameWithoutAnalog(trial, layout);

  // The parameter section's size does not depend on DATA_START's value: serialise once to size it.
  std::size_t param_bytes = SerializeParameters(params).size();
  const std::size_t data_block = 2 + param_bytes / kBlock;
  ACRO_DEMAND(data_block <= 0xFFFF);
  params.Set(
      "POINT",
      MakeInt16Parameter(
          "DATA_START", {static_cast<std::int16_t>(static_cast<std::uint16_t>(data_block))}, {}));
  const std::vector<std::uint8_t> section = SerializeParameters(params);
  ACRO_DEMAND(section.size() == param_bytes);

  // Header, parameters, data.
  const std::size_t frame_floats =
      std::size_t(P) * 4 + std::size_t(layout.channels) * layout.per_frame;
  std::vector<std::uint8_t> out(kBlock, 0);
  out.reserve(kBlock + section.size() + frame_floats * 4 * F);
  WriteHeader(trial, layout, data_block, out);
  out.insert(out.end(), section.begin(), section.end());
  WriteFrames(trial, params, layout, frame_floats, out);
  return out;
}

void WriteC3d(const Trial& trial, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = WriteC3dToMemory(trial);
  // A unique temporary name beside the target, renamed when complete (two writers of one file at
  // once never splice), and removed if the program is interrupted.
  WriteFileAtomically(path,
                      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace acro::capture
