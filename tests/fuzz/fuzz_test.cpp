// Seeded mutation fuzzing of the readers users feed text to: the scenario
// reader, the CSV reader with every analysis that reads its tables (fit,
// measured data), field paths as a study applies them, and the geometry
// readers (STL ascii and binary, OBJ, VTP, PLY, OFF surfaces; Gmsh .msh 2 and
// 4 and .geo scripts through Gmsh's library). Each target starts
// from the valid inputs in tests/fuzz/corpus/<target>/ and applies byte flips,
// insertions, deletions, splices from other corpus files, number swaps (huge,
// NaN, negative, malformed) and unit swaps, with std::mt19937_64 and a fixed
// seed, so every run tries the same mutants. Every mutant must either be read
// or be refused with needlesim::InputError: another exception type fails the
// test, and a crash or a mutant running longer than kHangSeconds prints the
// mutant (hex-escaped) before the process ends.
//
// Geometry targets try fewer mutants by default (kGeometryMutants: each is a file written and read;
// half as many .geo scripts, each meshed in a child process).
// The corpus of the geometry targets is written by tests/fuzz/make_geometry_corpus.py.
//
// Longer runs: NEEDLESIM_FUZZ_MUTANTS=100000 NEEDLESIM_FUZZ_SEED=7 build/release/tests/test_fuzz
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cxxabi.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <thread>
#include <typeinfo>

#include "needlesim/core/error.hpp"
#include "needlesim/fit/hyperelastic_fit.hpp"
#include "needlesim/fit/insertion.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/mesh/closed_surface.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/mesh/surface_formats.hpp"
#include "needlesim/scenario/measured_data.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"

namespace fs = std::filesystem;
using namespace needlesim;

// Under LeakSanitizer (the debug preset): Gmsh 4.8 leaks the elements of a .msh it stops reading
// halfway (GModel::_readMSH2/_readMSH4, MElementFactory::create); those are Gmsh's, not needlesim's.
extern "C" const char* __lsan_default_suppressions() { return "leak:libgmsh.so\n"; }

namespace {

constexpr int kDefaultMutants = 3000;
constexpr int kGeometryMutants = 600;
constexpr std::uint64_t kDefaultSeed = 19;
constexpr int kHangSeconds = 20;
constexpr std::size_t kReportedFailures = 10;

fs::path corpusDir(const std::string& target) {
  return fs::path(NEEDLESIM_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / target;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::uint64_t envNumber(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

// ---- Reporting a mutant: printable ASCII as is, everything else \xNN (also from a signal handler).

std::size_t escapeByte(unsigned char c, char* out) {
  static const char* const hex = "0123456789abcdef";
  if (c == '\n') return out[0] = '\\', out[1] = 'n', 2;
  if (c >= 0x20 && c < 0x7f && c != '\\') return out[0] = static_cast<char>(c), 1;
  out[0] = '\\';
  out[1] = 'x';
  out[2] = hex[c >> 4];
  out[3] = hex[c & 15];
  return 4;
}

std::string escaped(std::string_view s) {
  std::string out;
  char b[4];
  for (char c : s) out.append(b, escapeByte(static_cast<unsigned char>(c), b));
  return out;
}

// The mutant under test, for the crash and hang reports.
std::atomic<const char*> gTarget{""};
std::atomic<const std::string*> gMutant{nullptr};
std::atomic<long long> gStartedNs{0};  // 0: nothing running

void writeAll(const char* s, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(STDERR_FILENO, s, n);
    if (w <= 0) return;
    s += w;
    n -= static_cast<std::size_t>(w);
  }
}
void writeText(const char* s) { writeAll(s, std::char_traits<char>::length(s)); }

void reportCurrentMutant(const char* what) {
  writeText("\nfuzz: ");
  writeText(what);
  writeText(" in target '");
  writeText(gTarget.load());
  writeText("' on the mutant (hex-escaped):\n");
  if (const std::string* m = gMutant.load()) {
    char b[4];
    for (char c : *m) writeAll(b, escapeByte(static_cast<unsigned char>(c), b));
  }
  writeText("\n");
}

extern "C" void onCrash(int sig) {
  reportCurrentMutant(sig == SIGSEGV ? "SIGSEGV" : sig == SIGABRT ? "SIGABRT" : sig == SIGFPE ? "SIGFPE" : "SIGBUS");
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

long long nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Ends the process, printing the mutant, when one mutant runs longer than kHangSeconds.
class Watchdog {
 public:
  Watchdog() : thread_([this] { watch(); }) {
    for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS}) std::signal(sig, onCrash);
  }
  ~Watchdog() {
    stop_ = true;
    thread_.join();
    for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS}) std::signal(sig, SIG_DFL);
  }

