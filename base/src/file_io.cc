#include "acro/base/file_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"

namespace acro {

std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path, std::int64_t max_bytes) {
  const std::string name = path.string();
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::directory)
    throw InputError(name, "", "is a directory, not a file");
  // A FIFO, socket or device would block or never end: refuse it before opening.
  if (std::filesystem::exists(status) && status.type() != std::filesystem::file_type::regular)
    throw InputError(name, "", "is not a regular file (a pipe, socket or device)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name, "", std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(name, "", "cannot determine the file size");
  if (size > max_bytes) {
    throw InputError(name,
                     "",
                     "file of " + std::to_string(size) + " bytes exceeds the limit of " +
                         std::to_string(max_bytes) + " bytes");
  }
  in.seekg(0, std::ios::beg);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    throw InputError(name, AtByte(in.gcount()), "read failed before the end of the file");
  }
  return bytes;
}

void CheckOutputDirectory(const std::filesystem::path& dir) {
  std::error_code ec;
  // The directory itself, or the nearest ancestor that exists (where it would be created).
  std::filesystem::path at = dir.empty() ? std::filesystem::path(".") : dir;
  bool exists = true;
  while (!std::filesystem::exists(at, ec)) {
    exists = false;
    const std::filesystem::path up = at.parent_path();
    if (up.empty()) {
      at = ".";
      break;
    }
    if (up == at) break;
    at = up;
  }
  if (!std::filesystem::is_directory(at, ec)) {
    throw InputError(dir.string(),
                     "",
                     exists
                         ? "is a file, not a directory for the outputs"
                         : at.string() + " is a file: the output directory cannot be made in it");
  }
  // A probe file: permissions and read-only or virtual file systems show only when writing.
  std::random_device seed;
  const std::filesystem::path probe = at / (".acrolab-probe" + std::to_string(seed() % 1000000));
  std::FILE* file = std::fopen(probe.string().c_str(), "wb");
  if (file == nullptr) {
    throw InputError(dir.string(),
                     "",
                     std::string(exists ? "cannot write in the output directory: "
                                        : "cannot create the output directory: ") +
                         std::strerror(errno));
  }
  std::fclose(file);
  std::filesystem::remove(probe, ec);
}

void CreateOutputDirectory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), "", "cannot create the output directory: " + ec.message());
}

OutputTransaction::OutputTransaction(std::filesystem::path dir) : dir_(std::move(dir)) {
  CheckOutputDirectory(dir_);
  // Hidden and unique per run, in the nearest existing ancestor of `dir` (so that the moves stay
  // on one file system, and a failed run creates no directory on the way to `dir`).
  std::filesystem::path target = dir_.lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  std::filesystem::path parent =
      target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  std::error_code exists_ec;
  while (!std::filesystem::is_directory(parent, exists_ec)) {
    if (!parent.has_parent_path() || parent.parent_path() == parent) {
      parent = ".";  // a relative path's first component: the working directory
      break;
    }
    parent = parent.parent_path();
  }
  std::random_device seed;
  std::error_code ec;
  for (int attempt = 0; attempt < 100; ++attempt) {
    staging_ = parent / ("." + target.filename().string() + ".partial-" +
                         std::to_string(seed() % 100000000));
    if (std::filesystem::create_directory(staging_, ec)) break;
    staging_.clear();
    if (ec) break;  // not a name clash
  }
  if (staging_.empty()) {
    throw InputError(dir_.string(),
                     "",
                     "cannot create a staging directory beside the outputs" +
                         (ec ? ": " + ec.message() : std::string()));
  }
  registered_ = std::make_unique<ScopedTemporary>(staging_);
}

OutputTransaction::~OutputTransaction() {
  if (committed_) return;
  std::error_code ec;
  std::filesystem::remove_all(staging_, ec);
}

void OutputTransaction::Commit() {
  CreateOutputDirectory(dir_);
  // Another process committing to the same directory waits for this one (an advisory lock on the
  // directory itself, released when the descriptor closes), so two runs never interleave their
  // files: the directory holds one run's set whole, the later one's.
  const int lock = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  std::string failure;
  // The entries first: a directory is not moved out of while it is being listed.
  std::vector<std::filesystem::directory_entry> entries;
  std::error_code ec;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(staging_, ec))
    entries.push_back(entry);
  RunUninterrupted([&] {
    for (const std::filesystem::directory_entry& entry : entries) {
      const std::filesystem::path target = dir_ / entry.path().filename();
      std::error_code move;
      if (entry.is_directory() && std::filesystem::is_directory(target))
        std::filesystem::remove_all(target, move);
      std::filesystem::rename(entry.path(), target, move);
      if (move && failure.empty())
        failure =
            target.string() + ": cannot move the finished output into place: " + move.message();
    }
    if (ec && failure.empty()) failure = "cannot list the staging directory: " + ec.message();
  });
  if (lock >= 0) ::close(lock);
  if (!failure.empty()) throw InputError(dir_.string(), "", failure);
  std::filesystem::remove_all(staging_, ec);
  committed_ = true;
}

void WriteFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  // A unique temporary name in the same directory, so that the rename stays on one file system.
  std::random_device seed;
  const std::filesystem::path temp = path.parent_path() / ("." + path.filename().string() + ".tmp" +
                                                           std::to_string(seed() % 1000000));
  const ScopedTemporary registered(temp);  // removed if the program is interrupted
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw InputError(
          path.string(), "", std::string("cannot create output: ") + std::strerror(errno));
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(temp);
      throw InputError(path.string(), "", "write failed (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::filesystem::remove(temp);
    throw InputError(
        path.string(), "", "cannot rename the finished output into place: " + ec.message());
  }
}

std::string LowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return ext;
}

bool PathExists(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

bool IsRegularFile(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

bool IsDirectory(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec);
}

}  // namespace acro
