// SPDX-License-Identifier: Apache-2.0
// Independent double-precision reference of the n-sided Gregory patch (tests only).
// Follows /work/shared/design/gregory-patch.md ("the design page") equation by equation;
// equation numbers are the paper's, as quoted there. All derivatives are complex-step
// derivatives f'(x) = Im f(x + i h) / h, h = 1e-30, except C'(t) inside n_c(t), which is
// the exact derivative of the cubic Hermite basis (n_c must itself accept complex t).
#include "gregory_reference.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "ref_vec.h"

namespace sf::ref {

using detail::Cplx;
using detail::V3;
using V3d = V3<double>;
using namespace detail;

namespace {

int wrap(int i, int n) { return ((i % n) + n) % n; }

/// Edge k of a face: V_k -> V_{k+1} with its end tangents (Eq. 6-9 + guard).
struct EdgeData {
  V3d A, B;    ///< V_k, V_{k+1}
  V3d NA, NB;  ///< N_k, N_{k+1}
  V3d e;       ///< V_{k+1} - V_k
  double L = 0;
  V3d ts, te;  ///< unit end tangents
  int guardMask = 0;
};

/// End tangent at a vertex with unit normal N (Eq. 8 for t_s, Eq. 9 for t_e):
/// unit(N x (e x n_avg)). Degenerate (|N x (e x n_avg)| ~ 0): the edge projected on the
/// vertex's tangent plane, e - (e.N) N. Guard (Robustness 1): where the printed tangent
/// has t . e <= 0, the same projection. If the projection vanishes too (N along e, a case
/// the page leaves open) we use unit(e); all three choices are reversal symmetric.
V3d endTangent(const V3d& N, const V3d& e, const V3d& nAvg, double L, bool* guarded) {
  const V3d proj = e - dot(e, N) * N;
  const V3d fallback = realNorm(proj) > 1e-12 * L ? unit(proj) : unit(e);
  const V3d raw = cross(N, cross(e, nAvg));
  if (realNorm(raw) <= 1e-12 * L) return fallback;
  const V3d t = unit(raw);
  if (dot(t, e) <= 0.0) {
    *guarded = true;
    return fallback;
  }
  return t;
}

EdgeData makeEdge(const RefPatch& p, int k) {
  const int n = static_cast<int>(p.V.size());
  EdgeData E;
  E.A = fromEigen(p.V[wrap(k, n)]);
  E.B = fromEigen(p.V[wrap(k + 1, n)]);
  E.NA = fromEigen(p.N[wrap(k, n)]);
  E.NB = fromEigen(p.N[wrap(k + 1, n)]);
  E.e = E.B - E.A;                       // e = V_{k+1} - V_k
  E.L = std::sqrt(dot(E.e, E.e));        // L = |e|
  const V3d nAvg = 0.5 * (E.NA + E.NB);  // n_avg = (N_k + N_{k+1}) / 2
  bool gs = false, ge = false;
  E.ts = endTangent(E.NA, E.e, nAvg, E.L, &gs);  // t_s = unit(N_k x (e x n_avg))
  E.te = endTangent(E.NB, E.e, nAvg, E.L, &ge);  // t_e = unit(N_{k+1} x (e x n_avg))
  E.guardMask = (gs ? 1 : 0) | (ge ? 2 : 0);
  if (!p.TS.empty() && p.TS[wrap(k, n)].squaredNorm() > 0) E.ts = fromEigen(p.TS[wrap(k, n)]);
  if (!p.TE.empty() && p.TE[wrap(k, n)].squaredNorm() > 0) E.te = fromEigen(p.TE[wrap(k, n)]);
  return E;
}

/// C_k(t) = h00 V_k + h01 V_{k+1} + L h10 t_s + L h11 t_e (Eq. 6-7, cubic Hermite).
template <class T>
V3<T> curve(const EdgeData& E, const T& t) {
  const T t2 = t * t, t3 = t2 * t;
  const T h00 = T(2) * t3 - T(3) * t2 + T(1);
  const T h01 = T(-2) * t3 + T(3) * t2;
  const T h10 = t3 - T(2) * t2 + t;
  const T h11 = t3 - t2;
  return h00 * lift<T>(E.A) + h01 * lift<T>(E.B) + (T(E.L) * h10) * lift<T>(E.ts) + (T(E.L) * h11) * lift<T>(E.te);
}

/// C_k'(t): derivative of the Hermite basis (exact; used inside Eq. 10).
template <class T>
V3<T> curveDt(const EdgeData& E, const T& t) {
  const T t2 = t * t;
  const T d00 = T(6) * t2 - T(6) * t;
  const T d10 = T(3) * t2 - T(4) * t + T(1);
  const T d11 = T(3) * t2 - T(2) * t;
  return d00 * lift<T>(E.A) - d00 * lift<T>(E.B) + (T(E.L) * d10) * lift<T>(E.ts) + (T(E.L) * d11) * lift<T>(E.te);
}

/// n_c(t) = unit(C'(t) x (((1-t) N_k + t N_{k+1}) x e)) (Eq. 10, normalised), not turned
/// towards the interpolated normal (Robustness 1: the guarded end tangents make it N_k and
/// N_{k+1} at the ends).
template <class T>
V3<T> edgeNormal(const EdgeData& E, const T& t) {
  const V3<T> Nt = (T(1) - t) * lift<T>(E.NA) + t * lift<T>(E.NB);
  return unit(cross(curveDt(E, t), cross(Nt, lift<T>(E.e))));
}

/// Everything the cross tangent T_k(t) of edge k needs (Eq. 11-14, Robustness 2-3).
struct TangentData {
  EdgeData edge;                ///< edge k
  V3d Vprev, Vnext;             ///< V_{k-1}, V_{k+2}
  V3d Nprev, Nnext;             ///< N_{k-1}, N_{k+2}
  double Lprev = 0, Lnext = 0;  ///< |V_k - V_{k-1}|, |V_{k+2} - V_{k+1}|
  V3d d0, d1;                   ///< -t_e of edge k-1, t_s of edge k+1
  V3d p0, p1;                   ///< p(0), p(1)
  CrossTangent mode = CrossTangent::Corrected;
};

/// Robustness 4 (design page): where a tangent-plane direction field a(t), running from a0 at
/// t = 0 to a1 at t = 1, is shorter than eps, a + ((eps - |a|)^2 / eps) b with b = n_c x unit(a1 - a0)
/// turned inward (b . (n_c x C') >= 0), so that where it turns over it turns through b instead
/// of through zero. Branch on the real part; the length is analytic for the complex step.
template <class T>
V3<T> turnPastZero(const V3<T>& a, double eps, const V3<T>& nc, const EdgeData& E, const T& t, const V3d& a0,
                   const V3d& a1) {
  const V3d span = a1 - a0;
  const double ls = std::sqrt(dot(span, span));
  if (!(realNorm(a) < eps) || !(ls > 0)) return a;
  V3<T> b = cross(nc, lift<T>(span / ls));
  if (re(dot(b, cross(nc, curveDt(E, t)))) < 0.0) b = -b;
  const T m = T(eps) - T(std::sqrt(dot(a, a)));
  return a + (m * m / T(eps)) * b;
}

/// Robustness 4's eps: 1e-2 (times the largest of the edge's three lengths for t_c).
constexpr double kTurnEps = 1e-2;

/// p(t) = unit(t_c(t)), the printed cross-tangent direction:
/// v_int = (1-t) V_{k-1} + t V_{k+2} - C_k(t)            (Eq. 11)
/// n_int = ((1-t) N_{k-1} + t N_{k+2} + n_c(t)) / 2        (Eq. 12)
/// t_c   = n_c(t) x (v_int x n_int)                        (Eq. 13)
/// In the corrected construction t_c is turned where it vanishes (turnPastZero, Robustness 4;
/// a0 = V_{k-1} - V_k, a1 = V_{k+2} - V_{k+1}, eps relative to the largest of L, L_prev, L_next).
template <class T>
V3<T> printedDirection(const TangentData& D, const T& t) {
  const T s = T(1) - t;
  const V3<T> nc = edgeNormal(D.edge, t);
  const V3<T> vInt = s * lift<T>(D.Vprev) + t * lift<T>(D.Vnext) - curve(D.edge, t);
  const V3<T> nInt = T(0.5) * (s * lift<T>(D.Nprev) + t * lift<T>(D.Nnext) + nc);
  V3<T> tc = cross(nc, cross(vInt, nInt));
  if (D.mode == CrossTangent::Corrected) {
    const double scale = std::max(D.edge.L, std::max(D.Lprev, D.Lnext));
    tc = turnPastZero(tc, kTurnEps * scale, nc, D.edge, t, D.Vprev - D.edge.A, D.Vnext - D.edge.B);
  }
  return unit(tc);
}

/// T_k(t) = ((1-t) L_prev + t L_next) * direction (Eq. 14), the direction being
///   paper:     unit(t_c(t))
///   corrected: unit(q - (q.n_c) n_c), q = p(t) + (1-t)(d0 - p(0)) + t(d1 - p(1))
///   blend:     unit(q - (q.n_c) n_c), q = (1-t) d0 + t d1
/// the projection turned where it vanishes (turnPastZero, Robustness 4, a0 = d0, a1 = d1).
template <class T>
V3<T> crossTangent(const TangentData& D, const T& t) {
  const T s = T(1) - t;
  const T scale = s * T(D.Lprev) + t * T(D.Lnext);
  if (D.mode == CrossTangent::Paper) return scale * printedDirection(D, t);
  V3<T> q;
  if (D.mode == CrossTangent::Corrected) {
    q = printedDirection(D, t) + s * lift<T>(D.d0 - D.p0) + t * lift<T>(D.d1 - D.p1);
  } else {
    q = s * lift<T>(D.d0) + t * lift<T>(D.d1);
  }
  const V3<T> nc = edgeNormal(D.edge, t);
  return scale * unit(turnPastZero(q - dot(q, nc) * nc, kTurnEps, nc, D.edge, t, D.d0, D.d1));
}

}  // namespace

/// Per-patch constants: edges, cross-tangent data, T_k(0), T_k(1) and the twists.
struct RefPatchData {
  int n = 0;
  std::vector<V3d> V;
  std::vector<EdgeData> edges;
  std::vector<TangentData> tangents;
  std::vector<V3d> T0, T1;    ///< T_k(0), T_k(1)
  std::vector<V3d> dT0, dT1;  ///< dT_k/dt at 0 and at 1 (complex step)
};

namespace {

V3d toV3(const Eigen::Vector3d& v) { return fromEigen(v); }

RefPatchData buildPatch(const RefPatch& p) {
  const int n = static_cast<int>(p.V.size());
  if (n < 3 || p.N.size() != p.V.size())
    throw std::invalid_argument("RefPatch: need n >= 3 vertices and as many normals");
  RefPatchData P;
  P.n = n;
  for (const auto& v : p.V) P.V.push_back(toV3(v));
  for (int k = 0; k < n; ++k) P.edges.push_back(makeEdge(p, k));
  for (int k = 0; k < n; ++k) {
    TangentData D;
    D.edge = P.edges[k];
    D.Vprev = toV3(p.V[wrap(k - 1, n)]);
    D.Vnext = toV3(p.V[wrap(k + 2, n)]);
    D.Nprev = toV3(p.N[wrap(k - 1, n)]);
    D.Nnext = toV3(p.N[wrap(k + 2, n)]);
    D.Lprev = std::sqrt(dot(P.V[k] - D.Vprev, P.V[k] - D.Vprev));
    const V3d eNext = D.Vnext - P.V[wrap(k + 1, n)];
    D.Lnext = std::sqrt(dot(eNext, eNext));
    D.d0 = -P.edges[wrap(k - 1, n)].te;  // edge k-1 arrives at V_k along t_e; reversed
    D.d1 = P.edges[wrap(k + 1, n)].ts;   // edge k+1 leaves V_{k+1} along t_s
    D.mode = p.mode;
    D.p0 = printedDirection(D, 0.0);
    D.p1 = printedDirection(D, 1.0);
    P.tangents.push_back(D);
  }
  for (int k = 0; k < n; ++k) {
    const TangentData& D = P.tangents[k];
    P.T0.push_back(crossTangent(D, 0.0));
    P.T1.push_back(crossTangent(D, 1.0));
    // Twists (Eq. 2): exact derivatives of T_k by a complex step in t.
    P.dT0.push_back(toV3(stepDerivative(crossTangent(D, Cplx(0.0, kComplexStep)))));
    P.dT1.push_back(toV3(stepDerivative(crossTangent(D, Cplx(1.0, kComplexStep)))));
  }
  return P;
}

/// Corner interpolator r_k(u, v) (Eq. 1-2):
///   P(u) = C_k(u), T_P(u) = T_k(u), Q(v) = C_{k-1}(1-v), T_Q(v) = T_{k-1}(1-v),
///   T_P'(0) = dT_k/dt(0), T_Q'(0) = -dT_{k-1}/dt(1),
///   r = P(u) + Q(v) - V_k + v (T_P(u) - T_P(0)) + u (T_Q(v) - T_Q(0))
///       - u v (v T_P'(0) + u T_Q'(0)) / (u + v)        (last term := 0 at u = v = 0).
/// `atCorner`: the real parts of u and v are exactly 0. The twist term is then dropped:
/// it is O(|X - C_k|^2) inside the domain, but its continuation to complex X is singular on
/// u + v = 0 (the complex step in eta at C_0 of a triangle runs along that line).
template <class T>
V3<T> cornerInterpolant(const RefPatchData& P, int k, const T& u, const T& v, bool atCorner) {
  const int km = wrap(k - 1, P.n);
  const V3<T> Pu = curve(P.edges[k], u);
  const V3<T> TPu = crossTangent(P.tangents[k], u);
  const V3<T> Qv = curve(P.edges[km], T(1) - v);
  const V3<T> TQv = crossTangent(P.tangents[km], T(1) - v);
  const V3<T> TP0 = lift<T>(P.T0[k]);      // T_P(0) = T_k(0)
  const V3<T> TQ0 = lift<T>(P.T1[km]);     // T_Q(0) = T_{k-1}(1)
  const V3<T> dTP0 = lift<T>(P.dT0[k]);    // T_P'(0)
  const V3<T> dTQ0 = lift<T>(-P.dT1[km]);  // T_Q'(0)
  V3<T> r = Pu + Qv - lift<T>(P.V[k]) + v * (TPu - TP0) + u * (TQv - TQ0);
  if (!atCorner) r = r - (u * v / (u + v)) * (v * dTP0 + u * dTQ0);
  return r;
}

/// G(X) = sum_k w_k(X) r_k(u_k(X), v_k(X)) (Eq. 3-5) on the regular n-gon domain.
template <class T>
V3<T> evaluateG(const RefPatchData& P, const T& xi, const T& eta) {
  const int n = P.n;
  const double pi = std::numbers::pi;
  std::vector<T> d(n);
  for (int j = 0; j < n; ++j) {
    // d_j(X) = cos(pi/n) - X . m_j, m_j = (cos (2j+1) pi/n, sin (2j+1) pi/n)
    const double a = (2 * j + 1) * pi / n;
    d[j] = T(std::cos(pi / n)) - (xi * T(std::cos(a)) + eta * T(std::sin(a)));
    // Clamp rounding on the domain boundary: tiny negative real part -> exactly 0.
    if (re(d[j]) < 0.0 && re(d[j]) > -1e-12) d[j] -= T(re(d[j]));
  }
  auto D = [&](int j) -> const T& { return d[wrap(j, n)]; };
  // w_k = prod_{j != k-1, k} d_j^2 / sum_l prod_{j != l-1, l} d_j^2     (Eq. 5)
  std::vector<T> num(n, T(1));
  std::vector<double> numRe(n, 1.0);
  T sum = T(0);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      if (j == wrap(k - 1, n) || j == k) continue;
      num[k] *= d[j] * d[j];
      numRe[k] *= re(d[j]) * re(d[j]);
    }
    sum += num[k];
  }
  V3<T> G;
  for (int k = 0; k < n; ++k) {
    if (numRe[k] == 0.0) continue;                 // w_k = 0: skip (u_k may be 0/0 for n = 3)
    const T u = D(k - 1) / (D(k - 1) + D(k + 1));  // u_k = d_{k-1} / (d_{k-1} + d_{k+1})
    const T v = D(k) / (D(k - 2) + D(k));          // v_k = d_k / (d_{k-2} + d_k)
    // At u = v = 0 (decided on the real distances) the twist term is 0.
    const bool atCorner = re(D(k - 1)) == 0.0 && re(D(k)) == 0.0;
    G = G + (num[k] / sum) * cornerInterpolant(P, k, u, v, atCorner);
  }
  return G;
}

}  // namespace

