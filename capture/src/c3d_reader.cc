// C3D reader (C3D manual, Motion Lab Systems, "The C3D File Format User Guide": chapters "The
// header section", "The parameter section", "The 3D point and analog data section").

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "acro/capture/force_plate.h"
#include "c3d_internal.h"

namespace acro::capture {
namespace {

using internal::LoadF32;
using internal::LoadI16;
using internal::LoadU16;
using internal::Processor;
using internal::Warner;

constexpr std::size_t kBlock = 512;

// Values of the header (C3D manual, "The header section"), 16-bit words numbered from 1.
struct Header {
  int parameter_block = 0;             // word 1, low byte
  std::uint16_t num_points = 0;        // word 2
  std::uint16_t analog_words = 0;      // word 3: analog samples per frame × channels
  std::uint16_t first_frame = 0;       // word 4
  std::uint16_t last_frame = 0;        // word 5
  std::uint16_t max_gap = 0;           // word 6
  float scale = 0;                     // words 7–8
  std::uint16_t data_start = 0;        // word 9 (block number)
  std::uint16_t analog_per_frame = 0;  // word 10
  float frame_rate = 0;                // words 11–12
  // Event block: word 150 key 12345, word 151 count, words 153–188 times, 189–197 display flags,
  // 199–234 four-character labels.
  std::uint16_t event_key = 0;
  std::uint16_t num_events = 0;
};

// The first and the number of frames the file declares.
struct FrameRange {
  std::int64_t first = 0;
  std::int64_t frames = 0;
};

// The start of one parameter record, as its first bytes and its offset describe it.
struct ParameterRecord {
  std::size_t pos = 0;             // its first byte
  int name_length_signed = 0;      // negative = locked
  int group_id = 0;                // negative for a group, the group's id for a parameter
  std::string name;                // the group's or the parameter's
  std::size_t offset_at = 0;       // the offset word
  std::uint16_t offset = 0;        // from the offset word to the next record
  bool last = false;               // offset 0
  std::size_t next = 0;            // where the offset says the next record starts
  bool offset_past_limit = false;  // next lies past the parameter section
  std::size_t end = 0;             // where the record's content must end
};

// A parameter read before its group is known.
struct PendingParameter {
  int group_id;
  Parameter parameter;
};

class C3dReader {
 public:
  C3dReader(std::span<const std::uint8_t> bytes,
            const std::string& name,
            const C3dReadOptions& options)
      : bytes_(bytes), name_(name), options_(options), warn_(name, &trial_.warnings) {}

  Trial Read();

 private:
  [[noreturn]] void Fail(const std::string& where, const std::string& problem) const {
    throw InputError(name_, where, problem);
  }

  void DetectProcessor();
  void ReadHeader();

  // The parameter section, record by record.
  void ReadParameters();
  std::optional<ParameterRecord> ReadRecordStart(std::size_t pos) const;
  void WarnBeyondDeclaredSection(const ParameterRecord& record) const;
  std::string ReadDescription(std::size_t at,
                              const ParameterRecord& record,
                              const std::string& who) const;
  std::size_t ReadGroupRecord(const ParameterRecord& record,
                              std::vector<ParameterGroup>& groups) const;
  std::optional<std::size_t> ReadParameterRecord(const ParameterRecord& record,
                                                 const std::vector<ParameterGroup>& groups,
                                                 std::vector<PendingParameter>& pending) const;
  void DecodeParameterValues(const std::uint8_t* d, std::size_t count, Parameter& p) const;
  std::optional<std::size_t> FollowRecordOffset(const ParameterRecord& record,
                                                std::size_t natural_end) const;
  void AttachParametersToGroups(std::vector<PendingParameter>& pending,
                                std::vector<ParameterGroup>& groups) const;

  // The data section: its layout, the rates, the points, then the samples.
  void ReadData();
  std::vector<int> PointCountCandidates() const;
  double ReadPointScale() const;
  std::vector<int> AnalogLayoutCandidates();
  FrameRange CountFrames() const;
  std::size_t FindDataStart(std::int64_t frames) const;
  std::size_t FrameBytes(int points, int channels, std::size_t word) const;
  std::int64_t ChooseDataLayout(const std::vector<int>& point_candidates,
                                const std::vector<int>& channel_candidates,
                                std::size_t word,
                                std::size_t data_start,
                                std::int64_t frames);
  void ReadRates();
  double DescribePoints(bool is_float, double scale, const std::optional<std::string>& units);
  void DecodeData(const std::uint8_t* data,
                  bool is_float,
                  const internal::AnalogConversion& conversion,
                  const std::vector<double>& point_factor,
                  double scale);
  void MarkInvalidSamples();
  double GuessMissingUnits();
  template <Processor P, bool kFloat>
  void Decode(const std::uint8_t* data,
              const internal::AnalogConversion& conversion,
              const std::vector<double>& point_factor,
              double scale);
  void ReadEvents();

