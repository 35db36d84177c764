// What lab software writes: each form of an example data file (BOM, quoted
// header, ';' with decimal commas, tabs, units in parentheses or as a suffix,
// percent strain) gives the same fit as the plain CSV of the same numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/fit/fit_command.hpp"

namespace fs = std::filesystem;
using namespace needlesim;
using namespace needlesim::fit;

namespace {

std::string example(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/data/" + f; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A plain example file split into its parts (comment lines, header names, rows of number texts).
struct Table {
  std::vector<std::string> comments, header;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> splitAt(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, sep);) {
    f.erase(0, f.find_first_not_of(' '));
    out.push_back(f);
  }
  return out;
}

Table readPlain(const std::string& file) {
  Table t;
  std::stringstream ss(slurp(example(file)));
  for (std::string line; std::getline(ss, line);) {
    if (line.empty()) continue;
    if (line[0] == '#') t.comments.push_back(line);
    else if (t.header.empty()) t.header = splitAt(line, ',');
    else t.rows.push_back(splitAt(line, ','));
  }
  return t;
}

// How a lab program writes the table.
struct Form {
  std::string sep = ",";
  bool decimalComma = false;
  bool bom = false;
  bool quoteHeader = false;
  std::string eol = "\n";
  std::vector<std::string> header;  // replaces the plain names when given
};

std::string render(const Table& t, const Form& f) {
  std::string out = f.bom ? "\xEF\xBB\xBF" : "";
  for (const auto& c : t.comments) out += c + f.eol;
  const auto& names = f.header.empty() ? t.header : f.header;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i ? f.sep : "") + (f.quoteHeader ? "\"" + names[i] + "\"" : names[i]);
  out += f.eol;
  for (const auto& r : t.rows) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      std::string v = r[i];
      if (f.decimalComma) std::replace(v.begin(), v.end(), '.', ',');
      out += (i ? f.sep : "") + v;
    }
    out += f.eol;
  }
  return out;
}

