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
      if (!entry.is_directory()) {
        // A file goes where its name leads: through a link, into a device (OutputTarget).
        try {
          PlaceFinishedOutput(entry.path(), ResolveOutputTarget(target));
        } catch (const InputError& error) {
          if (failure.empty()) failure = error.what();
        }
        continue;
      }
      if (std::filesystem::is_directory(target)) std::filesystem::remove_all(target, move);
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

namespace {

std::string Errno() {
  return std::strerror(errno);
}

// Opens a character device or FIFO for writing in place. A FIFO nobody reads would block forever:
// opened without waiting, it fails at once with ENXIO, which is said.
int OpenWriteThrough(const OutputTarget& target) {
  const int fd = ::open(target.file.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errno == ENXIO)
      throw InputError(target.named.string(), "", "is a FIFO that no program reads");
    throw InputError(target.named.string(), "", "cannot open for writing: " + Errno());
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

void WriteAll(int fd, const OutputTarget& target, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = n < 0 ? Errno() : "nothing written";
      ::close(fd);
      throw InputError(target.named.string(), "", "write failed: " + why);
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

void CloseWritten(int fd, const OutputTarget& target) {
  if (::close(fd) != 0 && errno != EINTR)
    throw InputError(target.named.string(), "", "write failed: " + Errno());
}

// Copies `from` into a temporary beside `to` and renames it there: a finished output moved to
// another file system is never seen half-copied. Only OutputTransaction::Commit gets here (a
// staging directory on another file system than a link's target), inside RunUninterrupted, so the
// temporary is not registered (that would wait for the lock Commit holds).
void CopyThenRename(const std::filesystem::path& from, const OutputTarget& target) {
  const std::filesystem::path temp = TemporaryPathFor(target);
  std::error_code ec;
  std::filesystem::copy_file(from, temp, std::filesystem::copy_options::overwrite_existing, ec);
  if (!ec) std::filesystem::rename(temp, target.file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw InputError(
        target.named.string(), "", "cannot move the finished output into place: " + ec.message());
  }
}

}  // namespace

OutputTarget ResolveOutputTarget(const std::filesystem::path& named) {
  OutputTarget target{named, named, false};
  const std::string name = named.string();
  // Follow the chain of links by hand: a dangling link's target is a new file to create.
  std::error_code ec;
  for (int hops = 0;; ++hops) {
    const std::filesystem::file_status link = std::filesystem::symlink_status(target.file, ec);
    if (ec || link.type() != std::filesystem::file_type::symlink) break;
    if (hops == 40) throw InputError(name, "", "is a loop of symbolic links");
    const std::filesystem::path to = std::filesystem::read_symlink(target.file, ec);
    if (ec) throw InputError(name, "", "cannot read the symbolic link: " + ec.message());
    target.file = to.is_absolute() ? to : target.file.parent_path() / to;
  }
  const std::filesystem::file_status status = std::filesystem::status(target.file, ec);
  switch (status.type()) {
    case std::filesystem::file_type::not_found:
    case std::filesystem::file_type::none:
    case std::filesystem::file_type::regular:
      break;
    case std::filesystem::file_type::character:
    case std::filesystem::file_type::fifo:
      target.write_through = true;
      break;
    case std::filesystem::file_type::directory:
      throw InputError(name, "", "is a directory, not a file to write");
    case std::filesystem::file_type::block:
      throw InputError(name, "", "is a block device: Acrolab does not write over one");
    case std::filesystem::file_type::socket:
      throw InputError(name, "", "is a socket, not a file to write");
    default:
      throw InputError(name, "", "cannot be examined: " + ec.message());
  }
  return target;
}

std::filesystem::path TemporaryPathFor(const OutputTarget& target, std::string_view suffix) {
  std::random_device seed;
  const std::string name = "." + target.file.filename().string() + ".tmp" +
                           std::to_string(seed() % 1000000) + std::string(suffix);
  if (target.write_through) {
    std::error_code ec;
    std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
    if (ec) dir = "/tmp";
    return dir / name;
  }
  return target.file.parent_path() / name;
}

void PlaceFinishedOutput(const std::filesystem::path& finished, const OutputTarget& target) {
  std::error_code ec;
  if (target.write_through) {
    struct Remove {
      const std::filesystem::path& path;
      ~Remove() {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
      }
    } remove{finished};
    std::ifstream in(finished, std::ios::binary);
    if (!in) throw InputError(target.named.string(), "", "the finished output cannot be read back");
    const int fd = OpenWriteThrough(target);
    std::vector<char> buffer(1 << 16);
    while (in) {
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      WriteAll(fd, target, buffer.data(), static_cast<std::size_t>(in.gcount()));
    }
    CloseWritten(fd, target);
    return;
  }
  // Replacing a file keeps its permissions (a shared output stays shared).
  const std::filesystem::file_status old = std::filesystem::status(target.file, ec);
  if (!ec && old.type() == std::filesystem::file_type::regular)
    std::filesystem::permissions(finished, old.permissions(), ec);
  ec.clear();
  std::filesystem::rename(finished, target.file, ec);
  if (ec == std::errc::cross_device_link) {
    CopyThenRename(finished, target);
    std::filesystem::remove(finished, ec);
    return;
  }
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(finished, ignored);
    throw InputError(
        target.named.string(), "", "cannot rename the finished output into place: " + ec.message());
  }
}

void WriteFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  const OutputTarget target = ResolveOutputTarget(path);
  if (target.write_through) {
    const int fd = OpenWriteThrough(target);
    WriteAll(fd, target, bytes.data(), bytes.size());
    CloseWritten(fd, target);
    return;
  }
  // A unique temporary name beside the file, so that the rename stays on one file system.
  const std::filesystem::path temp = TemporaryPathFor(target);
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
  // One step for the interrupt handler: renamed and counted as kept, or not renamed at all.
  RunUninterrupted([&] { PlaceFinishedOutput(temp, target); });
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
