#pragma once
// The small mpm scenario of the engine tests (seconds per run) and helpers.
#include <gtest/gtest.h>

#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim::mpm_test {

// A 6 x 4 x 4 mm Fung block, 1 mm grid, 0.5 mm points (768), a blunt 1 mm
// needle from 0.5 mm outside to 3 mm deep: contact starts at depth 0.
inline std::string smallScenario(const std::string& extra = "", const std::string& tip = "blunt") {
  return R"(
name: mpm_engine_test
tissue:
  block: {length: 6 mm, width: 4 mm, height: 4 mm}
  material: {law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: 0.255}
needle:
  outer_diameter: 1 mm
  length: 40 mm
  tip: )" + tip + R"(
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {to: 3 mm, speed: 6 mm/s}
model:
  engine: mpm
  mpm:
    grid_spacing: 1 mm
    particle_spacing: 0.5 mm
    mass_scaling: 1e4
    threads: 1
    faces: {exit: fixed, y_min: roller, y_max: roller, z_min: roller, z_max: roller}
)" + extra + R"(
output:
  interval: 10 ms
)";
}

inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

inline MemorySink runText(const std::string& yaml) {
  const Scenario sc = scenario::readText(yaml, "mpm_engine_test.yaml");
  MemorySink sink;
  const EngineInfo* e = findEngine("mpm");
  EXPECT_NE(e, nullptr);
  if (e) e->run(sc, sink, RunOptions{false});
  return sink;
}

}  // namespace needlesim::mpm_test
