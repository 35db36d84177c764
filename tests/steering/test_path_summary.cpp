// The steering summaries report only meaningful numbers: radii of paths that are circular
// arcs (an S-curve gives the radius of each arc, not one across both), no seed 004 groups
// whose length scale is far from the insertion, coordinates within round-off as 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
MemorySink runExample(const std::string& name) {
  return runInMemory(scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/steering/" + name));
}
bool anyNoteHas(const MemorySink& s, const std::string& part) {
  return std::any_of(s.notes.begin(), s.notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}
}  // namespace

TEST(SteeringSummary, SCurveReportsEachArcAgainstTheKinematicClosedForm) {
  const MemorySink s = runExample("flip_s_curve.yaml");  // curvature 4 1/m, flip at 75 mm of 150 mm
  const double r = 1.0 / 4.0;                            // kinematic closed form r = 1/kappa
  ASSERT_TRUE(s.results.count("radius_arc1") && s.results.count("radius_arc2"));
  EXPECT_NEAR(s.results.at("radius_arc1").value, r, 1e-6);
  EXPECT_NEAR(s.results.at("radius_arc2").value, r, 1e-6);
  EXPECT_EQ(s.results.at("radius_arc1").unit, "m");
  // no radius fitted across both arcs, nor the ones built on it
  for (const char* gone : {"radius_whole", "curvature_whole", "radius_mean", "radius_50_100mm", "Pi1", "radius_arc3"})
    EXPECT_EQ(s.results.count(gone), 0u) << gone;
  // the sections that lie inside one arc keep their radius
  EXPECT_NEAR(s.results.at("radius_0_50mm").value, r, 1e-6);
  EXPECT_NEAR(s.results.at("radius_100_150mm").value, r, 1e-6);
  EXPECT_TRUE(anyNoteHas(s, "The tip path is not one circular arc")) << s.notes.front();
  EXPECT_TRUE(anyNoteHas(s, "an arc of radius 250 mm over 0-75 mm and an arc of radius 250 mm over 75-150 mm"));
  EXPECT_TRUE(anyNoteHas(s, "radius_whole, radius_50_100mm, radius_mean are not reported"));
  // the S-curve stays in its plane: exactly 0, not round-off
  EXPECT_EQ(s.results.at("tip_z").value, 0.0);
}

TEST(SteeringSummary, OneArcKeepsTheWholePathRadius) {
  const MemorySink s = runExample("table2_gelC_054_kinematic.yaml");
  const double kappa = s.results.at("curvature").value;
  EXPECT_NEAR(s.results.at("radius_whole").value, 1 / kappa, 1e-6);
  EXPECT_NEAR(s.results.at("radius_mean").value, 1 / kappa, 1e-6);
  EXPECT_EQ(s.results.count("radius_arc1"), 0u);
  EXPECT_FALSE(anyNoteHas(s, "not one circular arc"));
}

TEST(SteeringSummary, Seed004GroupsFarFromTheInsertionScaleAreLeftOutWithANote) {
  const MemorySink s = runExample("table2_gelC_054_kinematic.yaml");
  // E Gc / C10^2 = 50 GPa * 46.8 kN/m / (7.55 kPa)^2 = 4.1e7 m, 2.7e8 times the 150 mm inserted;
  // the note writes it in the scenario's unit of length (mm)
  for (const char* gone : {"length_s004", "Pi2_s004", "Pi3_s004"}) EXPECT_EQ(s.results.count(gone), 0u) << gone;
  EXPECT_TRUE(anyNoteHas(s, "Seed 004's length scale E Gc / C10^2 (eq 3) is 4.105e+10 mm here"));
  // seed 002's scale (rho0 = 22.8 mm) is kept
  EXPECT_NEAR(s.results.at("rho0").value, 0.0228265, 1e-6);
}

TEST(SteeringSummary, BeamFoundationPathOfSlowlyVaryingCurvatureIsOneArc) {
  const MemorySink s = runExample("table2_gelC_054_beam_foundation.yaml");
  EXPECT_EQ(s.results.count("radius_whole"), 1u);
  EXPECT_EQ(s.results.count("radius_mean"), 1u);
}

TEST(CurvatureFit, OneArcTestSeparatesAnArcFromAnSCurve) {
  std::vector<Eigen::Vector3d> arc, s;
  const double R = 0.25;
  for (int i = 0; i <= 150; ++i) {
    const double a = i * 1e-3 / R;
    arc.emplace_back(R * std::sin(a), R * (1 - std::cos(a)), 0.0);
  }
  // second half mirrored: an S
  s = std::vector<Eigen::Vector3d>(arc.begin(), arc.begin() + 76);
  const Eigen::Vector3d mid = arc[75], t(std::cos(0.075 / R), std::sin(0.075 / R), 0.0), nrm(-t.y(), t.x(), 0.0);
  for (int i = 1; i <= 75; ++i) {
    const Eigen::Vector3d d = arc[i] - arc[0];  // the first arc's shape, turned the other way
    s.push_back(mid + d.x() * t - d.y() * nrm);
  }
  EXPECT_TRUE(steering::isOneArc(steering::fitCircle(arc), arc));
  EXPECT_FALSE(steering::isOneArc(steering::fitCircle(s), s));
  const double breaks[] = {0.075};
  const auto pieces = steering::pathPieces(s, breaks);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_TRUE(pieces[0].arc && pieces[1].arc);
  EXPECT_NEAR(pieces[0].fit.radius, R, 1e-9);
  EXPECT_NEAR(pieces[1].fit.radius, R, 1e-9);
}
