// Reading a geometry cannot act (mesh/isolated_reader, mesh/geo_script_check): script commands
// that run programs, write files, include files outside the script's folder or end the reader
// are refused at their line and nothing on disk changes; the sandboxed child itself cannot exec,
// write or delete; meshing stays within its element, time budget and stops on request.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sched.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/mesh/isolated_reader.hpp"
#include "../support/refusal.hpp"

using namespace needlesim;
namespace fs = std::filesystem;

using needlesim::test::refusal;

namespace {

fs::path freshDir(const std::string& name) {
  const auto dir = fs::temp_directory_path() / fmt::format("needlesim_sandbox_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "scripts");
  return dir;
}

// Every file below `dir`: its size and modification time.
std::map<std::string, std::pair<std::uintmax_t, fs::file_time_type>> listing(const fs::path& dir) {
  std::map<std::string, std::pair<std::uintmax_t, fs::file_time_type>> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    files[e.path().string()] = {e.is_regular_file() ? e.file_size() : 0, e.last_write_time()};
  return files;
}

// A 10 mm square of triangles; line 5 is the command under test.
std::string squareWith(const std::string& command) {
  return "Point(1) = {0, 0, 0, 2}; Point(2) = {10, 0, 0, 2}; Point(3) = {10, 10, 0, 2}; Point(4) = {0, 10, 0, 2};\n"
         "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
         "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
         "/* a comment: SystemCall \"not run\"; */ Printf(\"no file\"); // Exit;\n" +
         command + "\n";
}


}  // namespace

TEST(GeoSandbox, CommandsThatActAreRefusedAtTheirLineAndNothingChanges) {
  const auto dir = freshDir("commands");
  std::ofstream(dir / "outside.geo") << "SystemCall \"touch INCLUDED_RAN\";\n";
  std::ofstream(dir / "scripts" / "victim.msh") << "the user's mesh\n";
  const std::map<std::string, std::string> cases = {
      {"system.geo", "SystemCall \"touch PWNED\";"},
      {"nonblocking.geo", "NonBlockingSystemCall \"touch PWNED\";"},
      {"save.geo", "Mesh 2; Save \"victim.msh\";"},
      {"printf.geo", "Printf(\"x = %g\", 1) > \"victim.txt\";"},
      {"include.geo", "Include \"../outside.geo\";"},
      {"exit.geo", "Exit;"},
      {"s2n.geo", "S2N[\"SystemCall\"] \"touch PWNED\";"},
  };
  for (const auto& [name, command] : cases) std::ofstream(dir / "scripts" / name) << squareWith(command);
  const auto before = listing(dir);
  for (const auto& [name, command] : cases) {
    SCOPED_TRACE(name);
    const std::string why = refusal([&] { mesh::readGmsh((dir / "scripts" / name).string()); });
    EXPECT_NE(why.find(name + ":5"), std::string::npos) << why;  // file:line
    const std::string word = command.substr(0, command.find_first_of(" ([;"));
    EXPECT_NE(why.find(word == "Mesh" ? "Save" : word), std::string::npos) << why;
  }
  EXPECT_EQ(listing(dir), before);
  fs::remove_all(dir);
}

TEST(GeoSandbox, ASurfaceFileHoldingAScriptCannotAct) {
  const auto dir = freshDir("off");
  std::ofstream(dir / "scripts" / "organ.off") << "SystemCall \"touch PWNED\";\nExit;\n";
  const auto before = listing(dir);
  const std::string why = refusal([&] { mesh::meshSurfaces({{(dir / "scripts" / "organ.off").string(), "organ"}}, 1.0); });
  EXPECT_NE(why.find("organ.off"), std::string::npos) << why;
  EXPECT_EQ(listing(dir), before);
  fs::remove_all(dir);
}

TEST(GeoSandbox, SurfacesTooFineForTheElementBudgetAreRefusedBeforeMeshing) {
  const auto dir = freshDir("fine_surface");
  // a closed tetrahedron of edge 10: 166.7 in regular tetrahedra of edge 0.01 is 1.4e9 of them
  std::ofstream(dir / "scripts" / "tet.stl") << R"(solid t
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 10 0
vertex 10 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 10 0 0
vertex 0 0 10
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 10
vertex 0 10 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 10 0 0
vertex 0 10 0
vertex 0 0 10
endloop
endfacet
endsolid t
)";
  const std::string why = refusal([&] { mesh::meshSurfaces({{(dir / "scripts" / "tet.stl").string(), "gel"}}, 0.01); });
  EXPECT_NE(why.find("about 1.41e+09 elements at an element size of 0.01 (file units), more than tissue.geometry.max_elements"), std::string::npos) << why;
  fs::remove_all(dir);
}