  std::span<const std::uint8_t> bytes_;
  std::string name_;
  C3dReadOptions options_;
  Trial trial_;
  Warner warn_;
  Processor processor_ = Processor::kIntel;
  Header header_;
  std::size_t parameter_start_ = 0;
  std::size_t data_start_byte_ = 0;
  // Where the parameter records must end, and where the declared parameter section ends.
  std::size_t parameter_limit_ = 0;
  std::size_t parameter_declared_end_ = 0;
  // Layout chosen for the data section.
  int num_points_ = 0;
  int num_channels_ = 0;
  int analog_per_frame_ = 0;
  std::int64_t num_frames_ = 0;
  std::int64_t invalid_samples_ = 0;
};

// The processor type byte of the parameter section decides how every number is stored. An invalid
// byte is reported, and the type is guessed from which decoding gives a plausible frame rate.
void C3dReader::DetectProcessor() {
  const std::uint8_t type = bytes_[parameter_start_ + 3];
  if (type == 84 || type == 85 || type == 86) {
    processor_ = static_cast<Processor>(type);
    return;
  }
  const std::uint8_t* rate = bytes_.data() + 20;
  processor_ = Processor::kIntel;
  for (Processor p : {Processor::kIntel, Processor::kDec, Processor::kMips}) {
    const float r = LoadF32(rate, p);
    if (std::isfinite(r) && r > 0.01f && r < 1e6f) {
      processor_ = p;
      break;
    }
  }
  warn_(AtByte(static_cast<long long>(parameter_start_ + 3)),
        "processor type byte is " + std::to_string(type) + " (expected 84, 85 or 86); " +
            internal::ProcessorName(processor_) + " assumed from the header frame rate");
}

void C3dReader::ReadHeader() {
  const std::uint8_t* h = bytes_.data();
  Header& hd = header_;
  hd.parameter_block = h[0];
  hd.num_points = LoadU16(h + 2, processor_);
  hd.analog_words = LoadU16(h + 4, processor_);
  hd.first_frame = LoadU16(h + 6, processor_);
  hd.last_frame = LoadU16(h + 8, processor_);
  hd.max_gap = LoadU16(h + 10, processor_);
  hd.scale = LoadF32(h + 12, processor_);
  hd.data_start = LoadU16(h + 16, processor_);
  hd.analog_per_frame = LoadU16(h + 18, processor_);
  hd.frame_rate = LoadF32(h + 20, processor_);
  hd.event_key = LoadU16(h + 298, processor_);
  hd.num_events = LoadU16(h + 300, processor_);
}

// The parameter section (C3D manual, "The parameter section"): a 4-byte block header (byte 3 =
// processor type), then records. Each record: name length (int8, negative = locked), group id
// (int8, negative for a group, the group's id for a parameter), the name, a 16-bit offset from the
// offset word to the next record (0 = last record), then for a group its description, for a
// parameter its type (−1 char, 1 byte, 2 int16, 4 float), dimension count, dimensions, data and
// description. A name length of 0 ends the section.
void C3dReader::ReadParameters() {
  std::vector<ParameterGroup> groups;
  std::vector<PendingParameter> pending;

  // Records must end before the data section when it follows the parameters, else at the file end.
  parameter_declared_end_ =
      parameter_start_ + kBlock * static_cast<std::size_t>(bytes_[parameter_start_ + 2]);
  parameter_limit_ = bytes_.size();
  if (data_start_byte_ > parameter_start_ && data_start_byte_ <= bytes_.size()) {
    parameter_limit_ = data_start_byte_;
  }

  // The records, one after the other, until the terminating record.
  bool warned_beyond_declared = false;
  std::size_t pos = parameter_start_ + 4;
  while (true) {
    const std::optional<ParameterRecord> record = ReadRecordStart(pos);
    if (!record) break;
    // A record beyond the declared section is read anyway, with one warning for the first.
    if (!warned_beyond_declared && record->end > parameter_declared_end_ && !record->last) {
      warned_beyond_declared = true;
      WarnBeyondDeclaredSection(*record);
    }
    // Its content: a group, or a parameter (skipped when its storage type is unknown).
    std::size_t natural_end = 0;
    if (record->group_id < 0) {
      natural_end = ReadGroupRecord(*record, groups);
    } else {
      const std::optional<std::size_t> end = ReadParameterRecord(*record, groups, pending);
      if (!end) {
        pos = record->next;
        continue;
      }
      natural_end = *end;
    }
    // On to the next record.
    const std::optional<std::size_t> next = FollowRecordOffset(*record, natural_end);
    if (!next) break;
    pos = *next;
  }

  AttachParametersToGroups(pending, groups);
  trial_.parameters.mutable_groups() = std::move(groups);
}

// The start of the record at `pos`: name, group id and offset; none where the section ends (a
// terminating record, or no room for one: warned).
std::optional<ParameterRecord> C3dReader::ReadRecordStart(std::size_t pos) const {
  const std::size_t limit = parameter_limit_;
  if (pos + 2 > limit) {
    warn_(AtByte(static_cast<long long>(pos)),
          "parameter section ends without a terminating record");
    return std::nullopt;
  }
  ParameterRecord r;
  r.pos = pos;
  r.name_length_signed = static_cast<std::int8_t>(bytes_[pos]);
  r.group_id = static_cast<std::int8_t>(bytes_[pos + 1]);
  if (r.name_length_signed == 0 || r.group_id == 0) return std::nullopt;  // end of the section
  const std::size_t name_length = static_cast<std::size_t>(std::abs(r.name_length_signed));
  r.offset_at = pos + 2 + name_length;
  if (r.offset_at + 2 > limit) {
    Fail(AtByte(static_cast<long long>(pos)),
         "parameter record runs past the end of the parameter section (byte " +
             std::to_string(limit) + ")");
  }
  r.name.assign(reinterpret_cast<const char*>(bytes_.data() + pos + 2), name_length);
  r.offset = LoadU16(bytes_.data() + r.offset_at, processor_);
  r.last = r.offset == 0;
  r.next = r.offset_at + r.offset;
  r.offset_past_limit = !r.last && r.next > limit;
  // Some writers store single offsets in the wrong byte order (c3d.org sample 2, SGI files):
  // the record's own content then says where it ends (checked once it is decoded).
  r.end = r.last ? limit : std::min(r.next, limit);
  return r;
}

void C3dReader::WarnBeyondDeclaredSection(const ParameterRecord& record) const {
  warn_("record '" + record.name + "' at " + AtByte(static_cast<long long>(record.pos)),
        "lies beyond the declared parameter section (" +
            std::to_string(bytes_[parameter_start_ + 2]) + " blocks ending at byte " +
            std::to_string(parameter_declared_end_) + "); read anyway");
}

// A description: a length byte then the text, both inside the record (cut at its end).
std::string C3dReader::ReadDescription(std::size_t at,
                                       const ParameterRecord& record,
                                       const std::string& who) const {
  if (at >= record.end) {
    if (!record.last)
      warn_(who,
            "record has no description length byte (record ends at " +
                AtByte(static_cast<long long>(record.end)) + ")");
    return std::string();
  }
  std::size_t length = bytes_[at];
  if (at + 1 + length > record.end) {
    warn_(who,
          "description of " + std::to_string(length) + " bytes runs past the record end at " +
              AtByte(static_cast<long long>(record.end)) + "; cut");
    length = record.end - at - 1;
  }
  return std::string(reinterpret_cast<const char*>(bytes_.data() + at + 1), length);
}

// A group record: its id, name, lock and description. Returns where its content ends.
std::size_t C3dReader::ReadGroupRecord(const ParameterRecord& record,
                                       std::vector<ParameterGroup>& groups) const {
  ParameterGroup group;
  group.id = -record.group_id;
  group.name = record.name;
  group.locked = record.name_length_signed < 0;
  group.description = ReadDescription(record.offset_at + 2, record, "group " + record.name);
  const std::size_t natural_end = record.offset_at + 3 + group.description.size();
  groups.push_back(std::move(group));
  return natural_end;
}

// A parameter record: type, dimensions, values and description, kept in `pending` until the
// groups are known. Returns where its content ends; none when its storage type is unknown and
// the record is skipped.
std::optional<std::size_t> C3dReader::ReadParameterRecord(
    const ParameterRecord& record,
    const std::vector<ParameterGroup>& groups,
    std::vector<PendingParameter>& pending) const {
  const std::size_t limit = parameter_limit_;
  const std::size_t offset_at = record.offset_at;
  Parameter p;
  p.name = record.name;
  p.locked = record.name_length_signed < 0;
  // Name the parameter GROUP:NAME when its group record has been seen already.
  std::string who =
      "parameter " + record.name + " (group id " + std::to_string(record.group_id) + ")";
  for (const ParameterGroup& g : groups) {
    if (g.id == record.group_id) who = g.name + ":" + record.name;
  }
  // Storage type and dimensions.
  if (offset_at + 4 > limit) Fail(AtByte(static_cast<long long>(offset_at)), who + " is cut short");
  const int type = static_cast<std::int8_t>(bytes_[offset_at + 2]);
  const std::size_t num_dims = bytes_[offset_at + 3];
  if (type != -1 && type != 1 && type != 2 && type != 4) {
    // Unknown storage: skip the record when its offset leads on, else give up.
    if (record.last || record.next <= record.pos || record.next > limit) {
      Fail(AtByte(static_cast<long long>(offset_at + 2)),
           who + " has type " + std::to_string(type) + " (expected -1, 1, 2 or 4)");
    }
    warn_(who, "has type " + std::to_string(type) + " (expected -1, 1, 2 or 4); skipped");
    return std::nullopt;
  }
  p.type = static_cast<ParameterType>(type);
  if (offset_at + 4 + num_dims > limit) {
    Fail(AtByte(static_cast<long long>(offset_at + 3)),
         who + " dimensions run past the parameter section");
  }
  p.dimensions.assign(bytes_.begin() + offset_at + 4, bytes_.begin() + offset_at + 4 + num_dims);
  const std::size_t element_size = static_cast<std::size_t>(std::abs(type));
  // Element count, saturating (up to 255 dimensions of up to 255 each).
  std::size_t count = 1;
  for (std::uint8_t d : p.dimensions) count = count > (std::size_t(1) << 40) ? count : count * d;
  const std::size_t data_at = offset_at + 4 + num_dims;
  // Check the count against the bytes left before anything is allocated.
  if (count > (limit - data_at) / element_size) {
    Fail(AtByte(static_cast<long long>(data_at)),
         who + " declares " + std::to_string(count) + " values of " + std::to_string(element_size) +
             " bytes, more than the " + std::to_string(limit - data_at) +
             " bytes left in the parameter section" +
             (limit == data_start_byte_ ? " before the data section at byte " +
                                              std::to_string(limit) + " (bad data first block)"
                                        : ""));
  }
  const std::size_t data_end = data_at + count * element_size;
  if (!record.last && data_end > record.end) {
    warn_(who,
          "data (" + std::to_string(count * element_size) + " bytes) overrun the next record at " +
              AtByte(static_cast<long long>(record.end)) +
              " given by the record offset; read as declared");
  }
  // The values, then the description after them.
  DecodeParameterValues(bytes_.data() + data_at, count, p);
  p.description =
      data_end < record.end || record.last ? ReadDescription(data_end, record, who) : std::string();
  if (!record.last && data_end >= record.end && data_end == record.end) {
    warn_(who,
          "record has no description length byte (record ends at " +
              AtByte(static_cast<long long>(record.end)) + ")");
  }
  const std::size_t natural_end = data_end + 1 + p.description.size();
  pending.push_back({record.group_id, std::move(p)});
  return natural_end;
}

// `count` values of p's type from `d`.
void C3dReader::DecodeParameterValues(const std::uint8_t* d,
                                      std::size_t count,
                                      Parameter& p) const {
  switch (p.type) {
    case ParameterType::kChar:
      p.chars.assign(reinterpret_cast<const char*>(d), reinterpret_cast<const char*>(d) + count);
      break;
    case ParameterType::kByte:
      p.bytes.assign(d, d + count);
      break;
    case ParameterType::kInt16:
      p.int16s.resize(count);
      for (std::size_t i = 0; i < count; ++i) p.int16s[i] = LoadI16(d + 2 * i, processor_);
      break;
    case ParameterType::kFloat:
      p.floats.resize(count);
      for (std::size_t i = 0; i < count; ++i) p.floats[i] = LoadF32(d + 4 * i, processor_);
      break;
  }
}

// Where the record after this one starts: at its offset, or, where the offset points past the
// section or backwards, after this record's content (its natural end). None after the last
// record, or when even the content would lead backwards.
std::optional<std::size_t> C3dReader::FollowRecordOffset(const ParameterRecord& record,
                                                         std::size_t natural_end) const {
  const std::size_t limit = parameter_limit_;
  if (record.last) return std::nullopt;
  std::size_t next = record.next;
  if (record.offset_past_limit) {
    if (natural_end > limit) {
      Fail(AtByte(static_cast<long long>(record.pos)),
           "record '" + record.name + "' extends to byte " + std::to_string(record.next) +
               ", past the end of the parameter section at byte " + std::to_string(limit) +
               (limit == data_start_byte_ ? " where the data section starts (bad data first block)"
                                          : ""));
    }
    warn_(AtByte(static_cast<long long>(record.offset_at)),
          "record '" + record.name + "' has offset " + std::to_string(record.offset) +
              " pointing past the parameter section (byte " + std::to_string(limit) +
              "); continuing after its content at byte " + std::to_string(natural_end));
    next = natural_end;
  }
  if (next <= record.pos) {
    // A backward offset would loop: continue after the record's own content instead.
    warn_(AtByte(static_cast<long long>(record.offset_at)),
          "record '" + record.name + "' has offset " + std::to_string(record.offset) +
              " pointing backwards; continuing after its content at byte " +
              std::to_string(natural_end));
    next = natural_end;
    if (next <= record.pos) return std::nullopt;
  }
  return next;
}

// Attaches parameters to their groups (records may come in any order); a parameter whose group
// has no record gets a group of its own, UNNAMED<id>.
void C3dReader::AttachParametersToGroups(std::vector<PendingParameter>& pending,
                                         std::vector<ParameterGroup>& groups) const {
  for (PendingParameter& item : pending) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const ParameterGroup& g) {
      return g.id == item.group_id;
    });
    if (it == groups.end()) {
      ParameterGroup orphan;
      orphan.id = item.group_id;
      orphan.name = "UNNAMED" + std::to_string(item.group_id);
      warn_("parameter " + item.parameter.name,
            "refers to group id " + std::to_string(item.group_id) +
                ", which has no group record; kept in group " + orphan.name);
      groups.push_back(std::move(orphan));
      it = groups.end() - 1;
    }
    it->parameters.push_back(std::move(item.parameter));
  }
}

