#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "needlesim/core/error.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/html_report.hpp"
#include "needlesim/io/references.hpp"
#include "needlesim/io/table.hpp"

using namespace needlesim::io;

TEST(Table, CsvHeaderNamesQuantitiesAndUnitsAndKeepsPrecision) {
  Table t({{"time", "s"}, {"force", "N"}});
  t.addRow({0.0, 1.0 / 3.0});
  t.addRow({1e-3, -2.5e-7});
  EXPECT_EQ(t.csv(), "time [s],force [N]\n0,0.3333333333\n0.001,-2.5e-07\n");
  EXPECT_EQ(t.column("force")[1], -2.5e-7);
  EXPECT_THROW(t.addRow({1.0}), needlesim::Error);
}

TEST(AtomicFile, ReplacesContentAndLeavesNoTemporaryFile) {
  auto dir = std::filesystem::temp_directory_path() / ("needlesim_atomic_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  writeFileAtomic(dir / "a.txt", "one");
  writeFileAtomic(dir / "a.txt", "two");
  std::ifstream in(dir / "a.txt");
  std::string s;
  in >> s;
  EXPECT_EQ(s, "two");
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++files;
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

TEST(HtmlReport, ThinsLongSeriesButKeepsThePeakAndDropsNaN) {
  HtmlReport r;
  r.title = "t <&>";
  PlotSeries s{"force", {}, {}};
  for (int i = 0; i < 100000; ++i) {
    s.x.push_back(i);
    s.y.push_back(i == 54321 ? 99.0 : std::sin(i * 1e-3));
  }
  s.x.push_back(1e6);
  s.y.push_back(NAN);
  r.plots.push_back(Plot{"p", "x", "y", {s}});
  std::string html = r.render();
  EXPECT_NE(html.find("t &lt;&amp;&gt;"), std::string::npos);
  EXPECT_NE(html.find("\"x\":54321.0,\"y\":99.0"), std::string::npos);
  std::string data = html.substr(html.find("const plots = "));
  EXPECT_EQ(data.find("NaN"), std::string::npos);
  EXPECT_EQ(data.find("null"), std::string::npos);
  EXPECT_LT(html.size(), 600000u);
}

// A wide, long table (a study's cases) scrolls inside a box at most 80 % of the window high,
// so that its sideways scroll bar is on screen, keeps its header rows in view, and says above
// it when its right part is out of view.
TEST(HtmlReport, AWideTableScrollsInABoxWithItsScrollBarOnScreen) {
  HtmlReport r;
  HtmlTable t;
  t.caption = "Cases";
  t.groups = {{"", 1}, {"inputs (varied)", 20}};
  t.header.push_back("case");
  for (int c = 0; c < 20; ++c) t.header.push_back("tissue.friction.field_" + std::to_string(c) + " [N/m]");
  for (int row = 0; row < 60; ++row) t.rows.push_back(std::vector<std::string>(21, "0.123456"));
  r.tables.push_back(t);
  const std::string html = r.render();
  const auto style = html.substr(html.find(".tablewrap{"), 200);
  EXPECT_NE(style.find("overflow:auto"), std::string::npos) << style;
  EXPECT_NE(style.find("max-height:80vh"), std::string::npos) << style;
  EXPECT_NE(html.find(".tablewrap thead{position:sticky;top:0"), std::string::npos);
  const auto head = html.find("<thead><tr class=\"groups\">"), body = html.find("</tr></thead>\n<tbody>");
  ASSERT_NE(head, std::string::npos);
  ASSERT_NE(body, std::string::npos);
  EXPECT_LT(head, body);
  EXPECT_LT(body, html.find("<td>0.123456</td>"));
  EXPECT_NE(html.find("class=\"scrollhint\""), std::string::npos);  // written by the page's script
}

// Every publication of docs/references.md is read, and a report lists the full citation of
// each seed it names (and only those).
TEST(HtmlReport, ListsTheCitationOfEverySeedItNames) {
  const auto& c = needlesim::io::seedCitations();
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NE(c.at("003").find("Needle tissue interaction modelling"), std::string::npos);
  EXPECT_NE(c.at("004").find("Misra"), std::string::npos);
  EXPECT_EQ(c.at("004").find('*'), std::string::npos);  // markdown emphasis dropped
  EXPECT_NE(c.at("004").find("10.1109/BIOROB.2008.4762872 (https://doi.org/"), std::string::npos);

  needlesim::io::HtmlReport r;
  r.title = "t";
  r.notes = {"Puncture force from seed 003 eq 3.16; tip loads as in seed 002."};
  const std::string html = r.render();
  EXPECT_NE(html.find("<h2>References</h2>"), std::string::npos);
  EXPECT_NE(html.find("<li>seed 002: S. Misra"), std::string::npos);
  EXPECT_NE(html.find("<li>seed 003: "), std::string::npos);
  EXPECT_EQ(html.find("<li>seed 004: "), std::string::npos);
  r.notes = {"no citation"};
  EXPECT_EQ(r.render().find("<h2>References</h2>"), std::string::npos);
}
