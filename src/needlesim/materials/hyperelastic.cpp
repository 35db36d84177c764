#include "needlesim/materials/hyperelastic.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/law_energy.hpp"

namespace needlesim::materials {

namespace {

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

[[noreturn]] void bad(const std::string& law, const std::string& key, double v,
                      const std::string& allowed) {
  throw Error("material law '" + law + "': parameter " + key + " = " + num(v) +
              " is not allowed; " + allowed);
}

}  // namespace

LawKind lawKind(const std::string& name) {
  if (name == "linear") return LawKind::Linear;
  if (name == "neo-hookean") return LawKind::NeoHookean;
  if (name == "mooney-rivlin") return LawKind::MooneyRivlin;
  if (name == "yeoh") return LawKind::Yeoh;
  if (name == "ogden") return LawKind::Ogden;
  if (name == "fung") return LawKind::Fung;
  throw Error("unknown constitutive law '" + name +
              "'; allowed: linear, neo-hookean, mooney-rivlin, yeoh, ogden, fung");
}

std::string lawName(LawKind kind) {
  switch (kind) {
    case LawKind::Linear: return "linear";
    case LawKind::NeoHookean: return "neo-hookean";
    case LawKind::MooneyRivlin: return "mooney-rivlin";
    case LawKind::Yeoh: return "yeoh";
    case LawKind::Ogden: return "ogden";
    case LawKind::Fung: return "fung";
  }
  return "?";
}

double Hyperelastic::initialShear() const {
  switch (kind) {
    case LawKind::Linear: return lame(E, nu).mu;
    case LawKind::NeoHookean:
    case LawKind::Yeoh: return 2.0 * C10;
    case LawKind::MooneyRivlin: return 2.0 * (C10 + C01);
    case LawKind::Ogden: {
      double s = 0.0;
      for (std::size_t p = 0; p < ogdenMu.size(); ++p) s += 0.5 * ogdenMu[p] * ogdenAlpha[p];
      return s;
    }
    case LawKind::Fung: return mu;
  }
  return 0.0;
}

double Hyperelastic::initialBulk() const { return kind == LawKind::Linear ? bulkModulus(E, nu) : bulk; }

Lame Hyperelastic::initialLame() const {
  if (kind == LawKind::Linear) return lame(E, nu);
  const double mu0 = initialShear();
  return {bulk - 2.0 / 3.0 * mu0, mu0};
}

void Hyperelastic::validate() const {
  const std::string n = lawName(kind);
  auto finite = [&](const char* key, double v) {
    if (!std::isfinite(v)) bad(n, key, v, "it must be a finite number");
  };
  switch (kind) {
    case LawKind::Linear:
      finite("E", E);
      finite("nu", nu);
      if (!(E > 0)) bad(n, "E", E, "E must be > 0 Pa");
      if (!(nu > -1.0 && nu < 0.5)) bad(n, "nu", nu, "-1 < nu < 0.5");
      return;
    case LawKind::NeoHookean:
      finite("C10", C10);
      if (!(C10 > 0)) bad(n, "C10", C10, "C10 must be > 0 Pa");
      break;
    case LawKind::MooneyRivlin:
      finite("C10", C10);
      finite("C01", C01);
      if (!(C10 + C01 > 0)) bad(n, "C10 + C01", C10 + C01, "the initial shear modulus 2 (C10 + C01) must be > 0");
      break;
    case LawKind::Yeoh:
      finite("C10", C10);
      finite("C20", C20);
      finite("C30", C30);
      if (!(C10 > 0)) bad(n, "C10", C10, "C10 must be > 0 Pa");
      break;
    case LawKind::Ogden:
      if (ogdenMu.empty() || ogdenMu.size() != ogdenAlpha.size() || ogdenMu.size() > 3)
        throw Error("material law 'ogden' needs 1 to 3 pairs (mu_p, alpha_p); got " +
                    std::to_string(ogdenMu.size()) + " mu and " + std::to_string(ogdenAlpha.size()) +
                    " alpha");
      for (std::size_t p = 0; p < ogdenMu.size(); ++p) {
        std::string k = std::to_string(p + 1);
        finite(("mu" + k).c_str(), ogdenMu[p]);
        finite(("alpha" + k).c_str(), ogdenAlpha[p]);
        if (ogdenAlpha[p] == 0.0) bad(n, "alpha" + k, 0.0, "alpha_p must be non-zero");
        if (!(ogdenMu[p] * ogdenAlpha[p] > 0))
          bad(n, "mu" + k, ogdenMu[p], "mu_p alpha_p must be > 0 (stability); alpha" + k + " = " + num(ogdenAlpha[p]));
      }
      break;
    case LawKind::Fung:
      finite("mu", mu);
      finite("gamma", gamma);
      if (!(mu > 0)) bad(n, "mu", mu, "mu must be > 0 Pa");
      if (!(gamma > 0)) bad(n, "gamma", gamma, "gamma must be > 0 (use neo-hookean for gamma = 0)");
      break;
  }
  finite("K", bulk);
  if (!(bulk > 0)) bad(n, "K", bulk, "the bulk modulus K must be > 0 Pa (or give nu < 0.5)");
}

Hyperelastic Hyperelastic::fromSpec(const MaterialSpec& spec) {
  Hyperelastic h;
  h.kind = lawKind(spec.law);
  switch (h.kind) {
    case LawKind::Linear:
      h.E = spec.param("E");
      h.nu = spec.param("nu");
      break;
    case LawKind::NeoHookean: h.C10 = spec.param("C10"); break;
    case LawKind::MooneyRivlin:
      h.C10 = spec.param("C10");
      h.C01 = spec.param("C01");
      break;
    case LawKind::Yeoh:
      h.C10 = spec.param("C10");
      h.C20 = spec.paramOr("C20", 0.0);
      h.C30 = spec.paramOr("C30", 0.0);
      break;
    case LawKind::Ogden:
      for (int p = 1; p <= 3; ++p) {
        std::string k = std::to_string(p);
        if (!spec.has("mu" + k) && !spec.has("alpha" + k)) continue;
        h.ogdenMu.push_back(spec.param("mu" + k));
        h.ogdenAlpha.push_back(spec.param("alpha" + k));
      }
      break;
    case LawKind::Fung:
      h.mu = spec.param("mu");
      h.gamma = spec.param("gamma");
      break;
  }
  if (h.kind != LawKind::Linear) {
    if (spec.has("K")) {
      h.bulk = spec.param("K");
    } else {
      double nu = spec.paramOr("nu", 0.49);
      if (!(nu > -1.0 && nu < 0.5)) bad(spec.law, "nu", nu, "-1 < nu < 0.5 (up to 0.499 for near-incompressible tissue)");
      double mu0 = h.initialShear();
      h.bulk = bulkFromShear(mu0, nu);
    }
  }
  h.validate();
  return h;
}

namespace {

using Sym6 = Eigen::Matrix<double, 6, 6>;

// Tensor-component 6x6 of A (x) B for symmetric A, B.
Sym6 outer(const Mat3& A, const Mat3& B) {
  Sym6 M;
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J)
      M(I, J) = A(kVoigt3[I][0], kVoigt3[I][1]) * B(kVoigt3[J][0], kVoigt3[J][1]);
  return M;
}

// (I_A)_ijkl = 1/2 (A_ik A_jl + A_il A_jk)
Sym6 symProduct(const Mat3& A) {
  Sym6 M;
  for (int I = 0; I < 6; ++I) {
    int i = kVoigt3[I][0], j = kVoigt3[I][1];
    for (int J = 0; J < 6; ++J) {
      int k = kVoigt3[J][0], l = kVoigt3[J][1];
      M(I, J) = 0.5 * (A(i, k) * A(j, l) + A(i, l) * A(j, k));
    }
  }
  return M;
}

// NV variables: J, I1, I2 (3), plus h1..h3 for Ogden (6).
template <int NV>
Stress3 evaluateImpl(const Hyperelastic& m, const Mat3& F, bool withTangent) {
  const double Jv = F.determinant();
  if (!(Jv > 0.0) || !std::isfinite(Jv))
    throw SolverError("deformation gradient with det F = " + num(Jv) +
                      " (an inverted or degenerate element); reduce the time step or refine the mesh");
  const Mat3 C = F.transpose() * F;
  const double I1v = C.trace();
  const double I2v = 0.5 * (I1v * I1v - (C * C).trace());
  const int nOgden = m.kind == LawKind::Ogden ? std::min(static_cast<int>(m.ogdenAlpha.size()), NV - 3) : 0;

  // Spectral data for the Ogden invariants h_p = tr C^(alpha_p/2).
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  Eigen::Vector3d c = Eigen::Vector3d::Ones();
  Mat3 N = Mat3::Identity();
  if (nOgden > 0) {
    eig.compute(C);
    c = eig.eigenvalues();
    N = eig.eigenvectors();
  }

  using A = detail::Ad2<NV>;
  A Jx = A::variable(Jv, 0), I1x = A::variable(I1v, 1), I2x = A::variable(I2v, 2);
  A hx[3] = {A(0.0), A(0.0), A(0.0)};  // constant zero unless Ogden
  for (int p = 0; p < nOgden; ++p) {
    double a = m.ogdenAlpha[p];
    double h = 0;
    for (int k = 0; k < 3; ++k) h += std::pow(c[k], 0.5 * a);
    hx[p] = A::variable(h, 3 + p);
  }
  A W = detail::totalEnergy(m, Jx, I1x, I2x, hx);

  // Gradients of the invariants with respect to C.
  const Mat3 I = Mat3::Identity();
  const Mat3 Cinv = C.inverse();
  Mat3 G[NV];
  G[0] = 0.5 * Jv * Cinv;
  G[1] = I;
  G[2] = I1v * I - C;
  for (int p = 3; p < NV; ++p) G[p].setZero();
  for (int p = 0; p < nOgden; ++p) {
    double a = m.ogdenAlpha[p];
    Eigen::Vector3d f1;
    for (int k = 0; k < 3; ++k) f1[k] = 0.5 * a * std::pow(c[k], 0.5 * a - 1.0);
    G[3 + p] = N * f1.asDiagonal() * N.transpose();
  }

  Stress3 out;
  out.energy = W.v;
  Mat3 S = Mat3::Zero();
  for (int k = 0; k < NV; ++k) S += 2.0 * W.g[k] * G[k];
  out.S = 0.5 * (S + S.transpose());
  out.sigma = F * out.S * F.transpose() / Jv;
  if (!withTangent) return out;

  // Hessians of the invariants (tensor components).
  Sym6 H[NV];
  H[0] = 0.25 * Jv * outer(Cinv, Cinv) - 0.5 * Jv * symProduct(Cinv);
  H[1].setZero();
  H[2] = outer(I, I) - symProduct(I);
  for (int p = 3; p < NV; ++p) H[p].setZero();
  for (int p = 0; p < nOgden; ++p) {
    // Daleckii-Krein: d(f'(C)) = sum_ab d_ab P_a dC P_b with divided differences d_ab.
    double a = m.ogdenAlpha[p];
    auto f1 = [&](double x) { return 0.5 * a * std::pow(x, 0.5 * a - 1.0); };
    auto f2 = [&](double x) { return 0.5 * a * (0.5 * a - 1.0) * std::pow(x, 0.5 * a - 2.0); };
    double d[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double gap = c[i] - c[j];
        if (std::abs(gap) <= 1e-6 * (std::abs(c[i]) + std::abs(c[j])))
          d[i][j] = f2(0.5 * (c[i] + c[j]));
        else
          d[i][j] = (f1(c[i]) - f1(c[j])) / gap;
      }
    Sym6 M = Sym6::Zero();
    for (int I6 = 0; I6 < 6; ++I6) {
      int i = kVoigt3[I6][0], j = kVoigt3[I6][1];
      for (int J6 = 0; J6 < 6; ++J6) {
        int k = kVoigt3[J6][0], l = kVoigt3[J6][1];
        double s = 0;
        for (int aa = 0; aa < 3; ++aa)
          for (int bb = 0; bb < 3; ++bb) {
            double ni = N(i, aa), nj = N(j, aa), nk = N(k, aa), nl = N(l, aa);
            double mi = N(i, bb), mj = N(j, bb), mk = N(k, bb), ml = N(l, bb);
            s += d[aa][bb] * (ni * nk * ml * mj + ni * nl * mk * mj + nj * nk * ml * mi + nj * nl * mk * mi);
          }
        M(I6, J6) = 0.25 * s;
      }
    }
    H[3 + p] = M;
  }
  Sym6 T = Sym6::Zero();
  for (int k = 0; k < NV; ++k) {
    if (W.g[k] != 0.0) T += W.g[k] * H[k];
    for (int l = 0; l < NV; ++l)
      if (W.hess(k, l) != 0.0) T += W.hess(k, l) * outer(G[k], G[l]);
  }
  out.tangent = 4.0 * 0.5 * (T + T.transpose());
  return out;
}

}  // namespace