TEST(GeoSandbox, IncludesInTheFolderAreReadAndCheckedInTurn) {
  const auto dir = freshDir("include");
  std::ofstream(dir / "scripts" / "square.geo") << squareWith("");
  std::ofstream(dir / "scripts" / "main.geo") << "Include \"square.geo\";\n";
  const auto m = mesh::readGmsh((dir / "scripts" / "main.geo").string());
  EXPECT_EQ(m.element, "tri3");
  std::ofstream(dir / "scripts" / "bad.geo") << "\n\nExit;\n";
  std::ofstream(dir / "scripts" / "main2.geo") << "Include \"bad.geo\";\n";
  const std::string why = refusal([&] { mesh::readGmsh((dir / "scripts" / "main2.geo").string()); });
  EXPECT_NE(why.find("bad.geo:3"), std::string::npos) << why;
  std::ofstream(dir / "scripts" / "computed.geo") << "f = \"square.geo\";\nInclude f;\n";
  EXPECT_NE(refusal([&] { mesh::readGmsh((dir / "scripts" / "computed.geo").string()); }).find("computed.geo:2"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(GeoSandbox, TheChildCannotExecWriteOrDelete) {
  const auto dir = freshDir("child");
  std::ofstream(dir / "keep.txt") << "keep\n";
  const auto before = listing(dir);
  const std::string errnos = mesh::runIsolated("test", {}, [&] {
    std::string r;
    auto note = [&](const char* what, long rc) { r += fmt::format("{}={} ", what, rc < 0 ? errno : 0); };
    char* argv[] = {const_cast<char*>("/bin/sh"), const_cast<char*>("-c"), const_cast<char*>("touch EXECED"), nullptr};
    note("execve", ::execv("/bin/sh", argv));
    note("system", std::system(("touch " + (dir / "SYSTEM").string()).c_str()) == 0 ? 0 : -1);
    note("open", ::open((dir / "new.txt").c_str(), O_WRONLY | O_CREAT, 0644));
    note("openrw", ::open((dir / "keep.txt").c_str(), O_RDWR));
    note("unlink", ::unlink((dir / "keep.txt").c_str()));
    note("rename", ::rename((dir / "keep.txt").c_str(), (dir / "moved.txt").c_str()));
    note("mkdir", ::mkdir((dir / "sub").c_str(), 0755));
    note("fork", ::fork());
    note("socket", ::socket(AF_INET, SOCK_STREAM, 0));
    note("kill", ::kill(::getppid(), 0));
    note("read", ::open((dir / "keep.txt").c_str(), O_RDONLY) >= 0 ? 0 : -1);
    return r;
  });
  // every call but the read refused with EPERM (system() reports failure its own way)
  for (const char* call : {"execve", "open", "openrw", "unlink", "rename", "mkdir", "fork", "socket", "kill"})
    EXPECT_NE(errnos.find(fmt::format("{}={} ", call, EPERM)), std::string::npos) << call << ": " << errnos;
  EXPECT_NE(errnos.find("read=0"), std::string::npos) << errnos;
  EXPECT_EQ(listing(dir), before);
  fs::remove_all(dir);
}

TEST(GeoSandbox, AChildThatEndsOrCrashesIsAnInputErrorNamingTheFile) {
  std::string why = refusal([] { mesh::runIsolated("ends.geo", {}, []() -> std::string { std::exit(0); }); });
  EXPECT_NE(why.find("ends.geo"), std::string::npos) << why;
  EXPECT_NE(why.find("ended the reader without a result (Exit or Abort"), std::string::npos) << why;
  why = refusal([] { mesh::runIsolated("crashes.stl", {}, []() -> std::string { std::abort(); }); });
  EXPECT_NE(why.find("crashes.stl"), std::string::npos) << why;
  EXPECT_NE(why.find("Gmsh failed reading this file (signal SIGABRT"), std::string::npos) << why;
}

TEST(GeoSandbox, TheChildCannotTakeMoreMemoryThanItsBudget) {
  const mesh::MeshBudget budget{2e6, 60.0, 64.0 * 1048576};
  const std::string why = refusal([&] {
    mesh::runIsolated("big.geo", budget, [] {
      std::vector<char> block(std::size_t{1} << 30, 1);  // 1 GiB
      return std::string(1, block[12345]);
    });
  });
  EXPECT_NE(why.find("big.geo"), std::string::npos) << why;
  EXPECT_NE(why.find("more memory than tissue.geometry.max_mesh_memory_mib (64 MiB)"), std::string::npos) << why;
}

TEST(GeoSandbox, AnEndlessScriptIsStoppedAtTheTimeBudget) {
  const auto dir = freshDir("loop");
  std::ofstream(dir / "scripts" / "loop.geo") << "x = 0;\nFor i In {1:2000000000}\n  x += i;\nEndFor\n";
  const auto start = std::chrono::steady_clock::now();
  const std::string why = refusal([&] { mesh::readGmsh((dir / "scripts" / "loop.geo").string(), 0.0, {2e6, 2.0, 4096.0 * 1048576}); });
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(why.find("max_mesh_time (2 s)"), std::string::npos) << why;
  EXPECT_LT(took, 10.0);
  fs::remove_all(dir);
}

namespace {

// Readers that close their pipe at once and end within a few ms of the time budget (the moment
// swept in 0.25 ms steps across the parent's polling interval, 1 ms), beside a bystander process:
// 0 while the bystander lives. Run as PID 1 of a private PID namespace, so that a kill(-1, SIGKILL)
// (a signal to every process this user may reach) can only reach the bystander.
int bystanderSurvivesReadersEndingAtTheDeadline() {
  const pid_t bystander = ::fork();
  if (bystander == 0) {
    for (;;) ::pause();
  }
  const mesh::MeshBudget budget{2e6, 0.05, 4096.0 * 1048576};
  for (int step = 0; step < 48; ++step) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(40000 + 250 * step);
    try {
      mesh::runIsolated("late.geo", budget, [end] {
        ::close_range(3, ~0U, 0);  // the reply pipe among them: the parent sees its end now, the exit later
        std::this_thread::sleep_until(end);
        return std::string();
      });
    } catch (const InputError&) {  // the time budget, or no result: either is right at the deadline
    }
  }
  int status = 0;
  const bool alive = ::waitpid(bystander, &status, WNOHANG) == 0;
  ::kill(bystander, SIGKILL);
  return alive ? 0 : 1;
}

}  // namespace

// A reader that ends as its time budget runs out is reaped before the parent's deadline check; the
// parent must not then signal the pid it no longer holds (-1: every process of the user; a CI run
// lost all its processes that way).
TEST(GeoSandbox, AReaderEndingAtItsDeadlineSignalsNoOtherProcess) {
  const pid_t helper = ::fork();
  if (helper == 0) {
    if (::unshare(CLONE_NEWPID) != 0 && ::unshare(CLONE_NEWUSER | CLONE_NEWPID) != 0) ::_exit(77);
    const pid_t init = ::fork();  // PID 1 of the new namespace
    if (init == 0) ::_exit(bystanderSurvivesReadersEndingAtTheDeadline());
    int status = 0;
    ::waitpid(init, &status, 0);
    ::_exit(WIFEXITED(status) ? WEXITSTATUS(status) : 2);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(helper, &status, 0), helper);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "no private PID namespace here (unshare refused)";
  EXPECT_EQ(WEXITSTATUS(status), 0) << "a reader's parent killed a process that was not its reader";
}

TEST(GeoSandbox, ATooSmallElementSizeIsRefusedWithTheEstimateBeforeMeshing) {
  const auto dir = freshDir("size");
  const std::string box = "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 40, 40, 40};\n";
  std::ofstream(dir / "scripts" / "box.geo") << box;
  std::ofstream(dir / "scripts" / "fine.geo") << box << "Mesh.MeshSizeMax = 0.05;\n";
  const auto start = std::chrono::steady_clock::now();
  for (const auto& [file, size] : {std::pair{"box.geo", 0.05}, std::pair{"fine.geo", 0.0}}) {
    SCOPED_TRACE(file);
    const std::string why = refusal([&] { mesh::readGmsh((dir / "scripts" / file).string(), size); });
    // 64000 mm^3 in regular tetrahedra of edge 0.05 mm: 4.3e9
    EXPECT_NE(why.find("about 4.34e+09 elements at an element size of 0.05 (file units), more than tissue.geometry.max_elements (2e+06)"), std::string::npos) << why;
    EXPECT_NE(why.find("element_size"), std::string::npos) << why;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
  fs::remove_all(dir);
}

// A point at 1e400 (the fuzzer's mutant): Gmsh would fill the child's memory with elements of the
// script's own size; the bounds are checked before meshing.
TEST(GeoSandbox, AScriptReachingAnInfiniteCoordinateIsRefusedBeforeMeshing) {
  const auto dir = freshDir("infinite");
  std::ofstream(dir / "scripts" / "far.geo")
      << "Point(1) = {0, 1e400, 0, 2}; Point(2) = {10, 0, 0, 2}; Point(3) = {10, 10, 0, 2}; Point(4) = {0, 10, 0, 2};\n"
         "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
         "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\nPhysical Surface(\"gel\", 5) = {1};\n";
  const auto start = std::chrono::steady_clock::now();
  const std::string why = refusal([&] { mesh::readGmsh((dir / "scripts" / "far.geo").string(), 0.0); });
  EXPECT_NE(why.find("its geometry reaches (0, 0, 0) to (10, inf, 0)"), std::string::npos) << why;
  EXPECT_NE(why.find("finite coordinates"), std::string::npos) << why;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  fs::remove_all(dir);
}

TEST(GeoSandbox, AStopRequestEndsMeshingWithinASecond) {
  const auto dir = freshDir("stop");
  std::ofstream(dir / "scripts" / "loop.geo") << "x = 0;\nFor i In {1:2000000000}\n  x += i;\nEndFor\n";
  clearStopRequest();
  std::chrono::steady_clock::time_point asked;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    asked = std::chrono::steady_clock::now();
    requestStop(SIGINT);
  });
  bool interrupted = false;
  try {
    mesh::readGmsh((dir / "scripts" / "loop.geo").string());
  } catch (const RunInterrupted& e) {
    interrupted = true;
    EXPECT_EQ(e.signal(), SIGINT);
  }
  const double after = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
  stopper.join();
  clearStopRequest();
  EXPECT_TRUE(interrupted);
  EXPECT_LT(after, 1.0);
  fs::remove_all(dir);
}
