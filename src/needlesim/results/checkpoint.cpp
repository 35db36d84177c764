#include "needlesim/results/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <signal.h>
#include <unistd.h>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/results/results_folder.hpp"

namespace needlesim::io {
namespace fs = std::filesystem;

Checkpoint::Checkpoint(Settings settings) : s_(std::move(settings)), last_(std::chrono::steady_clock::now()) {}

fs::path Checkpoint::folderFor(const fs::path& target) {
  fs::path p = target;
  if (!p.has_filename()) p = p.parent_path();  // "out/" -> "out"
  p += ".checkpoint";
  return p;
}

bool Checkpoint::due(long long steps) const {
  if (s_.everySteps > 0 && steps > 0 && steps % s_.everySteps == 0) return true;
  if (!(s_.interval > 0)) return false;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - last_).count() >= s_.interval;
}

void Checkpoint::write(std::string_view engine, const BinaryWriter& state, const Series& fields, double time,
                       long long steps) {
  fs::create_directories(s_.folder);
  ++seq_;
  BinaryWriter w;
  w.tag("header");
  w.str(s_.fingerprint);
  w.str(engine);
  w.str(fmt::format("{} ({})", needlesim::kVersion, needlesim::kGitRevision));
  w.pod(time);
  w.pod(steps);
  w.pod(seq_);
  w.pod(static_cast<std::uint64_t>(fields.size()));
  std::vector<std::string> keep{"state.bin"};
  for (const auto& [name, series] : fields) {
    const std::string file = fmt::format("{}.{}.h5", name, seq_);
    w.str(name);
    w.str(file);
    series->saveState(w, s_.folder / file);
    keep.push_back(file);
  }
  w.tag("engine");
  w.str(state.bytes());
  writeFileAtomic(stateFile(), frameState("checkpoint", kVersion, w.bytes()));
  // The copies the new state.bin does not name (earlier checkpoints, temporaries).
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(s_.folder, ec)) {
    const std::string n = e.path().filename().string();
    if (std::find(keep.begin(), keep.end(), n) == keep.end()) fs::remove(e.path(), ec);
  }
  last_ = std::chrono::steady_clock::now();
  ++written_;
  if (s_.progress)
    fmt::print(stderr, "{}{}: checkpoint at t = {:.6g} s, step {} -> {}\n", Progress::stderrIsTerminal() ? "\r\033[K" : "",
               engine, time, steps, s_.folder.string());
}

namespace {
// Opens state.bin and checks the header up to the needlesim version.
BinaryReader openChecked(const fs::path& folder, const fs::path& file, const std::string& fingerprint,
                         std::string_view engine) {
  if (!fs::exists(folder) || !fs::exists(file))
    throw InputError(SourceLocation{file.string(), 0, 0}, "--resume", "",
                     "no checkpoint to resume (the run never wrote one, or it finished and removed it)",
                     "run without --resume; with output.checkpoint_interval > 0 a long mpm run writes one");
  BinaryReader r = readStateFile(file, "checkpoint", Checkpoint::kVersion);
  r.tag("header");
  if (r.str() != fingerprint)
    r.fail("belongs to another scenario (the scenario or its file changed since the checkpoint was written)");
  const std::string eng = r.str();
  if (eng != engine) r.fail(fmt::format("was written by engine '{}', this scenario runs '{}'", eng, engine));
  r.str();  // needlesim version that wrote it (informative)
  return r;
}
}  // namespace

void Checkpoint::check(std::string_view engine) const { openChecked(s_.folder, stateFile(), s_.fingerprint, engine); }

BinaryReader Checkpoint::load(std::string_view engine, const Series& fields) {
  const fs::path file = stateFile();
  BinaryReader r = openChecked(s_.folder, file, s_.fingerprint, engine);
  r.pod(resumedTime_);
  r.pod(resumedSteps_);
  r.pod(seq_);  // the next checkpoint takes the next number: the files of this one stay valid until then
  const auto n = r.pod<std::uint64_t>();
  if (n != fields.size())
    r.fail(fmt::format("holds {} field series, this run writes {} (another set-up)", n, fields.size()));
  for (const auto& [name, series] : fields) {
    if (r.str() != name) r.fail("holds other field series than this run writes (another set-up)");
    const std::string h5 = r.str();
    if (h5.find('/') != std::string::npos) r.fail("names a field file outside its folder (damaged file)");
    series->restore(r, s_.folder / h5);
  }
  r.tag("engine");
  BinaryReader state(r.str(), file.string());
  if (!r.atEnd()) r.fail("has data after its end (damaged file)");
  last_ = std::chrono::steady_clock::now();
  return state;
}

void Checkpoint::remove() {
  std::error_code ec;
  fs::remove_all(s_.folder, ec);
}

namespace {
// state.bin, <series>.<n>.h5, or a temporary of either (<file>.tmp.<pid>).
bool isCheckpointEntry(const fs::directory_entry& e) {
  std::string n = e.path().filename().string();
  if (const auto tmp = n.rfind(".tmp."); tmp != std::string::npos) n.resize(tmp);
  if (!e.is_regular_file()) return false;
  return n == "state.bin" || (n.size() > 3 && n.ends_with(".h5"));
}

bool startsWithStateMagic(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string head(kStateFileMagic.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  return in && head == kStateFileMagic;
}
}  // namespace

bool isCheckpointFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (!isCheckpointEntry(e)) return false;
  if (ec) return false;
  return !fs::exists(dir / "state.bin") || startsWithStateMagic(dir / "state.bin");
}

std::string scenarioFingerprint(const Scenario& sc) {
  std::uint64_t h = fnv1a64(sc.understood);
  std::error_code ec;
  if (!sc.source.empty() && fs::is_regular_file(sc.source, ec)) {
    std::ifstream in(sc.source, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    h = fnv1a64(text, h);
  }
  return fmt::format("{:016x}", h);
}

}  // namespace needlesim::io
