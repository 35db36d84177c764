// explicit_relax: the needlesim side of scripts/calculix_compare.py
// (docs/validation/fe.md, "Independent solver: CalculiX"). Reads a Gmsh 4.1
// mesh and a small case file, drives the explicit engine to static
// equilibrium through its public API (smooth displacement ramp, then a hold
// with mass-proportional damping: dynamic relaxation, as
// tests/explicit/test_cook.cpp) and prints the displacements of chosen nodes
// and the reaction of the prescribed-displacement group.
//
// Case file (one keyword per line, node ids = Gmsh node tags, components 0 1 2):
//   neo-hookean C10 K density        material (W = C10 (I1bar - 3) + K/2 (J - 1)^2)
//   fix node comp                    a fixed dof
//   move node comp                   a dof of the prescribed group
//   displacement d                   final displacement of the group
//   ramp T  hold H  damping c        ramp time, hold time (s), damping (1/s)
//   print node                       report this node's displacement
//   hourglass h                      optional: SolverOptions::hourglass (default 1)
// Output: "node <tag> <ux> <uy> <uz>", "reaction <F>" (force the support
// applies, summed over the group), "kinetic_ratio <KE / strain energy>",
// "steps <n>".
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: explicit_relax mesh.msh case.txt\n");
    return 2;
  }
  try {
    Mesh mesh = fromVolumeMesh(mesh::readGmsh(argv[1]));
    std::ifstream in(argv[2]);
    if (!in) throw std::runtime_error(std::string("cannot open ") + argv[2]);
    double C10 = 0, K = 0, rho = 0, d = 0, T = 0, H = 0, c = 0, hourglass = 1.0;
    std::vector<std::pair<int, int>> fixed, moved;
    std::vector<int> printed;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
      ++lineNo;
      std::istringstream ls(line);
      std::string key;
      if (!(ls >> key) || key[0] == '#') continue;
      bool ok = true;
      if (key == "neo-hookean") ok = bool(ls >> C10 >> K >> rho);
      else if (key == "fix" || key == "move") {
        int n, k;
        ok = bool(ls >> n >> k) && n >= 1 && n <= mesh.nodes() && k >= 0 && k < mesh.dim;
        (key == "fix" ? fixed : moved).emplace_back(n - 1, k);
      } else if (key == "displacement") ok = bool(ls >> d);
      else if (key == "hourglass") ok = bool(ls >> hourglass) && hourglass >= 0;
      else if (key == "ramp") {
        std::string h, dm;
        ok = bool(ls >> T >> h >> H >> dm >> c) && h == "hold" && dm == "damping";
      } else if (key == "print") {
        int n;
        ok = bool(ls >> n) && n >= 1 && n <= mesh.nodes();
        printed.push_back(n - 1);
      } else ok = false;
      if (!ok) throw std::runtime_error(std::string(argv[2]) + ":" + std::to_string(lineNo) + ": bad line '" + line + "'");
    }
    if (C10 <= 0 || K <= 0 || rho <= 0 || T <= 0) throw std::runtime_error("case needs neo-hookean and ramp lines");

    materials::MaterialSpec sp;
    sp.law = "neo-hookean";
    sp.params = {{"C10", C10}, {"K", K}};
    sp.density = rho;
    SolverOptions o;
    o.damping = c;
    o.hourglass = hourglass;
    ExplicitSolver s(mesh, {Material::fromSpec(sp)}, o);
    const int gFix = s.addGroup(), gMove = s.addGroup();
    for (auto [n, k] : fixed) s.addDof(gFix, n, k);
    for (auto [n, k] : moved) s.addDof(gMove, n, k);
    // ramp: v(t) = d/T (1 - cos(2 pi t / T)), zero velocity and acceleration at both ends
    while (s.time() < T) {
      const double tm = s.time() + 0.5 * s.timeStep();
      s.setGroupVelocity(gMove, d / T * (1.0 - std::cos(2.0 * std::numbers::pi * tm / T)));
      s.step();
    }
    s.setGroupVelocity(gMove, 0.0);
    s.advanceTo(T + H);

    const auto& u = s.displacement();
    const int dim = mesh.dim;
    for (int n : printed) {
      std::printf("node %d", n + 1);
      for (int k = 0; k < 3; ++k) std::printf(" %.9e", k < dim ? u[n * dim + k] : 0.0);
      std::printf("\n");
    }
    if (!moved.empty()) {
      const auto [n, k] = moved.front();
      std::printf("prescribed %.9e\n", u[n * dim + k]);
    }
    std::printf("reaction %.9e\n", s.groupReaction(gMove));
    const auto& en = s.energies();
    std::printf("kinetic_ratio %.3e\n", en.kinetic / std::max(en.strain, 1e-300));
    std::printf("hourglass_ratio %.3e\n", en.hourglass / std::max(en.strain, 1e-300));
    std::printf("steps %ld\n", s.steps());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "explicit_relax: %s\n", e.what());
    return 1;
  }
  return 0;
}
