/* SPDX-License-Identifier: Apache-2.0 */
/* Domain, blending and evaluation of the n-sided Gregory patch (Eq. 1-5), with exact first
 * derivatives, and the per-patch quality measures (fold, bulge).
 * Part of gp_patch.h (after gp_tables.h); no include guard on purpose. Branch-free on
 * per-point data (see gp_vec.h, "Lanes"). */

/* Where the rational blending would lose its range under interval arithmetic, the interval
 * instantiation of the patch certificate (host patch_certificate.cpp, GP_INTERVAL) evaluates
 * the same functions in forms that keep it: d_k clamped at 0 as one interval operation, the
 * edge parameter a / (a + b) from its monotone bounds, and the twist term's rational factors
 * (u v^2 / (u + v) and the like) from monotone pieces; the blending weight times the edge
 * parameter's derivative with the weight's factor cancelled against the parameter's denominator
 * (which vanishes at a triangle's corners), and the edge functions over a wide parameter range as
 * the hull of pieces. Every other instantiation computes the expressions below as written (the
 * same operations, the same bits). */
#undef GP_CLAMP0
#undef GP_EDGE_PARAM
#ifdef GP_INTERVAL
#define GP_CLAMP0(x) gp_iv_clamp0(x)
#define GP_EDGE_PARAM(a, b, den, pos) gp_iv_ratio(a, b)
#else
#define GP_CLAMP0(x) GP_SEL((x) < GP_R(0.0), GP_R(0.0), (x))
#define GP_EDGE_PARAM(a, b, den, pos) GP_SEL(pos, (a) / (den), GP_R(0.0))
#endif

/* Fills d_k(X) = cos(pi/n) - X . m_k (Eq. 3) for the domain dom of an n-gon. Returns the smallest d_k
 * before clamping; d_k are clamped at 0 so that points on the boundary that rounding put a
 * hair outside evaluate as on it. */
GP_FN_INLINE GP_REAL gp_domain_distances(const gp_domain* dom, const int n, GP_REAL xi, GP_REAL eta, GP_REAL* d) {
  GP_REAL dmin = GP_R(1.0);
  GP_UNROLL
  for (int k = 0; k < n; ++k) {
    const GP_REAL dk = dom->apothem - (xi * dom->mx[k] + eta * dom->my[k]);
    dmin = GP_SEL(dk < dmin, dk, dmin);
    d[k] = GP_CLAMP0(dk);
  }
  return dmin;
}

/* Tolerance on d_k below zero for a point still counted as inside the domain. */
#undef GP_DOMAIN_TOL
#define GP_DOMAIN_TOL (GP_R(1024.0) * GP_EPS)

/* Edge record rec at t: the edge curve C and C', the cross tangent T and T' (Eq. 6-14), with the
 * edge's status bits added to *est. */
GP_FN_INLINE void gp_edge_at(const GP_REAL* rec, GP_REAL t, int mode, gp_vec3* C, gp_vec3* Cd, gp_vec3* T, gp_vec3* Td,
                             GP_STATUS* est) {
  gp_dvec3 c, cp;
  gp_edge_curve(rec, t, &c, &cp);
  const GP_REAL L = gp_edge_length(rec);
  const gp_dvec3 nc = gp_edge_normal(rec, t, cp, L, est);
  const gp_dvec3 tt = gp_cross_tangent(rec, t, mode, c, cp, nc, L, est);
  *C = c.v;
  *Cd = c.d;
  *T = tt.v;
  *Td = tt.d;
}

#ifdef GP_INTERVAL
/* True when every component's enclosure is bounded. */
GP_FN_INLINE int gp_iv_bounded3(gp_vec3 a) { return gp_iv_bounded(a.x) && gp_iv_bounded(a.y) && gp_iv_bounded(a.z); }
/* Componentwise hull of two enclosures as constant forms (the certificate's wide edge
 * parameters: the pieces' forms run on a symbol of their own, gp_iv_piece). */
GP_FN_INLINE gp_vec3 gp_iv_hull3(gp_vec3 a, gp_vec3 b) {
  gp_vec3 h;
  h.x = gp_iv_hull(a.x, b.x);
  h.y = gp_iv_hull(a.y, b.y);
  h.z = gp_iv_hull(a.z, b.z);
  return h;
}
#endif

/* The result of one patch evaluation. */
typedef struct {
  gp_vec3 pos, dxi, deta, normal; /* G, dG/dxi, dG/deta, unit normal (zero under GP_INTERVAL) */
  GP_STATUS status;               /* GP_ST_* bits */
} gp_eval_result;

