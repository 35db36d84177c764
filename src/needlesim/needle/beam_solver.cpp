#include "needlesim/needle/beam_solver.hpp"

#include <stdexcept>

#include "needlesim/needle/beam_element.hpp"

namespace needlesim::needle {

BeamSolution solveStraightBeam(const StraightBeam& beam, const std::vector<NodalLoad>& loads) {
  const int ne = beam.elements;
  if (ne < 1 || !(beam.length > 0) || !(beam.EI > 0))
    throw std::invalid_argument("beam needs elements >= 1, length > 0, EI > 0");
  const double h = beam.length / ne;
  const int nn = ne + 1;
  // Global dof g = 2*node + {0,1}; constrained dofs are removed by an offset.
  const int fixed = beam.clamp_left ? 2 : (beam.pin_left ? 1 : 0);
  auto dof = [&](int g) { return g - fixed; };  // < 0 means constrained
  const int n = 2 * nn - fixed;
  BandedSPD<3> K;
  K.reset(n);
  const Mat4 kb = bendingStiffness(beam.EI, h) + geometricStiffness(beam.axial_force, h);
  for (int e = 0; e < ne; ++e) {
    Mat4 ke = kb;
    if (!beam.foundation.empty()) ke += foundationStiffness(beam.foundation.at(e), h);
    const int d[4] = {dof(2 * e), dof(2 * e + 1), dof(2 * e + 2), dof(2 * e + 3)};
    K.addBlock(ke, d);
  }
  std::vector<double> f(n, 0.0);
  for (const auto& l : loads) {
    if (l.node < 0 || l.node >= nn) throw std::invalid_argument("load on a missing node");
    if (dof(2 * l.node) >= 0) f[dof(2 * l.node)] += l.force;
    if (dof(2 * l.node + 1) >= 0) f[dof(2 * l.node + 1)] += l.moment;
  }
  K.factor();
  K.solve(f.data());
  BeamSolution s;
  s.x.resize(nn);
  s.w.resize(nn);
  s.theta.resize(nn);
  for (int i = 0; i < nn; ++i) {
    s.x[i] = i * h;
    const int a = dof(2 * i), b = dof(2 * i + 1);
    s.w[i] = a >= 0 ? f[a] : 0.0;
    s.theta[i] = b >= 0 ? f[b] : 0.0;
  }
  return s;
}

}  // namespace needlesim::needle
