// The steering engines end to end: a scenario text through scenario::readText and the
// registered engine into an in-memory ResultSink, checked against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/steering/beam_foundation.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"
#include "needlesim/engines/steering/table2.hpp"
#include "needlesim/needle/section.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
constexpr double pi = std::numbers::pi;

namespace {

struct MemorySink : ResultSink {
  std::map<std::string, double> r;
  std::map<std::string, io::Table> tables;
  int plots = 0;
  void table(const std::string& name, io::Table t) override { tables[name] = std::move(t); }
  void result(const std::string& key, double v, const std::string&, const std::string&) override { r[key] = v; }
  void plot(io::Plot) override { ++plots; }
  void note(const std::string&) override {}
  double at(const std::string& k) const {
    auto it = r.find(k);
    if (it == r.end()) throw std::runtime_error("no result " + k);
    return it->second;
  }
};

// Gel C, 0.54 mm Nitinol (seed 002 sections 2.4, 3.1, 5.2), one profile and model section.
std::string scenarioText(const std::string& engine, const std::string& profile, const std::string& steering,
                         const std::string& tip = "bevel") {
  return "name: t\n"
         "tissue:\n"
         "  block: {length: 200 mm, width: 100 mm, height: 100 mm}\n"
         "  material: {law: neo-hookean, C10: 7.55 kPa, nu: 0.45}\n"
         "  interaction: {K_T: 12.61 kN/m^2, toughness: 46.8 kN/m}\n"
         "needle: {outer_diameter: 0.54 mm, inner_diameter: 0 mm, length: 200 mm, bevel_angle: 34.85 deg, "
         "youngs_modulus: 50 GPa, tip: " +
         tip + "}\n" + "insertion:\n  profile:\n" + profile + "model:\n  engine: " + engine +
         "\n  steering: {" + steering + "}\n";
}
const std::string straight150 = "    - insert: {to: 150 mm, speed: 2.5 mm/s}\n";

MemorySink run(const std::string& text) {
  const Scenario sc = scenario::readText(text, "test.yaml");
  const EngineInfo* e = findEngine(sc.model.engine);
  if (!e) throw std::runtime_error("engine not registered: " + sc.model.engine);
  MemorySink s;
  e->run(sc, s, RunOptions{false});
  return s;
}

}  // namespace

TEST(SteeringEngines, AreRegistered) {
  for (const char* n : {"kinematic", "energy", "beam-foundation"}) EXPECT_NE(findEngine(n), nullptr) << n;
}

TEST(SteeringEngines, KinematicRadiusIsOneOverKappaFromTheScenario) {
  const MemorySink s = run(scenarioText("kinematic", straight150, "curvature: 4 1/m"));
  const double r = 0.25, L = 0.15;
  EXPECT_NEAR(s.at("radius_whole"), r, 1e-9);
  for (const char* k : {"radius_0_50mm", "radius_50_100mm", "radius_100_150mm"}) EXPECT_NEAR(s.at(k), r, 1e-9) << k;
  EXPECT_NEAR(s.at("tip_y"), -r * (1 - std::cos(L / r)), 1e-12);  // towards the bevel (-y)
  EXPECT_NEAR(s.at("tip_x"), r * std::sin(L / r), 1e-12);
  EXPECT_NEAR(s.at("tip_z"), 0.0, 1e-15);
  ASSERT_TRUE(s.tables.count("tip_path") && s.tables.count("needle_shapes"));
  EXPECT_EQ(s.tables.at("tip_path").rows(), 151u);
  EXPECT_GE(s.plots, 3);
}

TEST(SteeringEngines, KinematicFlipInTheProfileGivesTheSCurve) {
  const std::string prof = "    - insert: {to: 75 mm, speed: 2.5 mm/s}\n"
                           "    - rotate: {by: 180 deg, rate: 360 deg/s}\n"
                           "    - insert: {to: 150 mm, speed: 2.5 mm/s}\n";
  const MemorySink s = run(scenarioText("kinematic", prof, "curvature: 4 1/m"));
  const double r = 0.25, th = 0.075 / r;
  EXPECT_NEAR(s.at("tip_y"), -2 * r * (1 - std::cos(th)), 1e-12);
  EXPECT_NEAR(s.at("tip_x"), 2 * r * std::sin(th), 1e-12);
}