/* The evaluation mode of a face: the cross-tangent mode (GP_CT_*) and, for a face whose
 * construction status has GP_ST_AFFINE, GP_EVAL_AFFINE. */
GP_FN int gp_eval_mode(int ctMode, gp_uint faceStatus) {
  return (faceStatus & GP_ST_AFFINE) ? (ctMode | GP_EVAL_AFFINE) : ctMode;
}

/* Sets the unit normal of an evaluation from its derivatives; where dG/dxi x dG/deta vanishes
 * against their lengths, the fallback normal nfb (or, where that vanishes too, N_0 of recs) and
 * GP_ST_SINGULAR. */
GP_FN_INLINE void gp_eval_normal(gp_eval_result* out, gp_vec3 nfb, const GP_REAL* recs) {
  const gp_vec3 nn = gp_cross(out->dxi, out->deta);
  /* rank-deficient Jacobian (e.g. at a 180-degree corner): the normal is noise, flag it */
  const GP_REAL jmax = gp_max(gp_len(out->dxi), gp_len(out->deta));
  const GP_REAL scale = jmax * jmax;
  /* unit(nn); where |nn| <= tiny scale, the weighted vertex normals (computed only then) */
  const GP_REAL lnn = gp_len(nn);
  const GP_MASK regular = lnn > GP_TINY * scale;
  out->normal = gp_scale(nn, GP_R(1.0) / lnn);
  if (GP_ANY(!regular)) {
    GP_STATUS ignore = 0u;
    out->normal = gp_sel3(regular, out->normal, gp_unit_or(nfb, gp_get3(recs, GP_E_N0), GP_TINY, &ignore, 0u));
    out->status |= GP_SEL(regular, (GP_STATUS)0u, (GP_STATUS)GP_ST_SINGULAR);
  }
}

/* Zeros and GP_ST_OUTSIDE on the lanes outside the domain (lanes only: a single point outside
 * returns before it is evaluated). */
GP_FN_INLINE void gp_eval_outside(gp_eval_result* out, GP_MASK outside) {
  if (GP_ANY(outside)) {
    out->pos = gp_sel3(outside, gp_zero3(), out->pos);
    out->dxi = gp_sel3(outside, gp_zero3(), out->dxi);
    out->deta = gp_sel3(outside, gp_zero3(), out->deta);
    out->normal = gp_sel3(outside, gp_zero3(), out->normal);
    out->status = GP_SEL(outside, (GP_STATUS)GP_ST_OUTSIDE, out->status);
  }
}

/* The patch of a face with GP_ST_AFFINE (a flat triangle whose corner normals are all its plane's,
 * its edge curves in that plane): the affine map of the domain triangle onto V_0 V_1 V_2 plus each
 * edge curve's deviation from its chord, blended in,
 *   G(X) = V_0 + lambda_1 (V_1 - V_0) + lambda_2 (V_2 - V_0)
 *          + sum_k (lambda_k + lambda_{k+1}) (C_k(t_k) - (1 - t_k) V_k - t_k V_{k+1}),
 * with the barycentric coordinates lambda_{k+2} = d_k / (3 cos(pi/3)) (d_k of Eq. 3; corner k + 2
 * lies opposite edge k) and t_k the edge parameter of Eq. 4. The deviation of the Hermite curve
 * (Eq. 6) is h10(t) (M_0 - E) + h11(t) (M_1 - E) with E = V_1 - V_0, zero on a straight edge. On
 * edge k, t_k runs along the edge and the other edges' deviations vanish (their t sits at an end),
 * so G is C_k(t_k), the Gregory patch's point there; it lies in the plane, which the neighbours'
 * patches take as their tangent plane along the edge from the same corner normals: the surface
 * stays closed and G1. With s = lambda_k + lambda_{k+1} (so s t_k = lambda_{k+1}), the blended
 * deviation is s (t (1-t)^2 a - t^2 (1-t) b), a = M_0 - E, b = M_1 - E; its partials in
 * p = d_{k-1} and q = d_{k+1} are polynomials in t (bounded where s -> 0, at the corner opposite
 * the edge; the certificate's enclosures need no cancelled form). The Gregory patch of a flat
 * triangle folds in its own plane where the triangle is thin or obtuse (the corner interpolators
 * of Eq. 2 do not reproduce an affine map; docs/fold-levers.md); the affine map with straight
 * edges never does, and markAffineTriangles marks a triangle with curved edges only where a bound
 * on the deviations' Jacobian proves this map regular. */
