// The sandboxed child process that runs Gmsh (see isolated_reader.hpp): fork, limits, seccomp
// filter, the pipe protocol and the parent's watch over the child.
#include "needlesim/mesh/isolated_reader.hpp"

#include <fcntl.h>
#include <poll.h>
#include <seccomp.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <new>
#include <thread>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"

namespace needlesim::mesh {

// ---- bytes --------------------------------------------------------------------------------

void ByteWriter::number(double v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
void ByteWriter::count(std::uint64_t n) { bytes.append(reinterpret_cast<const char*>(&n), sizeof n); }
void ByteWriter::text(const std::string& s) {
  count(s.size());
  bytes += s;
}
void ByteWriter::numbers(const std::vector<double>& v) {
  count(v.size());
  bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}
void ByteWriter::integers(const std::vector<int>& v) {
  count(v.size());
  bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(int));
}

void ByteReader::take(void* to, std::size_t n) {
  if (n > bytes_.size() - at_) throw Error("the geometry reader's result is truncated");
  std::memcpy(to, bytes_.data() + at_, n);
  at_ += n;
}
double ByteReader::number() {
  double v;
  take(&v, sizeof v);
  return v;
}
std::uint64_t ByteReader::count() {
  std::uint64_t n;
  take(&n, sizeof n);
  return n;
}
std::string ByteReader::text() {
  const std::uint64_t n = count();
  if (n > bytes_.size() - at_) throw Error("the geometry reader's result is truncated");
  std::string s(bytes_.data() + at_, n);
  at_ += n;
  return s;
}
std::vector<double> ByteReader::numbers() {
  const std::uint64_t n = count();
  if (n > (bytes_.size() - at_) / sizeof(double)) throw Error("the geometry reader's result is truncated");
  std::vector<double> v(n);
  take(v.data(), n * sizeof(double));
  return v;
}
std::vector<int> ByteReader::integers() {
  const std::uint64_t n = count();
  if (n > (bytes_.size() - at_) / sizeof(int)) throw Error("the geometry reader's result is truncated");
  std::vector<int> v(n);
  take(v.data(), n * sizeof(int));
  return v;
}

std::string encodeMesh(const VolumeMesh& m) {
  ByteWriter w;
  w.count(static_cast<std::uint64_t>(m.dim));
  w.text(m.element);
  w.numbers(m.X);
  w.integers(m.conn);
  w.integers(m.tag);
  w.count(m.groupNames.size());
  for (const auto& [tag, name] : m.groupNames) {
    w.count(static_cast<std::uint64_t>(static_cast<std::int64_t>(tag)));
    w.text(name);
  }
  return std::move(w.bytes);
}

VolumeMesh decodeMesh(const std::string& bytes) {
  ByteReader r(bytes);
  VolumeMesh m;
  m.dim = static_cast<int>(r.count());
  m.element = r.text();
  m.X = r.numbers();
  m.conn = r.integers();
  m.tag = r.integers();
  for (std::uint64_t n = r.count(), i = 0; i < n; ++i) {
    const int tag = static_cast<int>(static_cast<std::int64_t>(r.count()));
    m.groupNames[tag] = r.text();
  }
  return m;
}

std::string encodeSurface(const TriangleSurface& s) {
  ByteWriter w;
  w.numbers(s.xyz);
  w.integers(s.tri);
  return std::move(w.bytes);
}

TriangleSurface decodeSurface(const std::string& bytes) {
  ByteReader r(bytes);
  TriangleSurface s;
  s.xyz = r.numbers();
  s.tri = r.integers();
  return s;
}

namespace {

// ---- the child ------------------------------------------------------------------------------

// First byte of what the child hands back.
enum Reply : char { kResult = 'R', kInputError = 'I', kFailure = 'F', kOutOfMemory = 'M', kNoSandbox = 'U' };

void writeAll(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

// Standard streams to /dev/null, the pipe to fd 3, every other descriptor closed (the child
// holds none of the parent's files).
int isolateDescriptors(int pipeWrite) {
  const int high = ::fcntl(pipeWrite, F_DUPFD, 10);
  const int null = ::open("/dev/null", O_RDWR);
  for (int fd = 0; fd <= 2; ++fd) ::dup2(null, fd);
  ::dup2(high, 3);
  ::close_range(4, ~0U, 0);
  return 3;
}

bool limit(int resource, rlim_t soft, rlim_t hard) {
  rlimit now{};
  ::getrlimit(resource, &now);
  const rlimit wanted{std::min(soft, now.rlim_max), std::min(hard, now.rlim_max)};
  return ::setrlimit(resource, &wanted) == 0;
}

// The address space the process maps now (the first number of /proc/self/statm, in pages); read
// by the parent before it forks (the child maps the same).
rlim_t mappedBytes() {
  std::ifstream statm("/proc/self/statm");
  unsigned long long pages = 0;
  statm >> pages;
  return static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE));
}

std::string applyLimits(const MeshBudget& budget, rlim_t mapped) {
  const auto cpu = static_cast<rlim_t>(std::max(1.0, std::ceil(budget.seconds)));
  const auto as = mapped + static_cast<rlim_t>(budget.bytes);
  if (!limit(RLIMIT_CPU, cpu, cpu + 1) || !limit(RLIMIT_AS, as, as) || !limit(RLIMIT_FSIZE, 0, 0) ||
      !limit(RLIMIT_CORE, 0, 0))
    return fmt::format("setrlimit failed: {}", std::strerror(errno));
  return "";
}

// The seccomp filter: everything allowed except what could act outside the process.
std::string applySeccomp() {
  scmp_filter_ctx ctx = ::seccomp_init(SCMP_ACT_ALLOW);
  if (!ctx) return "seccomp_init failed";
  const auto deny = SCMP_ACT_ERRNO(EPERM);
  int rc = 0;
  auto refuse = [&](int call) { rc |= ::seccomp_rule_add(ctx, deny, call, 0); };
  for (int call : {SCMP_SYS(execve), SCMP_SYS(execveat), SCMP_SYS(fork), SCMP_SYS(vfork), SCMP_SYS(creat),
                   SCMP_SYS(unlink), SCMP_SYS(unlinkat), SCMP_SYS(rename), SCMP_SYS(renameat), SCMP_SYS(renameat2),
                   SCMP_SYS(mkdir), SCMP_SYS(mkdirat), SCMP_SYS(rmdir), SCMP_SYS(link), SCMP_SYS(linkat),
                   SCMP_SYS(symlink), SCMP_SYS(symlinkat), SCMP_SYS(truncate), SCMP_SYS(ftruncate),
                   SCMP_SYS(chmod), SCMP_SYS(fchmod), SCMP_SYS(fchmodat), SCMP_SYS(chown), SCMP_SYS(fchown),
                   SCMP_SYS(lchown), SCMP_SYS(fchownat), SCMP_SYS(utime), SCMP_SYS(utimes), SCMP_SYS(utimensat),
                   SCMP_SYS(futimesat), SCMP_SYS(mknod), SCMP_SYS(mknodat), SCMP_SYS(setxattr),
                   SCMP_SYS(lsetxattr), SCMP_SYS(fsetxattr), SCMP_SYS(removexattr), SCMP_SYS(lremovexattr),
                   SCMP_SYS(fremovexattr), SCMP_SYS(socket), SCMP_SYS(socketpair), SCMP_SYS(connect),
                   SCMP_SYS(bind), SCMP_SYS(ptrace), SCMP_SYS(process_vm_writev), SCMP_SYS(tkill),
                   SCMP_SYS(pidfd_send_signal), SCMP_SYS(setrlimit), SCMP_SYS(io_uring_setup), SCMP_SYS(shmget),
                   SCMP_SYS(semget), SCMP_SYS(msgget), SCMP_SYS(mq_open), SCMP_SYS(add_key),
                   SCMP_SYS(request_key), SCMP_SYS(keyctl)})
    refuse(call);
  // threads only (glibc falls back from clone3 to clone, whose flags the filter can read)
  rc |= ::seccomp_rule_add(ctx, SCMP_ACT_ERRNO(ENOSYS), SCMP_SYS(clone3), 0);
  rc |= ::seccomp_rule_add(ctx, SCMP_ACT_ERRNO(ENOSYS), SCMP_SYS(openat2), 0);
  rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(clone), 1, SCMP_A0(SCMP_CMP_MASKED_EQ, CLONE_THREAD, 0));
  // opening for anything but reading
  for (unsigned long flag : {O_WRONLY, O_RDWR, O_CREAT, O_TRUNC, O_APPEND}) {
    rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(open), 1, SCMP_A1(SCMP_CMP_MASKED_EQ, flag, flag));
    rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(openat), 1, SCMP_A2(SCMP_CMP_MASKED_EQ, flag, flag));
  }
  // signals to other processes, new limits
  const auto self = static_cast<scmp_datum_t>(::getpid());
  rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(kill), 1, SCMP_A0(SCMP_CMP_NE, self));
  rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(tgkill), 1, SCMP_A0(SCMP_CMP_NE, self));
  rc |= ::seccomp_rule_add(ctx, deny, SCMP_SYS(prlimit64), 1, SCMP_A2(SCMP_CMP_NE, 0));
  if (rc != 0) {
    ::seccomp_release(ctx);
    return "seccomp_rule_add failed";
  }
  rc = ::seccomp_load(ctx);
  ::seccomp_release(ctx);
  return rc == 0 ? "" : fmt::format("seccomp_load failed: {}", std::strerror(-rc));
}