Trial C3dReader::Read() {
  trial_.source.path = name_;
  trial_.source.format = "C3D";
  if (bytes_.empty()) Fail("", "file is empty (0 bytes)");
  if (bytes_.size() < kBlock) {
    Fail("",
         "file holds " + std::to_string(bytes_.size()) +
             " bytes, less than the 512-byte C3D header");
  }
  if (bytes_[1] != 0x50) {
    Fail(AtByte(1),
         fmt::format("not a C3D file: header key byte is 0x{:02X} (expected 0x50)", bytes_[1]));
  }
  if (bytes_[0] == 0) Fail(AtByte(0), "parameter section block number is 0");
  parameter_start_ = (std::size_t(bytes_[0]) - 1) * kBlock;
  if (parameter_start_ + 4 > bytes_.size()) {
    Fail(AtByte(0),
         "parameter section block " + std::to_string(bytes_[0]) +
             " lies beyond the end of the file (" + std::to_string(bytes_.size()) + " bytes)");
  }
  DetectProcessor();
  ReadHeader();
  data_start_byte_ = header_.data_start > 0 ? (std::size_t(header_.data_start) - 1) * kBlock : 0;
  ReadParameters();
  ReadData();
  ReadEvents();

  // Subject (SUBJECTS:NAMES, first entry).
  const std::vector<std::string> subjects =
      internal::ConcatStrings(trial_.parameters, "SUBJECTS", "NAMES");
  if (!subjects.empty()) trial_.subject_name = subjects.front();

  // Force platforms: geometry, then the ground reaction per analog sample.
  trial_.force_plates = internal::DecodeForcePlates(
      trial_.parameters, trial_.source.point_units_to_m, trial_.num_analog_channels(), warn_);
  if (options_.compute_force_plates) {
    for (ForcePlate& plate : trial_.force_plates)
      CalcForcePlateOutputs(trial_, &plate, &trial_.warnings);
  }
  GapImpossiblePositions(&trial_, name_);
  return std::move(trial_);
}

