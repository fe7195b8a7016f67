#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace acro {

class ScopedTemporary;

/// Reads a whole file. Throws acro::InputError naming the file when it cannot be opened or read,
/// or when it is larger than `max_bytes`.
std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path,
                                        std::int64_t max_bytes = std::int64_t(4) << 30);

/// Where an output the user named really goes (docs/limits.md, "Outputs"), one rule for every
/// writer: a symbolic link is followed to its final target, which is written and the link kept; a
/// character device (/dev/null) or a FIFO is written through in place, never replaced; a regular
/// file, or a name that does not exist yet, is replaced whole by a rename. A directory, a block
/// device, a socket or a link loop is refused.
struct OutputTarget {
  std::filesystem::path named;  ///< as the user named it
  std::filesystem::path file;   ///< what is written: `named`, or its link's final target
  bool write_through = false;   ///< a character device or a FIFO
};

/// Resolves `named` by the rule above. acro::InputError (file `named`) for what is refused.
OutputTarget ResolveOutputTarget(const std::filesystem::path& named);

/// A unique temporary name where a writer prepares `target`'s bytes: beside the file for a regular
/// target (the rename stays on one file system), in the system's temporary directory for a
/// device or FIFO. `suffix` ends the name (".mp4" for a muxer that reads the extension).
std::filesystem::path TemporaryPathFor(const OutputTarget& target, std::string_view suffix = "");

/// Puts the finished file `finished` in place of `target`: renamed over the regular file (copied
/// beside it first when on another file system; an existing file's permissions kept), or copied
/// through to the device or FIFO and removed. acro::InputError (file target.named) on failure,
/// with `finished` removed.
void PlaceFinishedOutput(const std::filesystem::path& finished, const OutputTarget& target);

/// Writes `bytes` to the output named `path` by the rule of OutputTarget: a regular file through a
/// temporary beside it renamed when complete, so that no reader ever sees a half-written output; a
/// device or FIFO written through. Throws acro::InputError on failure (and removes the temporary
/// file).
void WriteFileAtomically(const std::filesystem::path& path, std::string_view bytes);

/// Checks, before any work starts, that `dir` can take outputs, leaving nothing behind: it is a
/// directory, or it does not exist and its nearest existing ancestor is one; and a file can be
/// created there (a probe, removed at once). Throws acro::InputError (file `dir`) saying why not:
/// a file of that name, no permission, a read-only or virtual file system.
void CheckOutputDirectory(const std::filesystem::path& dir);

/// Creates `dir` and its parents when missing; acro::InputError (file `dir`) when that fails.
void CreateOutputDirectory(const std::filesystem::path& dir);

/// A command's outputs as one transaction (docs/limits.md, "Outputs"): they are written into a
/// staging directory in the nearest existing ancestor of `dir` (a unique hidden name, removed by
/// the interrupt handler and by the destructor unless committed), and Commit() moves them into
/// `dir` in one uninterrupted step, taking turns with other processes committing there (flock).
/// Until then the previous run's outputs in `dir` stay as they were; a failure or a Ctrl-C in
/// between leaves nothing.
class OutputTransaction {
 public:
  /// Checks `dir` (CheckOutputDirectory) and creates the staging directory.
  explicit OutputTransaction(std::filesystem::path dir);
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// Where the outputs are written.
  const std::filesystem::path& staging() const { return staging_; }
  /// Where they go.
  const std::filesystem::path& dir() const { return dir_; }
  /// Creates `dir` when missing and moves every entry of the staging directory into it,
  /// replacing entries of the same name; removes the staging directory. acro::InputError (file
  /// `dir`) when a move fails.
  void Commit();

 private:
  std::filesystem::path dir_, staging_;
  std::unique_ptr<ScopedTemporary> registered_;
  bool committed_ = false;
};

/// Lower-case extension without the dot ("c3d", "trc"), or empty.
std::string LowerExtension(const std::filesystem::path& path);

/// std::filesystem's queries without their exceptions: a path that cannot be examined (a name too
/// long, a component that is not a directory, no permission) is simply not there. For paths read
/// from files and command lines, whose trouble is the reader's to say in one line.
bool PathExists(const std::filesystem::path& path);
bool IsRegularFile(const std::filesystem::path& path);
bool IsDirectory(const std::filesystem::path& path);

}  // namespace acro
