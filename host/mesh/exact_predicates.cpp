// SPDX-License-Identifier: Apache-2.0
// orient2d / orient3d: Shewchuk's static filter, then exact expansion arithmetic (J. R.
// Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", 1997). The build pins -ffp-contract=off, which the error-free transformations
// below need; products use fma for their exact low part.
#include <smoothforce/mesh/exact_predicates.h>

#include <cmath>

namespace sf {
namespace {

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1
constexpr double kOrient3dBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;
constexpr double kOrient2dBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;

/// A non-overlapping expansion: components in increasing magnitude, zeros removed; the value
/// is their exact sum and its sign that of the last component. 192 components hold the
/// largest intermediate of orient3d (three products of a 2-, 2- and 2-component difference).
struct Expansion {
  static constexpr int kCapacity = 192;
  double c[kCapacity];
  int n = 0;
  int sign() const { return n == 0 ? 0 : (c[n - 1] > 0) - (c[n - 1] < 0); }
};

void twoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

void fastTwoSum(double a, double b, double& x, double& y) {  // |a| >= |b|
  x = a + b;
  y = b - (x - a);
}

void twoDiff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x, av = x + bv;
  y = (a - av) + (bv - b);
}

void twoProduct(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

/// a - b exactly, as a two-component expansion.
Expansion difference(double a, double b) {
  Expansion e;
  double x, y;
  twoDiff(a, b, x, y);
  if (y != 0) e.c[e.n++] = y;
  if (x != 0) e.c[e.n++] = x;
  return e;
}

/// h = e + b (Shewchuk's grow_expansion_zeroelim).
void grow(const Expansion& e, double b, Expansion& h) {
  double q = b;
  h.n = 0;
  for (int i = 0; i < e.n; ++i) {
    double sum, low;
    twoSum(q, e.c[i], sum, low);
    q = sum;
    if (low != 0) h.c[h.n++] = low;
  }
  if (q != 0) h.c[h.n++] = q;
}

/// e + f by growing e by each component of f (quadratic, but only the filter's failures get here).
Expansion add(const Expansion& e, const Expansion& f) {
  Expansion a = e, b;
  for (int j = 0; j < f.n; ++j) {
    grow(a, f.c[j], b);
    a = b;
  }
  return a;
}

Expansion negate(Expansion e) {
  for (int i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
  return e;
}

/// e * b (Shewchuk's scale_expansion_zeroelim).
Expansion scale(const Expansion& e, double b) {
  Expansion h;
  if (e.n == 0 || b == 0) return h;
  double q, low;
  twoProduct(e.c[0], b, q, low);
  if (low != 0) h.c[h.n++] = low;
  for (int i = 1; i < e.n; ++i) {
    double hi1, lo1, sum;
    twoProduct(e.c[i], b, hi1, lo1);
    twoSum(q, lo1, sum, low);
    if (low != 0) h.c[h.n++] = low;
    fastTwoSum(hi1, sum, q, low);
    if (low != 0) h.c[h.n++] = low;
  }
  if (q != 0) h.c[h.n++] = q;
  return h;
}

Expansion multiply(const Expansion& e, const Expansion& f) {
  Expansion acc;
  for (int j = 0; j < f.n; ++j) acc = add(acc, scale(e, f.c[j]));
  return acc;
}

int orient3dExact(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& d) {
  const Expansion adx = difference(a.x(), d.x()), ady = difference(a.y(), d.y()), adz = difference(a.z(), d.z());
  const Expansion bdx = difference(b.x(), d.x()), bdy = difference(b.y(), d.y()), bdz = difference(b.z(), d.z());
  const Expansion cdx = difference(c.x(), d.x()), cdy = difference(c.y(), d.y()), cdz = difference(c.z(), d.z());
  // det = adx (bdy cdz - bdz cdy) - ady (bdx cdz - bdz cdx) + adz (bdx cdy - bdy cdx)
  const Expansion m1 = add(multiply(bdy, cdz), negate(multiply(bdz, cdy)));
  const Expansion m2 = add(multiply(bdx, cdz), negate(multiply(bdz, cdx)));
  const Expansion m3 = add(multiply(bdx, cdy), negate(multiply(bdy, cdx)));
  return add(add(multiply(adx, m1), negate(multiply(ady, m2))), multiply(adz, m3)).sign();
}

int orient2dExact(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Expansion acx = difference(a.x(), c.x()), acy = difference(a.y(), c.y());
  const Expansion bcx = difference(b.x(), c.x()), bcy = difference(b.y(), c.y());
  return add(multiply(acx, bcy), negate(multiply(acy, bcx))).sign();
}

}  // namespace

int orient3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
             const Eigen::Vector3d& d) noexcept {
  const double adx = a.x() - d.x(), bdx = b.x() - d.x(), cdx = c.x() - d.x();
  const double ady = a.y() - d.y(), bdy = b.y() - d.y(), cdy = c.y() - d.y();
  const double adz = a.z() - d.z(), bdz = b.z() - d.z(), cdz = c.z() - d.z();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  if (!std::isfinite(permanent)) return 0;  // non-finite input or overflow: not decided
  const double bound = kOrient3dBound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return orient3dExact(a, b, c, d);
}

int orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) noexcept {
  const double left = (a.x() - c.x()) * (b.y() - c.y()), right = (a.y() - c.y()) * (b.x() - c.x());
  const double det = left - right, permanent = std::abs(left) + std::abs(right);
  if (!std::isfinite(permanent)) return 0;
  const double bound = kOrient2dBound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return orient2dExact(a, b, c);
}

}  // namespace sf
