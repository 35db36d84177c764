// The CSV reader: the forms lab software writes read to the same numbers as
// plain CSV, and ambiguous files are refused naming file, line, column and value.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "needlesim/core/error.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/measured_data.hpp"

using namespace needlesim;

namespace {

const char* const kPlain = "depth [mm], force [N]\n0, 0\n1.5, 0.25\n3, 0.5\n";

std::string errorOf(const std::string& text) {
  try {
    io::parseCsv(text, "data.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

void expectContains(const std::string& msg, std::initializer_list<std::string> parts) {
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

void expectSameData(const io::CsvData& a, const io::CsvData& b) {
  ASSERT_EQ(a.columns.size(), b.columns.size());
  for (std::size_t c = 0; c < a.columns.size(); ++c) {
    EXPECT_EQ(a.columns[c].name, b.columns[c].name);
    EXPECT_EQ(a.columns[c].dim, b.columns[c].dim);
    EXPECT_EQ(a.values[c], b.values[c]) << a.columns[c].name;
  }
}

}  // namespace

TEST(CsvReader, LabFormsReadAsPlainCsv) {
  const io::CsvData plain = io::parseCsv(kPlain, "plain.csv");
  EXPECT_EQ(plain.formatNote(), "");
  for (const char* text : {
           "\xEF\xBB\xBF" "depth [mm], force [N]\n0, 0\n1.5, 0.25\n3, 0.5\n",  // UTF-8 byte-order mark
           "\"depth [mm]\",\"force [N]\"\r\n0,0\r\n1.5,0.25\r\n3,0.5\r\n",     // quoted header, CRLF
           "Depth (mm);Force (N)\n0;0\n1,5;0,25\n3;0,5\n",                       // ';', decimal commas
           "depth_mm\tforce_N\n0\t0\n1.5\t0.25\n3\t0.5\n",                       // tabs, unit suffixes
           "depth_mm\tforce_N\n0\t0\n1,5\t0,25\n3\t0,5\n",                       // tabs, decimal commas
           "\"Depth (mm)\";\"Force (N)\"\r0;0\r\"1,5\";0,25\r3;0,5\r",           // CR line ends, a quoted number
       })
    expectSameData(io::parseCsv(text, "form.csv"), plain);
  // A quoted name may hold the separator.
  const io::CsvData q = io::parseCsv("\"depth, tip [mm]\",force [N]\n1,2\n", "q.csv");
  EXPECT_EQ(q.columns[0].name, "depth, tip");
  EXPECT_DOUBLE_EQ(q.col(0)[0], 1e-3);
}

TEST(CsvReader, UnitsInBracketsParenthesesOrSuffix) {
  const io::CsvData d = io::parseCsv("Strain (%), stress_kPa, time_sec, Force (axial) (mN), tip_ux [mm], x\n10, 2, 3, 4, 5, 6\n",
                                     "u.csv");
  ASSERT_EQ(d.columns.size(), 6u);
  EXPECT_EQ(d.columns[0].name, "strain");
  EXPECT_DOUBLE_EQ(d.col(0)[0], 0.1);
  EXPECT_EQ(d.columns[1].name, "stress");
  EXPECT_DOUBLE_EQ(d.col(1)[0], 2000.0);
  EXPECT_EQ(d.columns[2].name, "time");
  EXPECT_EQ(d.columns[2].dim, units::dim::Time);
  EXPECT_EQ(d.columns[3].name, "force (axial)");
  EXPECT_DOUBLE_EQ(d.col(3)[0], 4e-3);
  EXPECT_EQ(d.columns[4].name, "tip ux");
  EXPECT_EQ(d.find({"tip_ux"}), 4);  // '_' and ' ' are the same in names
  EXPECT_EQ(d.columns[5].dim, units::dim::None);
  // A suffix that is not a unit stays in the name.
  const io::CsvData n = io::parseCsv("force_total [N], tip_uy\n1, 2\n", "n.csv");
  EXPECT_EQ(n.columns[0].name, "force total");
  EXPECT_EQ(n.columns[1].name, "tip uy");
}

TEST(CsvReader, FormatNoteSaysHowTheFileWasRead) {
  EXPECT_EQ(io::parseCsv("a [1];b [1]\n1,5;2\n", "f.csv").formatNote(),
            "read as columns separated by ';', numbers with decimal commas");
  EXPECT_EQ(io::parseCsv("a [1]\tb [1]\n1.5\t2\n", "f.csv").formatNote(), "read as columns separated by a tab");
}

TEST(CsvReader, AmbiguousSeparatorIsRefused) {
  expectContains(errorOf("strain [1]; stress, axial [kPa]\n0.1; 1\n"),
                 {"data.csv:1", "mixes column separators", "1 x ','", "1 x ';'", "double quotes"});
  expectContains(errorOf("strain [1]\tstress [kPa];x [1]\n"), {"data.csv:1", "a tab", "';'"});
}

TEST(CsvReader, AmbiguousDecimalMarksAreRefused) {
  // A decimal comma where commas separate the columns.
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, \"1,5\"\n"),
                 {"data.csv:2:", "column 'stress'", "'1,5'", "decimal comma in a comma-separated file", "';' or tabs"});
  // Both marks in one number: a thousands separator.
  expectContains(errorOf("strain [1]; stress [kPa]\n0,1; 1.234,5\n"),
                 {"data.csv:2:", "column 'stress'", "'1.234,5'", "more than one decimal mark", "1234,5"});
  expectContains(errorOf("strain [1]; stress [kPa]\n0,1; 1.234.567\n"), {"data.csv:2:", "'1.234.567'", "thousands"});
  // Decimal commas first, then a point (which may be a thousands separator).
  expectContains(errorOf("strain [1]; stress [kPa]\n0,1; 1,5\n0,2; 1.500\n"),
                 {"data.csv:3:", "column 'stress'", "'1.500'", "a decimal point", "line 2", "'0,1'", "a decimal comma",
                  "thousands separator", "one decimal mark in the whole file"});
  expectContains(errorOf("strain [1]\tstress [kPa]\n0.1\t1.5\n0,2\t1.5\n"),
                 {"data.csv:3:", "column 'strain'", "'0,2'", "a decimal comma", "line 2"});
  // Numbers with points in a ';' file read as points.
  const io::CsvData d = io::parseCsv("strain [1]; stress [kPa]\n0.1; 1.5\n", "p.csv");
  EXPECT_DOUBLE_EQ(d.col(1)[0], 1500.0);
  EXPECT_EQ(d.formatNote(), "read as columns separated by ';'");
}

TEST(CsvReader, QuotingProblemsAreRefused) {
  expectContains(errorOf("\"strain [1], stress [kPa]\n"), {"data.csv:1:1", "quote is not closed", "double quotes"});
  expectContains(errorOf("\"strain\" [1], stress [kPa]\n"), {"data.csv:1:", "text after the closing quote"});
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, \"1.5\n"), {"data.csv:2:", "quote is not closed"});
}