 private:
  void watch() {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      const long long start = gStartedNs.load();
      if (start != 0 && nowNs() - start > kHangSeconds * 1'000'000'000LL) {
        reportCurrentMutant("a hang (over the time limit per mutant)");
        std::_Exit(124);
      }
    }
  }
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// ---- Mutations.

const std::vector<std::string> kNumberSwaps{
    "1e400", "-1e400", "1e-400", "nan", "NaN", "-nan", "inf", "-inf", "-0", "0", "-1", "-5", "1e308", "-1e308",
    "99999999999", "-99999999999", "99999999999999999999999", "0x10", "1.2.3", "1,5", "1.234,5", "+", "-", ".",
    "1e", "4.9e-324", "2147483648", "-2147483649", "1_000", "0.0000000000000000001"};
const std::vector<std::string> kUnits{"mm/s", "N s/m^2", "N/m", "kg/m^3", "kPa", "GPa", "MPa", "Pa", "mm",
                                      "deg",  "ms",      "N",   "s",      "G",   "%",   "m"};
const std::vector<std::string> kUnitSwaps{"mm", "kPa", "N", "s", "mm/s", "deg", "%", "G", "1", "-", "Pa^2", "m/s/s",
                                          "\xC2\xB5m", "furlong", "", "kPaa", "N s/m^2", "rad", "1/0", "m^99999"};
const std::vector<std::string> kTokens{
    "\xEF\xBB\xBF", "\"", ",", ";", "\t", "\n", "\r", "\r\n", "[", "]", "(", ")", "_", "#", ":", ": ", "- ", "{", "}",
    "&a ", "*a", "<<: *a", "!!binary ", "!tag ", "? ", "|", std::string(1, '\0'), "\xFF\xFE", "\xC3\x28", "~", "null",
    "[-1]", "[99999999999]", "[x]", "[0]", ".", "..", "\\", "'", "---\n", "...\n", "%YAML 1.2\n", "  ", "\n  "};

