#include "framework/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "framework/text.h"

namespace rome {

namespace {

namespace fs = std::filesystem;

std::runtime_error FileError(const std::string& what, const std::string& path, const std::string& reason) {
  return std::runtime_error(what + " " + Excerpt(path, 200) + ": " + reason);
}

const char* FileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Closes the descriptor on every path out of ReadRegularFile.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

mode_t ProcessUmask() {
  static const mode_t mask = [] {
    const mode_t m = ::umask(0);
    ::umask(m);
    return m;
  }();
  return mask;
}

std::string FolderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

}  // namespace

std::string ReadRegularFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  if (path.empty()) throw FileError(what, "''", "the path is empty");
  // O_NONBLOCK: opening a FIFO must not wait for a writer; the fstat below refuses it.
  Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (f.fd < 0) {
    const int err = errno;
    if (err == ENOENT) throw FileError(what, path, "file does not exist");
    throw FileError(what, path, std::string("cannot be opened (") + std::strerror(err) + ")");
  }
  struct stat st {};
  if (::fstat(f.fd, &st) != 0)
    throw FileError(what, path, std::string("cannot be read (") + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode))
    throw FileError(what, path, std::string("is ") + FileKind(st.st_mode) + ", not a regular file");
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    throw FileError(
        what, path,
        "file is " + std::to_string(st.st_size) + " bytes; the limit is " + std::to_string(max_bytes) + " bytes");
  std::string text;
  text.reserve(static_cast<size_t>(st.st_size));
  std::vector<char> buffer(1 << 16);
  for (;;) {
    const ssize_t n = ::read(f.fd, buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw FileError(what, path, std::string("cannot be read (") + std::strerror(errno) + ")");
    }
    if (n == 0) break;
    if (text.size() + static_cast<size_t>(n) > max_bytes)  // the file grew while it was read
      throw FileError(what, path, "file is larger than the limit of " + std::to_string(max_bytes) + " bytes");
    text.append(buffer.data(), static_cast<size_t>(n));
  }
  return text;
}

std::string CheckOutputPath(const std::string& path, const std::string& what) {
  if (path.empty()) return what + " '': the path is empty";
  if (path.back() == '/') return what + " " + Excerpt(path, 200) + ": names a folder; give a file name";
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {  // an existing symlink is replaced, never followed
    if (S_ISDIR(st.st_mode)) return what + " " + Excerpt(path, 200) + ": is a directory, not a file";
    if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode))
      return what + " " + Excerpt(path, 200) + ": is " + FileKind(st.st_mode) +
             ", not a regular file; give a file name";
  }
  const std::string folder = FolderOf(path);
  if (::stat(folder.c_str(), &st) != 0)
    return what + " " + Excerpt(path, 200) + ": the folder " + Excerpt(folder, 200) + " does not exist";
  if (!S_ISDIR(st.st_mode))
    return what + " " + Excerpt(path, 200) + ": " + Excerpt(folder, 200) + " is a file, not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    return what + " " + Excerpt(path, 200) + ": the folder " + Excerpt(folder, 200) + " is not writable";
  return {};
}

AtomicFileWriter::AtomicFileWriter(std::string path, std::string what)
    : path_(std::move(path)), what_(std::move(what)) {
  if (const std::string problem = CheckOutputPath(path_, what_); !problem.empty()) throw std::runtime_error(problem);
  std::string name = ".";  // appended piece by piece: GCC 12 warns falsely (-Wstringop-overflow) on "." + string
  name.append(fs::path(path_).filename().string());
  name.append(".XXXXXX");
  std::string templ = (fs::path(FolderOf(path_)) / name).string();
  const int fd = ::mkstemp(templ.data());  // O_CREAT | O_EXCL, mode 0600
  if (fd < 0)
    throw FileError(what_, path_,
                    std::string("cannot create a temporary file beside it (") + std::strerror(errno) + ")");
  ::fchmod(fd, 0644 & ~ProcessUmask());  // as an ordinary new file, not mkstemp's 0600
  temp_path_ = templ;
  file_ = ::fdopen(fd, "w");
  if (file_ == nullptr) {
    ::close(fd);
    ::unlink(temp_path_.c_str());
    throw FileError(what_, path_, "cannot open its temporary file");
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (file_ != nullptr) {
    std::fclose(file_);
    ::unlink(temp_path_.c_str());
  }
}

void AtomicFileWriter::Append(std::string_view text) {
  if (file_ == nullptr) throw FileError(what_, path_, "written after Commit");
  if (!text.empty() && std::fwrite(text.data(), 1, text.size(), file_) != text.size() && write_errno_ == 0)
    write_errno_ = errno != 0 ? errno : EIO;
}

void AtomicFileWriter::Commit() {
  if (file_ == nullptr) throw FileError(what_, path_, "committed twice");
  int err = write_errno_;  // each step's errno is kept as it happens
  if (err == 0 && std::fflush(file_) != 0) err = errno;
  if (err == 0 && ::fsync(::fileno(file_)) != 0) err = errno;
  if (std::fclose(file_) != 0 && err == 0) err = errno;
  file_ = nullptr;
  if (err != 0) {
    ::unlink(temp_path_.c_str());
    throw FileError(what_, path_, std::string("writing failed (") + std::strerror(err) + "); the old file is kept");
  }
  if (::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    const int rename_err = errno;
    ::unlink(temp_path_.c_str());
    throw FileError(what_, path_, std::string("cannot be replaced (") + std::strerror(rename_err) + ")");
  }
}

void WriteFileAtomically(const std::string& path, const std::string& content, const std::string& what) {
  AtomicFileWriter writer(path, what);
  writer.Append(content);
  writer.Commit();
}

std::string ResolveInsideFolder(const std::string& root, const std::string& relative, const std::string& what) {
  if (relative.empty()) throw FileError(what, "''", "the path is empty");
  const fs::path rel(relative);
  if (rel.is_absolute())
    throw FileError(what, relative, "is an absolute path; a robot package names its files relative to its own folder");
  std::error_code ec;
  const fs::path base = fs::canonical(fs::absolute(root.empty() ? "." : root, ec), ec);
  if (ec) throw FileError(what, root, "the package folder cannot be resolved (" + ec.message() + ")");
  // canonical() resolves every link of the whole path on the disk (weakly_canonical would resolve "missing/../link"
  // by text and keep the link), so the check below sees where the file really is.
  const fs::path full = fs::canonical(base / rel, ec);
  const fs::path where = ec ? (base / rel).lexically_normal() : full;
  const auto inside = [&base](const fs::path& p) {
    return std::mismatch(base.begin(), base.end(), p.begin(), p.end()).first == base.end();
  };
  if (!inside(where))
    throw FileError(
        what, relative,
        "leaves its package folder " + Excerpt(base.string(), 200) + " (to " + Excerpt(where.string(), 200) + ")");
  if (ec) throw FileError(what, (base / rel).string(), "file does not exist");
  return full.string();
}

TempFolder::TempFolder(const std::string& prefix) {
  const char* env = std::getenv("TMPDIR");
  const std::string base = (env != nullptr && *env != '\0') ? env : "/tmp";
  std::string templ = base + "/" + prefix + "-XXXXXX";
  if (::mkdtemp(templ.data()) == nullptr)
    throw FileError("temporary folder", templ, std::string("cannot be created (") + std::strerror(errno) + ")");
  path_ = templ;
}

TempFolder::~TempFolder() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempFolder::File(const std::string& name) const { return path_ + "/" + name; }

}  // namespace rome
