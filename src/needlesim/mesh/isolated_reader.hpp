#pragma once
// Runs Gmsh's library in a child process that cannot act: the child is forked, moves into a private
// empty temporary folder, gets CPU-time, address-space and file-size limits and a seccomp filter
// (libseccomp) that refuses exec, fork, writing, creating, renaming or deleting files, sockets,
// signals to other processes and raising its limits; it hands its result back through a pipe
// and _exit()s. The parent never calls Gmsh: it reads the pipe, honours stop requests (Ctrl-C,
// SIGTERM) within 100 ms, kills the child when the wall-clock budget runs out, and turns a child
// that died (a signal, Exit in a script) into an InputError naming the file.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "needlesim/mesh/closed_surface.hpp"
#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

// What reading and meshing one geometry may take (tissue.geometry.max_elements, max_mesh_time,
// max_mesh_memory_mib).
struct MeshBudget {
  double maxElements = 2e6;
  double seconds = 120.0;                     // wall clock, and CPU time of the reader
  double bytes = 4096.0 * 1024.0 * 1024.0;    // address space the reader may add to its own
};

// Results in bytes, as the child writes them and the parent reads them (sizes checked).
class ByteWriter {
 public:
  void number(double v);
  void count(std::uint64_t n);
  void text(const std::string& s);
  void numbers(const std::vector<double>& v);
  void integers(const std::vector<int>& v);
  std::string bytes;
};
class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  double number();
  std::uint64_t count();
  std::string text();
  std::vector<double> numbers();
  std::vector<int> integers();
  bool atEnd() const { return at_ == bytes_.size(); }

 private:
  void take(void* to, std::size_t n);
  const std::string& bytes_;
  std::size_t at_ = 0;
};

std::string encodeMesh(const VolumeMesh& m);
VolumeMesh decodeMesh(const std::string& bytes);
std::string encodeSurface(const TriangleSurface& s);
TriangleSurface decodeSurface(const std::string& bytes);

// Runs `work` in the sandboxed child and returns what it returned. An InputError it throws is
// thrown here as it was; a std::bad_alloc is the memory budget; any other failure, a signal, a
// child that ends without a result or runs past budget.seconds is an InputError naming `file`.
// A stop request kills the child and throws RunInterrupted. Where the sandbox cannot be set up
// (no seccomp), the work is refused, never run without it.
std::string runIsolated(const std::string& file, const MeshBudget& budget, const std::function<std::string()>& work);

}  // namespace needlesim::mesh