class Mutator {
 public:
  Mutator(std::uint64_t seed, const std::vector<std::string>& corpus) : rng_(seed), corpus_(corpus) {}

  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng_() % n); }

  std::string mutate(std::string s) {
    const std::size_t count = 1 + below(4);
    for (std::size_t k = 0; k < count; ++k) {
      switch (below(8)) {
        case 0: flipByte(s); break;
        case 1: insertBytes(s); break;
        case 2: insertToken(s); break;
        case 3: deleteRange(s); break;
        case 4: splice(s); break;
        case 5: swapNumber(s); break;
        case 6: swapUnit(s); break;
        case 7: repeatLine(s); break;
      }
    }
    return s;
  }

 private:
  void flipByte(std::string& s) {
    if (s.empty()) return;
    char& c = s[below(s.size())];
    c = below(2) ? static_cast<char>(c ^ (1 << below(8))) : static_cast<char>(below(256));
  }
  void insertBytes(std::string& s) {
    std::string bytes(1 + below(8), '\0');
    for (char& c : bytes) c = static_cast<char>(below(256));
    s.insert(below(s.size() + 1), bytes);
  }
  void insertToken(std::string& s) { s.insert(below(s.size() + 1), kTokens[below(kTokens.size())]); }
  void deleteRange(std::string& s) {
    if (s.empty()) return;
    const std::size_t at = below(s.size());
    s.erase(at, 1 + below(below(2) ? 8 : 256));
  }
  void splice(std::string& s) {
    const std::string& other = corpus_[below(corpus_.size())];
    if (other.empty()) return;
    const std::size_t from = below(other.size());
    const std::string chunk = other.substr(from, 1 + below(64));
    const std::size_t at = below(s.size() + 1);
    if (below(2)) s.insert(at, chunk);
    else s.replace(at, chunk.size(), chunk);
  }
  // A number written in the text (digits with sign, point, comma or exponent) becomes another.
  void swapNumber(std::string& s) {
    std::vector<std::size_t> digits;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (std::isdigit(static_cast<unsigned char>(s[i])) && (i == 0 || !std::isdigit(static_cast<unsigned char>(s[i - 1]))))
        digits.push_back(i);
    if (digits.empty()) return;
    const auto inNumber = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E'; };
    std::size_t b = digits[below(digits.size())], e = b;
    while (b > 0 && (inNumber(s[b - 1]) || s[b - 1] == '-' || s[b - 1] == '+')) --b;
    while (e < s.size() && (inNumber(s[e]) || ((s[e] == '-' || s[e] == '+') && (s[e - 1] == 'e' || s[e - 1] == 'E')))) ++e;
    s.replace(b, e - b, kNumberSwaps[below(kNumberSwaps.size())]);
  }
  // A unit after a number, in brackets or parentheses, or as a '_' suffix becomes another.
  void swapUnit(std::string& s) {
    std::vector<std::pair<std::size_t, std::size_t>> found;
    for (const auto& u : kUnits)
      for (std::size_t at = s.find(u); at != std::string::npos; at = s.find(u, at + 1)) {
        const char before = at > 0 ? s[at - 1] : '\0';
        const char after = at + u.size() < s.size() ? s[at + u.size()] : '\0';
        if ((before == ' ' || before == '[' || before == '(' || before == '_') && !std::isalnum(static_cast<unsigned char>(after)))
          found.emplace_back(at, u.size());
      }
    if (found.empty()) return;
    const auto [at, n] = found[below(found.size())];
    s.replace(at, n, kUnitSwaps[below(kUnitSwaps.size())]);
  }
  void repeatLine(std::string& s) {
    if (s.empty()) return;
    const std::size_t at = below(s.size());
    const std::size_t b = s.rfind('\n', at) == std::string::npos ? 0 : s.rfind('\n', at) + 1;
    const std::size_t e = std::min(s.find('\n', at), s.size());
    const std::string line = s.substr(b, e - b) + "\n";
    std::string copies;
    for (std::size_t k = 1 + below(40); k > 0; --k) copies += line;
    s.insert(b, copies);
  }

  std::mt19937_64 rng_;
  const std::vector<std::string>& corpus_;
};

// ---- Running targets.

// An exception other than InputError, named by the step that let it out.
struct Escaped {
  std::string what;
};

std::string typeName(const std::exception& e) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> d(abi::__cxa_demangle(typeid(e).name(), nullptr, nullptr, &status), std::free);
  return status == 0 && d ? d.get() : typeid(e).name();
}

// Runs one step of a target: InputError is an answer, anything else escapes with the step's name.
template <class F>
void step(const std::string& name, F&& f) {
  try {
    f();
  } catch (const InputError&) {
  } catch (const Escaped&) {
    throw;  // from a step inside this one, already named
  } catch (const std::exception& e) {
    throw Escaped{name + ": " + typeName(e) + ": " + e.what()};
  } catch (...) {
    throw Escaped{name + ": an exception that is not a std::exception"};
  }
}

struct Target {
  std::string name;
  std::vector<std::string> names, corpus;  // corpus file names and contents
  // Reads one input (corpus file `source` or a mutant of it); must return or throw InputError.
  std::function<void(const std::string& text, const std::string& source)> read;
};