void C3dReader::ReadData() {
  const ParameterSet& params = trial_.parameters;
  // Point count candidates: POINT:USED, then the header's.
  const std::vector<int> point_candidates = PointCountCandidates();

  // Storage: POINT:SCALE negative = float (C3D manual, "POINT:SCALE"); the header holds a copy.
  const double scale = ReadPointScale();
  const bool is_float = scale < 0;
  const std::size_t word = is_float ? 4 : 2;

  // Analog layout: samples per frame and channel count candidates.
  const std::vector<int> channel_candidates = AnalogLayoutCandidates();

  // Frames, the data start, and the point and channel counts that the data section can hold.
  const FrameRange range = CountFrames();
  const std::size_t data_start = FindDataStart(range.frames);
  const std::int64_t frames =
      ChooseDataLayout(point_candidates, channel_candidates, word, data_start, range.frames);
  const std::size_t frame_size = FrameBytes(num_points_, num_channels_, word);
  num_frames_ = frames;
  trial_.num_frames = static_cast<int>(frames);
  trial_.first_frame = range.first;

  // Rates: POINT:RATE, else the header frame rate; the analog rate.
  ReadRates();

  // Point descriptions and units. POINT:UNITS converts markers to metres (C3D manual,
  // "POINT:UNITS"); other point types keep the file's units.
  const std::optional<std::string> units = params.FindString("POINT", "UNITS");
  double to_m = DescribePoints(is_float, scale, units);
  std::vector<double> point_factor(num_points_, 1.0);
  for (int p = 0; p < num_points_; ++p) {
    if (trial_.points[p].type == PointType::kMarker) point_factor[p] = units ? to_m : 1.0;
  }

  // Analog channels.
  internal::AnalogConversion conversion;
  trial_.analog_channels =
      internal::DecodeAnalogChannels(params, num_channels_, &conversion, warn_);

  // Allocate once (sizes are bounded by the file size checked above), then decode in one pass.
  trial_.positions.resize(3, frames * num_points_);
  trial_.residuals.resize(num_points_, frames);
  trial_.camera_masks.resize(num_points_, frames);
  trial_.analog.resize(num_channels_, num_channels_ > 0 ? frames * analog_per_frame_ : 0);
  if (frames > 0 && frame_size > 0)
    DecodeData(bytes_.data() + data_start, is_float, conversion, point_factor, scale);

  // Invalid samples become gaps; missing units are guessed from the coordinates.
  MarkInvalidSamples();
  if (!units) to_m = GuessMissingUnits();
  trial_.source.point_units_to_m = to_m;
}

// Point count candidates, preferred first: POINT:USED (read unsigned), then the header's when it
// differs or POINT:USED is missing (warned).
std::vector<int> C3dReader::PointCountCandidates() const {
  const ParameterSet& params = trial_.parameters;
  std::vector<int> point_candidates;
  if (const Parameter* used = params.Find("POINT", "USED"); used && !used->AsUnsigned().empty()) {
    point_candidates.push_back(static_cast<int>(used->AsUnsigned().front()));
  }
  if (point_candidates.empty() || point_candidates.front() != header_.num_points) {
    if (!point_candidates.empty()) {
      warn_("POINT:USED",
            "is " + std::to_string(point_candidates.front()) + " but the header says " +
                std::to_string(header_.num_points) + " points");
    } else if (header_.num_points > 0) {
      warn_("POINT:USED",
            "missing; header point count " + std::to_string(header_.num_points) + " used");
    }
    point_candidates.push_back(header_.num_points);
  }
  return point_candidates;
}

