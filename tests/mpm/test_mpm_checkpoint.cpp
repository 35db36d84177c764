// Checkpoints of the mpm engine (results/checkpoint.hpp, MpmSolver::saveState /
// loadState; docs/models/mpm.md "Checkpoints"): a run interrupted after a
// checkpoint and resumed must give the same results folder, bit for bit, as
// one uninterrupted run with the same thread count; a checkpoint of another
// scenario, a damaged one or a missing one is refused with an error naming
// the file; the checkpoint folder is removed once the results are committed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mpm_test_materials.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/results/checkpoint.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::mpm;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << s;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

// The quick example (2304 points, a conical 20 G needle 5 mm deep, markers,
// fields every 0.25 s) shortened to `depth` and run on `threads` threads.
std::string quickScenario(int threads, const std::string& depth = "2 mm") {
  std::string s = slurp(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/mpm/quick_needle_block.yaml");
  s = replaced(s, "insert: {to: 5 mm", "insert: {to: " + depth);
  s = replaced(s, "field_interval: 0.25 s", "field_interval: 0.1 s\n    threads: " + std::to_string(threads));
  return s;
}

struct Dir {
  fs::path path;
  explicit Dir(const std::string& name)
      : path(fs::temp_directory_path() / ("needlesim_ckpt_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
};

io::Checkpoint::Settings settings(const Scenario& sc, const fs::path& target, long long every, bool resume) {
  return {io::Checkpoint::folderFor(target), io::scenarioFingerprint(sc), 0.0, every, resume, false};
}

// Runs `sc` into target with a checkpoint every `every` steps, stopped after `stop` steps.
void interruptedRun(const Scenario& sc, const fs::path& target, long long every, long long stop) {
  io::Checkpoint ck(settings(sc, target, every, false));
  RunOptions o;
  o.progress = false;
  o.checkpoint = &ck;
  o.stopAfterSteps = stop;
  EXPECT_THROW(runScenario(sc, target, false, o), RunInterrupted);
  EXPECT_EQ(ck.written(), 1);
}

std::string errorOfResume(const Scenario& sc, const fs::path& target) {
  io::Checkpoint ck(settings(sc, target, 0, true));
  RunOptions o;
  o.progress = false;
  o.checkpoint = &ck;
  try {
    runScenario(sc, target, false, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

double result(const nlohmann::json& summary, const std::string& key) {
  return summary.at("results").at(key).at("value").get<double>();
}

// Uninterrupted vs interrupted after 2/3 of the steps (checkpoint at 1/3) and
// resumed; `inclusions`: a tissue.inclusions list added to the scenario (with the grid contact,
// which sliding inclusions and per-region needle friction need).
void resumedRunIsIdentical(int threads, const std::string& depth, const std::string& inclusions = "") {
  Dir dir("resume_" + std::to_string(threads) + (inclusions.empty() ? "" : "_inclusions"));
  const fs::path file = dir.path / "quick.yaml";
  std::string text = quickScenario(threads, depth);
  if (!inclusions.empty()) {
    text = replaced(text, "  friction: {coefficient: 0.255}\n", "  friction: {coefficient: 0.255}\n  inclusions:\n" + inclusions);
    text = replaced(text, "    threads: ", "    contact: grid\n    threads: ");
  }
  spit(file, text);
  const Scenario sc = scenario::readFile(file);
  RunOptions plain;
  plain.progress = false;
  const fs::path ref = dir.path / "ref", res = dir.path / "res";
  runScenario(sc, ref, false, plain);
  const auto refSummary = nlohmann::json::parse(slurp(ref / "summary.json"));
  const auto steps = static_cast<long long>(result(refSummary, "steps"));
  ASSERT_GT(steps, 30);
  const long long every = steps / 3;
  interruptedRun(sc, res, every, 2 * every - 1);  // the frames and rows after the checkpoint are lost
  EXPECT_FALSE(fs::exists(res));
  ASSERT_TRUE(fs::exists(io::Checkpoint::folderFor(res) / "state.bin"));
  {
    // Resumed, checkpointed again and killed again: a checkpoint of a resumed run resumes too.
    io::Checkpoint again(settings(sc, res, every, true));
    RunOptions o = plain;
    o.checkpoint = &again;
    o.stopAfterSteps = 2 * every + 5;
    EXPECT_THROW(runScenario(sc, res, false, o), RunInterrupted);
    EXPECT_EQ(again.written(), 1);
  }
  // What a crash in the middle of the next checkpoint leaves: a half copy of
  // the fields and a half-written temporary state file beside the good ones.
  const fs::path folder = io::Checkpoint::folderFor(res);
  spit(folder / "particles.99.h5", "half an HDF5 file");
  spit(folder / "state.bin.tmp.12345", slurp(folder / "state.bin").substr(0, 100));

  io::Checkpoint ck(settings(sc, res, 0, true));
  RunOptions o = plain;
  o.checkpoint = &ck;
  runScenario(sc, res, false, o);
  EXPECT_EQ(ck.resumedSteps(), 2 * every);
  EXPECT_FALSE(fs::exists(io::Checkpoint::folderFor(res))) << "the checkpoint outlived the committed results";

  // Every CSV byte for byte (full precision), every key result bit for bit.
  int csvs = 0;
  for (const auto& e : fs::directory_iterator(ref)) {
    if (e.path().extension() != ".csv") continue;
    ++csvs;
    EXPECT_EQ(slurp(e.path()), slurp(res / e.path().filename())) << e.path().filename();
  }
  EXPECT_GE(csvs, 4);  // forces, energy, markers, fracture
  const auto resSummary = nlohmann::json::parse(slurp(res / "summary.json"));
  EXPECT_EQ(refSummary.at("results"), resSummary.at("results"));
  for (const auto& [key, v] : refSummary.at("results").items())
    if (v.at("value").is_number())
      EXPECT_EQ(std::memcmp(&v.at("value").get_ref<const double&>(),
                            &resSummary.at("results").at(key).at("value").get_ref<const double&>(), sizeof(double)),
                0)
          << key;
  // The field series: the same steps at the same times (the XDMF lists both).
  const std::string xr = slurp(ref / "particles.xdmf"), xs = slurp(res / "particles.xdmf");
  std::size_t frames = 0;
  for (std::size_t i = xr.find("<Time "); i != std::string::npos; i = xr.find("<Time ", i + 1)) ++frames;
  EXPECT_GE(frames, 3u);
  EXPECT_EQ(xr, xs);
  EXPECT_EQ(slurp(ref / "needle.xdmf"), slurp(res / "needle.xdmf"));  // the needle series resumes too
  // The resumed run says so.
  bool said = false;
  for (const auto& n : resSummary.at("notes"))
    said = said || n.get<std::string>().find(fmt::format("Resumed from the checkpoint at t = ")) != std::string::npos;
  EXPECT_TRUE(said);
}

}  // namespace

TEST(MpmCheckpoint, ResumedRunIsBitIdenticalOneThread) { resumedRunIsIdentical(1, "2 mm"); }

// Two threads: the coloured scatter's block order is part of the state (a
// shorter insertion: two threads on 2304 points mostly wait at barriers).
TEST(MpmCheckpoint, ResumedRunIsBitIdenticalTwoThreads) { resumedRunIsIdentical(2, "0.3 mm"); }

// A sliding target in the needle's path (a second body in pair contact, its
// motion in inclusions.csv) and a bonded sphere with another needle friction.
TEST(MpmCheckpoint, ResumedRunWithInclusionsIsBitIdentical) {
  resumedRunIsIdentical(1, "2 mm",
                        "    - {name: target, depth: 3 mm, radius: 1 mm, interface: sliding, interface_friction: 0.2,\n"
                        "       target: true, material: {law: fung, mu: 30 kPa, gamma: 1.0, nu: 0.45}}\n"
                        "    - {name: bonded, depth: 5 mm, lateral: 1.5 mm, radius: 1 mm, friction: 0.5,\n"
                        "       material: {law: fung, mu: 30 kPa, gamma: 1.0, nu: 0.45}}\n");
}

TEST(MpmCheckpoint, RefusesAnotherScenarioAndDamagedFiles) {
  Dir dir("refuse");
  const fs::path file = dir.path / "quick.yaml", res = dir.path / "res";
  spit(file, quickScenario(1));
  const Scenario sc = scenario::readFile(file);
  const fs::path state = io::Checkpoint::folderFor(res) / "state.bin";

  // No checkpoint at all.
  EXPECT_NE(errorOfResume(sc, res).find("no checkpoint to resume"), std::string::npos) << errorOfResume(sc, res);

  interruptedRun(sc, res, 20, 30);
  const std::string good = slurp(state);

  // The scenario changed (a slower insertion).
  spit(file, replaced(quickScenario(1), "speed: 6 mm/s", "speed: 5 mm/s"));
  const Scenario other = scenario::readFile(file);
  std::string e = errorOfResume(other, res);
  EXPECT_NE(e.find(state.string()), std::string::npos) << e;
  EXPECT_NE(e.find("another scenario"), std::string::npos) << e;
  EXPECT_TRUE(fs::exists(state)) << "a refused resume must keep the checkpoint";
  spit(file, quickScenario(1));

  // Truncated (a crash while copying it, a full disk).
  spit(state, good.substr(0, good.size() / 2));
  e = errorOfResume(sc, res);
  EXPECT_NE(e.find(state.string()), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  // One flipped byte in the particle data.
  std::string bad = good;
  bad[bad.size() / 2] ^= 0x20;
  spit(state, bad);
  e = errorOfResume(sc, res);
  EXPECT_NE(e.find(state.string()), std::string::npos) << e;
  EXPECT_NE(e.find("corrupt"), std::string::npos) << e;
  // Not a state file.
  spit(state, "hello");
  e = errorOfResume(sc, res);
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  spit(state, "hello, this is not a needlesim state file at all");
  e = errorOfResume(sc, res);
  EXPECT_NE(e.find("not a needlesim state file"), std::string::npos) << e;
  // The good one still resumes (and nothing above removed it).
  spit(state, good);
  EXPECT_EQ(errorOfResume(sc, res), "(no InputError)");
  EXPECT_FALSE(fs::exists(state.parent_path()));
}

// ---------------------------------------------------------------- solver round trip

namespace {

// Steps `a` k steps, saves it into a fresh solver `b` made by `make`, then
// steps both n more steps: the states must agree bit for bit.
void roundTrip(const std::function<MpmSolver()>& make, int k, int n, const std::function<void(MpmSolver&)>& before = {}) {
  MpmSolver a = make();
  for (int i = 0; i < k; ++i) {
    if (before) before(a);
    a.step();
  }
  if (a.config().bodies > 1) EXPECT_GT(a.lastReport().contact, 0.0) << "save in contact";
  io::BinaryWriter w;
  a.saveState(w);
  MpmSolver b = make();
  io::BinaryReader r(w.bytes(), "test state");
  b.loadState(r);
  ASSERT_EQ(a.time(), b.time());
  ASSERT_EQ(a.steps(), b.steps());
  for (int i = 0; i < n; ++i) {
    if (before) {
      before(a);
      before(b);
    }
    const StepReport ra = a.step(), rb = b.step();
    ASSERT_EQ(ra.dt, rb.dt) << "step " << i;
    ASSERT_EQ(ra.kinetic, rb.kinetic) << "step " << i;
    ASSERT_EQ(ra.contact, rb.contact) << "step " << i;
  }
  std::size_t differ = 0;
  for (std::size_t p = 0; p < a.size(); ++p) {
    const Vec3 xa = a.position(p), xb = b.position(p), va = a.velocity(p), vb = b.velocity(p);
    const Mat3 Fa = a.defGrad(p), Fb = b.defGrad(p);
    if (std::memcmp(xa.data(), xb.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(va.data(), vb.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(Fa.data(), Fb.data(), sizeof(double) * 9) != 0)
      ++differ;
  }
  EXPECT_EQ(differ, 0u) << "of " << a.size() << " points";
  const MpmSolver start = make();
  double moved = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) moved = std::max(moved, (a.position(p) - start.position(p)).norm());
  EXPECT_GT(moved, 0.1 * a.particleSpacing()) << "the test moved nothing";
}

// Two elastic blocks (4 x 10 x 4 mm) approaching along x at 2 x 0.5 m/s, 1 mm
// apart, two-body penalty contact with friction: in contact from about step
// 30 (1 ms). On two threads the scatter order (sorted by grid block, the
// blocks by colour) is not the creation order (body by body, x-major): a lost
// block order shows.
MpmSolver twoBlocks(int threads) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-3e-3, -3e-3, -3e-3);
  cfg.cells = {15, 16, 10};
  cfg.bodies = 2;
  cfg.friction = 0.3;
  cfg.threads = threads;
  MpmSolver s(cfg);
  s.addMaterial(test::linearMaterial(1e5, 0.3, 1000));
  s.addBlock(Vec3(0, 0, 0), Vec3(4e-3, 10e-3, 4e-3), 0.5e-3, 0, 0, Vec3(0.5, 0.1, 0));
  s.addBlock(Vec3(5e-3, 0, 0), Vec3(9e-3, 10e-3, 4e-3), 0.5e-3, 0, 1, Vec3(-0.5, -0.1, 0));
  s.finalize();
  return s;
}

// A block pushed by a rigid conical needle moving at 1 m/s (grid contact with friction).
MpmSolver needleBlock(int threads, bool cfemp) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-3e-3, -3e-3, -3e-3);
  cfg.cells = {14, 12, 12};
  cfg.threads = threads;
  cfg.boxLo = Vec3::Zero();
  cfg.boxHi = Vec3(8e-3, 6e-3, 6e-3);
  cfg.faces[1] = FaceBC::Fixed;  // x+
  MpmSolver s(cfg);
  s.addMaterial(test::linearMaterial(2e4, 0.45, 1000));
  s.addBlock(Vec3(0, 0, 0), Vec3(8e-3, 6e-3, 6e-3), 0.5e-3, 0, 0);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = RigidBody::Tip::Conical;
  n.radius = 0.5e-3;
  n.axis = Vec3::UnitX();
  n.point = Vec3(-0.2e-3, 3e-3, 3e-3);
  n.velocity = Vec3(1.0, 0, 0);
  n.friction = 0.2;
  n.surfaceContact = cfemp;
  n.elementSize = 0.3e-3;
  s.addRigid(n);
  s.finalize();
  return s;
}

void moveNeedle(MpmSolver& s) { s.rigid(0).point = Vec3(-0.2e-3 + s.time() * 1.0, 3e-3, 3e-3); }

}  // namespace

TEST(MpmCheckpoint, SolverStateRoundTripTwoBodyPenalty) {
  roundTrip([] { return twoBlocks(1); }, 60, 60);
}

TEST(MpmCheckpoint, SolverStateRoundTripTwoBodyPenaltyTwoThreads) {
  roundTrip([] { return twoBlocks(2); }, 45, 20);
}

TEST(MpmCheckpoint, SolverStateRoundTripRigidNeedle) {
  roundTrip([] { return needleBlock(1, false); }, 120, 80, moveNeedle);
  roundTrip([] { return needleBlock(1, true); }, 120, 80, moveNeedle);  // CFEMP surface contact
}

TEST(MpmCheckpoint, SolverStateOfAnotherSetUpIsRefused) {
  MpmSolver a = twoBlocks(2);
  a.step();
  io::BinaryWriter w;
  a.saveState(w);
  auto error = [&](MpmSolver b) {
    io::BinaryReader r(w.bytes(), "state.bin");
    try {
      b.loadState(r);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no InputError)");
  };
  const std::string threads = error(twoBlocks(1));
  EXPECT_NE(threads.find("2 thread(s), this one has 1"), std::string::npos) << threads;
  const std::string other = error(needleBlock(2, false));
  EXPECT_NE(other.find("material points"), std::string::npos) << other;
  EXPECT_NE(other.find("state.bin"), std::string::npos) << other;
}