GP_FN_INLINE gp_eval_result gp_patch_eval_affine3(const gp_domain* dom, const GP_REAL* recs, GP_REAL xi, GP_REAL eta,
                                                  const GP_REAL* d, int deriv) {
  gp_eval_result out;
  out.pos = out.dxi = out.deta = out.normal = gp_zero3();
  out.status = 0u;
  const gp_vec3 v0 = gp_get3(recs, GP_E_V0);
  const gp_vec3 e1 = gp_sub(gp_get3(recs + GP_E_NFIELDS, GP_E_V0), v0);
  const gp_vec3 e2 = gp_sub(gp_get3(recs + 2 * GP_E_NFIELDS, GP_E_V0), v0);
  const GP_REAL ih = GP_R(1.0) / (GP_R(3.0) * dom->apothem); /* 1 / the domain triangle's height */
  const GP_REAL l1 = (dom->apothem - (xi * dom->mx[2] + eta * dom->my[2])) * ih;
  const GP_REAL l2 = (dom->apothem - (xi * dom->mx[0] + eta * dom->my[0])) * ih;
  out.pos = gp_madd(gp_madd(v0, e1, l1), e2, l2);
  if (deriv) {
    out.dxi = gp_add(gp_scale(e1, -dom->mx[2] * ih), gp_scale(e2, -dom->mx[0] * ih));
    out.deta = gp_add(gp_scale(e1, -dom->my[2] * ih), gp_scale(e2, -dom->my[0] * ih));
  }
  GP_UNROLL
  for (int k = 0; k < 3; ++k) { /* the curved edges' deviations from their chords */
    const GP_REAL* rec = recs + k * GP_E_NFIELDS;
    const gp_vec3 e = gp_sub(gp_get3(rec, GP_E_V1), gp_get3(rec, GP_E_V0));
    const gp_vec3 a = gp_sub(gp_get3(rec, GP_E_M0), e), b = gp_sub(gp_get3(rec, GP_E_M1), e);
    const int km = k == 0 ? 2 : k - 1, kp = k == 2 ? 0 : k + 1;
    const GP_REAL p = d[km], q = d[kp], s = p + q;
    const GP_REAL t = GP_EDGE_PARAM(p, q, s, s > GP_R(0.0)), t1 = GP_R(1.0) - t;
    /* position: ih s t (1-t) ((1-t) a - t b) */
    const gp_vec3 dev = gp_scale(gp_sub(gp_scale(a, t1), gp_scale(b, t)), ih * s * t * t1);
#ifdef GP_INTERVAL
    const GP_MASK curved = (GP_MASK)(1); /* a straight edge adds exact zeros */
#else
    /* a straight edge (a = b = 0 exactly) leaves the affine map's bits */
    const GP_MASK curved =
        GP_FABS(a.x) + GP_FABS(a.y) + GP_FABS(a.z) + GP_FABS(b.x) + GP_FABS(b.y) + GP_FABS(b.z) > GP_R(0.0);
    if (!GP_ANY(curved)) continue;
#endif
    out.pos = gp_sel3(curved, gp_add(out.pos, dev), out.pos);
    if (!deriv) continue;
    /* partials of s h10(t) and s (-h11(t)) in p and q (t = p / s); grad p = -m_{k-1}, grad q = -m_{k+1} */
    const gp_vec3 dp = gp_sub(gp_scale(a, t1 * t1 * (GP_R(1.0) - GP_R(2.0) * t)), gp_scale(b, GP_R(2.0) * t * t1 * t1));
    const gp_vec3 dq = gp_sub(gp_scale(a, GP_R(2.0) * t * t * t1), gp_scale(b, t * t * (GP_R(2.0) * t - GP_R(1.0))));
    const gp_vec3 gx = gp_scale(gp_add(gp_scale(dp, dom->mx[km]), gp_scale(dq, dom->mx[kp])), -ih);
    const gp_vec3 gy = gp_scale(gp_add(gp_scale(dp, dom->my[km]), gp_scale(dq, dom->my[kp])), -ih);
    out.dxi = gp_sel3(curved, gp_add(out.dxi, gx), out.dxi);
    out.deta = gp_sel3(curved, gp_add(out.deta, gy), out.deta);
  }
  if (!deriv) return out;
#ifndef GP_INTERVAL
  gp_eval_normal(&out, gp_get3(recs, GP_E_N0), recs);
#endif
  return out;
}