TEST(SteeringEngines, KinematicDutyCyclingFromSpinRateAndDutyCycle) {
  // 2.5 mm/s, one turn per cycle at 360 deg/s for 50 % of the time: 5 mm cycles,
  // kappa_eff = kappa (1 - DC) = 2 1/m (Minhas et al. 2007)
  const std::string prof = "    - insert: {to: 150 mm, speed: 2.5 mm/s, spin_rate: 360 deg/s, duty_cycle: 0.5}\n";
  const MemorySink s = run(scenarioText("kinematic", prof, "curvature: 4 1/m, increment: 0.25 mm"));
  EXPECT_NEAR(s.at("curvature_whole"), 2.0, 0.02 * 2.0);
  // without duty cycling the same needle curves at 4 1/m
  const MemorySink f = run(scenarioText("kinematic", straight150, "curvature: 4 1/m"));
  EXPECT_NEAR(f.at("curvature_whole"), 4.0, 1e-6);
}

TEST(SteeringEngines, KinematicWithoutCurvatureUsesTheBeamFoundationClosedForm) {
  const MemorySink k = run(scenarioText("kinematic", straight150, "beta_over_alpha: 0.75, input_force: 15 mN"));
  const MemorySink b = run(scenarioText("beam-foundation", straight150, "beta_over_alpha: 0.75, input_force: 15 mN"));
  // closed form by hand: Q = P/tan(beta), kappa = Q/(lambda EI), lambda = (K_T/4EI)^(1/4)
  const double EI = needle::Section{50e9, 0.54e-3, 0}.EI(), KT = 12.61e3, P = 15e-3;
  const double beta = 0.75 * 34.85 * pi / 180, lambda = std::pow(KT / (4 * EI), 0.25);
  const double kappa = P / std::tan(beta) / (lambda * EI);
  EXPECT_NEAR(k.at("curvature"), kappa, 1e-9 * kappa);
  EXPECT_NEAR(b.at("curvature_closed_form"), kappa, 1e-9 * kappa);
  EXPECT_NEAR(k.at("radius_whole"), 1 / kappa, 1e-6);
  // the beam model converges to it at O(h) (docs/models/steering.md); the axial load P_input,
  // absent from the closed form, adds ~1 % here
  EXPECT_NEAR(b.at("radius_whole"), 1 / kappa, 0.025 / kappa);
  EXPECT_LT(b.at("tip_y"), 0.0);
}

TEST(SteeringEngines, BeamFoundationTipLoadChoice) {
  const MemorySink roller = run(scenarioText("beam-foundation", straight150, "beta_over_alpha: 0.5, input_force: 10 mN"));
  const double beta = 0.5 * 34.85 * pi / 180;
  EXPECT_NEAR(roller.at("applied_Q"), -10e-3 / std::tan(beta), 1e-15);
  EXPECT_EQ(roller.at("applied_M"), 0.0);
  const MemorySink edges =
      run(scenarioText("beam-foundation", straight150, "beta_over_alpha: 0.2, tip_load: bevel-edges"));
  EXPECT_EQ(edges.at("applied_Q"), edges.at("tip_Q"));  // eq 25
  EXPECT_EQ(edges.at("applied_M"), edges.at("tip_M"));  // eq 26
  // the edge loads of eq 25 are sub-mN for a 0.54 mm needle: a much straighter path
  EXPECT_LT(std::abs(edges.at("tip_Q")), 2e-3);
  EXPECT_GT(edges.at("radius_whole"), 5 * roller.at("radius_whole"));
  // a planar case stays exactly planar (a dangling Eigen expression once made it drift and blow up)
  EXPECT_EQ(edges.at("tip_z"), 0.0);
  EXPECT_EQ(roller.at("tip_z"), 0.0);
}

TEST(SteeringEngines, SymmetricTipGoesStraightInEveryEngine) {
  for (const char* e : {"kinematic", "energy", "beam-foundation"}) {
    const MemorySink s = run(scenarioText(e, straight150, "beta_over_alpha: 0.75", "conical"));
    EXPECT_EQ(s.at("final_deflection"), 0.0) << e;
    EXPECT_EQ(s.at("curvature_whole"), 0.0) << e;
  }
}

