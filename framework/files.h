#pragma once
// Files at a trust boundary: reading what a user or a shared package names, and writing outputs that neither a crash
// nor a planted symlink can damage. Every error is one line naming what, the path and the reason.
//
// Reading: only a regular file (not a device, FIFO, socket or directory); the size cap is checked while reading, so
// /dev/zero or a file that grows cannot allocate without bound.
// Writing: content goes to a new temporary file created in the destination folder with O_CREAT|O_EXCL (mkstemp; a
// name that exists, a symlink included, is never opened), is flushed and closed, and is then renamed over the
// destination. rename() replaces a symlink at the destination instead of following it, and a failure or an
// interrupted run leaves the old file intact.

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace rome {

/// The whole content of the regular file `path`; std::runtime_error "<what> <path>: <reason>" if it does not exist,
/// is not a regular file, cannot be read, or holds more than `max_bytes` bytes.
std::string ReadRegularFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

/// Empty if `path` can be written by AtomicFileWriter (its folder exists and is writable, and it is absent, a regular
/// file or a symlink, which is replaced; never a directory or a device such as /dev/full); otherwise the one-line
/// reason, naming `what` and the path. Creates nothing.
std::string CheckOutputPath(const std::string& path, const std::string& what);

/// One output file, written atomically (see above). Append, then Commit; destroyed without Commit (an exception, an
/// early return) it removes its temporary file and the destination keeps its old content.
class AtomicFileWriter {
 public:
  /// Creates the temporary file beside `path`; std::runtime_error naming `what` and the path if it cannot.
  AtomicFileWriter(std::string path, std::string what);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void Append(std::string_view text);
  /// Flushes, syncs and closes the temporary file, then renames it over the destination; std::runtime_error naming
  /// the file if any step failed (a full disk, an I/O error), and the destination is then unchanged.
  void Commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, what_, temp_path_;
  std::FILE* file_ = nullptr;
  int write_errno_ = 0;  ///< the first failed write's errno
};

/// Writes `content` to `path` through an AtomicFileWriter.
void WriteFileAtomically(const std::string& path, const std::string& content, const std::string& what);

/// `relative` resolved inside the folder `root`, with symlinks followed: std::runtime_error naming `what` if it is
/// absolute, is empty, or ends outside `root` (a `../` that climbs out, or a link that points out).
std::string ResolveInsideFolder(const std::string& root, const std::string& relative, const std::string& what);

/// A private folder (mkdtemp, mode 0700) under $TMPDIR or /tmp, removed with its content by the destructor. For
/// tests and scratch files: its name cannot be predicted, so nothing can be planted in it beforehand.
class TempFolder {
 public:
  explicit TempFolder(const std::string& prefix = "rome");
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::string& path() const { return path_; }
  /// path() + "/" + name.
  std::string File(const std::string& name) const;

 private:
  std::string path_;
};

}  // namespace rome
