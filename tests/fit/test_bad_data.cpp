// Bad data: each problem is an InputError naming the file and the line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "needlesim/core/error.hpp"
#include "needlesim/fit/fit_command.hpp"
#include "needlesim/fit/hyperelastic_fit.hpp"
#include "needlesim/io/csv_reader.hpp"

using namespace needlesim;
using namespace needlesim::fit;

namespace {

// Runs the whole reading + fitting path of `needlesim fit` on text and returns the error message.
std::string errorOf(const std::string& text, const std::string& law = "neo-hookean") {
  try {
    io::CsvData csv = io::parseCsv(text, "data.csv");
    UniaxialData d = readUniaxial(csv, {});
    fitHyperelastic(d, law);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

void expectContains(const std::string& msg, std::initializer_list<std::string> parts) {
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

}  // namespace

TEST(BadData, EmptyFile) {
  expectContains(errorOf(""), {"data.csv:1", "empty"});
  expectContains(errorOf("# only a comment\n\n"), {"data.csv:1", "empty"});
  expectContains(errorOf("strain [1], stress [Pa]\n"), {"data.csv:1", "no data rows"});
}

TEST(BadData, MissingColumn) {
  expectContains(errorOf("strain [1]\n0.1\n0.2\n"), {"data.csv:1", "no column for stress or force", "'stress'"});
  expectContains(errorOf("stress [Pa]\n10\n20\n"), {"data.csv:1", "strain"});
}

TEST(BadData, TextInANumber) {
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1.0\n0.2, abc\n"),
                 {"data.csv:3:", "column 'stress'", "not a number", "'abc'"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1.0\n0.2, 1.5x\n"), {"data.csv:3:", "1.5x"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1.0\n0.2\n"), {"data.csv:3", "1 fields", "names 2"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, \n"), {"data.csv:2:", "missing"});
}

TEST(BadData, NaNAndInfinity) {
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1.0\n0.2, NaN\n"), {"data.csv:3:", "not a finite number", "NaN"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, inf\n"), {"data.csv:2:", "not a finite number"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1e999\n"), {"data.csv:2:"});
}

TEST(BadData, NonMonotonicStrain) {
  expectContains(errorOf("strain [%], stress [kPa]\n1, 0.1\n2, 0.2\n1.5, 0.15\n3, 0.3\n"),
                 {"data.csv:4", "not monotonic", "line 3"});
  expectContains(errorOf("strain [%], stress [kPa]\n1, 0.1\n1, 0.2\n3, 0.3\n"), {"data.csv:3", "not monotonic"});
  expectContains(errorOf("strain [1], stress [kPa]\n-0.5, -1\n-1.2, -3\n"), {"data.csv:3", "stretch <= 0"});
}

TEST(BadData, FewerPointsThanParameters) {
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1\n0.2, 2\n", "mooney-rivlin"),
                 {"data.csv:3", "too few points", "at least 3"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1\n", "neo-hookean"), {"data.csv:2", "too few points"});
}

TEST(BadData, UnknownLawAndWrongUnits) {
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1\n0.2, 2\n0.3, 3\n", "hookean"), {"--law", "hookean", "neo-hookean"});
  expectContains(errorOf("strain [1], stress [mm]\n0.1, 1\n"), {"data.csv:1:", "wrong dimension", "Pa"});
  expectContains(errorOf("strain [1], stress [kPaa]\n0.1, 1\n"), {"data.csv:1:", "unknown unit", "kPaa"});
  expectContains(errorOf("strain [1], stress [kPa\n0.1, 1\n"), {"data.csv:1:", "closing"});
  expectContains(errorOf("strain [1]; stress [kPa], x [1]\n0.1; 1\n"), {"data.csv:1", "mixes column separators"});
  FitRequest rq;
  rq.data = {"x.csv"};
  rq.law = "elastic";
  rq.write = false;
  try {
    runFit(rq);
    FAIL();
  } catch (const InputError& e) {
    expectContains(e.what(), {"--law", "elastic", "auto", "friction"});
  }
}

TEST(BadData, MissingFileAndExistingOutputFolder) {
  FitRequest rq;
  rq.data = {"/nonexistent/dir/data.csv"};
  rq.law = "fung";
  rq.write = false;
  try {
    runFit(rq);
    FAIL();
  } catch (const InputError& e) {
    expectContains(e.what(), {"/nonexistent/dir/data.csv", "cannot be opened"});
  }
  auto dir = std::filesystem::temp_directory_path() / "needlesim_fit_exists.fit";
  std::filesystem::create_directories(dir);
  rq.data = {std::string(NEEDLESIM_SOURCE_DIR) + "/examples/data/plastisol_compression.csv"};
  rq.out = dir;
  rq.write = true;
  EXPECT_THROW(runFit(rq), InputError);
  std::filesystem::remove_all(dir);
}

// Units: % and kPa are converted to SI.
TEST(CsvReader, ConvertsUnitsToSI) {
  auto csv = io::parseCsv("# comment\nStrain [%], Stress [kPa]\r\n10, 2.5\n\n20, 5\n", "u.csv");
  ASSERT_EQ(csv.rows(), 2u);
  EXPECT_EQ(csv.columns[0].name, "strain");
  EXPECT_DOUBLE_EQ(csv.col(0)[1], 0.2);
  EXPECT_DOUBLE_EQ(csv.col(1)[0], 2500.0);
  EXPECT_EQ(csv.lines[1], 5);
}