Stress3 evaluate(const Hyperelastic& m, const Mat3& F, bool withTangent) {
  return m.kind == LawKind::Ogden ? evaluateImpl<6>(m, F, withTangent) : evaluateImpl<3>(m, F, withTangent);
}

Stress2 evaluatePlaneStrain(const Hyperelastic& m, const Mat2& F, bool withTangent) {
  Mat3 F3 = Mat3::Identity();
  F3.topLeftCorner<2, 2>() = F;
  Stress3 s = evaluate(m, F3, withTangent);
  Stress2 out;
  out.energy = s.energy;
  out.S = s.S.topLeftCorner<2, 2>();
  out.sigma = s.sigma.topLeftCorner<2, 2>();
  out.sigma33 = s.sigma(2, 2);
  if (withTangent) {
    const int idx[3] = {0, 1, 3};
    for (int I = 0; I < 3; ++I)
      for (int J = 0; J < 3; ++J) out.tangent(I, J) = s.tangent(idx[I], idx[J]);
  }
  return out;
}

double strainEnergy(const Hyperelastic& law, const Mat3& F) { return evaluate(law, F, false).energy; }
Mat3 secondPiolaKirchhoff(const Hyperelastic& law, const Mat3& F) { return evaluate(law, F, false).S; }
Mat3 cauchyStress(const Hyperelastic& law, const Mat3& F) { return evaluate(law, F, false).sigma; }

}  // namespace needlesim::materials