// POINT:SCALE, else the header's scale; 1 when not finite (warned). Negative means float storage.
double C3dReader::ReadPointScale() const {
  double scale = header_.scale;
  if (const std::optional<double> s = trial_.parameters.FindDouble("POINT", "SCALE")) {
    if ((*s < 0) != (header_.scale < 0)) {
      warn_(
          "POINT:SCALE",
          fmt::format("is {:.9g} but the header scale is {:.9g}; the parameter decides the storage",
                      *s,
                      header_.scale));
    }
    scale = *s;
  }
  if (!std::isfinite(scale)) {
    warn_("POINT:SCALE", "is not finite; 1 assumed");
    scale = 1.0;
  }
  // 0 would make every integer coordinate 0 (and says nothing of the storage, which its sign
  // gives): the header's copy when it has one, else refused.
  if (scale == 0.0) {
    if (header_.scale == 0.0 || !std::isfinite(header_.scale))
      Fail("POINT:SCALE", "is 0 (and so is the header's): the coordinates cannot be scaled");
    warn_("POINT:SCALE", fmt::format("is 0; the header's scale {:.9g} is used", header_.scale));
    scale = header_.scale;
  }
  return scale;
}

// Analog layout: sets the samples per frame from the header (word 10; from ANALOG:USED when
// the header's is 0); returns the channel count candidates, preferred first: ANALOG:USED, then
// the header's when it differs (warned).
std::vector<int> C3dReader::AnalogLayoutCandidates() {
  analog_per_frame_ = header_.analog_per_frame;
  std::vector<int> channel_candidates;
  if (const Parameter* used = trial_.parameters.Find("ANALOG", "USED");
      used && !used->AsUnsigned().empty()) {
    channel_candidates.push_back(static_cast<int>(used->AsUnsigned().front()));
  }
  // Header word 10 missing (0) while word 3 announces analog words: samples per frame from
  // ANALOG:USED.
  if (analog_per_frame_ == 0 && header_.analog_words > 0 && !channel_candidates.empty() &&
      channel_candidates.front() > 0 && header_.analog_words % channel_candidates.front() == 0) {
    analog_per_frame_ = header_.analog_words / channel_candidates.front();
    warn_(AtByte(18),
          "header analog samples per frame is 0 with " + std::to_string(header_.analog_words) +
              " analog words per frame; " + std::to_string(analog_per_frame_) +
              " samples per frame from ANALOG:USED");
  }
  const int header_channels = analog_per_frame_ > 0 ? header_.analog_words / analog_per_frame_ : 0;
  if (channel_candidates.empty() || channel_candidates.front() != header_channels) {
    if (!channel_candidates.empty()) {
      warn_("ANALOG:USED",
            "is " + std::to_string(channel_candidates.front()) + " but the header gives " +
                std::to_string(header_.analog_words) + " analog words per frame at " +
                std::to_string(analog_per_frame_) + " samples per frame (" +
                std::to_string(header_channels) + " channels)");
    }
    channel_candidates.push_back(header_channels);
  }
  return channel_candidates;
}

// Frames: header first/last (unsigned 16-bit); beyond 65535 frames TRIAL:ACTUAL_START_FIELD and
// ACTUAL_END_FIELD (two 16-bit halves each) or POINT:FRAMES (float or unsigned).
FrameRange C3dReader::CountFrames() const {
  const ParameterSet& params = trial_.parameters;
  FrameRange range;
  range.first = header_.first_frame;
  range.frames = header_.last_frame >= header_.first_frame
                     ? std::int64_t(header_.last_frame) - header_.first_frame + 1
                     : 0;
  // POINT:FRAMES.
  std::optional<std::int64_t> point_frames;
  if (const Parameter* pf = params.Find("POINT", "FRAMES")) {
    if (pf->type == ParameterType::kFloat && !pf->floats.empty()) {
      if (pf->floats[0] >= 0 && pf->floats[0] < 2e9f)
        point_frames = static_cast<std::int64_t>(pf->floats[0]);
    } else if (!pf->AsUnsigned().empty()) {
      point_frames = pf->AsUnsigned().front();
    }
  }
  // The TRIAL range.
  const Parameter* start_field = params.Find("TRIAL", "ACTUAL_START_FIELD");
  const Parameter* end_field = params.Find("TRIAL", "ACTUAL_END_FIELD");
  bool from_trial = false;
  if (start_field && end_field && start_field->AsUnsigned().size() >= 2 &&
      end_field->AsUnsigned().size() >= 2) {
    const std::vector<std::uint32_t> s = start_field->AsUnsigned();
    const std::vector<std::uint32_t> e = end_field->AsUnsigned();
    const std::int64_t trial_first =
        std::int64_t(s[0] & 0xFFFF) | (std::int64_t(s[1] & 0xFFFF) << 16);
    const std::int64_t trial_last =
        std::int64_t(e[0] & 0xFFFF) | (std::int64_t(e[1] & 0xFFFF) << 16);
    // The 16-bit header cannot count beyond 65535 frames: a longer TRIAL range wins when the header
    // is saturated or the range itself exceeds 16 bits (a header that wrapped around).
    const std::int64_t count = trial_last - trial_first + 1;
    if (trial_last >= trial_first && count > range.frames &&
        (header_.last_frame == 0xFFFF || count > 0xFFFF || trial_last > 0xFFFF)) {
      range.first = trial_first;
      range.frames = count;
      from_trial = true;
    }
  }
  // Else POINT:FRAMES, when the header is saturated or it exceeds 16 bits.
  if (!from_trial && point_frames && *point_frames != range.frames) {
    if (*point_frames > range.frames && (header_.last_frame == 0xFFFF || *point_frames > 0xFFFF)) {
      range.frames = *point_frames;
    } else {
      warn_("POINT:FRAMES",
            "is " + std::to_string(*point_frames) + " but the header frames " +
                std::to_string(header_.first_frame) + ".." + std::to_string(header_.last_frame) +
                " give " + std::to_string(range.frames) + "; the header is used");
    }
  }
  return range;
}