/* The body of gp_patch_eval_dom_d for an n-gon (n = dom->n), inlined where n is a constant so
 * that the short loops over the edges (distances, edge parameters, weights) unroll and their
 * index arithmetic folds (the same operations in the same order: the same bits as with n
 * unknown). */
GP_FN_INLINE gp_eval_result gp_patch_eval_dom_n(const gp_domain* dom, const int n, const GP_REAL* recs, int mode,
                                                GP_REAL xi, GP_REAL eta, int deriv) {
  gp_eval_result out;
  out.pos = out.dxi = out.deta = out.normal = gp_zero3();
  out.status = 0u;
  GP_REAL d[GP_MAX_N];
  const GP_REAL dmin = gp_domain_distances(dom, n, xi, eta, d);
  /* the domain lies in the unit disc; this also rejects NaN and Inf */
#ifdef GP_INTERVAL
  /* the certificate evaluates boxes that meet the domain, for their points in it */
  const GP_MASK outside = (GP_MASK)(0);
  (void)dmin;
#else
  const GP_MASK outside = !(GP_FABS(xi) <= GP_R(1.5) && GP_FABS(eta) <= GP_R(1.5)) || dmin < -GP_DOMAIN_TOL;
#endif
  if (GP_ALL(outside)) {
    out.status = GP_ST_OUTSIDE;
    return out;
  }
  if (n == 3 && (mode & GP_EVAL_AFFINE)) {
    out = gp_patch_eval_affine3(dom, recs, xi, eta, d, deriv);
    gp_eval_outside(&out, outside);
    return out;
  }
  mode &= GP_CT_MASK;
  /* u_k = d_{k-1} / (d_{k-1} + d_{k+1}) is also 1 - v_{k+1}: one edge parameter t_k per edge
   * serves corners k and k+1. Gradients: grad d_j = -m_j. */
  GP_REAL t[GP_MAX_N], tx[GP_MAX_N], ty[GP_MAX_N];
  GP_UNROLL
  for (int k = 0; k < n; ++k) {
    const int km = k == 0 ? n - 1 : k - 1, kp = k + 1 == n ? 0 : k + 1;
    const GP_REAL den = d[km] + d[kp];
    /* den = 0 only where both corners using this edge have zero weight: t = 0 there */
    const GP_MASK pos = den > GP_R(0.0);
    t[k] = GP_EDGE_PARAM(d[km], d[kp], den, pos);
    tx[k] = ty[k] = GP_R(0.0); /* set below where derivatives are wanted (deriv 0 never reads them) */
    if (!deriv) continue;
#ifdef GP_INTERVAL
    /* the numerators alone: the corner loop divides by (a+b)^2 where the weight cancels it */
    (void)pos;
    tx[k] = d[kp] * -dom->mx[km] - d[km] * -dom->mx[kp];
    ty[k] = d[kp] * -dom->my[km] - d[km] * -dom->my[kp];
#else
    const GP_REAL id2 = GP_R(1.0) / (den * den);
    /* d(a/(a+b)) = (b da - a db) / (a+b)^2 */
    tx[k] = GP_SEL(pos, (d[kp] * -dom->mx[km] - d[km] * -dom->mx[kp]) * id2, GP_R(0.0));
    ty[k] = GP_SEL(pos, (d[kp] * -dom->my[km] - d[km] * -dom->my[kp]) * id2, GP_R(0.0));
#endif
  }
  /* W_k = prod_{j != k-1, k} d_j^2 and its gradient; S = sum W (Eq. 5). */
  GP_REAL W[GP_MAX_N], Wx[GP_MAX_N], Wy[GP_MAX_N];
  GP_REAL S = GP_R(0.0), Sx = GP_R(0.0), Sy = GP_R(0.0);
  GP_UNROLL
  for (int k = 0; k < n; ++k) {
    GP_REAL w = GP_R(1.0), wx = GP_R(0.0), wy = GP_R(0.0);
    int j = k;
    for (int i = 1; i <= n - 2; ++i) {
      j = j + 1 == n ? 0 : j + 1; /* (k + i) mod n */
      const GP_REAL f = d[j] * d[j];
      if (deriv) {
        wx = wx * f + w * GP_R(2.0) * d[j] * -dom->mx[j];
        wy = wy * f + w * GP_R(2.0) * d[j] * -dom->my[j];
      }
      w = w * f;
    }
    W[k] = w;
    Wx[k] = wx;
    Wy[k] = wy;
    S += w;
    Sx += wx;
    Sy += wy;
  }
  /* Edge k at t_k: C, C', T, T' (needed when corner k or k+1 has weight; computed for every
   * edge, their status bits counted only where needed). */
  gp_vec3 C[GP_MAX_N], Cd[GP_MAX_N], T[GP_MAX_N], Td[GP_MAX_N];
  for (int k = 0; k < n; ++k) {
    const int kp = k + 1 == n ? 0 : k + 1;
    const GP_REAL* rec = recs + k * GP_E_NFIELDS;
    GP_STATUS est = 0u;
    gp_edge_at(rec, t[k], mode, &C[k], &Cd[k], &T[k], &Td[k], &est);
#ifdef GP_INTERVAL
    /* Where t_k takes a wide range on the box (near a triangle's corner t_k takes all of [0, 1]
     * on any box, and the corners using edge k have no weight there), one evaluation over the
     * whole range can be unbounded (the normalised edge normal's length reaches 0): then the
     * hull of the evaluations over pieces of the range at most 1/32 wide encloses the same
     * functions. */
    if (gp_iv_wide(t[k]) && !(gp_iv_bounded3(C[k]) && gp_iv_bounded3(Cd[k]) && gp_iv_bounded3(T[k]) &&
                              gp_iv_bounded3(Td[k]))) {
      const int m = gp_iv_pieces(t[k]);
      for (int i = 0; i < m; ++i) {
        gp_vec3 pc, pcd, pt, ptd;
        gp_edge_at(rec, gp_iv_piece(t[k], i, m), mode, &pc, &pcd, &pt, &ptd, &est);
        C[k] = gp_iv_hull3(i == 0 ? pc : C[k], pc);
        Cd[k] = gp_iv_hull3(i == 0 ? pcd : Cd[k], pcd);
        T[k] = gp_iv_hull3(i == 0 ? pt : T[k], pt);
        Td[k] = gp_iv_hull3(i == 0 ? ptd : Td[k], ptd);
      }
    }
#endif
    out.status |= GP_BITS(W[k] > GP_R(0.0) || W[kp] > GP_R(0.0), est);
  }
  const GP_REAL iS = GP_R(1.0) / S;
  gp_vec3 nfb = gp_zero3(); /* fallback normal: weighted vertex normals */
  for (int k = 0; k < n; ++k) {
    const GP_MASK has = W[k] > GP_R(0.0); /* a corner without weight adds nothing */
    if (!GP_ANY(has)) continue;
#ifdef GP_INTERVAL
    /* on a box where W_k may vanish, the increments below enclose both cases without a select
     * (whose undecided mask would keep only the hull of both sides, losing every correlation):
     * where W_k = 0, so are w, its gradient and the factors ou and ov, and the other factors are
     * bounded (else the sum is unbounded anyway), so the increment's model holds 0 there */
    const GP_MASK add = (GP_MASK)(1);
#else
    const GP_MASK add = has;
#endif
    const int km = k == 0 ? n - 1 : k - 1;
    const GP_REAL* rk = recs + k * GP_E_NFIELDS;
    const GP_REAL* rm = recs + km * GP_E_NFIELDS;
    /* corner interpolator r_k(u, v) (Eq. 2): P(u) = C_k(u), Q(v) = C_{k-1}(1 - v) */
    const GP_REAL u = t[k], v = GP_R(1.0) - t[km];
    const gp_vec3 tp0 = gp_get3(rk, GP_E_T0), tq0 = gp_get3(rm, GP_E_T1);
    const gp_vec3 a = gp_get3(rk, GP_E_DT0);         /* T_P'(0) = dT_k/dt(0) */
    const gp_vec3 b = gp_neg(gp_get3(rm, GP_E_DT1)); /* T_Q'(0) = -dT_{k-1}/dt(1) */
    const gp_vec3 dTP = gp_sub(T[k], tp0), dTQ = gp_sub(T[km], tq0);
    gp_vec3 r = gp_sub(gp_add(C[k], C[km]), gp_get3(rk, GP_E_V0));
    r = gp_madd(gp_madd(r, dTP, v), dTQ, u);
    const GP_REAL s = u + v;
    const GP_MASK sp = s > GP_R(0.0);
    const GP_REAL is = GP_R(1.0) / s;
    /* - u v (v a + u b) / (u + v) where u + v > 0 */
#ifdef GP_INTERVAL
    GP_REAL tw[6]; /* u v^2/s, u^2 v/s, v^3/s^2, u v (u+2v)/s^2, u v (2u+v)/s^2, u^3/s^2 */
    gp_iv_twist_factors(u, v, tw);
    (void)sp;
    (void)is;
    r = gp_sub(r, gp_add(gp_scale(a, tw[0]), gp_scale(b, tw[1])));
#else
    r = gp_sel3(sp, gp_sub(r, gp_scale(gp_add(gp_scale(a, u * v * v), gp_scale(b, u * u * v)), is)), r);
#endif
    const GP_REAL w = W[k] * iS;
    out.pos = gp_sel3(add, gp_madd(out.pos, r, w), out.pos);
    if (!deriv) continue;
    const GP_REAL ux = tx[k], uy = ty[k], vx = -tx[km], vy = -ty[km];
    gp_vec3 ru = gp_madd(gp_add(Cd[k], dTQ), Td[k], v);    /* P' + v T_P' + (T_Q - T_Q(0)) */
    gp_vec3 rv = gp_madd(gp_sub(dTP, Cd[km]), Td[km], -u); /* Q' + (T_P - T_P(0)) + u T_Q' */
#ifdef GP_INTERVAL
    ru = gp_sub(ru, gp_add(gp_scale(a, tw[2]), gp_scale(b, tw[3])));
    rv = gp_sub(rv, gp_add(gp_scale(a, tw[4]), gp_scale(b, tw[5])));
#else
    { /* the partials of the term above, where u + v > 0 */
      const GP_REAL is2 = is * is;
      ru = gp_sel3(
          sp, gp_sub(ru, gp_scale(gp_add(gp_scale(a, v * v * v), gp_scale(b, u * v * (u + GP_R(2.0) * v))), is2)), ru);
      rv = gp_sel3(
          sp, gp_sub(rv, gp_scale(gp_add(gp_scale(a, u * v * (GP_R(2.0) * u + v)), gp_scale(b, u * u * u)), is2)), rv);
    }
#endif
    const GP_REAL wx = (Wx[k] - w * Sx) * iS, wy = (Wy[k] - w * Sy) * iS;
#ifdef GP_INTERVAL
    /* w t_k' and w t_{k-1}' with t' = numerator / den^2: den_k = d_{k-1} + d_{k+1} and
     * den_{k-1} = d_{k-2} + d_k vanish at a triangle's corners (inside its domain), where any
     * enclosure of 1 / den^2 is unbounded. W_k holds d_{k+1}^2 and d_{k-2}^2, so
     * W_k / den_k^2 = (1 - t_k)^2 prod_{i=2..n-2} d_{k+i}^2 and
     * W_k / den_{k-1}^2 = t_{k-1}^2 prod_{i=1..n-3} d_{k+i}^2: bounded, the same function. */
    (void)vx;
    (void)vy;
    GP_REAL pu = GP_R(1.0), pv = GP_R(1.0);
    for (int i = 2; i <= n - 2; ++i) {
      const int j = (k + i) % n;
      pu = pu * (d[j] * d[j]);
    }
    for (int i = 1; i <= n - 3; ++i) {
      const int j = (k + i) % n;
      pv = pv * (d[j] * d[j]);
    }
    const GP_REAL ou = (GP_R(1.0) - u) * (GP_R(1.0) - u) * pu * iS, ov = (GP_R(1.0) - v) * (GP_R(1.0) - v) * pv * iS;
    out.dxi = gp_sel3(
        add, gp_madd(gp_madd(out.dxi, r, wx), gp_sub(gp_scale(ru, ux * ou), gp_scale(rv, tx[km] * ov)), GP_R(1.0)),
        out.dxi);
    out.deta = gp_sel3(
        add, gp_madd(gp_madd(out.deta, r, wy), gp_sub(gp_scale(ru, uy * ou), gp_scale(rv, ty[km] * ov)), GP_R(1.0)),
        out.deta);
#else
    out.dxi = gp_sel3(has, gp_madd(gp_madd(out.dxi, r, wx), gp_add(gp_scale(ru, ux), gp_scale(rv, vx)), w), out.dxi);
    out.deta = gp_sel3(has, gp_madd(gp_madd(out.deta, r, wy), gp_add(gp_scale(ru, uy), gp_scale(rv, vy)), w), out.deta);
#endif
#ifndef GP_INTERVAL
    nfb = gp_sel3(has, gp_madd(nfb, gp_get3(rk, GP_E_N0), w), nfb);
#endif
  }
#ifdef GP_INTERVAL
  /* the certificate bounds dG/dxi x dG/deta itself and reads no unit normal: none computed */
  (void)nfb;
#else
  if (deriv) gp_eval_normal(&out, nfb, recs);
#endif
  gp_eval_outside(&out, outside);
  return out;
}

