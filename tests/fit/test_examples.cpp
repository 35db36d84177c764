// The worked examples of docs/fitting.md run through the same path as the CLI.
#include <gtest/gtest.h>

#include <regex>

#include "needlesim/fit/fit_command.hpp"

using namespace needlesim::fit;

namespace {
std::string ex(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/data/" + f; }
double param(const nlohmann::json& j, const std::string& name) {
  for (const auto& p : j["result"]["parameters"])
    if (p["name"] == name) return p["value"].get<double>();
  return -1;
}
}  // namespace

// The PVA compression example fitted with the Fung law (18 mm high, 900 mm^2 sample).
static FitRequest pvaFungRequest() {
  FitRequest rq;
  rq.data = {ex("pva_compression.csv")};
  rq.law = "fung";
  rq.write = false;
  rq.uniaxial.sample.height = 18e-3;
  rq.uniaxial.sample.area = 900e-6;
  return rq;
}

TEST(Examples, PvaFungFromForceDisplacement) {
  auto o = runFit(pvaFungRequest());
  // generated with mu = 2.3 kPa, gamma = 3.1 and 1 % noise (make_examples.py)
  EXPECT_NEAR(param(o.json, "mu"), 2.3e3, 0.03 * 2.3e3);
  EXPECT_NEAR(param(o.json, "gamma"), 3.1, 0.05 * 3.1);
  EXPECT_NE(o.materialYaml.find("law: fung"), std::string::npos);
}

TEST(Examples, ResidualStatisticsNameTheirStressUnit) {
  const auto o = runFit(pvaFungRequest());
  const std::regex line(R"(RMSE = [0-9.]+ k?Pa, mean \|res\| = [0-9.]+ k?Pa, max \|res\| = [0-9.]+ k?Pa \(seed)");
  EXPECT_TRUE(std::regex_search(o.table, line)) << o.table;
}

TEST(Examples, FrictionFromFourSpeeds) {
  FitRequest rq;
  rq.data = {ex("gelatin_2.5mms.csv"), ex("gelatin_3.33mms.csv"), ex("gelatin_5mms.csv"), ex("gelatin_10mms.csv")};
  rq.law = "friction";
  rq.thickness = 55e-3;
  rq.write = false;
  auto o = runFit(rq);
  auto ps = o.json["result"]["parameters"];
  EXPECT_NEAR(ps[0]["value"].get<double>(), 3.791, 0.05);
  EXPECT_NEAR(ps[1]["value"].get<double>(), 285.053, 5.0);
}

TEST(Examples, ToughnessAndProny) {
  FitRequest rq;
  rq.data = {ex("plastisol_toughness.csv")};
  rq.law = "toughness";
  rq.needleDiameter = 0.71e-3;
  rq.thickness = 102e-3;
  rq.deltaC = 0.71e-3;
  rq.write = false;
  auto o = runFit(rq);
  // G_c A = F_cut L1 with F_cut = 0.16 N over L1 = L2 - puncture depth
  double A = 3.14159265358979 / 4 * 0.71e-3 * 0.71e-3;
  double L1 = o.json["runs"][0]["toughness"]["L1"].get<double>();
  EXPECT_NEAR(o.json["G_c_mean"].get<double>(), 0.16 * L1 / A, 0.02 * 0.16 * L1 / A);
  FitRequest rp;
  rp.data = {ex("muscle_relaxation.csv")};
  rp.law = "prony";
  rp.write = false;
  auto p = runFit(rp);
  EXPECT_EQ(p.json["result"]["terms"].get<int>(), 2);
}
