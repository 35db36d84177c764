#include "needlesim/engines/explicit/cohesive.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::explicit_fe {

CohesiveLaw CohesiveLaw::fromCriticalSeparation(double E, double T0, double Gc, double deltaC) {
  if (!(E > 0 && T0 > 0 && Gc > 0 && deltaC > 0))
    throw Error("cohesive law (seed 004): E, constitutive thickness, G_c and delta_c must be > 0");
  CohesiveLaw l;
  l.stiffness = E / T0;             // K_n = K_s = E per unit constitutive thickness (seed 004 IV-A)
  l.strength = 2.0 * Gc / deltaC;   // t_c = 2 G_c / delta_c (seed 004 IV-A, Table I last column)
  l.energy = Gc;
  return l;
}

void CohesiveLaw::validate() const {
  if (!(stiffness > 0 && strength > 0 && energy > 0 && sc() > 0 && G2() > 0))
    throw Error("cohesive law: stiffness, strength and fracture energy must be > 0");
  // The bilinear triangle needs the onset separation t_c / K below the final one 2 G_c / t_c.
  const double d0 = strength / stiffness, df = 2 * energy / strength;
  if (!(d0 < df))
    throw Error("cohesive law: the strength t_c = " + std::to_string(strength) + " Pa is reached at t_c/K = " +
                std::to_string(d0) + " m, beyond the final separation 2 G_c/t_c = " + std::to_string(df) +
                " m: no bilinear law exists (raise the stiffness K or lower t_c; seed 004's Table I values with "
                "K = E per unit thickness and delta_c = 0.71 mm are of this kind, see docs/models/cohesive.md)");
  const double s0 = sc() / stiffness, sf = 2 * G2() / sc();
  if (!(s0 < sf)) throw Error("cohesive law: shear onset separation s_c/K exceeds 2 G_IIc/s_c");
}

void cohesiveMixedMode(const CohesiveLaw& law, double dn, double ds, double& d0, double& df) {
  const double K = law.stiffness, d0n = law.strength / K, d0s = law.sc() / K;
  if (dn > 0) {
    const double b2 = (ds * ds) / (dn * dn);  // beta^2, beta = delta_s / delta_n
    // quadratic initiation (<t_n>/t_c)^2 + (t_s/s_c)^2 = 1 (Camanho-Davila eq 21)
    d0 = d0n * d0s * std::sqrt((1 + b2) / (d0s * d0s + b2 * d0n * d0n));
    // linear energy criterion G_I/G_Ic + G_II/G_IIc = 1 (Camanho-Davila eq 26 with alpha = 1)
    df = 2 * (1 + b2) / (K * d0) / (1.0 / law.energy + b2 / law.G2());
  } else {
    d0 = d0s;
    df = 2 * law.G2() / law.sc();
  }
}

CohesiveTraction cohesiveUpdate(const CohesiveLaw& law, double dn, double ds, CohesiveState& st) {
  const double K = law.stiffness;
  const double dnp = std::max(dn, 0.0), dnc = std::min(dn, 0.0);
  const double dm2 = dnp * dnp + ds * ds, dm = std::sqrt(dm2);
  const double Y = 0.5 * K * dm2;  // energy release per unit damage
  if (st.damage < 1.0 && dm > 0) {
    double d0, df;
    cohesiveMixedMode(law, dn, ds, d0, df);
    if (dm > d0) {
      const double dTrial = std::min(1.0, df * (dm - d0) / (dm * (df - d0)));
      if (dTrial > st.damage) {  // irreversible: d only grows
        // Exact dissipation int Y dd, Y = K delta(d)^2 / 2 along the softening branch of the current
        // mode: delta(d) = df d0 / (df - d (df - d0)) gives D(d) = K (df d0)^2 / (2 (df - d0))
        // (1/(df - d (df - d0)) - 1/df), D(1) = K d0 df / 2 = G. Independent of the step size (a
        // trapezoid in Y overshoots G when a pair opens by much of df in one step).
        auto Dof = [&](double d) {
          return 0.5 * K * (df * d0) * (df * d0) / (df - d0) * (1.0 / (df - d * (df - d0)) - 1.0 / df);
        };
        st.dissipated += Dof(dTrial) - Dof(st.damage);
        st.damage = dTrial;
      }
    }
  }
  st.Yprev = Y;
  CohesiveTraction t;
  const double s = 1.0 - st.damage;
  t.tn = s * K * dnp + K * dnc;  // compression: undamaged penalty (crack faces never interpenetrate)
  t.ts = s * K * ds;
  t.stored = s * Y + 0.5 * K * dnc * dnc;
  return t;
}