/* Evaluates G(X) = sum_k w_k(X) r_k(u_k(X), v_k(X)) (Eq. 2-5) and, when deriv is non-zero, its
 * exact first derivatives and the unit normal at X = (xi, eta) in the domain dom of an n-gon
 * (gp_domain_of). recs: the patch's n edge records (record-major, private memory). deriv 0:
 * the position only (dxi, deta and normal zero; the same position bits: the same operations),
 * for callers that need no derivatives (the quality check's bulge samples); pass a constant,
 * so that the inlined derivative code drops out. Points outside the domain return
 * GP_ST_OUTSIDE and zeros. Triangles and quads run the body with n a constant (the short loops
 * unrolled), other polygons with n as read. Measured (callgrind, AVX2 lanes, double): 4% fewer
 * instructions per tracking step and per 3-lane group of the refinement; unrolling the per-edge
 * loops too saved another 1.5% but made each instance about 30 times larger (up to 360 KB) and
 * the sweep probe's instruction-cache misses 17 times as many. */
GP_FN gp_eval_result gp_patch_eval_dom_d(const gp_domain* dom, const GP_REAL* recs, int mode, GP_REAL xi, GP_REAL eta,
                                         int deriv) {
  switch (dom->n) {
    case 3:
      return gp_patch_eval_dom_n(dom, 3, recs, mode, xi, eta, deriv);
    case 4:
      return gp_patch_eval_dom_n(dom, 4, recs, mode, xi, eta, deriv);
    default:
      return gp_patch_eval_dom_n(dom, dom->n, recs, mode, xi, eta, deriv);
  }
}

