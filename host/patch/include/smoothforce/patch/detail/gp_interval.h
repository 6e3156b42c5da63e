// SPDX-License-Identifier: Apache-2.0
// Enclosure types that stand in for GP_REAL, so that the single-source patch math
// (kernels/gp_patch.h) evaluated on a box of domain points encloses every value it takes
// there: the patch certificate (patch_certificate.h) bounds the patch's derivatives with them.
//
// Interval: [lo, hi], arithmetic rounded outward (each bound of a correctly rounded operation
// moved one step away). Plain intervals lose correlation at every operation: over the patch
// math a box of width w gave derivative bounds about 2000 w wide (measured on the spot cage),
// so the certificate would need boxes of 1e-6. Taylor (below) keeps the first- and second-order
// parts exactly: x = c + gx ex + gy ey + hxx ex^2 + hxy ex ey + hyy ey^2 + err e, with ex, ey the
// box's two coordinates scaled to [-1, 1] and e an error symbol in [-1, 1], so the excess of a
// bound shrinks with the cube of the box's size (a second-order Taylor model: K. Makino, M. Berz,
// "Taylor models and other validated functional inclusion methods", Int. J. Pure Appl. Math. 4,
// 2003; nonlinear steps by Taylor's theorem with the Lagrange remainder). Its first-order
// predecessor (affine arithmetic: J. Stolfi, L. H. de Figueiredo, "Self-validated numerical
// methods and applications", IMPA 1997) lumped every product's quadratic part into err, where the
// rational blend's cancellations were lost: on a flat square patch, over a box 1/64 of the
// domain wide, its bound of J was 170 times as wide as the second-order one (docs/certificate.md).
//
// Comparisons give a three-valued mask (certainly / possibly true); GP_SEL of an undecided mask
// is the hull of both sides, GP_ANY is "possibly", GP_ALL "certainly", so that the branch-free
// math (kernels/gp_vec.h, "Lanes") takes every path a point of the box can take.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#if defined(__GNUC__)
#define SF_TAYLOR_INLINE inline __attribute__((always_inline))
#else
#define SF_TAYLOR_INLINE inline
#endif

namespace sf::interval {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A bound one rounding step below / above x (x itself where infinite).
inline double roundDown(double x) {
  if (!(std::fabs(x) < kInf)) return x;
  return x - (std::fabs(x) * 0x1p-52 + DBL_TRUE_MIN);
}
inline double roundUp(double x) {
  if (!(std::fabs(x) < kInf)) return x;
  return x + (std::fabs(x) * 0x1p-52 + DBL_TRUE_MIN);
}

/// Three-valued comparison result: `possible` (true for some point of the operands),
/// `certain` (true for every point). certain implies possible.
struct Mask {
  bool possible = false, certain = false;
  Mask() = default;
  Mask(bool b) : possible(b), certain(b) {}  // NOLINT: a decided condition, like a scalar's
  Mask(bool p, bool c) : possible(p), certain(c) {}
  friend Mask operator&&(Mask a, Mask b) { return {a.possible && b.possible, a.certain && b.certain}; }
  friend Mask operator||(Mask a, Mask b) { return {a.possible || b.possible, a.certain || b.certain}; }
  friend Mask operator!(Mask a) { return {!a.certain, !a.possible}; }
  friend bool gp_any(Mask a) { return a.possible; }
  friend bool gp_all(Mask a) { return a.certain; }
};

/// A closed interval [lo, hi] of reals (lo <= hi; infinite bounds allowed).
struct Interval {
  double lo = 0, hi = 0;
  Interval() = default;
  Interval(double x) : lo(x), hi(x) {}  // NOLINT: a constant, like a scalar
  Interval(double l, double h) : lo(std::isnan(l) ? -kInf : l), hi(std::isnan(h) ? kInf : h) {}
  static Interval rounded(double l, double h) { return {roundDown(l), roundUp(h)}; }
  bool contains(double x) const { return lo <= x && x <= hi; }
  double width() const { return hi - lo; }

