#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace acro {

/// Reads a whole file. Throws acro::InputError naming the file when it cannot be opened or read,
/// or when it is larger than `max_bytes`.
std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path,
                                        std::int64_t max_bytes = std::int64_t(4) << 30);

/// Writes `bytes` to a temporary file beside `path` and renames it over `path` when complete, so
/// that no reader ever sees a half-written output. Throws acro::InputError on failure (and removes
/// the temporary file).
void WriteFileAtomically(const std::filesystem::path& path, std::string_view bytes);

/// Lower-case extension without the dot ("c3d", "trc"), or empty.
std::string LowerExtension(const std::filesystem::path& path);

}  // namespace acro
