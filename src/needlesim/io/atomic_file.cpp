#include "needlesim/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "needlesim/core/error.hpp"

namespace needlesim::io {
namespace {

// Writes all of `content` to the open file `fd`; the errno of the failure, or 0.
int writeAll(int fd, std::string_view content) {
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : ENOSPC;
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

// Creates `tmp` and writes `content` into it; the errno of the failure, or 0.
int writeNewFile(const std::filesystem::path& tmp, std::string_view content) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  int err = writeAll(fd, content);
  if (::close(fd) != 0 && err == 0) err = errno;
  return err;
}

}  // namespace

void throwWriteFailure(const std::filesystem::path& path, int errnum) {
  const bool full = errnum == ENOSPC || errnum == EFBIG || errnum == EDQUOT || errnum == 0;
  const std::string why = errnum != 0 ? std::strerror(errnum) : "no reason given";
  throw Error("cannot write " + path.string() + (full ? ": disk full / write failed: " : ": write failed: ") + why);
}

void writeFileAtomic(const std::filesystem::path& path, std::string_view content) {
  namespace fs = std::filesystem;
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  fs::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  if (const int err = writeNewFile(tmp, content); err != 0) {
    fs::remove(tmp, ec);
    throwWriteFailure(path, err);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error("cannot move " + tmp.string() + " to " + path.string() + ": " + ec.message());
  }
}

}  // namespace needlesim::io