/* gp_patch_eval_dom_d with the derivatives and the normal. */
GP_FN gp_eval_result gp_patch_eval_dom(const gp_domain* dom, const GP_REAL* recs, int mode, GP_REAL xi, GP_REAL eta) {
  return gp_patch_eval_dom_d(dom, recs, mode, xi, eta, 1);
}

/* gp_patch_eval_dom on the domain of the n-gon; n outside 3..GP_MAX_N gives
 * GP_ST_TOO_MANY_SIDES and zeros. */
GP_FN gp_eval_result gp_patch_eval(int n, const GP_REAL* recs, int mode, GP_REAL xi, GP_REAL eta GP_DT_PARAM) {
  if (n < 3 || n > GP_MAX_N) {
    gp_eval_result out;
    out.pos = out.dxi = out.deta = out.normal = gp_zero3();
    out.status = GP_ST_TOO_MANY_SIDES;
    return out;
  }
  gp_domain scratch;
  return gp_patch_eval_dom(gp_domain_of(n, &scratch, 0 GP_DT_ARG), recs, mode, xi, eta);
}

/* Quality samples (design page, "Robustness"): for each edge k, GP_Q_STEPS + 1 points s along
 * it on each of three rings, f ((1-s) C_k + s C_{k+1}) with f = 1 - 1e-3, 0.66, 0.33. */
