#pragma once

// Content hashes of the library: SHA-256 (FIPS 180-4) by Nettle, as lowercase hex. A trial is
// known by its file's hash, so that re-adding an unchanged file does nothing and a changed one is
// analysed again, whatever its modification time says.

#include <filesystem>
#include <string>
#include <string_view>

namespace acro::library {

std::string Sha256Hex(std::string_view bytes);
/// The hash of a file's content, read in blocks. Throws acro::InputError naming the file when it
/// cannot be read.
std::string Sha256OfFile(const std::filesystem::path& path);

}  // namespace acro::library
