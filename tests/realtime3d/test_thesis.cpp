// Seed 003 in 3D (sections 4.1, 5.1, 5.4-5.6): the thesis experiment on the whole gelatin phantom
// (examples/realtime3d/thesis_gelatin_18G_3mms.yaml) on the coarsest grid of the mesh study
// (examples/studies/realtime3d_thesis_mesh.yaml), checked against closed forms, not against
// needlesim's own output: the Kelvin point-force solution integrated along the shaft.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "needlesim/engines/engine.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/thesis_force.hpp"

using namespace needlesim;

namespace {
struct MemorySink final : ResultSink {
  std::map<std::string, double> results;
  std::map<std::string, io::Table> tables;
  void table(const std::string& name, io::Table t) override { tables[name] = std::move(t); }
  void result(const std::string& key, double v, const std::string&, const std::string&) override { results[key] = v; }
  void plot(io::Plot) override {}
  void note(const std::string&) override {}
};

// The printed inputs (section 5.1): E, nu, friction C + b v at 3 mm/s, cutting force; 60 mm in.
constexpr double kE = 30.74e3, kNu = 0.422, kFriction = 3.791 + 285.053 * 3e-3, kCut = 0.04335, kDepth = 0.06;

// Kelvin's solution (infinite body), axial displacement of a point dx ahead of and r beside an
// axial point force P: u = P / (16 pi G (1 - nu) R) [(3 - 4 nu) + dx^2 / R^2].
double kelvinPoint(double P, double dx, double r) {
  const double G = kE / (2 * (1 + kNu)), R = std::hypot(dx, r);
  return P / (16 * std::numbers::pi * G * (1 - kNu) * R) * ((3 - 4 * kNu) + dx * dx / (R * R));
}

// The same integrated in closed form over the shaft friction q per unit length from the entry
// face to the tip: int [(3 - 4 nu)/R + s^2/R^3] ds = (4 - 4 nu) asinh(s/r) - s/R; plus the
// cutting force at the tip. The point at depth x_m, r beside the path.
double kelvinDrag(double x_m, double r) {
  const double G = kE / (2 * (1 + kNu));
  auto primitive = [&](double s) { return (4 - 4 * kNu) * std::asinh(s / r) - s / std::hypot(s, r); };
  const double shaft = kFriction / (16 * std::numbers::pi * G * (1 - kNu)) * (primitive(kDepth - x_m) - primitive(-x_m));
  return shaft + kelvinPoint(kCut, kDepth - x_m, r);
}

// Boussinesq against Kelvin along a load on the free face: 8 (1 - nu)^2 / (3 - 4 nu).
double freeFaceFactor() { return 8 * (1 - kNu) * (1 - kNu) / (3 - 4 * kNu); }

Scenario coarseThesis() {
  std::ifstream in(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/realtime3d/thesis_gelatin_18G_3mms.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  Scenario sc = scenario::readText(ss.str(), "thesis_gelatin_18G_3mms.yaml");
  auto& r = sc.model.realtime3d;
  r.nodes_depth = 21;  // the study's coarsest grid: 4 mm along the depth, 1.7 mm across at the path
  r.nodes_lateral = 15;
  r.nodes_height = 11;
  return sc;
}
}  // namespace

// The closed form reproduces scripts/seed003_kelvin_drag.py (its numerical integral): 0.160 mm at n1.
TEST(Realtime3dSeed003, KelvinClosedFormMatchesTheScript) {
  EXPECT_NEAR(kelvinDrag(0.020, 4e-3), 0.1603e-3, 0.0005e-3);
  EXPECT_NEAR(kelvinDrag(0.050, 4e-3), 0.1659e-3, 0.0005e-3);
  EXPECT_NEAR(freeFaceFactor(), 2.04, 0.005);
}

// The four markers (4 mm beside the path at depths 20-50 mm) in the whole phantom, held on every
// face but the entry face (section 3.5 item 3). Upper limit: the free entry face raises the
// infinite body's drag by at most the Boussinesq factor 2.04 (for a load on the face; less for the
// loads inside), and the held faces and the (compatible, too stiff) tets only lower it. Lower
// limit: the held faces, nearest 27.5 mm from the path, remove about what the infinite body moves
// there (Kelvin at 27.5 mm: 0.29 of the value at 4 mm), leaving about 0.7; 0.5 leaves room for
// that estimate (the far face is 30 mm beyond n4) and for the coarse grid (marker x changes by
// 3 % over the study's three grids). The glitter (0.84-1.45 mm, Table 5.6) is out of reach of a
// linear elastic body with the printed E and forces: every marker stays below a quarter of the
// smallest glitter value. The tip deflection, which grows with refinement of
// the path (1.13, 1.26, 1.36 mm over the study; like ln(1/h), the needle's radius not meshed), lies
// within the measured 1.301 +- 2 x 0.274 mm. The axial force while the needle still slides at the
// end is the thesis' lumped model, (C_p + b_p v) d + F_c, within 2 % (the dragged nodes' slip
// deficit, as in realtime2d's ThesisExampleForceAndDeflection).
TEST(Realtime3dSeed003, MarkerDragLiesNearTheElasticBodyAndFarBelowTheGlitter) {
  const Scenario sc = coarseThesis();
  MemorySink out;
  findEngine("realtime3d")->run(sc, out, RunOptions{false});
  const double depths[4] = {0.020, 0.030, 0.040, 0.050};
  const char* names[4] = {"n1", "n2", "n3", "n4"};
  for (int i = 0; i < 4; ++i) {
    const double ux = out.results.at(std::string("marker_") + names[i] + "_ux_max");
    const double kelvin = kelvinDrag(depths[i], 4e-3);
    std::printf("%s: ux %.4f mm, Kelvin %.4f mm, ratio %.3f\n", names[i], ux * 1e3, kelvin * 1e3, ux / kelvin);
    EXPECT_LT(ux, freeFaceFactor() * kelvin) << names[i];
    EXPECT_GT(ux, 0.5 * kelvin) << names[i];
    EXPECT_LT(ux, 0.839e-3 / 4) << names[i];
  }
  EXPECT_NEAR(out.results.at("max_tip_deflection"), 1.301e-3, 2 * 0.274e-3);
  const thesis::ForceSample end = thesis::lastMovingForce(out.tables.at("forces"));
  EXPECT_NEAR(end.depth, kDepth, 0.1e-3);
  const double lumped = thesis::axialForce(end.velocity, end.depth, kCut);
  std::printf("axial force at %.2f mm, sliding: %.4f N, closed form %.4f N (%+.2f %%)\n", end.depth * 1e3, end.force,
              lumped, 100 * (end.force / lumped - 1));
  EXPECT_NEAR(end.force, lumped, 0.02 * lumped);
}
