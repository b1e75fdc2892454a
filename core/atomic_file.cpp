// Atomic file writes with POSIX rename.
#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ext/stdio_filebuf.h>
#include <fstream>
#include <sstream>

#include "core/errors.h"

namespace cellform::core {

namespace fs = std::filesystem;

void ensure_directory(const fs::path& dir, std::error_code& ec) {
  ec.clear();
  if (dir.empty()) return;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) ec = std::make_error_code(std::errc::not_a_directory);
    return;
  }
  ec.clear();
  fs::create_directories(dir, ec);
}

void ensure_directory(const fs::path& dir) {
  std::error_code ec;
  ensure_directory(dir, ec);
  std::error_code probe;
  if (ec == std::errc::not_a_directory && fs::exists(dir, probe))
    throw FileError("'" + dir.string() + "' exists and is not a directory");
  if (ec) throw FileError("cannot create directory '" + dir.string() + "': " + ec.message());
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw FileError("cannot write '" + path.string() + "': '" + dir.string() + "' is not a directory");
  if (fs::is_directory(path, ec))
    throw FileError("cannot write '" + path.string() + "': it is a folder (move that folder away)");
  // a temporary of our own, made anew beside the file (O_EXCL: never a file or link that is there already,
  // which another user could have put in a shared folder), then written and renamed over the file
  fs::path tmp;
  int fd = -1;
  for (int attempt = 0;; ++attempt) {
    tmp = path;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(attempt);
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) break;
    if (errno != EEXIST) throw FileError("cannot write '" + path.string() + "': " + std::strerror(errno));
    if (attempt == 99)
      throw FileError("cannot write '" + path.string() + "': the temporary names beside it (" +
                      path.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-0 to -99) are all taken");
  }
  struct stat made {};
  try {
    {
      // written and synced through the descriptor just made: the name is never opened again, so nothing
      // put in its place meanwhile is written to (the buffer closes the descriptor)
      __gnu_cxx::stdio_filebuf<char> buf(fd, std::ios::out | std::ios::binary, 1 << 16);
      if (!buf.is_open()) {
        ::close(fd);
        throw FileError("cannot write '" + path.string() + "': out of memory");
      }
      std::ostream out(&buf);
      errno = 0;
      write(out);
      out.flush();
      const int err = errno;  // of the write that failed, if the stream set it
      if (!out)
        throw FileError("cannot write '" + path.string() + "': " +
                        (err == EFBIG    ? "the file is larger than this process may write (ulimit -f)"
                         : err == ENOSPC ? "the disk is full"
                                         : "write failed (disk full?)"));
      if (::fsync(fd) != 0 || ::fstat(fd, &made) != 0)
        throw FileError("cannot write '" + path.string() + "': " + std::strerror(errno));
    }
    // the name still leads to the file written (in a folder others may write to, it could have been
    // replaced meanwhile, and the rename would put that in the file's place)
    struct stat named {};
    if (::lstat(tmp.c_str(), &named) != 0 || named.st_dev != made.st_dev || named.st_ino != made.st_ino)
      throw FileError("cannot write '" + path.string() + "': its temporary " + tmp.filename().string() +
                      " was replaced while it was written (is the folder writable by others?)");
    fs::rename(tmp, path, ec);
    if (ec) throw FileError("cannot write '" + path.string() + "': " + ec.message());
    sync_directory(path.parent_path());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))  // a name too long or a loop of links is not "missing"
    throw FileError(ec ? "cannot read '" + path.string() + "': " + ec.message()
                       : "file '" + path.string() + "' does not exist");
  if (fs::is_directory(path, ec)) throw FileError("'" + path.string() + "' is a directory, not a file");
  // a pipe would block, a device such as /dev/zero never ends: only regular files are read
  if (!fs::is_regular_file(path, ec))
    throw FileError("'" + path.string() + "' is not a regular file (a pipe, socket or device cannot be read)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read '" + path.string() + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw FileError("cannot read '" + path.string() + "'");
  return ss.str();
}

}  // namespace cellform::core