[[noreturn]] void runChild(int pipeWrite, const std::string& folder, const MeshBudget& budget, rlim_t mapped,
                           const std::function<std::string()>& work) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  // Ctrl-C reaches the whole process group: the parent decides (it kills the child on a stop request)
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  const int out = isolateDescriptors(pipeWrite);
  std::string reply;
  std::string problem = ::chdir(folder.c_str()) == 0 ? "" : "chdir failed";
  if (problem.empty()) problem = applyLimits(budget, mapped);
  if (problem.empty()) problem = applySeccomp();
  if (!problem.empty()) {
    reply = std::string(1, kNoSandbox) + problem;
  } else {
    try {
      reply = std::string(1, kResult) + work();
    } catch (const InputError& e) {
      ByteWriter w;
      w.text(e.where().file);
      w.count(static_cast<std::uint64_t>(e.where().line));
      w.count(static_cast<std::uint64_t>(e.where().column));
      w.text(e.field());
      w.text(e.what());
      reply = std::string(1, kInputError) + w.bytes;
    } catch (const std::bad_alloc&) {
      reply = std::string(1, kOutOfMemory);
    } catch (const std::exception& e) {
      reply = std::string(1, kFailure) + e.what();
    } catch (...) {
      reply = std::string(1, kFailure) + "an unknown error";
    }
  }
  writeAll(out, reply);
  ::_exit(0);
}

