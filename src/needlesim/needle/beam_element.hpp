#pragma once
// Euler-Bernoulli beam element (cubic Hermite interpolation), reusable by any
// engine that needs a needle shaft: steering beam-on-foundation, 2D real-time FE.
// Element dofs (w1, theta1, w2, theta2); the 2D frame element adds the axial
// displacement: (u1, w1, theta1, u2, w2, theta2). Fixed-size Eigen, no allocation.
// Reference: standard FE texts (Przemieniecki 1968; Cook et al. 2002, ch. 2).
#include <cmath>

#include <Eigen/Core>

namespace needlesim::needle {

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Hermite shape functions N(xi) and derivatives w.r.t. x, xi = x/h in [0, 1].
inline Vec4 hermiteN(double xi, double h) {
  const double x2 = xi * xi, x3 = x2 * xi;
  return Vec4(1 - 3 * x2 + 2 * x3, h * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, h * (x3 - x2));
}
inline Vec4 hermiteDN(double xi, double h) {  // dN/dx
  const double x2 = xi * xi;
  return Vec4((-6 * xi + 6 * x2) / h, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / h, 3 * x2 - 2 * xi);
}
inline Vec4 hermiteD2N(double xi, double h) {  // d2N/dx2
  return Vec4((-6 + 12 * xi) / (h * h), (-4 + 6 * xi) / h, (6 - 12 * xi) / (h * h), (6 * xi - 2) / h);
}
inline Vec4 hermiteD3N(double h) {  // d3N/dx3 (constant)
  return Vec4(12 / (h * h * h), 6 / (h * h), -12 / (h * h * h), 6 / (h * h));
}

// Bending stiffness EI/h^3 [...]: exact for cubic fields (seed 003 eq 3.14; the thesis
// extraction prints 4/L in row 4 col 2, the symmetric matrix has 2/L).
inline Mat4 bendingStiffness(double EI, double h) {
  const double h2 = h * h;
  Mat4 k;
  k << 12, 6 * h, -12, 6 * h,  //
      6 * h, 4 * h2, -6 * h, 2 * h2,  //
      -12, -6 * h, 12, -6 * h,  //
      6 * h, 2 * h2, -6 * h, 4 * h2;
  return k * (EI / (h2 * h));
}

// Consistent Winkler-foundation stiffness: k_f * int N N^T dx, k_f in N/m^2.
inline Mat4 foundationStiffness(double kf, double h) {
  const double h2 = h * h;
  Mat4 k;
  k << 156, 22 * h, 54, -13 * h,  //
      22 * h, 4 * h2, 13 * h, -3 * h2,  //
      54, 13 * h, 156, -22 * h,  //
      -13 * h, -3 * h2, -22 * h, 4 * h2;
  return k * (kf * h / 420.0);
}

// Geometric stiffness for an axial force N (tension positive): N int N'N'^T dx.
inline Mat4 geometricStiffness(double N, double h) {
  const double h2 = h * h;
  Mat4 k;
  k << 36, 3 * h, -36, 3 * h,  //
      3 * h, 4 * h2, -3 * h, -h2,  //
      -36, -3 * h, 36, -3 * h,  //
      3 * h, -h2, -3 * h, 4 * h2;
  return k * (N / (30.0 * h));
}

// Load vector of a uniform transverse load q (N/m).
inline Vec4 uniformLoad(double q, double h) { return Vec4(6, h, 6, -h) * (q * h / 12.0); }

// Load vector of a stress-free (natural) curvature kappa0 of the reference the
// deflection is measured from: the energy EI/2 int (kappa0 + w'')^2 gives
// f = -EI kappa0 int N'' dx = EI kappa0 (0, 1, 0, -1).
inline Vec4 naturalCurvatureLoad(double EI, double kappa0) {
  return Vec4(0, 1, 0, -1) * (EI * kappa0);
}

// 2D frame element in local coordinates (u1, w1, theta1, u2, w2, theta2).
inline Mat6 frameStiffnessLocal(double EA, double EI, double h) {
  Mat6 k = Mat6::Zero();
  const double ka = EA / h;
  k(0, 0) = k(3, 3) = ka;
  k(0, 3) = k(3, 0) = -ka;
  const Mat4 kb = bendingStiffness(EI, h);
  constexpr int idx[4] = {1, 2, 4, 5};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) k(idx[i], idx[j]) = kb(i, j);
  return k;
}

// Rotation from global (X, Y, theta) nodal dofs to local dofs, element axis at angle phi.
inline Mat6 frameRotation(double c, double s) {
  Mat6 T = Mat6::Zero();
  for (int n = 0; n < 2; ++n) {
    const int o = 3 * n;
    T(o, o) = c;
    T(o, o + 1) = s;
    T(o + 1, o) = -s;
    T(o + 1, o + 1) = c;
    T(o + 2, o + 2) = 1;
  }
  return T;
}

// Global stiffness T^T K T of a frame element from node (x1, y1) to (x2, y2).
inline Mat6 frameStiffnessGlobal(double EA, double EI, double x1, double y1, double x2, double y2) {
  const double dx = x2 - x1, dy = y2 - y1, h = std::hypot(dx, dy);
  const Mat6 T = frameRotation(dx / h, dy / h);
  return T.transpose() * frameStiffnessLocal(EA, EI, h) * T;
}

// Closed-form influence functions of a cantilever clamped at x = 0: deflection at a and
// slope at a per unit transverse force at b. The Hermite FE with nodes at the load points
// reproduces them exactly (its static condensation); min^2 (3 max - min) / (6 EI) is seed 003
// eq 3.12's k = l^3 / 3EI generalised to two points.
inline double cantileverDeflection(double a, double b, double EI) {
  const double lo = a < b ? a : b, hi = a < b ? b : a;
  return lo * lo * (3.0 * hi - lo) / (6.0 * EI);
}
inline double cantileverSlope(double a, double b, double EI) {
  return a <= b ? a * (2.0 * b - a) / (2.0 * EI) : b * b / (2.0 * EI);
}

}  // namespace needlesim::needle
