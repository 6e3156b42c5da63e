// SPDX-License-Identifier: Apache-2.0
// Tiny 3-vector templated on the scalar, for the reference patch (double or
// std::complex<double> for complex-step derivatives). Deliberately not Eigen: Eigen's dot()
// conjugates its first complex argument, which would break the complex step.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>

namespace sf::ref::detail {

using Cplx = std::complex<double>;

/// Complex step of f'(x) = Im f(x + i h) / h.
inline constexpr double kComplexStep = 1e-30;

inline double re(double x) { return x; }
inline double re(const Cplx& x) { return x.real(); }
inline double im(double) { return 0.0; }
inline double im(const Cplx& x) { return x.imag(); }

template <class T>
struct V3 {
  T x{}, y{}, z{};
};

template <class T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
V3<T> operator-(const V3<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class T>
V3<T> operator*(const T& s, const V3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
V3<T> operator/(const V3<T>& a, const T& s) {
  return {a.x / s, a.y / s, a.z / s};
}

/// Plain (non-conjugating) dot product: analytic in complex arguments.
template <class T>
T dot(const V3<T>& a, const V3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// unit(v) = v / sqrt(v.x^2 + v.y^2 + v.z^2), analytic (no conj) so the complex step
/// passes through normalisations.
template <class T>
V3<T> unit(const V3<T>& v) {
  return v / T(std::sqrt(dot(v, v)));
}
/// Length of the real part (for branch decisions and real-only data).
template <class T>
double realNorm(const V3<T>& v) {
  return std::sqrt(re(v.x) * re(v.x) + re(v.y) * re(v.y) + re(v.z) * re(v.z));
}

/// Real vector promoted to scalar type T.
template <class T>
V3<T> lift(const V3<double>& a) {
  return {T(a.x), T(a.y), T(a.z)};
}

inline V3<double> fromEigen(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
template <class T>
Eigen::Vector3d realPart(const V3<T>& v) {
  return {re(v.x), re(v.y), re(v.z)};
}
/// Im(v) / h: the complex-step derivative.
inline Eigen::Vector3d stepDerivative(const V3<Cplx>& v) {
  return Eigen::Vector3d(v.x.imag(), v.y.imag(), v.z.imag()) / kComplexStep;
}

}  // namespace sf::ref::detail
