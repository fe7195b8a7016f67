#pragma once

// The campaign's defect classes (issue "Rules, not examples"; docs/limits.md, "The campaign"):
// each turns a good file's bytes into a bad one, variant by variant, deterministically (the same
// variant index gives the same bytes on every machine), so a failing case can be made again by
// its name alone.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace acro::campaign {

enum class Defect {
  kTruncation,  ///< cut at a structural boundary (a line, a token, a 512-byte block, an MP4 box)
  kBitFlip,     ///< 1–4 bits flipped anywhere
  kCounts,      ///< a declared count or size far beyond the content
  kNonFinite,   ///< a number made nan, inf or beyond double's range
  kAbsurd,      ///< a number made 1e300, −1e300, 300 digits, 0, −1, a denormal
  kUnits,       ///< a number in another unit (×1000, ÷1000), a unit name changed
  kNames,       ///< names duplicated, emptied or 10 KB long
  kEncoding,    ///< UTF-16, a byte-order mark, Latin-1, NUL, terminal escapes, invalid UTF-8, CR
  kSpecial,     ///< the path is a directory, a FIFO, a link loop, a dangling link, empty, a device
  kNesting,     ///< 100 000 brackets or elements deep
  kHugeLine,    ///< one line (or a tail) of 16 MB
  kOption,      ///< a command's option: non-finite, absurd, empty, not a number
  kOutput,      ///< an output that cannot be written as asked
  kSignal,      ///< SIGINT or SIGTERM at a random instant
  kFullDisk,    ///< outputs on a filesystem with no room
};
inline constexpr int kDefectCount = 15;
const char* DefectName(Defect d);

/// What a file is, for the mutations that need its structure.
enum class Format { kText, kXml, kJson, kC3d, kMp4, kSqlite, kBinary };

/// The kind of special file a kSpecial variant puts in place of the input.
enum class Special {
  kNone,
  kDirectory,
  kFifo,
  kLinkLoop,
  kDanglingLink,
  kEmpty,
  kZeroDevice,
  kOneByte
};

struct Mutation {
  std::string what;  ///< a few words: "truncated at line 12 (byte 300)"
  std::string bytes;
  Special special = Special::kNone;
  /// A count or size the file declares was changed: reading on must say so (a warning).
  bool declared_count = false;
};

/// The variant `index` of `defect` on `seed`; nothing when the class has no such variant for this
/// format (e.g. nesting in a video). `huge_bytes` sizes kHugeLine.
std::optional<Mutation> Mutate(const std::string& seed,
                               Format format,
                               Defect defect,
                               int index,
                               std::uint64_t salt,
                               std::size_t huge_bytes = 16u << 20);

}  // namespace acro::campaign