TEST(SteeringEngines, EnergyRunsTheSection4ModelAndSteersTowardsTheBevel) {
  // beta/alpha 0.25 keeps the default (path-window) path below a quarter turn
  const MemorySink s = run(scenarioText("energy", straight150, "beta_over_alpha: 0.25, input_force: 15 mN"));
  EXPECT_LT(s.at("tip_y"), 0.0);
  EXPECT_GT(s.at("increments"), 10);
  // the tip ends on a circular arc of 150 mm: chord 2 rho sin(L / (2 rho))
  const double rho = s.at("radius_whole");
  EXPECT_NEAR(std::hypot(s.at("tip_x"), s.at("tip_y")), 2 * rho * std::sin(0.15 / (2 * rho)), 1.5e-3);
  EXPECT_TRUE(s.tables.count("increments"));
  // the same numbers as the library run of Table 2 (gel C, 0.54 mm)
  const auto& c = steering::table2Cases()[8];
  const steering::Table2Row row = steering::runTable2Case(c, "energy", 0.25);
  EXPECT_NEAR(s.at("final_deflection"), row.deflection_pred, 1e-12);
}

TEST(SteeringEngines, EnergyReadsTheFractureEnergy) {
  // model.steering.fracture_energy (choice 10): a rupture cost above the push leaves no share for
  // the sideways cut, the path is straight; the default G_f leaves most of it
  const MemorySink tough =
      run(scenarioText("energy", straight150, "beta_over_alpha: 0.25, input_force: 15 mN, fracture_energy: 100 J/m^2"));
  EXPECT_EQ(tough.at("cut_share"), 0.0);
  EXPECT_EQ(tough.at("final_deflection"), 0.0);
  const MemorySink soft = run(scenarioText("energy", straight150, "beta_over_alpha: 0.25, input_force: 15 mN"));
  EXPECT_NEAR(soft.at("cut_share"), 1 - 0.27e-3 * 0.44 / 15e-3, 1e-12);
  EXPECT_GT(soft.at("final_deflection"), 0.01);
  EXPECT_THROW(scenario::readText(scenarioText("energy", straight150, "fracture_energy: -1 N/m"), "t.yaml"), InputError);
}

TEST(SteeringEngines, EnergyRefusesRotationsOtherThanFlips) {
  const std::string prof = "    - insert: {to: 75 mm, speed: 2.5 mm/s}\n"
                           "    - rotate: {by: 90 deg, rate: 360 deg/s}\n"
                           "    - insert: {to: 150 mm, speed: 2.5 mm/s}\n";
  EXPECT_THROW(run(scenarioText("energy", prof, "")), InputError);
  // a flip is fine and cancels much of the deflection
  const std::string flip = "    - insert: {to: 75 mm, speed: 2.5 mm/s}\n"
                           "    - rotate: {by: 180 deg, rate: 360 deg/s}\n"
                           "    - insert: {to: 150 mm, speed: 2.5 mm/s}\n";
  const MemorySink f = run(scenarioText("energy", flip, "beta_over_alpha: 0.75, input_force: 15 mN"));
  const MemorySink n = run(scenarioText("energy", straight150, "beta_over_alpha: 0.75, input_force: 15 mN"));
  EXPECT_LT(f.at("final_deflection"), 0.7 * n.at("final_deflection"));
}

TEST(SteeringEngines, InPlaneRotationIsRefused) {
  const std::string prof = "    - insert: {to: 75 mm, speed: 2.5 mm/s}\n"
                           "    - rotate: {by: 10 deg, rate: 10 deg/s, axis: in-plane}\n"
                           "    - insert: {to: 150 mm, speed: 2.5 mm/s}\n";
  EXPECT_THROW(run(scenarioText("kinematic", prof, "curvature: 1 1/m")), InputError);
}

