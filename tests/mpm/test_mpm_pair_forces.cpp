// The pair penalty contact of two deformable bodies (src/needlesim/engines/mpm/penalty_contact.*):
// forces that are minus the gradient of the energy the code reports. The impacts are in
// test_mpm_penalty_{contact,spheres,oblique}.cpp; docs/validation/mpm.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Geometry>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/penalty_contact.hpp"
#include "mpm_test_materials.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

using test::linearMaterial;

constexpr double kE = 1e5, kNu = 0.3;

MpmConfig twoBodies() {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-4e-3, -4e-3, -4e-3);
  cfg.cells = {18, 16, 16};
  cfg.bodies = 2;
  cfg.threads = 1;
  return cfg;
}

}  // namespace

// The forces are minus the gradient of the energy the code reports (central
// differences of contactForces' energy when one point moves by +-1e-8 m,
// 2e-5 of a spacing: truncation ~1e-8 of the forces (measured 1.3e-6 at
// +-1e-7 m, the barrier's (G/r)^6 is steep), round-off ~1e-11), for
// two blocks on different, offset lattices (0.5 and 0.4 mm) overlapping by
// 0.15 mm (0.33 of the contact distance: into the barrier beyond 0.3 d); the forces sum to zero and so do their moments (central pair
// forces: momentum and angular momentum are conserved to round-off).
TEST(MpmPairContact, ForcesAreMinusTheEnergyGradient) {
  {
    MpmSolver s(twoBodies());
    s.addMaterial(linearMaterial(kE, kNu, 1000));
    s.addBlock(Vec3(0, 0, 0), Vec3(3e-3, 3e-3, 3e-3), 0.5e-3, 0, 0);
    s.addBlock(Vec3(2.85e-3, 0.13e-3, -0.21e-3), Vec3(5.65e-3, 3.33e-3, 2.99e-3), 0.4e-3, 0, 1);
    std::vector<Vec3> f, g;
    const double e = s.contactForces(f);
    ASSERT_GT(e, 0.0);
    Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
    double fmax = 0, xf = 0;
    std::vector<std::size_t> order(s.size());
    for (std::size_t p = 0; p < s.size(); ++p) {
      sum += f[p];
      moment += s.position(p).cross(f[p]);
      fmax = std::max(fmax, f[p].norm());
      xf += s.position(p).norm() * f[p].norm();
      order[p] = p;
    }
    // The 12 points with the largest forces and 4 with small ones.
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f[a].norm() > f[b].norm(); });
    std::vector<std::size_t> probe(order.begin(), order.begin() + 12);
    for (std::size_t p : order)
      if (f[p].norm() > 0 && f[p].norm() < 0.05 * fmax && probe.size() < 16) probe.push_back(p);
    const double eps = 1e-8;
    double worst = 0;
    for (std::size_t p : probe)
      for (int d = 0; d < 3; ++d) {
        const Vec3 x = s.position(p);
        Vec3 dx = Vec3::Zero();
        dx[d] = eps;
        s.setPosition(p, x + dx);
        const double ep = s.contactForces(g);
        s.setPosition(p, x - dx);
        const double em = s.contactForces(g);
        s.setPosition(p, x);
        worst = std::max(worst, std::abs((ep - em) / (2 * eps) + f[p][d]));
      }
    std::printf("pair penalty: energy %.6e J, largest |f| %.4e N, worst |dE/dx + f| %.2e of it over %zu points, net force %.1e, "
                "net moment %.1e (of sum |x||f|)\n",
                e, fmax, worst / fmax, probe.size(),
                sum.norm() / fmax, moment.norm() / xf);
    EXPECT_LT(worst, 1e-6 * fmax);
    EXPECT_LT(sum.norm(), 1e-12 * fmax);
    EXPECT_LT(moment.norm(), 1e-12 * xf);
  }
}
