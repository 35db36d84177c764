#include "needlesim/materials/hyperelastic.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/law_energy.hpp"
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials {

namespace {

std::string num(double v) { return laws::numberText(v); }

}  // namespace

LawKind lawKind(const std::string& name) { return lawUnit(name).kind; }

std::string lawName(LawKind kind) { return lawUnit(kind).name; }

double Hyperelastic::initialShear() const { return lawUnit(kind).shear(*this); }

double Hyperelastic::initialBulk() const {
  const LawUnit& u = lawUnit(kind);
  return u.volumetric ? bulk : u.bulk(*this);
}

Lame Hyperelastic::initialLame() const {
  const LawUnit& u = lawUnit(kind);
  if (!u.volumetric) return u.lame(*this);
  const double mu0 = initialShear();
  return {bulk - 2.0 / 3.0 * mu0, mu0};
}

void Hyperelastic::validate() const {
  const LawUnit& u = lawUnit(kind);
  u.validate(*this);
  if (!u.volumetric) return;
  laws::requireFinite(u.name, "K", bulk);
  if (!(bulk > 0)) laws::badParam(u.name, "K", bulk, "the bulk modulus K must be > 0 Pa (or give nu < 0.5)");
}

Hyperelastic Hyperelastic::fromSpec(const MaterialSpec& spec) {
  const LawUnit& u = lawUnit(spec.law);
  Hyperelastic h;
  h.kind = u.kind;
  u.read(spec, h);
  if (u.volumetric) {
    if (spec.has("K")) {
      h.bulk = spec.param("K");
    } else {
      double nu = spec.paramOr("nu", 0.49);
      if (!(nu > -1.0 && nu < 0.5))
        laws::badParam(spec.law, "nu", nu, "-1 < nu < 0.5 (up to 0.499 for near-incompressible tissue)");
      h.bulk = bulkFromShear(h.initialShear(), nu);
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
  const int nOgden = lawUnit(m.kind).stretches ? std::min(static_cast<int>(m.ogdenAlpha.size()), NV - 3) : 0;

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
  return lawUnit(m.kind).stretches ? evaluateImpl<6>(m, F, withTangent) : evaluateImpl<3>(m, F, withTangent);
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