// ---------------------------------------------------------------- public API

Eigen::Vector3d refEdgeCurve(const RefPatch& p, int k, double t) { return realPart(curve(makeEdge(p, k), t)); }

Eigen::Vector3d refEdgeCurveDerivative(const RefPatch& p, int k, double t) {
  return stepDerivative(curve(makeEdge(p, k), Cplx(t, kComplexStep)));
}

Eigen::Vector3d refEdgeNormal(const RefPatch& p, int k, double t) { return realPart(edgeNormal(makeEdge(p, k), t)); }

Eigen::Vector3d refCrossTangent(const RefPatch& p, int k, double t) {
  const RefPatchData P = buildPatch(p);
  return realPart(crossTangent(P.tangents[wrap(k, P.n)], t));
}

Eigen::Vector3d refCrossTangentDerivative(const RefPatch& p, int k, double t) {
  const RefPatchData P = buildPatch(p);
  return stepDerivative(crossTangent(P.tangents[wrap(k, P.n)], Cplx(t, kComplexStep)));
}

Eigen::Vector2d refDomainCorner(int n, int k) {
  const double a = 2.0 * std::numbers::pi * k / n;  // C_k = (cos 2 pi k/n, sin 2 pi k/n)
  return {std::cos(a), std::sin(a)};
}

