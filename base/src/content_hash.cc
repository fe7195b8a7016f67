#include "acro/base/content_hash.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include <nettle/sha2.h>

#include "acro/base/input_error.h"

namespace acro {

namespace {

std::string Hex(const unsigned char* digest, size_t size) {
  static const char* kDigits = "0123456789abcdef";
  std::string out(2 * size, '0');
  for (size_t i = 0; i < size; ++i) {
    out[2 * i] = kDigits[digest[i] >> 4];
    out[2 * i + 1] = kDigits[digest[i] & 15];
  }
  return out;
}

}  // namespace

std::string Sha256Hex(std::string_view bytes) {
  sha256_ctx ctx;
  sha256_init(&ctx);
  sha256_update(&ctx, bytes.size(), reinterpret_cast<const uint8_t*>(bytes.data()));
  unsigned char digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, SHA256_DIGEST_SIZE, digest);
  return Hex(digest, SHA256_DIGEST_SIZE);
}

std::string Sha256OfFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", std::string("cannot read: ") + std::strerror(errno));
  sha256_ctx ctx;
  sha256_init(&ctx);
  std::vector<char> block(1 << 20);
  while (in) {
    in.read(block.data(), std::streamsize(block.size()));
    const std::streamsize got = in.gcount();
    if (got > 0) sha256_update(&ctx, size_t(got), reinterpret_cast<const uint8_t*>(block.data()));
  }
  if (in.bad()) throw InputError(path.string(), "", "read error");
  unsigned char digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, SHA256_DIGEST_SIZE, digest);
  return Hex(digest, SHA256_DIGEST_SIZE);
}

}  // namespace acro