// Data start byte: header word 9, else POINT:DATA_START (read unsigned); with `frames` to read
// and neither valid, the file is refused.
std::size_t C3dReader::FindDataStart(std::int64_t frames) const {
  const ParameterSet& params = trial_.parameters;
  std::size_t data_start = data_start_byte_;
  if (const Parameter* ds = params.Find("POINT", "DATA_START");
      ds && !ds->AsUnsigned().empty() && ds->AsUnsigned()[0] != header_.data_start &&
      header_.data_start >= 2 && data_start < bytes_.size()) {
    warn_("POINT:DATA_START",
          "is " + std::to_string(ds->AsUnsigned()[0]) + " but the header says block " +
              std::to_string(header_.data_start) + "; the header is used");
  }
  if (header_.data_start < 2 || data_start >= bytes_.size()) {
    const Parameter* ds = params.Find("POINT", "DATA_START");
    const std::vector<std::uint32_t> v = ds ? ds->AsUnsigned() : std::vector<std::uint32_t>{};
    if (!v.empty() && v[0] >= 2) {
      warn_(AtByte(16),
            "header data start block " + std::to_string(header_.data_start) +
                " is invalid; POINT:DATA_START = " + std::to_string(v[0]) + " used");
      data_start = (std::size_t(v[0]) - 1) * kBlock;
    } else if (frames > 0) {
      Fail(AtByte(16),
           "data start block " + std::to_string(header_.data_start) +
               " is invalid and POINT:DATA_START gives no alternative");
    }
  }
  return data_start;
}

// Bytes of one frame of `points` points and `channels` analog channels, in words of `word` bytes.
std::size_t C3dReader::FrameBytes(int points, int channels, std::size_t word) const {
  return (std::size_t(points) * 4 + std::size_t(channels) * analog_per_frame_) * word;
}

// Sets the point and channel counts to the first candidates (parameters preferred) whose frames
// the data section can hold; when none fit, the preferred ones and as many frames as the file
// holds (truncated, warned). Refuses counts that no file could back. Returns the frame count.
std::int64_t C3dReader::ChooseDataLayout(const std::vector<int>& point_candidates,
                                         const std::vector<int>& channel_candidates,
                                         std::size_t word,
                                         std::size_t data_start,
                                         std::int64_t frames) {
  const std::size_t available = data_start < bytes_.size() ? bytes_.size() - data_start : 0;
  // The first pair of counts that fits.
  num_points_ = point_candidates.front();
  num_channels_ = channel_candidates.front();
  bool fits = false;
  for (int points : point_candidates) {
    for (int channels : channel_candidates) {
      const std::size_t fb = FrameBytes(points, channels, word);
      if (fb == 0 || std::size_t(frames) <= available / fb) {
        if (points != num_points_ || channels != num_channels_) {
          warn_("data section",
                "holds " + std::to_string(points) + " points and " + std::to_string(channels) +
                    " analog channels per frame (the counts that fit the file); used");
        }
        num_points_ = points;
        num_channels_ = channels;
        fits = true;
        break;
      }
    }
    if (fits) break;
  }
  // None fits: the complete frames the file holds.
  const std::size_t frame_size = FrameBytes(num_points_, num_channels_, word);
  if (!fits) {
    const std::int64_t whole = static_cast<std::int64_t>(available / frame_size);
    if (whole == 0) {
      Fail(AtByte(static_cast<long long>(data_start)),
           "data section holds " + std::to_string(available) + " bytes, less than one frame of " +
               std::to_string(frame_size) + " bytes (" + std::to_string(frames) +
               " frames expected)");
    }
    warn_(AtByte(static_cast<long long>(data_start)),
          "data section holds " + std::to_string(whole) + " complete frames of the " +
              std::to_string(frames) + " declared (file truncated); " + std::to_string(whole) +
              " read");
    frames = whole;
  }
  // Counts this reader can hold and the file can back.
  // No points and no analog channels: the frames hold nothing, and a declared count (up to 2³¹
  // from TRIAL:ACTUAL_END_FIELD) is backed by no byte of the file; read none.
  if (frame_size == 0 && frames > 0) {
    warn_("POINT:USED",
          "no points and no analog channels: the " + std::to_string(frames) +
              " declared frames hold no data; none read");
    frames = 0;
  }
  if (frames > std::numeric_limits<int>::max() / std::max(1, num_points_ + 1)) {
    Fail("POINT:FRAMES", std::to_string(frames) + " frames are more than this reader supports");
  }
  // Without frames, nothing in the file backs the counts: bound them by the file size.
  if (frames == 0 && (std::size_t(num_points_) + std::size_t(num_channels_)) * 4 > bytes_.size()) {
    Fail("POINT:USED",
         std::to_string(num_points_) + " points and " + std::to_string(num_channels_) +
             " analog channels with no frames are more than a " + std::to_string(bytes_.size()) +
             "-byte file can describe");
  }
  return frames;
}

// Rates: POINT:RATE, else the header frame rate (0 when invalid); the analog rate from
// ANALOG:RATE, else the point rate times the samples per frame.
void C3dReader::ReadRates() {
  const ParameterSet& params = trial_.parameters;
  // The point rate.
  double rate = header_.frame_rate;
  if (const std::optional<double> r = params.FindDouble("POINT", "RATE"); r && *r > 0) {
    if (std::abs(*r - rate) > 1e-3 * std::abs(*r)) {
      warn_("POINT:RATE",
            fmt::format("is {:.9g} Hz but the header says {:.9g} Hz; POINT:RATE used", *r, rate));
    }
    rate = *r;
  } else if (!params.Find("POINT", "RATE")) {
    if (params.FindGroup("POINT"))
      warn_("POINT:RATE", fmt::format("missing; header rate {:.9g} Hz used", rate));
  }
  if (!std::isfinite(rate) || rate < 0) {
    warn_("POINT:RATE", fmt::format("rate {:.9g} Hz is invalid; 0 used", rate));
    rate = 0;
  }
  trial_.point_rate_hz = rate;
  // The analog rate.
  if (num_channels_ == 0) {
    // No analog data: the analog rate is still reported (as BTK does), from ANALOG:RATE or the
    // point rate times the header's samples per frame (at least 1).
    const std::optional<double> r = params.FindDouble("ANALOG", "RATE");
    trial_.analog_rate_hz =
        r && *r > 0 && std::isfinite(*r) ? *r : rate * std::max(1, analog_per_frame_);
  } else if (analog_per_frame_ > 0) {
    double analog_rate = rate * analog_per_frame_;
    if (const std::optional<double> r = params.FindDouble("ANALOG", "RATE");
        r && *r > 0 && std::isfinite(*r)) {
      if (std::abs(*r - analog_rate) > 1e-3 * *r) {
        warn_("ANALOG:RATE",
              fmt::format("is {:.9g} Hz but the data hold {} samples per frame at {:.9g} Hz; "
                          "ANALOG:RATE kept",
                          *r,
                          analog_per_frame_,
                          rate));
      }
      analog_rate = *r;
    } else {
      warn_("ANALOG:RATE",
            fmt::format("missing or invalid; {:.9g} Hz used (point rate × samples per frame)",
                        analog_rate));
    }
    trial_.analog_rate_hz = analog_rate;
  }
}