// ---- the parent -----------------------------------------------------------------------------

InputError readerError(const std::string& file, const std::string& problem, const std::string& allowed) {
  return InputError(SourceLocation{file, 0, 0}, "tissue.geometry", std::filesystem::path(file).filename().string(),
                    problem, allowed);
}

InputError timeBudgetError(const std::string& file, const MeshBudget& budget) {
  return readerError(file,
                     fmt::format("took longer than tissue.geometry.max_mesh_time ({:g} s) to read and mesh", budget.seconds),
                     "a coarser tissue.geometry.element_size (or Mesh.MeshSizeMax), a simpler script, or a larger "
                     "tissue.geometry.max_mesh_time");
}

InputError memoryBudgetError(const std::string& file, const MeshBudget& budget) {
  return readerError(file,
                     fmt::format("needed more memory than tissue.geometry.max_mesh_memory_mib ({:g} MiB) to read and mesh",
                                 budget.bytes / (1024.0 * 1024.0)),
                     "a coarser tissue.geometry.element_size (or Mesh.MeshSizeMax), or a larger "
                     "tissue.geometry.max_mesh_memory_mib");
}

class Child {
 public:
  Child(pid_t pid, int pipeRead) : pid_(pid), pipe_(pipeRead) {}
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      reap();
    }
    if (pipe_ >= 0) ::close(pipe_);
  }
  // Reads the pipe for up to 100 ms; false once it is closed.
  bool readSome(std::string& into) {
    pollfd p{pipe_, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) return true;
    char buffer[1 << 16];
    const ssize_t n = ::read(pipe_, buffer, sizeof buffer);
    if (n < 0) return errno == EINTR || errno == EAGAIN;
    into.append(buffer, static_cast<std::size_t>(n));
    return n > 0;
  }
  // Waits for the child's end; its wait status.
  int reap() {
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    return status;
  }
  bool exited(int& status) {
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    pid_ = -1;
    return true;
  }
  // Only a child not yet reaped: once waitpid has taken it, pid_ is -1, and kill(-1) would reach
  // every process this user may signal.
  void kill() {
    if (pid_ > 0) ::kill(pid_, SIGKILL);
  }

 private:
  pid_t pid_;
  int pipe_;
};