  friend Interval operator+(Interval a, Interval b) { return rounded(a.lo + b.lo, a.hi + b.hi); }
  friend Interval operator-(Interval a, Interval b) { return rounded(a.lo - b.hi, a.hi - b.lo); }
  friend Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
  friend Interval operator*(Interval a, Interval b) {
    // 0 times an infinite bound: the operands are reals, so the product is 0
    auto m = [](double x, double y) {
      const double p = x * y;
      return std::isnan(p) ? 0.0 : p;
    };
    const double p0 = m(a.lo, b.lo), p1 = m(a.lo, b.hi), p2 = m(a.hi, b.lo), p3 = m(a.hi, b.hi);
    return rounded(std::min(std::min(p0, p1), std::min(p2, p3)), std::max(std::max(p0, p1), std::max(p2, p3)));
  }
  friend Interval operator/(Interval a, Interval b) {
    if (b.lo <= 0 && b.hi >= 0) return {-kInf, kInf};
    const double q0 = a.lo / b.lo, q1 = a.lo / b.hi, q2 = a.hi / b.lo, q3 = a.hi / b.hi;
    return rounded(std::min(std::min(q0, q1), std::min(q2, q3)), std::max(std::max(q0, q1), std::max(q2, q3)));
  }
  Interval& operator+=(Interval b) { return *this = *this + b; }
  Interval& operator-=(Interval b) { return *this = *this - b; }
  Interval& operator*=(Interval b) { return *this = *this * b; }

  friend Mask operator<(Interval a, Interval b) { return {a.lo < b.hi, a.hi < b.lo}; }
  friend Mask operator>(Interval a, Interval b) { return {a.hi > b.lo, a.lo > b.hi}; }
  friend Mask operator<=(Interval a, Interval b) { return {a.lo <= b.hi, a.hi <= b.lo}; }
  friend Mask operator>=(Interval a, Interval b) { return {a.hi >= b.lo, a.lo >= b.hi}; }

  friend Interval gp_sqrt(Interval a) {
    if (!(a.hi >= 0)) return {0.0, 0.0};  // only reached where the exact argument is >= 0
    return {std::max(0.0, roundDown(std::sqrt(std::max(a.lo, 0.0)))), roundUp(std::sqrt(a.hi))};
  }
  friend Interval gp_fabs(Interval a) {
    if (a.lo >= 0) return a;
    if (a.hi <= 0) return -a;
    return {0.0, std::max(-a.lo, a.hi)};
  }
  friend Interval gp_sel(Mask m, Interval a, Interval b) {
    if (m.certain) return a;
    if (!m.possible) return b;
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
  }
};

/// Status bits: those of both sides where the mask is undecided.
inline unsigned gp_sel(Mask m, unsigned a, unsigned b) {
  if (m.certain) return a;
  if (!m.possible) return b;
  return a | b;
}

/// max(x, 0) over the interval.
inline Interval gp_iv_clamp0(Interval x) { return {std::max(x.lo, 0.0), std::max(x.hi, 0.0)}; }

/// a / (a + b) for a, b >= 0 (taken as the parts of a and b that are >= 0), where a + b > 0;
/// where both may be 0 the ratio's whole range [0, 1]. Increasing in a, decreasing in b, so the
/// bounds come from the corners (no dependency between numerator and denominator).
inline Interval gp_iv_ratio(Interval a, Interval b) {
  a = gp_iv_clamp0(a);
  b = gp_iv_clamp0(b);
  const double lo = a.lo > 0 ? roundDown(a.lo / roundUp(a.lo + b.hi)) : 0.0;
  const double hi = a.hi + b.lo > 0 ? roundUp(a.hi / roundDown(a.hi + b.lo)) : 1.0;
  return {std::max(0.0, lo), std::min(1.0, hi)};
}

/// The rational factors of the corner interpolator's twist term (Eq. 2) and of its partials,
/// for u, v in [0, 1] (their parts >= 0 are used), each 0 where u = v = 0:
///   f[0] = u v^2 / s, f[1] = u^2 v / s, f[2] = v^3 / s^2, f[3] = u v (u + 2v) / s^2,
///   f[4] = u v (2u + v) / s^2, f[5] = u^3 / s^2, with s = u + v.
/// Written as m = u v / s (increasing in u and v), p = v / s and q = u / s (gp_iv_ratio):
/// f = m v, m u, v p^2, m (1 + p), m (1 + q), u q^2.
inline void gp_iv_twist_factors(Interval u, Interval v, Interval* f) {
  u = gp_iv_clamp0(u);
  v = gp_iv_clamp0(v);
  // u v / s at a corner of the box, rounded down or up; u v / s <= min(u, v) bounds it above too
  auto mAt = [](double a, double b, bool up) {
    if (!(a + b > 0)) return 0.0;
    if (!up) return roundDown(roundDown(a * b) / roundUp(a + b));
    const double den = roundDown(a + b);
    return den > 0 ? std::min(roundUp(roundUp(a * b) / den), std::min(a, b)) : std::min(a, b);
  };
  const Interval m{std::max(0.0, mAt(u.lo, v.lo, false)), mAt(u.hi, v.hi, true)};
  const Interval p = gp_iv_ratio(v, u), q = gp_iv_ratio(u, v);
  f[0] = m * v;
  f[1] = m * u;
  f[2] = v * (p * p);
  f[3] = m * (Interval(1.0) + p);
  f[4] = m * (Interval(1.0) + q);
  f[5] = u * (q * q);
}

/// A second-order Taylor model c + gx ex + gy ey + hxx ex^2 + hxy ex ey + hyy ey^2 + err e over a
/// box (ex, ey, e in [-1, 1]); see the top of this file. Products keep their terms up to the
/// second order and bound the rest (third and fourth order, and every term err touches) in err;
/// every operation adds its rounding to err (a relative 2^-49 of the magnitudes it combined, plus
/// the smallest subnormal), so the exact real result on every point of the box lies in the
/// result's range.
struct Taylor {
  double c = 0, gx = 0, gy = 0, hxx = 0, hxy = 0, hyy = 0, err = 0;
  Taylor() = default;
  Taylor(double x) : c(x) {}  // NOLINT: a constant, like a scalar
  /// The first-order model c + gx ex + gy ey + err e.
  Taylor(double c_, double gx_, double gy_, double e) : c(c_), gx(gx_), gy(gy_), err(e) {}
  Taylor(double c_, double gx_, double gy_, double hxx_, double hxy_, double hyy_, double e)
      : c(c_), gx(gx_), gy(gy_), hxx(hxx_), hxy(hxy_), hyy(hyy_), err(e) {}
  /// The constant model of an interval (no correlation kept).
  static Taylor of(Interval i) {
    if (!(i.lo > -kInf && i.hi < kInf)) return {0.0, 0.0, 0.0, kInf};
    const double m = 0.5 * i.lo + 0.5 * i.hi;
    return {m, 0.0, 0.0, roundUp(std::max(i.hi - m, m - i.lo))};
  }
  /// Bounds of |first-order part| and |second-order part| over the box (not rounded).
  SF_TAYLOR_INLINE double lin() const { return std::fabs(gx) + std::fabs(gy); }
  SF_TAYLOR_INLINE double quad() const { return std::fabs(hxx) + std::fabs(hxy) + std::fabs(hyy); }
  /// A bound of |x - c| over the box.
  double rad() const { return wide(lin() + quad() + err); }
  /// The range: ex^2 and ey^2 lie in [0, 1], so hxx ex^2 and hyy ey^2 take only their sign.
  Interval range() const {
    const double l = lin() + std::fabs(hxy) + err;
    if (!(l < kInf) || !(std::fabs(c) < kInf) || !(quad() < kInf)) return {-kInf, kInf};
    const double below = wide(l + std::max(0.0, -hxx) + std::max(0.0, -hyy));
    const double above = wide(l + std::max(0.0, hxx) + std::max(0.0, hyy));
    return {roundDown(c - below), roundUp(c + above)};
  }
  double lo() const { return range().lo; }
  double hi() const { return range().hi; }