Target loadTarget(const std::string& name, std::function<void(const std::string&, const std::string&)> read) {
  Target t{name, {}, {}, std::move(read)};
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(corpusDir(name)))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    t.names.push_back(f.string());
    t.corpus.push_back(slurp(f));
  }
  return t;
}

struct FuzzReport {
  int mutants = 0, read = 0, refused = 0;
  double seconds = 0;
  std::vector<std::string> failures;
  struct Kind {
    int count = 0;
    std::string smallest;  // the first mutant of this kind, minimized
  };
  std::map<std::string, Kind> kinds;  // escaped exception (step, type, start of message)
};

// An escaped exception's kind for the summary: "step: type: " and the start of
// its message, with numbers (byte positions, values) written '#'.
std::string kindOf(const std::string& what) {
  const std::size_t typeEnd = what.find(": ", what.find(": ") + 2);
  const std::string head = what.substr(0, typeEnd == std::string::npos ? what.size() : std::min(what.size(), typeEnd + 42));
  std::string k;
  for (char c : head)
    if (!std::isdigit(static_cast<unsigned char>(c))) k += c;
    else if (k.empty() || k.back() != '#') k += '#';
  return k;
}

// Outcome of one input: true when read, false when refused with InputError; Escaped otherwise.
bool readOnce(const Target& t, const std::string& text, const std::string& source) {
  gMutant = &text;
  gStartedNs = nowNs();
  bool read = false;
  try {
    step(t.name, [&] {
      t.read(text, source);
      read = true;
    });
  } catch (...) {
    gStartedNs = 0;
    throw;
  }
  gStartedNs = 0;
  return read;
}

// A smaller input that fails the same way: chunks of halving size are dropped while the kind stays.
std::string minimize(const Target& t, std::string input, const std::string& source, const std::string& kind) {
  const auto failsTheSameWay = [&](const std::string& s) {
    try {
      readOnce(t, s, source);
      return false;
    } catch (const Escaped& e) {
      return kindOf(e.what) == kind;
    }
  };
  int tries = 0;
  for (std::size_t chunk = std::max<std::size_t>(input.size() / 2, 1); chunk >= 1 && tries < 4000; chunk /= 2)
    for (std::size_t at = 0; at < input.size() && tries < 4000; ++tries) {
      std::string smaller = input.substr(0, at) + input.substr(std::min(input.size(), at + chunk));
      if (failsTheSameWay(smaller)) input = std::move(smaller);
      else at += chunk;
    }
  return input;
}

FuzzReport fuzz(const Target& t, int defaultMutants) {
  FuzzReport r;
  gTarget = t.name.c_str();
  Watchdog watchdog;
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t seed = envNumber("NEEDLESIM_FUZZ_SEED", kDefaultSeed);
  Mutator mutator(seed, t.corpus);
  const int n = static_cast<int>(envNumber("NEEDLESIM_FUZZ_MUTANTS", static_cast<std::uint64_t>(defaultMutants)));
  for (int i = 0; i < n; ++i) {
    const std::size_t k = mutator.below(t.corpus.size());
    const std::string mutant = mutator.mutate(t.corpus[k]);
    ++r.mutants;
    try {
      (readOnce(t, mutant, t.names[k]) ? r.read : r.refused)++;
    } catch (const Escaped& e) {
      FuzzReport::Kind& kind = r.kinds[kindOf(e.what)];
      if (kind.count++ == 0) kind.smallest = minimize(t, mutant, t.names[k], kindOf(e.what));
      r.failures.push_back("mutant " + std::to_string(i) + " of " + fs::path(t.names[k]).filename().string() +
                           " (seed " + std::to_string(seed) + "): " + e.what + "\n  input: " + escaped(mutant));
    }
  }
  gMutant = nullptr;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

void expectCorpusReads(const Target& t) {
  ASSERT_FALSE(t.corpus.empty()) << "no corpus in " << corpusDir(t.name);
  for (std::size_t k = 0; k < t.corpus.size(); ++k) {
    try {
      EXPECT_TRUE(readOnce(t, t.corpus[k], t.names[k])) << t.names[k] << " is refused: the corpus must be valid input";
    } catch (const Escaped& e) {
      ADD_FAILURE() << t.names[k] << ": " << e.what;
    }
  }
}

void runTarget(const Target& t, int defaultMutants = kDefaultMutants) {
  expectCorpusReads(t);
  const FuzzReport r = fuzz(t, defaultMutants);
  std::string failures;
  for (const auto& [kind, k] : r.kinds)
    failures += std::to_string(k.count) + " x " + kind + "\n  smallest: " + escaped(k.smallest) + "\n";
  for (std::size_t i = 0; i < std::min(r.failures.size(), kReportedFailures); ++i) failures += r.failures[i] + "\n";
  std::printf("fuzz %s: %d mutants in %.2f s: %d read, %d refused with InputError, %zu failures\n", t.name.c_str(),
              r.mutants, r.seconds, r.read, r.refused, r.failures.size());
  EXPECT_TRUE(r.failures.empty()) << r.failures.size() << " mutant(s) of " << t.name
                                  << " escaped with another exception than InputError (by kind, then the first "
                                  << std::min(r.failures.size(), kReportedFailures) << "):\n" << failures;
}

// ---- The readers.

// A result a fit returns must be a number: no silent NaN.
void expectFinite(const std::string& what, std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) throw Escaped{what + ": returned a non-finite value"};
}