#undef GP_Q_STEPS
#define GP_Q_STEPS 4
#ifndef GP_LANES /* uniform: lane instantiations use the scalar one (gp_lanes-inl.h) */
/* The sample of edge k, step i, ring (0: near the edge) of domain dom, and its s. */
GP_FN void gp_quality_sample(const gp_domain* dom, int k, int i, int ring, GP_REAL* s, GP_REAL* px, GP_REAL* py) {
  const int k1 = k + 1 == dom->n ? 0 : k + 1;
  const GP_REAL ax = dom->cx[k], ay = dom->cy[k], bx = dom->cx[k1], by = dom->cy[k1];
  const GP_REAL inset = GP_R(1.0e-3);
  *s = (GP_REAL)i / (GP_REAL)GP_Q_STEPS;
  const GP_REAL f = ring == 0 ? GP_R(1.0) - inset : (ring == 1 ? GP_R(0.66) : GP_R(0.33));
  *px = f * ((GP_R(1.0) - *s) * ax + *s * bx);
  *py = f * ((GP_R(1.0) - *s) * ay + *s * by);
}
#endif

/* The body of gp_patch_quality for an n-gon, inlined where n is a constant (as
 * gp_patch_eval_dom_n). The sample at the end of edge k (s = 1) is the one at the start of edge
 * k + 1 (s = 0) on every ring, the same domain point bit for bit, and the fold test uses
 * neither: each is evaluated once, as s = 0 of the next edge (4n of the 5n samples per ring).
 * The bulge is their maximum, so the same value. */
