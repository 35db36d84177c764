// The reference insertion of docs/validation/agreement.md (examples/agreement/reference.yaml)
// through the engines whose models coincide on it: lumped and realtime3d take the same cutting
// force and Karnopp friction (seed 003 eqs 3.23-3.24) with b_p = 0, so while every node slides the
// axial force of both is F_cut + C_p L exactly (L: the shaft in the tissue). realtime3d measures L
// from its coupled nodes' current order; a node that overtakes another, a length counted twice or
// a cutting force counted again would show as a difference.
#include <gtest/gtest.h>

#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

const std::string kReference = std::string(NEEDLESIM_SOURCE_DIR) + "/examples/agreement/reference.yaml";

MemorySink runReference(const std::string& engine) {
  Scenario sc = scenario::readFile(kReference);
  sc.model.engine = engine;
  sc.output.html = false;
  return runInMemory(sc);
}

// force_total at tip depth d, linear between the rows around it (first insertion only).
double forceAt(const MemorySink& m, double d) {
  const auto& t = m.tables.at("forces");
  const auto depth = t.column("depth"), f = t.column("force_total");
  for (std::size_t r = 1; r < depth.size(); ++r)
    if (depth[r - 1] <= d && d <= depth[r] && depth[r] > depth[r - 1])
      return f[r - 1] + (d - depth[r - 1]) / (depth[r] - depth[r - 1]) * (f[r] - f[r - 1]);
  ADD_FAILURE() << "depth " << d << " m not reached";
  return 0.0;
}

}  // namespace

TEST(Agreement, ReferenceInsertionRealtime3dCarriesTheLumpedForce) {
  const MemorySink lumped = runReference("lumped");
  const MemorySink rt3 = runReference("realtime3d");
  const double cut = 16.1e-3, Cp = 12.7;  // N, N/m: the file's a priori inputs
  for (double d : {5e-3, 10e-3, 15e-3, 19.9e-3}) {  // the last row is at 20 mm up to rounding
    // The lumped model is the closed form itself (contact from the entry face to the tip).
    EXPECT_NEAR(forceAt(lumped, d), cut + Cp * d, 1e-4) << d;
    // realtime3d: the same law over its nodes' tributary lengths, which add up to the shaft in the
    // tissue; 1 % leaves room for a node held in the static band near the entry, nothing more.
    EXPECT_NEAR(forceAt(rt3, d), forceAt(lumped, d), 0.01 * forceAt(lumped, d)) << d;
  }
}
