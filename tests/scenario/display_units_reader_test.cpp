// The scenario's display units: per dimension the unit the file writes most often (the first
// written on a tie), output.units over it, SI where the file writes none.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
const std::string kCm = R"(name: t
tissue:
  block: {length: 5.5 cm, width: 12 cm, height: 80 mm}
  material: {law: linear, E: 30.74 kPa, nu: 0.422}
  puncture: {force: 100 mN}
  cutting: {force: 0.04335 N}
  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2}
needle:
  outer_diameter: 18 G
  length: 15 cm
  bevel_angle: 0.35 rad
  youngs_modulus: 200 GPa
insertion:
  profile:
    - insert: {to: 60 mm, speed: 3 mm/s}
)";
}  // namespace

TEST(DisplayUnitsReader, TheUnitWrittenMostOftenPerDimension) {
  const Scenario s = scenario::readText(kCm, "t.yaml");
  const auto& u = s.output.units;
  EXPECT_EQ(u.unitFor("m"), "cm");       // cm 3 times, mm twice (the gauge is not a length unit written)
  EXPECT_EQ(u.unitFor("N"), "mN");       // mN once, N once: the first written
  EXPECT_EQ(u.unitFor("Pa"), "kPa");     // kPa once, GPa once: the first written
  EXPECT_EQ(u.unitFor("m/s"), "mm/s");
  EXPECT_EQ(u.unitFor("rad"), "rad");
  EXPECT_EQ(u.unitFor("s"), "s");        // none written: SI
  EXPECT_EQ(u.unitFor("N/m"), "N/m");    // not a display dimension
  // all recorded with the scenario as understood, so summary.json shows the same again
  const auto understood = nlohmann::json::parse(s.understood);
  EXPECT_EQ(understood["output"]["units"]["length"], "cm");
  EXPECT_EQ(understood["output"]["units"]["time"], "s");
  const Scenario again = scenario::readText(s.understood, "summary.json");
  for (const auto& [dimension, unit] : s.output.units.chosen())
    EXPECT_EQ(again.output.units.unitFor(units::findDisplayDimension(dimension)->si), unit) << dimension;
}

TEST(DisplayUnitsReader, OutputUnitsOverrideTheWrittenOnes) {
  const Scenario s = scenario::readText(kCm + "output:\n  units: {length: um, time: ms, moment: N mm}\n", "t.yaml");
  EXPECT_EQ(s.output.units.unitFor("m"), "um");
  EXPECT_EQ(s.output.units.unitFor("s"), "ms");
  EXPECT_EQ(s.output.units.unitFor("N m"), "N mm");
  EXPECT_EQ(s.output.units.unitFor("N"), "mN");  // not given: the written one
}

TEST(DisplayUnitsReader, SolverSettingsVoteOnlyForDimensionsTheProblemDoesNotWrite) {
  // one duration in s in the profile, two settings in ms: durations stay s
  const std::string withPause = kCm + "    - pause: {duration: 2 s}\nmodel: {time_step: 1 ms}\noutput: {interval: 10 ms}\n";
  EXPECT_EQ(scenario::readText(withPause, "t.yaml").output.units.unitFor("s"), "s");
  // no time in the problem: the settings' unit
  const std::string settingsOnly = kCm + "model: {time_step: 1 ms}\n";
  EXPECT_EQ(scenario::readText(settingsOnly, "t.yaml").output.units.unitFor("s"), "ms");
}