GP_FN_INLINE GP_STATUS gp_patch_quality_n(const gp_domain* dom, const int n, const GP_REAL* recs, int mode,
                                          GP_REAL* bulge) {
  GP_STATUS st = 0u;
  gp_vec3 lo = gp_get3(recs, GP_E_V0), hi = lo;
  GP_REAL diam = GP_R(0.0);
  for (int k = 0; k < n; ++k) {
    const gp_vec3 p = gp_get3(recs + k * GP_E_NFIELDS, GP_E_V0);
    lo = gp_v3(gp_min(p.x, lo.x), gp_min(p.y, lo.y), gp_min(p.z, lo.z));
    hi = gp_v3(gp_max(p.x, hi.x), gp_max(p.y, hi.y), gp_max(p.z, hi.z));
    for (int j = 0; j < k; ++j) diam = gp_max(diam, gp_len(gp_sub(p, gp_get3(recs + j * GP_E_NFIELDS, GP_E_V0))));
  }
  GP_REAL worst = GP_R(0.0);
  for (int k = 0; k < n; ++k) {
    const GP_REAL Lk = gp_edge_length(recs + k * GP_E_NFIELDS);
    for (int i = 0; i < GP_Q_STEPS; ++i) { /* i = GP_Q_STEPS: edge k + 1's i = 0 */
      for (int ring = 0; ring < 3; ++ring) {
        /* points on the segment from the centre towards the edge: near the edge and inside */
        GP_SREAL s, px, py;
        gp_quality_sample(dom, k, i, ring, &s, &px, &py);
        /* the fold test needs the normal (ring 0 inside the edge); the bulge, positions only */
        const int normal = ring == 0 && i > 0 && i < GP_Q_STEPS;
        const gp_eval_result g = normal ? gp_patch_eval_dom_n(dom, n, recs, mode, px, py, 1)
                                        : gp_patch_eval_dom_n(dom, n, recs, mode, px, py, 0);
        const gp_vec3 q = g.pos;
        GP_REAL out = GP_R(0.0);
        out = gp_max(out, gp_max(lo.x - q.x, q.x - hi.x));
        out = gp_max(out, gp_max(lo.y - q.y, q.y - hi.y));
        out = gp_max(out, gp_max(lo.z - q.z, q.z - hi.z));
        worst = gp_max(worst, out);
        if (ring == 0 && i > 0 && i < GP_Q_STEPS) {
          gp_dvec3 c, cp;
          GP_STATUS ignore = 0u;
          gp_edge_curve(recs + k * GP_E_NFIELDS, s, &c, &cp);
          const gp_dvec3 nc = gp_edge_normal(recs + k * GP_E_NFIELDS, s, cp, Lk, &ignore);
          st |= GP_BITS(gp_dot(nc.v, g.normal) < GP_R(0.0), GP_ST_FOLD);
        }
      }
    }
  }
  *bulge = GP_SEL(diam > GP_R(0.0), worst / diam, GP_R(0.0));
  st |= GP_BITS(*bulge > GP_R(0.5), GP_ST_BULGE);
  return st;
}

/* Quality of one built patch (design page, "Robustness"): fold = the patch normal opposite
 * to n_c at points 1e-3 inside an edge; bulge = the largest distance of sampled surface
 * points outside the face's bounding box over the face diameter. Returns GP_ST_FOLD and/or
 * GP_ST_BULGE (bulge > 0.5); the bulge value goes to *bulge. Triangles and quads run the body
 * with n a constant. */
GP_FN GP_STATUS gp_patch_quality(int n, const GP_REAL* recs, int mode, GP_REAL* bulge GP_DT_PARAM) {
  gp_domain scratch;
  const gp_domain* dom = gp_domain_of(n, &scratch, 1 GP_DT_ARG);
  switch (n) {
    case 3:
      return gp_patch_quality_n(dom, 3, recs, mode, bulge);
    case 4:
      return gp_patch_quality_n(dom, 4, recs, mode, bulge);
    default:
      return gp_patch_quality_n(dom, n, recs, mode, bulge);
  }
}