// The points' labels, descriptions, types and units, and the storage in the source info.
// Returns the factor from POINT:UNITS to metres (millimetres assumed for an unknown unit, 0
// when POINT:UNITS is missing).
double C3dReader::DescribePoints(bool is_float,
                                 double scale,
                                 const std::optional<std::string>& units) {
  const ParameterSet& params = trial_.parameters;
  trial_.points = internal::DecodePoints(params, num_points_, warn_);
  SourceInfo& src = trial_.source;
  src.processor = internal::ProcessorName(processor_);
  src.point_storage = is_float ? "float" : "integer";
  src.max_interpolation_gap = header_.max_gap;
  src.point_scale = scale;
  double to_m = 0;
  if (units) {
    src.point_units = *units;
    to_m = internal::LengthUnitToMetres(*units);
    if (to_m == 0) {
      warn_("POINT:UNITS", "unknown unit '" + *units + "'; millimetres assumed");
      to_m = 1e-3;
    }
  }
  const std::string x = params.FindString("POINT", "X_SCREEN").value_or("");
  const std::string y = params.FindString("POINT", "Y_SCREEN").value_or("");
  if (!x.empty() || !y.empty()) src.axis_convention = x + " " + y;
  return to_m;
}

// Decodes the data section at `data` with the decoder for the processor and storage.
void C3dReader::DecodeData(const std::uint8_t* data,
                           bool is_float,
                           const internal::AnalogConversion& conversion,
                           const std::vector<double>& point_factor,
                           double scale) {
  switch (processor_) {
    case Processor::kIntel:
      is_float ? Decode<Processor::kIntel, true>(data, conversion, point_factor, scale)
               : Decode<Processor::kIntel, false>(data, conversion, point_factor, scale);
      break;
    case Processor::kDec:
      is_float ? Decode<Processor::kDec, true>(data, conversion, point_factor, scale)
               : Decode<Processor::kDec, false>(data, conversion, point_factor, scale);
      break;
    case Processor::kMips:
      is_float ? Decode<Processor::kMips, true>(data, conversion, point_factor, scale)
               : Decode<Processor::kMips, false>(data, conversion, point_factor, scale);
      break;
  }
}

// Residual word negative = invalid sample → a gap (NaN). If every sample is invalid but the
// coordinates are not all zero (SIMI files, c3d.org sample 16), keep them and say so.
void C3dReader::MarkInvalidSamples() {
  const std::int64_t frames = num_frames_;
  const std::int64_t samples = frames * num_points_;
  if (samples <= 0 || invalid_samples_ <= 0) return;
  bool keep = false;
  if (invalid_samples_ == samples) {
    for (std::int64_t i = 0; i < samples && !keep; ++i) {
      keep =
          trial_.positions(0, i) != 0 || trial_.positions(1, i) != 0 || trial_.positions(2, i) != 0;
    }
    if (keep) {
      warn_("POINT residuals",
            "every sample has residual -1 (invalid) but the coordinates are not zero; "
            "coordinates kept as valid samples (residuals stay -1)");
    }
  }
  if (!keep) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::int64_t f = 0; f < frames; ++f) {
      for (int p = 0; p < num_points_; ++p) {
        if (trial_.residuals(p, f) < 0) trial_.positions.col(f * num_points_ + p).setConstant(nan);
      }
    }
  }
}

// Missing POINT:UNITS: millimetres unless the marker coordinates are small enough to be metres
// (median magnitude of up to 20000 sampled marker coordinates below 20); markers in millimetres
// are converted. Returns the factor to metres.
double C3dReader::GuessMissingUnits() {
  const std::int64_t frames = num_frames_;
  const std::int64_t samples = frames * num_points_;
  // The median magnitude.
  std::vector<double> magnitudes;
  for (std::int64_t i = 0; i < samples; i += std::max<std::int64_t>(1, samples / 20000)) {
    const int p = static_cast<int>(i % std::max(1, num_points_));
    if (trial_.points[p].type != PointType::kMarker) continue;
    const double m = trial_.positions.col(i).cwiseAbs().maxCoeff();
    if (std::isfinite(m) && m > 0) magnitudes.push_back(m);
  }
  double median = 0;
  if (!magnitudes.empty()) {
    std::nth_element(
        magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2, magnitudes.end());
    median = magnitudes[magnitudes.size() / 2];
  }
  // The unit it suggests, and the markers converted.
  const double to_m = (median > 0 && median < 20.0) ? 1.0 : 1e-3;
  if (num_points_ > 0) {
    warn_("POINT:UNITS",
          std::string("missing; ") + (to_m == 1.0 ? "metres" : "millimetres") +
              fmt::format(" assumed (median marker coordinate magnitude {:.9g})", median));
  }
  if (to_m != 1.0 && num_points_ > 0) {
    for (std::int64_t f = 0; f < frames; ++f) {
      for (int p = 0; p < num_points_; ++p) {
        if (trial_.points[p].type == PointType::kMarker)
          trial_.positions.col(f * num_points_ + p) *= to_m;
      }
    }
  }
  return to_m;
}