Eigen::Vector2d refDomainEdgeNormal(int n, int k) {
  const double a = (2 * k + 1) * std::numbers::pi / n;
  return {std::cos(a), std::sin(a)};
}

int refEdgeGuardMask(const RefPatch& p, int k) { return makeEdge(p, wrap(k, static_cast<int>(p.V.size()))).guardMask; }

RefPatchEvaluator::RefPatchEvaluator(const RefPatch& p) : d_(std::make_shared<const RefPatchData>(buildPatch(p))) {}

int RefPatchEvaluator::size() const { return d_->n; }

Eigen::Vector3d RefPatchEvaluator::position(double xi, double eta) const { return realPart(evaluateG(*d_, xi, eta)); }

RefEval RefPatchEvaluator::evaluate(double xi, double eta) const {
  RefEval r;
  const V3<Cplx> gx = evaluateG(*d_, Cplx(xi, kComplexStep), Cplx(eta, 0.0));
  const V3<Cplx> ge = evaluateG(*d_, Cplx(xi, 0.0), Cplx(eta, kComplexStep));
  r.pos = realPart(gx);
  r.dxi = stepDerivative(gx);   // dG/dxi
  r.deta = stepDerivative(ge);  // dG/deta
  r.normal = r.dxi.cross(r.deta).normalized();
  return r;
}

RefEval refEvaluate(const RefPatch& p, double xi, double eta) { return RefPatchEvaluator(p).evaluate(xi, eta); }

}  // namespace sf::ref