  // A NaN or an infinity anywhere propagates to range(), which then gives the whole line.
  /// A bound of a sum of up to eight non-negative terms, rounded up (infinity stays).
  static SF_TAYLOR_INLINE double wide(double x) { return x * (1.0 + 0x1p-48) + DBL_TRUE_MIN; }
  /// A bound of a sum of non-negative terms, rounded up (infinity stays).
  static SF_TAYLOR_INLINE double up(double x) { return x * (1.0 + 0x1p-51) + DBL_TRUE_MIN; }
  static SF_TAYLOR_INLINE double slop(double mag) { return mag * 0x1p-49 + 4 * DBL_TRUE_MIN; }
  /// A bound of |x| over the box (not rounded).
  SF_TAYLOR_INLINE double mag() const { return std::fabs(c) + lin() + quad() + err; }
  friend SF_TAYLOR_INLINE Taylor operator+(Taylor a, Taylor b) {
    return {a.c + b.c,
            a.gx + b.gx,
            a.gy + b.gy,
            a.hxx + b.hxx,
            a.hxy + b.hxy,
            a.hyy + b.hyy,
            up(a.err + b.err + slop(a.mag() + b.mag()))};
  }
  friend SF_TAYLOR_INLINE Taylor operator-(Taylor a) { return {-a.c, -a.gx, -a.gy, -a.hxx, -a.hxy, -a.hyy, a.err}; }
  friend SF_TAYLOR_INLINE Taylor operator-(Taylor a, Taylor b) { return a + (-b); }
  /// (ca + La + Qa + Ea e)(cb + Lb + Qb + Eb e'), L and Q the first- and second-order parts: the
  /// terms up to the second order exactly; La Qb + Qa Lb + Qa Qb and every term with an E in err.
  friend SF_TAYLOR_INLINE Taylor operator*(Taylor a, Taylor b) {
    const double la = a.lin(), lb = b.lin(), qa = a.quad(), qb = b.quad();
    const double pa = std::fabs(a.c) + la + qa, pb = std::fabs(b.c) + lb + qb;  // bounds of |x - err e|
    const double e = la * qb + qa * lb + qa * qb + a.err * pb + b.err * pa + a.err * b.err;
    return {a.c * b.c,
            a.c * b.gx + b.c * a.gx,
            a.c * b.gy + b.c * a.gy,
            a.c * b.hxx + b.c * a.hxx + a.gx * b.gx,
            a.c * b.hxy + b.c * a.hxy + a.gx * b.gy + a.gy * b.gx,
            a.c * b.hyy + b.c * a.hyy + a.gy * b.gy,
            up(e + slop((pa + a.err) * (pb + b.err)))};
  }
  /// f(x) = f0 + f1 d + f2 d^2 + rem e with d = x - c: the second-order Taylor polynomial of f at
  /// the centre (f0 = f(c), f1 = f'(c), f2 = f''(c) / 2, each within a few roundings) plus
  /// rem >= 0, a bound of the Lagrange remainder over the range.
  static Taylor expand(const Taylor& x, double f0, double f1, double f2, double rem) {
    Taylor d = x;
    d.c = 0;
    const Taylor d2 = d * d;
    const double R = x.rad();
    const double mag = std::fabs(f0) + std::fabs(f1) * R + std::fabs(f2) * R * R + rem;
    return {f0,
            f1 * d.gx,
            f1 * d.gy,
            f1 * d.hxx + f2 * d2.hxx,
            f1 * d.hxy + f2 * d2.hxy,
            f1 * d.hyy + f2 * d2.hyy,
            up(std::fabs(f1) * d.err + std::fabs(f2) * d2.err + rem + slop(4 * mag))};
  }
  /// 1 / b: 1/x = 1/c - d/c^2 + d^2/c^3 - d^3 / (c^3 x) exactly, so the remainder is at most
  /// R^3 / (|c|^3 min|x|) (R = rad()); the interval 1 / range where the model's error term is
  /// wider than that (narrower: near a pole the remainder grows without bound); the whole line
  /// where b's range holds 0.
  friend Taylor recip(Taylor b) {
    const Interval r = b.range();
    if (r.lo <= 0 && r.hi >= 0) return {0.0, 0.0, 0.0, kInf};
    const double xmin = std::min(std::fabs(r.lo), std::fabs(r.hi)), f = 1.0 / b.c, R = b.rad();
    const double ac = std::fabs(b.c);
    const Taylor t = expand(b, f, -f * f, f * f * f, (R * R * R) / ((ac * ac) * (ac * xmin)));
    return narrower(t, Interval(1.0) / r);
  }
  friend Taylor operator/(Taylor a, Taylor b) { return a * recip(b); }
  Taylor& operator+=(Taylor b) { return *this = *this + b; }
  Taylor& operator-=(Taylor b) { return *this = *this - b; }
  Taylor& operator*=(Taylor b) { return *this = *this * b; }