fs::path writeTemp(const std::string& name, const std::string& text) {
  fs::path p = fs::temp_directory_path() / ("needlesim_csv_forms_" + name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::vector<double> fittedParameters(const std::vector<fs::path>& files, const std::string& law) {
  FitRequest rq;
  rq.data = files;
  rq.law = law;
  rq.write = false;
  rq.thickness = 55e-3;
  const FitOutcome o = runFit(rq);
  std::vector<double> v;
  for (const auto& p : o.json["result"]["parameters"]) v.push_back(p["value"].get<double>());
  return v;
}

std::vector<double> fitText(const std::string& name, const std::string& text, const std::string& law = "neo-hookean") {
  const fs::path p = writeTemp(name, text);
  std::vector<double> v = fittedParameters({p}, law);
  fs::remove(p);
  return v;
}

std::string errorOfText(const std::string& text, const std::string& law = "neo-hookean") {
  const fs::path p = writeTemp("error.csv", text);
  try {
    fittedParameters({p}, law);
  } catch (const InputError& e) {
    fs::remove(p);
    return e.what();
  }
  fs::remove(p);
  return "(no error)";
}

void expectContains(const std::string& msg, std::initializer_list<std::string> parts) {
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

const Table& plastisol() {
  static const Table t = readPlain("plastisol_compression.csv");
  return t;
}

std::vector<double> plainFit() {
  static const std::vector<double> v = fittedParameters({example("plastisol_compression.csv")}, "neo-hookean");
  return v;
}

}  // namespace

TEST(CsvForms, PlainRenderIsTheExampleFit) {
  ASSERT_EQ(plastisol().header.size(), 2u);
  ASSERT_GT(plastisol().rows.size(), 30u);
  EXPECT_EQ(fitText("plain.csv", render(plastisol(), {})), plainFit());
}

TEST(CsvForms, Utf8ByteOrderMarkIsSkipped) {
  Form f;
  f.bom = true;
  EXPECT_EQ(fitText("bom.csv", render(plastisol(), f)), plainFit());
  f.eol = "\r\n";
  EXPECT_EQ(fitText("bom_crlf.csv", render(plastisol(), f)), plainFit());
}

TEST(CsvForms, QuotedHeader) {
  Form f;
  f.quoteHeader = true;
  EXPECT_EQ(fitText("quoted.csv", render(plastisol(), f)), plainFit());
}

TEST(CsvForms, SemicolonWithDecimalComma) {
  Form f;
  f.sep = ";";
  f.decimalComma = true;
  EXPECT_EQ(fitText("semicolon.csv", render(plastisol(), f)), plainFit());
}

TEST(CsvForms, TabSeparated) {
  Form f;
  f.sep = "\t";
  EXPECT_EQ(fitText("tab.tsv", render(plastisol(), f)), plainFit());
  f.decimalComma = true;
  EXPECT_EQ(fitText("tab_comma.tsv", render(plastisol(), f)), plainFit());
}

TEST(CsvForms, UnitsInParentheses) {
  Form f;
  f.header = {"Compressive Strain (%)", "Compressive Stress (kPa)"};
  EXPECT_EQ(fitText("parentheses.csv", render(plastisol(), f)), plainFit());
}

TEST(CsvForms, UnitsAsSuffix) {
  Form f;
  f.header = {"compressive_strain_pct", "compressive_stress_kPa"};
  EXPECT_EQ(fitText("suffix.csv", render(plastisol(), f)), plainFit());
  f.header = {"Compressive_Strain_percent", "compressive_stress_kPa"};
  EXPECT_EQ(fitText("suffix2.csv", render(plastisol(), f)), plainFit());
}

// Excel in a decimal-comma locale: BOM, CRLF, quoted names with units in parentheses, ';', decimal commas.
TEST(CsvForms, ExcelCsvUtf8WithDecimalCommas) {
  Form f;
  f.bom = true;
  f.eol = "\r\n";
  f.quoteHeader = true;
  f.sep = ";";
  f.decimalComma = true;
  f.header = {"Compressive strain (%)", "Compressive stress (kPa)"};
  EXPECT_EQ(fitText("excel.csv", render(plastisol(), f)), plainFit());
}

// Strain in percent, by any spelling of the unit, is the same data as strain in [1].
TEST(CsvForms, PercentStrain) {
  Table unitless = plastisol();
  unitless.header[0] = "compressive strain [1]";
  for (auto& r : unitless.rows) r[0] = std::to_string(std::stod(r[0]) / 100.0);
  const std::vector<double> ref = fitText("unitless.csv", render(unitless, {}));
  for (const std::string& strain : {"compressive strain (%)", "compressive_strain_pct", "compressive strain [percent]"}) {
    Form f;
    f.header = {strain, "compressive stress [kPa]"};
    const std::vector<double> v = fitText("percent.csv", render(plastisol(), f));
    ASSERT_EQ(v.size(), ref.size());
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(v[i], ref[i], 1e-9 * std::abs(ref[i])) << strain;
  }
}

// Insertion logs (the friction fit over four files) read the same from ';' files with decimal commas.
TEST(CsvForms, InsertionLogsWithSemicolonsAndDecimalCommas) {
  const std::vector<std::string> names{"gelatin_2.5mms.csv", "gelatin_3.33mms.csv", "gelatin_5mms.csv", "gelatin_10mms.csv"};
  std::vector<fs::path> plain, european;
  Form f;
  f.sep = ";";
  f.decimalComma = true;
  f.bom = true;
  for (const auto& n : names) {
    plain.push_back(example(n));
    european.push_back(writeTemp("eu_" + n, render(readPlain(n), f)));
  }
  EXPECT_EQ(fittedParameters(european, "friction"), fittedParameters(plain, "friction"));
  for (const auto& p : european) fs::remove(p);
}

// A column named 'compressive ...' holds magnitudes: a negative value there is a tensile
// point (e.g. load-cell noise at zero strain), not a compression of the same size.
TEST(CsvForms, NegativeValueInCompressiveColumnIsTension) {
  Table magnitudes = plastisol();
  magnitudes.rows.insert(magnitudes.rows.begin(), {"0.1", "-0.05"});
  Table signedData = magnitudes;
  signedData.header = {"strain [%]", "stress [kPa]"};
  for (auto& r : signedData.rows)
    for (auto& v : r) v = v[0] == '-' ? v.substr(1) : (v == "0" ? v : "-" + v);
  const std::vector<double> fromMagnitudes = fitText("magnitudes.csv", render(magnitudes, {}));
  EXPECT_EQ(fromMagnitudes, fitText("signed.csv", render(signedData, {})));
  // Read as -|x|, the noise point would be a compressive stress: a different fit.
  Table flipped = magnitudes;
  flipped.rows.front()[1] = "0.05";
  EXPECT_NE(fromMagnitudes, fitText("flipped.csv", render(flipped, {})));
}

TEST(CsvForms, SignedDataInCompressiveColumnIsRefused) {
  Table t = plastisol();
  for (auto& r : t.rows) r[1] = "-" + r[1];
  const std::string msg = errorOfText(render(t, {}));
  expectContains(msg, {"needlesim_csv_forms_error.csv:", "column 'compressive stress'", "kPa", "largest value is negative",
                       "compression negative", "'stress'", "--loading compression"});
  // The same numbers in a plain 'stress' column with --loading compression fit as the magnitudes do.
  t.header = {"compressive strain [%]", "stress [kPa]"};
  const fs::path p = writeTemp("signed_plain.csv", render(t, {}));
  FitRequest rq;
  rq.data = {p};
  rq.law = "neo-hookean";
  rq.write = false;
  rq.uniaxial.loading = Loading::Compression;
  const FitOutcome o = runFit(rq);
  EXPECT_EQ(o.json["result"]["parameters"][0]["value"].get<double>(), plainFit()[0]);
  fs::remove(p);
}

TEST(CsvForms, TensionLoadingContradictsACompressiveColumn) {
  const fs::path p = writeTemp("tension.csv", render(plastisol(), {}));
  FitRequest rq;
  rq.data = {p};
  rq.law = "neo-hookean";
  rq.write = false;
  rq.uniaxial.loading = Loading::Tension;
  try {
    runFit(rq);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expectContains(e.what(), {"--loading", "tension", "contradicts", "compressive strain"});
  }
  fs::remove(p);
}