void expectFiniteParameters(const fit::FitResult& r) {
  for (const auto& p : r.params) expectFinite(r.law + " parameter " + p.name, {p.value});
}

// Every analysis that reads a CSV table: the fits, insertion logs and the scenario's measured data.
void readCsvEveryWay(const std::string& text, const std::string& source) {
  const io::CsvData csv = io::parseCsv(text, source);  // InputError: the file is refused
  fit::UniaxialReadOptions opt;
  opt.sample.height = 18e-3;
  opt.sample.area = 900e-6;
  step("uniaxial fit", [&] { expectFiniteParameters(fit::fitHyperelastic(fit::readUniaxial(csv, opt), "neo-hookean")); });
  step("relaxation fit", [&] { expectFiniteParameters(fit::fitProny(fit::readRelaxation(csv, opt.sample), 1)); });
  step("insertion logs", [&] {
    const auto logs = fit::readInsertionLogs(csv);
    fit::ToughnessOptions t;
    t.diameter = 0.71e-3;
    t.shaftLength = 55e-3;
    for (const auto& log : logs) {
      step("puncture", [&] {
        const fit::Puncture p = fit::detectPuncture(log);
        expectFinite("puncture", {p.depth, p.force, p.drop});
      });
      step("toughness", [&] { expectFinite("toughness G_c", {fit::ruptureToughness(log, t).Gc}); });
    }
    step("friction fit", [&] {
      const fit::FrictionFit f = fit::fitFrictionCutting(logs, 55e-3, fit::CuttingModel::PerSpeed);
      expectFinite("friction fit C_p, b_p", {f.C, f.b});
    });
  });
  step("friction summary", [&] {
    const fit::FrictionFit f = fit::frictionFromSummaries(fit::readFrictionSummaries(csv), csv.file);
    expectFinite("friction summary C_p, b_p", {f.C, f.b});
  });
  step("measured force", [&] { scenario::measuredCurveFrom(csv); });
  step("measured markers", [&] { scenario::measuredMarkersFrom(csv, {{"beside_tip", 3e-3, 1.5e-3, 0.0}}); });
}

void readScenario(const std::string& text, const std::string& source) { scenario::readText(text, source); }

