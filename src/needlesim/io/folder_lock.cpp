// FolderLock: flock on .<name>.lock beside a results or study folder.
#include "needlesim/io/folder_lock.hpp"

#include "needlesim/core/progress.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace needlesim::io {
namespace fs = std::filesystem;

namespace {
// Whether the open file `fd` is still the file at `path` (not unlinked by a holder that let go).
bool stillAt(int fd, const fs::path& path) {
  struct stat held {}, named {};
  if (::fstat(fd, &held) != 0 || ::stat(path.c_str(), &named) != 0) return false;
  return held.st_dev == named.st_dev && held.st_ino == named.st_ino;
}

// The process id the holder wrote into the lock file ("" when unreadable).
std::string holderOf(const fs::path& file) {
  std::ifstream in(file);
  long pid = 0;
  if (in >> pid && pid > 0) return fmt::format(" (process {})", pid);
  return "";
}
}  // namespace

fs::path FolderLock::lockFileOf(const fs::path& folder) {
  const fs::path parent = folder.parent_path().empty() ? fs::path(".") : folder.parent_path();
  return parent / fmt::format(".{}.lock", folder.filename().string());
}

FolderLock::FolderLock(const fs::path& folder, const std::string& field, const SourceLocation& where, Mode mode)
    : file_(lockFileOf(folder)) {
  const int op = (mode == Mode::Exclusive ? LOCK_EX : LOCK_SH) | LOCK_NB;
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0)
      throw Error(fmt::format("cannot make the lock file {} for {}: {}", file_.string(), folder.string(),
                              std::strerror(errno)));
    if (::flock(fd_, op) != 0) {
      const int err = errno;
      ::close(fd_);
      fd_ = -1;
      if (err != EWOULDBLOCK)
        throw Error(fmt::format("cannot lock {} for {}: {}", file_.string(), folder.string(), std::strerror(err)));
      throw InputError(where, field, "",
                       folder.string() + " is being written by another needlesim" + holderOf(file_) +
                           ", which holds its lock " + file_.filename().string(),
                       "wait until that run or study has finished, or choose another folder");
    }
    if (stillAt(fd_, file_)) break;
    ::close(fd_);  // its holder removed the file as we opened it: lock the new one
    fd_ = -1;
  }
  if (fd_ < 0) throw Error("cannot lock " + file_.string() + ": it keeps being replaced");
  if (mode == Mode::Exclusive) removeIfStoppedHard(file_);
  if (mode == Mode::Exclusive) {
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd_, 0) == 0 && ::write(fd_, pid.data(), pid.size()) < 0) {
      // the process id only makes the refusal's message nicer
    }
  }
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  forgetOnStop(file_);
  // The last holder removes the file (an exclusive lock shows that nobody else holds it).
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0 && stillAt(fd_, file_)) ::unlink(file_.c_str());
  ::close(fd_);
}

}  // namespace needlesim::io