TEST(SteeringEngines, ReportsTheDimensionalGroups) {
  const MemorySink s = run(scenarioText("kinematic", straight150, "curvature: 4 1/m"));
  const double I = needle::Section{50e9, 0.54e-3, 0}.secondMoment(), Gc = 46.8e3, C10 = 7.55e3;
  EXPECT_NEAR(s.at("rho0"), Gc * Gc / (50e9 * C10 * std::pow(I, 0.25)), 1e-9 * s.at("rho0"));  // seed 002 eq 3
  EXPECT_NEAR(s.at("Pi1"), 0.25 / s.at("rho0"), 1e-6 * s.at("Pi1"));
}

TEST(SteeringEngines, SteeringSectionIsValidated) {
  EXPECT_THROW(scenario::readText(scenarioText("energy", straight150, "beta_over_alpha: 1.5"), "t.yaml"), InputError);
  EXPECT_THROW(scenario::readText(scenarioText("energy", straight150, "input_force: 3 mm"), "t.yaml"), InputError);
  EXPECT_THROW(scenario::readText(scenarioText("energy", straight150, "tip_load: magic"), "t.yaml"), InputError);
  EXPECT_THROW(scenario::readText(scenarioText("energy", straight150, "bogus: 1"), "t.yaml"), InputError);
}

TEST(SteeringEngines, ExamplesRun) {
  const std::filesystem::path dir = std::filesystem::path(NEEDLESIM_SOURCE_DIR) / "examples" / "steering";
  int n = 0;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    if (f.path().extension() != ".yaml") continue;
    const Scenario sc = scenario::readFile(f.path());
    MemorySink s;
    findEngine(sc.model.engine)->run(sc, s, RunOptions{false});
    EXPECT_GT(s.at("final_deflection"), 0.0) << f.path();
    ++n;
  }
  EXPECT_GE(n, 5);
}

// The paths are reported in the shared tissue frame (needle/insertion_frame.hpp): the
// entry offset and angle place the path, and a bevel turned a quarter turn steers out
// of the insertion plane towards -z (the bevel face looks to +z, the tissue pushes the tip back).
TEST(SteeringEngines, KinematicPathsLieInTheSharedFrame) {
  auto withInsertion = [&](const std::string& extra) {
    std::string t = scenarioText("kinematic", straight150, "curvature: 4 1/m");
    const auto at = t.find("insertion:\n");
    return t.insert(at + 11, extra);
  };
  const MemorySink tilted = run(withInsertion("  entry_angle: 60 deg\n  entry_offset: 5 mm\n"));
  const MemorySink normal = run(scenarioText("kinematic", straight150, "curvature: 4 1/m"));
  // the 90 deg path rotated by 30 deg towards +y about the entry point, moved by the offset
  const double c = std::cos(pi / 6), s = std::sin(pi / 6);
  const double x = normal.at("tip_x"), y = normal.at("tip_y");
  EXPECT_NEAR(tilted.at("tip_x"), c * x - s * y, 1e-12);
  EXPECT_NEAR(tilted.at("tip_y"), 5e-3 + s * x + c * y, 1e-12);
  const MemorySink quarter = run(withInsertion("  bevel_orientation: 90 deg\n"));
  EXPECT_NEAR(quarter.at("tip_z"), normal.at("tip_y"), 1e-12);  // -z by as much as bevel 0 goes to -y
  EXPECT_NEAR(quarter.at("tip_y"), 0.0, 1e-12);
}

TEST(SteeringEngines, RefuseLayeredTissueNamingTheField) {
  std::string t = scenarioText("kinematic", straight150, "curvature: 4 1/m");
  const std::string from = "  material: {law: neo-hookean, C10: 7.55 kPa, nu: 0.45}\n"
                           "  interaction: {K_T: 12.61 kN/m^2, toughness: 46.8 kN/m}\n";
  t.replace(t.find(from), from.size(),
            "  layers:\n"
            "    - {thickness: 100 mm, material: {law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}\n"
            "    - {thickness: 100 mm, material: {law: neo-hookean, C10: 15 kPa, nu: 0.45}}\n");
  try {
    run(t);
    ADD_FAILURE() << "two layers accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("tissue.layers"), std::string::npos) << m;
    EXPECT_NE(m.find("kinematic"), std::string::npos) << m;
  }
}