// A field path as a study applies it: one line 'path = value' of the corpus, varied
// over the base scenario (field_path/base.yaml) by study::expandCases, which also
// reads the resulting scenario.
void applyFieldPath(const std::string& text, const std::string& source) {
  static const std::string base = slurp(corpusDir("field_path") / "base.yaml");
  const std::size_t eq = text.find('=');
  study::Parameter p;
  p.field = std::string(text.substr(0, eq == std::string::npos ? text.size() : eq));
  p.values = {eq == std::string::npos ? "1 mm" : text.substr(eq + 1)};
  p.line = 1;
  for (std::string* s : {&p.field, &p.values.front()}) {
    s->erase(0, s->find_first_not_of(" \t\r\n"));
    s->erase(s->find_last_not_of(" \t\r\n") + 1);
  }
  study::StudySpec spec;
  spec.name = "fuzz";
  spec.file = source;
  spec.method = study::Method::List;
  spec.parameters = {p};
  study::expandCases(spec, base);
}

// The field-path corpus: one 'path = value' per line of field_path/paths.txt.
Target fieldPathTarget() {
  Target t{"field_path", {}, {}, applyFieldPath};
  std::stringstream ss(slurp(corpusDir("field_path") / "paths.txt"));
  for (std::string line; std::getline(ss, line);)
    if (!line.empty() && line[0] != '#') {
      t.names.push_back((corpusDir("field_path") / "paths.txt").string());
      t.corpus.push_back(line);
    }
  return t;
}

// A geometry file: the input written to a file of the given extension in a folder of this process,
// then read as the scenario reads it.
struct GeometryFolder {
  fs::path dir = fs::temp_directory_path() / ("needlesim_fuzz_" + std::to_string(::getpid()));
  GeometryFolder() { fs::create_directories(dir); }
  ~GeometryFolder() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

std::string geometryFile(const std::string& text, const std::string& extension) {
  static const GeometryFolder folder;
  const fs::path p = folder.dir / ("input" + extension);
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
  return p.string();
}

// A surface as meshSurfaces reads it: one of needlesim's readers, then whether it is closed.
std::function<void(const std::string&, const std::string&)> surfaceReader(const std::string& extension) {
  return [extension](const std::string& text, const std::string&) {
    const auto s = mesh::readOwnSurfaceFormat(geometryFile(text, extension));
    if (!s) throw Escaped{"readOwnSurfaceFormat: no reader for " + extension};
    mesh::openEdge(*s);
  };
}

// A mesh or script through Gmsh's library (format 2 or 4 .msh, .geo meshed at its own sizes).
std::function<void(const std::string&, const std::string&)> gmshReader(const std::string& extension) {
  return [extension](const std::string& text, const std::string&) { mesh::readGmsh(geometryFile(text, extension)); };
}

}  // namespace

TEST(Fuzz, CsvReaderAndFits) { runTarget(loadTarget("csv", readCsvEveryWay)); }

TEST(Fuzz, ScenarioReader) { runTarget(loadTarget("scenario", readScenario)); }

TEST(Fuzz, FieldPaths) { runTarget(fieldPathTarget()); }

TEST(Fuzz, StlAscii) { runTarget(loadTarget("stl_ascii", surfaceReader(".stl")), kGeometryMutants); }

TEST(Fuzz, StlBinary) { runTarget(loadTarget("stl_binary", surfaceReader(".stl")), kGeometryMutants); }

TEST(Fuzz, Obj) { runTarget(loadTarget("obj", surfaceReader(".obj")), kGeometryMutants); }

TEST(Fuzz, Vtp) { runTarget(loadTarget("vtp", surfaceReader(".vtp")), kGeometryMutants); }

TEST(Fuzz, Ply) { runTarget(loadTarget("ply", surfaceReader(".ply")), kGeometryMutants); }

TEST(Fuzz, Off) { runTarget(loadTarget("off", surfaceReader(".off")), kGeometryMutants); }

TEST(Fuzz, Msh2) { runTarget(loadTarget("msh2", gmshReader(".msh")), kGeometryMutants); }

TEST(Fuzz, Msh4) { runTarget(loadTarget("msh4", gmshReader(".msh")), kGeometryMutants); }

// Scripts are meshed in the sandboxed child (mesh/isolated_reader), one process per mutant: fewer.
TEST(Fuzz, Geo) { runTarget(loadTarget("geo", gmshReader(".geo")), kGeometryMutants / 2); }
