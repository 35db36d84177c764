// The mpm engine's tissue: every layer's needle friction, inclusions bonded to
// the tissue or sliding against it as a second body (penalty_contact.hpp), and
// what it reports about them (results/inclusion_motion.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mpm_test_scenario.hpp"
#include "needlesim/core/error.hpp"

using namespace needlesim;
using namespace needlesim::mpm_test;

namespace {

const std::string kFung = "{law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.45, density: 1000 kg/m^3}";

// The grid contact (eqs 14-21): a needle coefficient per region and sliding inclusions (the default
// CFEMP contact has one coefficient and refuses a second body).
const std::string kGrid = "    contact: grid\n";

// The small block as two layers of one material, 4 mm and 2 mm thick, with
// needle friction mu0 and mu1; the conical needle goes 3 mm deep.
std::string twoLayers(const std::string& mu0, const std::string& mu1) {
  return replaced(smallScenario(kGrid, "conical"),
                  "  material: {law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.45, density: 1000 kg/m^3}\n"
                  "  friction: {coefficient: 0.255}\n",
                  "  layers:\n"
                  "    - {thickness: 4 mm, material: " + kFung + ", friction: {coefficient: " + mu0 + "}}\n"
                  "    - {thickness: 2 mm, material: " + kFung + ", friction: {coefficient: " + mu1 + "}}\n");
}

std::vector<double> forceColumn(const MemorySink& out, const std::string& name) {
  return out.tables.at("forces").column(name);
}

// An 8 x 8 x 6 mm Fung block (3,072 points) with the inclusions given; a
// conical 1 mm needle from 0.5 mm outside to 3 mm deep.
std::string blockWith(const std::string& inclusions) {
  std::string s = replaced(smallScenario(kGrid, "conical"), "length: 6 mm, width: 4 mm, height: 4 mm",
                           "length: 8 mm, width: 8 mm, height: 6 mm");
  return replaced(s, "  friction: {coefficient: 0.255}\n",
                  "  friction: {coefficient: 0.255}\n  inclusions:\n" + inclusions);
}

const std::string kStiff = "{law: fung, mu: 50 kPa, gamma: 1.0, nu: 0.45, density: 1000 kg/m^3}";

}  // namespace

// The needle's Coulomb coefficient is the one of the layer whose point touches
// it: a needle that stays in layer 0 (3 mm of its 4 mm) gives, bit for bit,
// the forces of a one-layer block with layer 0's coefficient, whatever layer 1's.
TEST(MpmTissue, NeedleFrictionOfTheLayerItTouches) {
  const MemorySink frictionless = runText(replaced(smallScenario(kGrid, "conical"), "coefficient: 0.255", "coefficient: 0"));
  const MemorySink frictional = runText(replaced(smallScenario(kGrid, "conical"), "coefficient: 0.255", "coefficient: 0.5"));
  const MemorySink layered0 = runText(twoLayers("0", "0.5"));
  const MemorySink layered5 = runText(twoLayers("0.5", "0"));
  for (const char* c : {"force_total", "force_shaft", "force_lateral"}) {
    EXPECT_EQ(forceColumn(layered0, c), forceColumn(frictionless, c)) << c;
    EXPECT_EQ(forceColumn(layered5, c), forceColumn(frictional, c)) << c;
  }
  // Friction resists the insertion along the shaft.
  EXPECT_GT(layered5.results.at("final_shaft_force").value, layered0.results.at("final_shaft_force").value);
}