TEST(CsvReader, HeaderProblemsAreRefused) {
  expectContains(errorOf("Strain (%, stress [kPa]\n1, 2\n"), {"data.csv:1:", "column 'strain (%'", "no closing ')'"});
  expectContains(errorOf("strain (%) raw, stress [kPa]\n1, 2\n"), {"data.csv:1:", "text after the unit"});
  expectContains(errorOf("force (axial), depth [mm]\n1, 2\n"), {"data.csv:1:", "unknown unit", "axial"});
  expectContains(errorOf("force [N], force_min\n1, 2\n"),
                 {"data.csv:1:", "'force' appears twice", "'_min' is read as the unit", "force_min [N]"});
  expectContains(errorOf("force [N]; force [mN]\n1; 2\n"), {"data.csv:1:", "'force' appears twice"});
  expectContains(errorOf("strain [1];;stress [kPa]\n1;2;3\n"), {"data.csv:1:", "a column has no name"});
}

TEST(CsvReader, Utf16IsRefused) {
  expectContains(errorOf(std::string("\xFF\xFE" "s\0t\0", 6)), {"data.csv:1:1", "UTF-16", "CSV UTF-8"});
}

TEST(CsvReader, RowsKeepTheirSeparatorInMessages) {
  expectContains(errorOf("strain [1]; stress [kPa]\n0,1, 1\n"), {"data.csv:2", "1 fields", "names 2", "separated by ';'"});
  // Decimal commas in a comma-separated file split each number in two.
  expectContains(errorOf("strain [1], stress [kPa]\n0,1,1,5\n"),
                 {"data.csv:2", "4 fields", "names 2", "decimal commas need columns separated by ';' or tabs"});
}

TEST(CsvReader, FolderIsNotAFile) {
  try {
    io::readCsv(std::filesystem::temp_directory_path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expectContains(e.what(), {"is a folder", "CSV file"});
  }
}

// The scenario layer's measured force curve reads through the same reader.
TEST(CsvReader, MeasuredCurveFromExcelStyleFile) {
  const MeasuredCurve plain = scenario::measuredCurveFrom(io::parseCsv(kPlain, "plain.csv"));
  const MeasuredCurve excel = scenario::measuredCurveFrom(
      io::parseCsv("\xEF\xBB\xBF\"Insertion depth (mm)\";\"Force (N)\"\r\n0;0\r\n1,5;0,25\r\n3;0,5\r\n", "excel.csv"));
  EXPECT_EQ(excel.depth, plain.depth);
  EXPECT_EQ(excel.force, plain.force);
}

// Fits sum squares: a value whose square overflows is refused where it is written.
TEST(CsvReader, ValuesTooLargeToComputeWithAreRefused) {
  expectContains(errorOf("strain [1], stress [kPa]\n0.1, 1\n0.2, 1e308\n"),
                 {"data.csv:3:", "column 'stress'", "'1e308 kPa'", "too large to compute with", "1e100"});
  expectContains(errorOf("strain [1]; stress [Pa]\n0,1; -1e101\n"), {"data.csv:2:", "'-1e101 Pa'", "too large"});
  EXPECT_DOUBLE_EQ(io::parseCsv("strain [1], stress [Pa]\n0.1, 1e99\n", "ok.csv").col(1)[0], 1e99);
}

TEST(CsvReader, UnitExponentBeyondAnIntIsAnUnknownUnit) {
  expectContains(errorOf("strain [1], stress [m^99999999999]\n0.1, 1\n"), {"data.csv:1:", "column 'stress'", "unknown unit"});
  // As a suffix it is not a unit, so it stays in the name.
  EXPECT_EQ(io::parseCsv("stress_m^99999999999\n1\n", "n.csv").columns[0].name, "stress m^99999999999");
}