// A private empty folder for the child to work in; removed (only if still empty) afterwards.
class WorkFolder {
 public:
  WorkFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "needlesim-gmsh-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw Error(fmt::format("could not make a temporary folder for reading a geometry: {}", std::strerror(errno)));
    path_ = pattern;
  }
  ~WorkFolder() { ::rmdir(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

InputError diedError(const std::string& file, int status, const MeshBudget& budget) {
  const int sig = WTERMSIG(status);
  if (sig == SIGXCPU || sig == SIGKILL) return timeBudgetError(file, budget);
  if (sig == SIGXFSZ)
    return readerError(file, "tried to write a file", "a script that only describes geometry and mesh options");
  const char* name = sigabbrev_np(sig);
  return readerError(file,
                     fmt::format("Gmsh failed reading this file (signal SIG{}; it may also have run out of "
                                 "tissue.geometry.max_mesh_memory_mib = {:g} MiB)",
                                 name ? name : std::to_string(sig).c_str(), budget.bytes / (1024.0 * 1024.0)),
                     "a file Gmsh reads (a .msh it wrote, a .geo it meshes, a closed surface)");
}

// What the child handed back: the result, or the error it stands for.
std::string interpret(const std::string& file, const std::string& reply, const MeshBudget& budget) {
  const std::string body = reply.substr(1);
  switch (reply[0]) {
    case kResult:
      return body;
    case kInputError: {
      ByteReader r(body);
      SourceLocation where;
      where.file = r.text();
      where.line = static_cast<int>(r.count());
      where.column = static_cast<int>(r.count());
      const std::string field = r.text();
      throw InputError::withMessage(std::move(where), field, r.text());
    }
    case kOutOfMemory:
      throw memoryBudgetError(file, budget);
    case kNoSandbox:
      throw readerError(file, fmt::format("cannot be read safely here: the reader's sandbox could not be set up ({})", body),
                        "a system with seccomp (Linux), or a mesh converted to .msh elsewhere");
    default:
      throw readerError(file, fmt::format("could not be read: {}", printable(body, 300)),
                        "a file Gmsh reads (a .msh it wrote, a .geo it meshes, a closed surface)");
  }
}

}  // namespace

std::string runIsolated(const std::string& file, const MeshBudget& budget, const std::function<std::string()>& work) {
  WorkFolder folder;
  const rlim_t mapped = mappedBytes();
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(fmt::format("could not make a pipe: {}", std::strerror(errno)));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error(fmt::format("could not start the geometry reader: {}", std::strerror(errno)));
  }
  if (pid == 0) runChild(fds[1], folder.path(), budget, mapped, work);
  ::close(fds[1]);
  Child child(pid, fds[0]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget.seconds);
  std::string reply;
  int status = 0;
  bool open = true, ended = false;
  while (open || !ended) {
    if (open) open = child.readSome(reply);
    else std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!ended) ended = child.exited(status);
    if (stopRequested()) {
      child.kill();
      throwIfStopRequested("reading " + file);
    }
    if (!ended && std::chrono::steady_clock::now() > deadline) {
      child.kill();
      throw timeBudgetError(file, budget);
    }
  }
  throwIfStopRequested("reading " + file);
  if (WIFSIGNALED(status)) throw diedError(file, status, budget);
  if (reply.empty())
    throw readerError(file, "ended the reader without a result (Exit or Abort in a script)",
                      "a script without Exit or Abort");
  return interpret(file, reply, budget);
}

}  // namespace needlesim::mesh
