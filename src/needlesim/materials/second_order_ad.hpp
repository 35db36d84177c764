#pragma once
// A scalar that carries its exact gradient and Hessian with respect to N
// variables (forward-mode, second order). The constitutive laws are written
// once as scalar functions of a few invariants; this type gives their first
// and second derivatives exactly, so stresses and consistent tangents come from
// the same formula as the energy. Internal to the materials library.
#include <array>
#include <cmath>

namespace needlesim::materials::detail {

template <int N>
struct Ad2 {
  double v = 0.0;
  std::array<double, N> g{};
  std::array<double, N * N> h{};  // row-major, symmetric

  Ad2() = default;
  Ad2(double value) : v(value) {}  // NOLINT: constants convert implicitly
  static Ad2 variable(double value, int i) {
    Ad2 r(value);
    r.g[i] = 1.0;
    return r;
  }
  double hess(int i, int j) const { return h[i * N + j]; }
};

// Applies a scalar function with value f0, slope f1 and curvature f2 at a.v.
template <int N>
Ad2<N> chain(const Ad2<N>& a, double f0, double f1, double f2) {
  Ad2<N> r(f0);
  for (int i = 0; i < N; ++i) r.g[i] = f1 * a.g[i];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) r.h[i * N + j] = f1 * a.h[i * N + j] + f2 * a.g[i] * a.g[j];
  return r;
}

template <int N>
Ad2<N> operator+(const Ad2<N>& a, const Ad2<N>& b) {
  Ad2<N> r(a.v + b.v);
  for (int i = 0; i < N; ++i) r.g[i] = a.g[i] + b.g[i];
  for (int k = 0; k < N * N; ++k) r.h[k] = a.h[k] + b.h[k];
  return r;
}
template <int N>
Ad2<N> operator-(const Ad2<N>& a) {
  Ad2<N> r(-a.v);
  for (int i = 0; i < N; ++i) r.g[i] = -a.g[i];
  for (int k = 0; k < N * N; ++k) r.h[k] = -a.h[k];
  return r;
}
template <int N>
Ad2<N> operator-(const Ad2<N>& a, const Ad2<N>& b) {
  return a + (-b);
}
template <int N>
Ad2<N> operator*(const Ad2<N>& a, const Ad2<N>& b) {
  Ad2<N> r(a.v * b.v);
  for (int i = 0; i < N; ++i) r.g[i] = a.g[i] * b.v + a.v * b.g[i];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      r.h[i * N + j] = a.h[i * N + j] * b.v + b.h[i * N + j] * a.v + a.g[i] * b.g[j] +
                       a.g[j] * b.g[i];
  return r;
}
template <int N>
Ad2<N> operator*(double s, const Ad2<N>& a) {
  Ad2<N> r(s * a.v);
  for (int i = 0; i < N; ++i) r.g[i] = s * a.g[i];
  for (int k = 0; k < N * N; ++k) r.h[k] = s * a.h[k];
  return r;
}
template <int N>
Ad2<N> operator*(const Ad2<N>& a, double s) {
  return s * a;
}
template <int N>
Ad2<N> operator+(const Ad2<N>& a, double s) {
  Ad2<N> r = a;
  r.v += s;
  return r;
}
template <int N>
Ad2<N> operator+(double s, const Ad2<N>& a) {
  return a + s;
}
template <int N>
Ad2<N> operator-(const Ad2<N>& a, double s) {
  return a + (-s);
}
template <int N>
Ad2<N> operator-(double s, const Ad2<N>& a) {
  return (-a) + s;
}
template <int N>
Ad2<N> inv(const Ad2<N>& a) {
  double x = a.v;
  return chain(a, 1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x));
}
template <int N>
Ad2<N> operator/(const Ad2<N>& a, const Ad2<N>& b) {
  return a * inv(b);
}
template <int N>
Ad2<N> operator/(const Ad2<N>& a, double s) {
  return (1.0 / s) * a;
}
template <int N>
Ad2<N> exp(const Ad2<N>& a) {
  double e = std::exp(a.v);
  return chain(a, e, e, e);
}
template <int N>
Ad2<N> expm1(const Ad2<N>& a) {
  double e = std::exp(a.v);
  return chain(a, std::expm1(a.v), e, e);
}
template <int N>
Ad2<N> log(const Ad2<N>& a) {
  double x = a.v;
  return chain(a, std::log(x), 1.0 / x, -1.0 / (x * x));
}
template <int N>
Ad2<N> pow(const Ad2<N>& a, double p) {
  double x = a.v;
  return chain(a, std::pow(x, p), p * std::pow(x, p - 1.0), p * (p - 1.0) * std::pow(x, p - 2.0));
}
template <int N>
Ad2<N> sqrt(const Ad2<N>& a) {
  return pow(a, 0.5);
}

}  // namespace needlesim::materials::detail
