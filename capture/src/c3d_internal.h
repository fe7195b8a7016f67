#pragma once

// Shared by the C3D reader and writer: byte decoding per processor type and the decoding of the
// parameters that describe points, analog channels, events and force platforms. The writer decodes
// the parameters it was given with the same functions as the reader, so it can tell whether the
// Trial still matches them (then they are written byte for byte) or must be rewritten.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "acro/capture/parameter_set.h"
#include "acro/capture/trial.h"

namespace acro::capture::internal {

/// Processor type byte of the parameter section (C3D manual, "The parameter section": 83 + type).
enum class Processor : std::uint8_t { kIntel = 84, kDec = 85, kMips = 86 };

const char* ProcessorName(Processor processor);

inline std::uint16_t LoadU16(const std::uint8_t* p, Processor processor) {
  std::uint16_t v;
  std::memcpy(&v, p, 2);
  if (processor == Processor::kMips) v = static_cast<std::uint16_t>((v >> 8) | (v << 8));
  return v;
}

inline std::int16_t LoadI16(const std::uint8_t* p, Processor processor) {
  return static_cast<std::int16_t>(LoadU16(p, processor));
}

/// A VAX F-float (DEC processor) from its four bytes: the two 16-bit halves are swapped relative to
/// IEEE little-endian, the exponent bias is 128 instead of 127 and the hidden bit sits one place
/// lower, so the IEEE reading of the swapped bits is 4 times too large (C3D manual, "DEC floating
/// point"). Exponent 0 is zero; the division by 4 is done on the exponent, exactly.
inline float DecodeVaxFloat(const std::uint8_t* p) {
  const std::uint32_t bits = std::uint32_t(p[2]) | (std::uint32_t(p[3]) << 8) |
                             (std::uint32_t(p[0]) << 16) | (std::uint32_t(p[1]) << 24);
  const std::uint32_t exponent = (bits >> 23) & 0xFF;
  if (exponent == 0) return 0.0f;
  if (exponent <= 2) {
    // The result is subnormal in IEEE: scale in float arithmetic (exact, a power of two).
    return std::bit_cast<float>(bits) * 0.25f;
  }
  return std::bit_cast<float>(bits - (2u << 23));
}

inline float LoadF32(const std::uint8_t* p, Processor processor) {
  std::uint32_t bits;
  switch (processor) {
    case Processor::kIntel:
      std::memcpy(&bits, p, 4);
      return std::bit_cast<float>(bits);
    case Processor::kMips:
      std::memcpy(&bits, p, 4);
      return std::bit_cast<float>(__builtin_bswap32(bits));
    case Processor::kDec:
      return DecodeVaxFloat(p);
  }
  return 0.0f;
}

/// Collects warnings "file: field: problem" (or drops them when `out` is null).
class Warner {
 public:
  Warner(std::string file, std::vector<std::string>* out) : file_(std::move(file)), out_(out) {}
  void operator()(const std::string& where, const std::string& problem) const {
    if (out_ != nullptr) out_->push_back(file_ + ": " + where + ": " + problem);
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::vector<std::string>* out_;
};

/// A character list with its continuations: NAME, NAME2, NAME3, … (C3D manual, "POINT:LABELS2").
std::vector<std::string> ConcatStrings(const ParameterSet& parameters,
                                       std::string_view group,
                                       std::string_view name);

/// Numeric values of NAME, NAME2, … concatenated (e.g. ANALOG:SCALE2 for more than 255 channels).
std::vector<double> ConcatDoubles(const ParameterSet& parameters,
                                  std::string_view group,
                                  std::string_view name);

/// The factor from a length unit string ("mm", "cm", "m", "meters", "in") to metres; 0 if unknown.
double LengthUnitToMetres(std::string unit);

/// Labels, descriptions, types and units of `count` points (markers get unit "m").
std::vector<PointInfo> DecodePoints(const ParameterSet& parameters, int count, const Warner& warn);

/// Per-channel conversion (C3D manual, "ANALOG:SCALE"): value = (raw − offset) · scale · gen_scale.
struct AnalogConversion {
  std::vector<double> offset;
  std::vector<double> coefficient;  // scale · gen_scale
  bool unsigned_format = false;
};

std::vector<AnalogChannel> DecodeAnalogChannels(const ParameterSet& parameters,
                                                int count,
                                                AnalogConversion* conversion,
                                                const Warner& warn);

/// The EVENT group (C3D manual, "The EVENT group"); empty if absent or EVENT:USED is 0.
std::vector<Event> DecodeEventGroup(const ParameterSet& parameters, const Warner& warn);

/// FORCE_PLATFORM geometry and channels (outputs are not computed here). `length_to_m` converts
/// CORNERS and ORIGIN (stored in POINT:UNITS).
std::vector<ForcePlate> DecodeForcePlates(const ParameterSet& parameters,
                                          double length_to_m,
                                          int num_analog_channels,
                                          const Warner& warn);

}  // namespace acro::capture::internal