  friend Mask operator<(Taylor a, Taylor b) { return a.range() < b.range(); }
  friend Mask operator>(Taylor a, Taylor b) { return a.range() > b.range(); }
  friend Mask operator<=(Taylor a, Taylor b) { return a.range() <= b.range(); }
  friend Mask operator>=(Taylor a, Taylor b) { return a.range() >= b.range(); }

  /// sqrt: the third derivative over 6 is 1 / (16 x^2.5), so the remainder is at most
  /// R^3 / (16 min(x)^2.5); the interval sqrt(range) where the model's error term is wider than
  /// that (narrower), and where the range reaches 0.
  friend Taylor gp_sqrt(Taylor a) {
    const Interval r = a.range();
    if (!(r.lo > 0) || !(a.c > 0)) return of(gp_sqrt(r));
    const double s = std::sqrt(a.c), R = a.rad();
    const Taylor t = expand(a, s, 0.5 / s, -0.125 / (a.c * s), (R * R * R) / (16.0 * (r.lo * r.lo) * std::sqrt(r.lo)));
    return narrower(t, gp_sqrt(r));
  }
  /// t, or the constant model of i where t's error term alone is wider than i's half-width (both
  /// enclose the same function; the model's correlation is worth keeping wherever its error term
  /// does not swamp it: a model whose range is a little wider than i keeps the cancellations
  /// that the operations after it need).
  static Taylor narrower(const Taylor& t, Interval i) { return !(t.err > 0.5 * (i.hi - i.lo)) ? t : of(i); }
  friend Taylor gp_fabs(Taylor a) {
    const Interval r = a.range();
    if (r.lo >= 0) return a;
    if (r.hi <= 0) return -a;
    return of(gp_fabs(r));
  }
  friend Taylor gp_sel(Mask m, Taylor a, Taylor b) {
    if (m.certain) return a;
    if (!m.possible) return b;
    const Interval ra = a.range(), rb = b.range();
    return of({std::min(ra.lo, rb.lo), std::max(ra.hi, rb.hi)});
  }
};

/// The domain distances' clamp at 0, on Taylor models: x itself. At a point of the domain every
/// d_k >= 0 already (the scalar clamp only absorbs rounding); a box that crosses the domain's
/// boundary then encloses the unclamped continuation there too, a superset of what its points
/// in the domain take. Clamping would turn d_k into a constant model and lose the
/// correlation that keeps the Hermite basis' cancellations (80 times wider bounds, measured).
inline Taylor gp_iv_clamp0(Taylor x) { return x; }

/// a / (a + b) for a, b >= 0: as a Taylor quotient where a + b > 0 on the box, else from the
/// monotone interval bounds (gp_iv_ratio of the ranges).
inline Taylor gp_iv_ratio(Taylor a, Taylor b) {
  const Taylor s = a + b;
  if (s.lo() > 0) return a * recip(s);
  return Taylor::of(gp_iv_ratio(a.range(), b.range()));
}

/// The twist term's factors (see the Interval version): as Taylor models where u + v > 0 on the
/// box, else from the monotone interval bounds.
inline void gp_iv_twist_factors(Taylor u, Taylor v, Taylor* f) {
  const Taylor s = u + v;
  if (s.lo() > 0) {
    const Taylor is = recip(s), m = u * v * is, p = v * is, q = u * is;
    f[0] = m * v;
    f[1] = m * u;
    f[2] = v * (p * p);
    f[3] = m * (Taylor(1.0) + p);
    f[4] = m * (Taylor(1.0) + q);
    f[5] = u * (q * q);
    return;
  }
  Interval fi[6];
  gp_iv_twist_factors(u.range(), v.range(), fi);
  for (int i = 0; i < 6; ++i) f[i] = Taylor::of(fi[i]);
}

/// Pieces of a wide edge parameter range (gp_eval.h): a range wider than 1/16 is cut into
/// pieces at most 1/32 wide (gp_iv_pieces of them) whose evaluations' hull encloses the edge
/// functions on it.
inline bool gp_iv_wide(Taylor t) {
  const Interval r = t.range();
  return !(r.hi - r.lo <= 1.0 / 16);
}
/// t's range clipped to [0, 1] (t's part in the domain: t_k lies in [0, 1] at every point of it).
inline Interval gp_iv_unit_part(Taylor t) {
  const Interval r = t.range();
  double lo = std::max(0.0, r.lo), hi = std::min(1.0, r.hi);
  if (!(lo <= hi)) lo = hi = std::clamp(r.lo, 0.0, 1.0);  // no point of the domain: any value
  return {lo, hi};
}
inline int gp_iv_pieces(Taylor t) {
  const Interval r = gp_iv_unit_part(t);
  return std::max(1, static_cast<int>(std::ceil((r.hi - r.lo) * 32)));
}
/// Piece i of m of t's unit part; neighbouring pieces share their bound. The model runs on the
/// first noise symbol, so that what is computed from it keeps its first-order dependence on t:
/// it must not meet the box's models, only its range may (gp_iv_hull).
inline Taylor gp_iv_piece(Taylor t, int i, int m) {
  const Interval r = gp_iv_unit_part(t);
  const double lo = r.lo, hi = r.hi, w = hi - lo;
  const double a = i == 0 ? lo : lo + w * i / m;
  const double b = i + 1 == m ? hi : lo + w * (i + 1) / m;
  const double c = 0.5 * a + 0.5 * b;
  return Taylor(c, roundUp(std::max(b - c, c - a)), 0.0, 0.0);
}
/// True when the model's range is bounded.
inline bool gp_iv_bounded(Taylor a) {
  const Interval r = a.range();
  return r.lo > -kInf && r.hi < kInf;
}
/// The hull of two models' ranges, as a constant model.
inline Taylor gp_iv_hull(Taylor a, Taylor b) {
  const Interval ra = a.range(), rb = b.range();
  return Taylor::of({std::min(ra.lo, rb.lo), std::max(ra.hi, rb.hi)});
}

}  // namespace sf::interval