CohesiveInterface::CohesiveInterface(const std::vector<double>& X, const std::vector<std::pair<int, int>>& pairs,
                                     std::vector<CohesiveLaw> laws, Eigen::Vector2d direction, double thickness)
    : dir_(direction.normalized()), w_(thickness) {
  const int n = static_cast<int>(pairs.size());
  if (laws.size() != 1 && laws.size() != pairs.size())
    throw Error("cohesive interface: one law per pair or one for all");
  for (const auto& l : laws) l.validate();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto sOf = [&](int k) { return X[2 * pairs[k].first] * dir_.x() + X[2 * pairs[k].first + 1] * dir_.y(); };
  std::sort(order.begin(), order.end(), [&](int i, int j) { return sOf(i) < sOf(j); });
  for (int k : order) {
    a_.push_back(pairs[k].first);
    b_.push_back(pairs[k].second);
    s_.push_back(sOf(k));
    law_.push_back(laws.size() == 1 ? laws[0] : laws[k]);
  }
  len_.assign(n, 0.0);
  for (int i = 0; i + 1 < n; ++i) {
    const double dx = X[2 * a_[i + 1]] - X[2 * a_[i]], dy = X[2 * a_[i + 1] + 1] - X[2 * a_[i] + 1];
    const double seg = std::hypot(dx, dy);
    len_[i] += 0.5 * seg;  // nodal (Newton-Cotes) integration of each linear segment
    len_[i + 1] += 0.5 * seg;
  }
  st_.assign(n, CohesiveState{});
  psi_.assign(n, 0.0);
  dn_.assign(n, 0.0);
}

void CohesiveInterface::addEndLength(double first, double last) {
  if (a_.empty()) return;
  len_.front() += first;
  len_.back() += last;
}

void CohesiveInterface::addForces(const std::vector<double>& X, const std::vector<double>& u, std::vector<double>& f) {
  if (dim_ == 3) return addForces3D(X, u, f);
  const int n = pairs();
  auto mid = [&](int i) {
    return Eigen::Vector2d(0.5 * (X[2 * a_[i]] + u[2 * a_[i]] + X[2 * b_[i]] + u[2 * b_[i]]),
                           0.5 * (X[2 * a_[i] + 1] + u[2 * a_[i] + 1] + X[2 * b_[i] + 1] + u[2 * b_[i] + 1]));
  };
  double stored = 0, diss = 0;
  for (int i = 0; i < n; ++i) {
    // current mid-surface tangent from the neighbouring pairs; normal = tangent turned +90 deg
    Eigen::Vector2d tau = n > 1 ? Eigen::Vector2d(mid(std::min(i + 1, n - 1)) - mid(std::max(i - 1, 0))) : dir_;
    const double tl = tau.norm();
    tau = tl > 0 && std::isfinite(tl) ? Eigen::Vector2d(tau / tl) : dir_;
    const Eigen::Vector2d nrm(-tau.y(), tau.x());
    const int a = a_[i], b = b_[i];
    const Eigen::Vector2d delta(X[2 * b] + u[2 * b] - X[2 * a] - u[2 * a],
                                X[2 * b + 1] + u[2 * b + 1] - X[2 * a + 1] - u[2 * a + 1]);
    const double dn = delta.dot(nrm), ds = delta.dot(tau);
    dn_[i] = dn;
    const CohesiveTraction t = cohesiveUpdate(law_[i], dn, ds, st_[i]);
    const Eigen::Vector2d F = (t.tn * nrm + t.ts * tau) * (len_[i] * w_);
    f[2 * a] += F.x(), f[2 * a + 1] += F.y();
    f[2 * b] -= F.x(), f[2 * b + 1] -= F.y();
    psi_[i] = t.stored;
    stored += t.stored * len_[i] * w_;
    diss += st_[i].dissipated * len_[i] * w_;
  }
  stored_ = stored;
  dissipated_ = diss;
}

double CohesiveInterface::maxOmega2(const std::vector<double>& m) const {
  double w2 = 0;
  for (int i = 0; i < pairs(); ++i)
    w2 = std::max(w2, law_[i].stiffness * len_[i] * w_ * (1.0 / m[a_[i]] + 1.0 / m[b_[i]]));
  return w2;
}

int CohesiveInterface::fullyDamaged() const {
  int c = 0;
  for (const auto& s : st_) c += s.damage >= 1.0;
  return c;
}

double CohesiveInterface::crackedLength() const {
  double L = 0;
  for (int i = 0; i < pairs(); ++i)
    if (st_[i].damage >= 1.0) L += len_[i];
  return L;
}

double CohesiveInterface::crackTip(double threshold) const {
  double s = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < pairs(); ++i)
    if (st_[i].damage >= threshold) s = std::max(s, s_[i]);
  return s;
}

void CohesiveInterface::forceOpen(int p) {
  auto& st = st_[p];
  if (st.damage >= 1.0) return;
  st.dissipated += psi_[p];  // the released elastic energy of the pair counts as dissipated
  st.damage = 1.0;
  psi_[p] = 0.0;
}

}  // namespace needlesim::explicit_fe