// A bonded inclusion of the tissue's own material and friction is the tissue:
// the same forces bit for bit; one 5 times stiffer on the needle path resists
// the needle more once the tip reaches it.
TEST(MpmTissue, BondedInclusionIsPartOfTheTissue) {
  const MemorySink plain = runText(blockWith("    []\n"));
  const MemorySink same = runText(blockWith("    - {name: same, depth: 3 mm, radius: 1.5 mm, material: " + kFung + "}\n"));
  const MemorySink stiff = runText(blockWith("    - {name: stiff, depth: 3 mm, radius: 1.5 mm, material: " + kStiff + "}\n"));
  EXPECT_EQ(forceColumn(same, "force_total"), forceColumn(plain, "force_total"));
  EXPECT_GT(stiff.results.at("final_force").value, plain.results.at("final_force").value);
  EXPECT_TRUE(same.tables.count("inclusions"));
  EXPECT_EQ(same.tables.count("energy"), 1u);
}

// A sliding stiff sphere at the entry face on the needle path is a second body
// the needle touches first: the force rises from the entry face, the sphere is
// pushed forward along the needle axis, and the pair contact between it and
// the tissue stores energy. A second sliding sphere far off the path (3.6 mm
// from it) moves much less.
TEST(MpmTissue, NeedlePushesASlidingTarget) {
  const MemorySink out = runText(blockWith(
      "    - {name: target, depth: 1.5 mm, radius: 1.5 mm, material: " + kStiff +
      ", interface: sliding, interface_friction: 0.2, target: true}\n"
      "    - {name: far, depth: 5 mm, lateral: 2.5 mm, elevation: 1.5 mm, radius: 1.25 mm, material: " + kStiff +
      ", interface: sliding, interface_friction: 0.2}\n"));
  const double shift = out.results.at("target_shift_axial").value;
  const double target = out.results.at("target_displacement").value, far = out.results.at("far_displacement").value;
  std::printf("target: shift %.4g mm (|u| %.4g mm), far |u| %.4g mm, peak force %.4g N\n", shift * 1e3,
              target * 1e3, far * 1e3, out.results.at("peak_force").value);
  EXPECT_GT(shift, 0.0);
  EXPECT_GT(target, 3.0 * far);
  const io::Table& inc = out.tables.at("inclusions");
  EXPECT_EQ(inc.rows(), out.tables.at("forces").rows());
  const auto contact = out.tables.at("energy").column("contact");
  double most = 0.0;
  for (const double e : contact) most = std::max(most, e);
  EXPECT_GT(most, 0.0) << "the pair contact of the two bodies never acted";
  // The needle meets the sphere at the entry face.
  const auto depth = forceColumn(out, "depth"), force = forceColumn(out, "force_total");
  for (std::size_t i = 0; i < depth.size(); ++i)
    if (depth[i] >= 0.5e-3) {
      EXPECT_GT(force[i], 0.0);
      break;
    }
}

// What mpm cannot honour is refused, naming the field.
TEST(MpmTissue, Refusals) {
  const auto refused = [](const std::string& yaml, const std::string& field) {
    try {
      runText(yaml);
      ADD_FAILURE() << "accepted: " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  // CFEMP has one needle coefficient; and it is not verified with a second body.
  refused(replaced(twoLayers("0", "0.5"), kGrid, "    contact: cfemp\n"),
          "tissue.layers[1].friction.coefficient");
  refused(replaced(blockWith("    - {depth: 3 mm, radius: 1.5 mm, material: " + kStiff + ", interface: sliding}\n"),
                   kGrid, "    contact: cfemp\n"),
          "tissue.inclusions[0].interface");
  // Sliding inclusions are one body: one interface coefficient.
  refused(blockWith("    - {depth: 2 mm, radius: 1 mm, material: " + kStiff + ", interface: sliding, interface_friction: 0.1}\n"
                    "    - {depth: 6 mm, radius: 1 mm, material: " + kStiff + ", interface: sliding, interface_friction: 0.3}\n"),
          "tissue.inclusions[1].interface_friction");
  // An inclusion between the material points.
  refused(blockWith("    - {depth: 3.5 mm, lateral: 0.5 mm, elevation: 0.5 mm, radius: 0.1 mm, material: " + kStiff + "}\n"),
          "tissue.inclusions[0].radius");
}