// Decodes every frame: per point x, y, z and the residual word, then the analog samples (C3D
// manual, "The 3D point and analog data section"). Integer storage multiplies x, y, z by
// POINT:SCALE; the residual word holds the camera mask in its high byte and the residual (in units
// of |POINT:SCALE|) in its low byte; float storage keeps the same word as a float.
template <Processor P, bool kFloat>
void C3dReader::Decode(const std::uint8_t* data,
                       const internal::AnalogConversion& conversion,
                       const std::vector<double>& point_factor,
                       double scale) {
  constexpr std::size_t kWord = kFloat ? 4 : 2;
  const int num_points = num_points_;
  const int channels = num_channels_;
  const int per_frame = analog_per_frame_;
  const std::size_t frame_size =
      (std::size_t(num_points) * 4 + std::size_t(channels) * per_frame) * kWord;
  const double abs_scale = std::abs(scale);
  const float residual_unit = static_cast<float>(abs_scale);
  const bool unsigned_analog = conversion.unsigned_format;
  double* pos = trial_.positions.data();
  float* residuals = trial_.residuals.data();
  std::uint8_t* masks = trial_.camera_masks.data();
  double* analog = trial_.analog.data();
  std::int64_t invalid = 0;
  const auto value = [&](const std::uint8_t* at) -> double {
    if constexpr (kFloat) {
      return LoadF32(at, P);
    } else {
      return LoadI16(at, P);
    }
  };
  for (std::int64_t f = 0; f < num_frames_; ++f) {
    const std::uint8_t* frame = data + f * frame_size;
    for (int p = 0; p < num_points; ++p) {
      const std::uint8_t* at = frame + std::size_t(p) * 4 * kWord;
      const double factor = kFloat ? point_factor[p] : point_factor[p] * scale;
      pos[0] = value(at) * factor;
      pos[1] = value(at + kWord) * factor;
      pos[2] = value(at + 2 * kWord) * factor;
      pos += 3;
      int word;
      if constexpr (kFloat) {
        const float w = LoadF32(at + 3 * kWord, P);
        // NaN and negative words are invalid; large values are clamped to the 16-bit word.
        word = !(w >= 0.0f) ? -1 : static_cast<int>(std::min(w, 32767.0f));
      } else {
        word = LoadI16(at + 3 * kWord, P);
      }
      if (word < 0) {
        *residuals++ = -1.0f;
        *masks++ = 0;
        ++invalid;
      } else {
        *residuals++ = static_cast<float>(word & 0xFF) * residual_unit;
        *masks++ = static_cast<std::uint8_t>(word >> 8);
      }
    }
    const std::uint8_t* at = frame + std::size_t(num_points) * 4 * kWord;
    for (int s = 0; s < per_frame; ++s) {
      for (int c = 0; c < channels; ++c) {
        double raw;
        if constexpr (kFloat) {
          raw = LoadF32(at, P);
        } else {
          raw = unsigned_analog ? double(LoadU16(at, P)) : double(LoadI16(at, P));
        }
        *analog++ = (raw - conversion.offset[c]) * conversion.coefficient[c];
        at += kWord;
      }
    }
  }
  invalid_samples_ = invalid;
}

// Events: the EVENT group when it has events (labels, contexts, descriptions), else the header
// event block (up to 18 events with 4-character labels, C3D manual "The header section").
void C3dReader::ReadEvents() {
  trial_.events = internal::DecodeEventGroup(trial_.parameters, warn_);
  if (!trial_.events.empty()) return;
  int count = header_.num_events;
  if (count == 0) return;
  if (count > 18) {
    warn_(AtByte(300),
          "header says " + std::to_string(count) + " events; the header holds at most 18");
    count = 18;
  }
  const std::uint8_t* h = bytes_.data();
  for (int i = 0; i < count; ++i) {
    Event e;
    e.time_s = LoadF32(h + 304 + 4 * i, processor_);
    e.displayed = h[376 + i] != 0;
    std::string label(reinterpret_cast<const char*>(h + 396 + 4 * i), 4);
    while (!label.empty() && (label.back() == ' ' || label.back() == '\0')) label.pop_back();
    e.label = label;
    trial_.events.push_back(std::move(e));
  }
}

}  // namespace

Trial ReadC3dFromMemory(std::span<const std::uint8_t> bytes,
                        const std::string& name,
                        const C3dReadOptions& options) {
  if (static_cast<std::int64_t>(bytes.size()) > options.max_file_bytes) {
    throw InputError(name,
                     "",
                     "file of " + std::to_string(bytes.size()) + " bytes exceeds the limit of " +
                         std::to_string(options.max_file_bytes) + " bytes");
  }
  return C3dReader(bytes, name, options).Read();
}

Trial ReadC3d(const std::filesystem::path& path, const C3dReadOptions& options) {
  const std::string name = path.string();
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(name, "", "cannot open: " + ec.message());
  if (static_cast<std::int64_t>(size) > options.max_file_bytes) {
    throw InputError(name,
                     "",
                     "file of " + std::to_string(size) + " bytes exceeds the limit of " +
                         std::to_string(options.max_file_bytes) + " bytes");
  }
  if (size == 0) return ReadC3dFromMemory({}, name, options);
  // The file is mapped read-only with its pages populated in one call (no copy, no page fault per
  // 4 KiB); the decoder then makes one pass over it. Where mapping fails, one read into one buffer.
  const int fd = ::open(name.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw InputError(name, "", std::string("cannot open for reading: ") + std::strerror(errno));
  void* mapped = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  if (mapped != MAP_FAILED) {
    ::close(fd);
    struct Unmap {
      void* at;
      std::size_t size;
      ~Unmap() { ::munmap(at, size); }
    } unmap{mapped, size};
    return ReadC3dFromMemory(
        std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(mapped), size),
        name,
        options);
  }
  std::unique_ptr<std::uint8_t[]> buffer(new std::uint8_t[size]);
  std::size_t got = 0;
  while (got < size) {
    const ssize_t n = ::read(fd, buffer.get() + got, size - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (got != size) {
    throw InputError(
        name, "", "read " + std::to_string(got) + " of " + std::to_string(size) + " bytes");
  }
  return ReadC3dFromMemory(std::span<const std::uint8_t>(buffer.get(), size), name, options);
}

}  // namespace acro::capture
