#pragma once

// Content hashes: SHA-256 (FIPS 180-4) by Nettle, as lowercase hex. The library knows a trial by
// its file's hash (re-adding an unchanged file does nothing, a changed one is analysed again,
// whatever its modification time says); the pose networks are checked against the hashes their
// installation pinned.

#include <filesystem>
#include <string>
#include <string_view>

namespace acro {

std::string Sha256Hex(std::string_view bytes);
/// The hash of a file's content, read in blocks. Throws acro::InputError naming the file when it
/// cannot be read.
std::string Sha256OfFile(const std::filesystem::path& path);

}  // namespace acro
