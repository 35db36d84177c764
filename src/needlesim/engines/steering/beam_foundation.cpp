#include "needlesim/engines/steering/beam_foundation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "needlesim/needle/beam_element.hpp"

namespace needlesim::steering {

double beamFoundationSteadyCurvature(double EI, double K_T, double Q, double M) {
  const double lambda = std::sqrt(std::sqrt(K_T / (4 * EI)));
  return (M + Q / lambda) / EI;
}

BeamFoundationModel::BeamFoundationModel(const BeamFoundationParams& p) : p_(p) {
  if (!(p.EI > 0 && p.K_T >= 0 && p.increment > 0 && p.max_length > p.increment))
    throw std::invalid_argument("beam-foundation model needs EI > 0, K_T >= 0, 0 < increment < max_length");
  const int cap = static_cast<int>(std::ceil(p.max_length / p.increment)) + 2;
  for (auto* v : {&X_, &T_, &N1_, &N2_}) v->resize(cap);
  k1_.assign(cap, 0.0);
  k2_.assign(cap, 0.0);
  rhs1_.resize(2 * cap);
  rhs2_.resize(2 * cap);
  K_.reserve(2 * cap);
  const double h = p.increment;
  kb_ = needle::bendingStiffness(p.EI, h) + needle::geometricStiffness(p.axial_force, h);
  kbf_ = kb_ + needle::foundationStiffness(p.K_T, h);
  reset(Pose{});
}

void BeamFoundationModel::reset(const Pose& entry, double bevel) {
  n_ = 0;
  bevel_ = bevel;
  X_[0] = entry.p;
  T_[0] = entry.R.col(2);
  N1_[0] = entry.R.col(1);  // bevel +y at angle 0
  N2_[0] = T_[0].cross(N1_[0]);
  k1_[0] = k2_[0] = 0.0;
}

void BeamFoundationModel::advance() {
  const int m = n_ + 1;  // elements after this increment
  if (m + 1 >= static_cast<int>(X_.size()))
    throw std::length_error("beam-foundation model: max_length exceeded");
  const double h = p_.increment;
  // Unknowns: (w, theta) at nodes 1..m, node 0 clamped; dof of node j = 2(j-1).
  const int nd = 2 * m;
  // Appending at the tip changes only the last rows: the old free element gains its
  // foundation, a new free element is appended, and the channel curvature of the last
  // elements is completed. Rows < first keep their Cholesky factor and their
  // forward-substituted load, so an increment costs O(1) instead of O(n).
  const int first = std::max(0, nd - 8);
  K_.truncateRows(first, nd);
  std::fill(rhs1_.begin() + first, rhs1_.begin() + nd, 0.0);
  std::fill(rhs2_.begin() + first, rhs2_.begin() + nd, 0.0);
  for (int e = std::max(0, first / 2 - 1); e < m; ++e) {
    const int d[4] = {2 * e - 2, 2 * e - 1, 2 * e, 2 * e + 1};
    // the foundation acts only where the channel has been cut (all but the new element)
    K_.addBlockRows(e < m - 1 ? kbf_ : kb_, d, first);
    if (e < m - 1) {
      // natural curvature of the channel: mean of the end-node curvatures
      const double c1 = 0.5 * (k1_[e] + k1_[e + 1]), c2 = 0.5 * (k2_[e] + k2_[e + 1]);
      const needle::Vec4 f1 = needle::naturalCurvatureLoad(p_.EI, c1);
      const needle::Vec4 f2 = needle::naturalCurvatureLoad(p_.EI, c2);
      for (int i = 0; i < 4; ++i)
        if (d[i] >= first) {
          rhs1_[d[i]] += f1(i);
          rhs2_[d[i]] += f2(i);
        }
    }
  }
  // bevel loads at the tip, in the tip frame of the previous tip (node n_)
  const double cb = std::cos(bevel_), sb = std::sin(bevel_);
  rhs1_[nd - 2] += p_.Q * cb;
  rhs2_[nd - 2] += p_.Q * sb;
  rhs1_[nd - 1] += p_.M * cb;
  rhs2_[nd - 1] += p_.M * sb;
  K_.factorFrom(first);
  K_.forwardFrom(rhs1_.data(), first);
  K_.forwardFrom(rhs2_.data(), first);
  // tip deviation: back substitution of the last two rows only
  const double w1 = K_.backLastTwo(rhs1_.data()), w2 = K_.backLastTwo(rhs2_.data());
  // new channel node: straight extension of the tip direction plus the tip deviation
  const Vec3& Xn = X_[n_];
  const Vec3 t = T_[n_], n1 = N1_[n_], n2 = N2_[n_];
  const Vec3 Xm = Xn + h * t + w1 * n1 + w2 * n2;
  Vec3 tm = (Xm - Xn).normalized();
  // parallel transport of the frame from t to tm (minimal rotation)
  const Vec3 axis = t.cross(tm);
  const double s = axis.norm(), c = t.dot(tm);
  Vec3 m1 = n1, m2 = n2;
  if (s > 1e-15) {
    const Vec3 k = axis / s;
    // -> Vec3: an Eigen expression returned by auto would dangle (k.cross(v) is a temporary)
    auto rot = [&](const Vec3& v) -> Vec3 { return v * c + k.cross(v) * s + k * k.dot(v) * (1 - c); };
    m1 = rot(n1);
    m2 = rot(n2);
  }
  // curvature at node n_: turning from its incoming tangent to the new chord
  const Vec3 kv = (tm - t) / h;
  k1_[n_] = kv.dot(n1);
  k2_[n_] = kv.dot(n2);
  X_[m] = Xm;
  T_[m] = tm;
  N1_[m] = m1;
  N2_[m] = m2;
  k1_[m] = k2_[m] = 0.0;
  n_ = m;
}

void BeamFoundationModel::shape(std::vector<Vec3>& out) const {
  out.resize(n_ + 1);
  out[0] = X_[0];
  if (n_ == 0) return;
  // full back substitution of the last solve on copies of the forward-substituted loads
  std::vector<double> b1(rhs1_.begin(), rhs1_.begin() + 2 * n_), b2(rhs2_.begin(), rhs2_.begin() + 2 * n_);
  K_.backward(b1.data());
  K_.backward(b2.data());
  for (int j = 1; j <= n_; ++j) {
    const int d = 2 * (j - 1);  // deviation of node j, in its frame; the tip lies on its node
    out[j] = j == n_ ? X_[j] : X_[j] + b1[d] * N1_[j] + b2[d] * N2_[j];
  }
}

}  // namespace needlesim::steering
