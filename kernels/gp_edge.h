/* SPDX-License-Identifier: Apache-2.0 */
/* Edge curves, edge normals and cross tangents of the n-sided Gregory patch, and the
 * construction of a face's per-edge records.
 * Source: Wu et al., "Smooth Force Rendering on Coarse Polygonal Meshes", Eq. 6-14, with
 * the conventions of shared/design/gregory-patch.md (unit n_c, guard, correction).
 * Part of gp_patch.h; no include guard on purpose. */

/* Cubic Hermite edge curve C_k(t) (Eq. 6) with its first and second t-derivatives.
 * Returned as two duals: c = (C, C'), cp = (C', C''). */
GP_FN_INLINE void gp_edge_curve(const GP_REAL* rec, GP_REAL t, gp_dvec3* c, gp_dvec3* cp) {
  const GP_REAL t2 = t * t, t3 = t2 * t;
  const GP_REAL h00 = GP_R(2.0) * t3 - GP_R(3.0) * t2 + GP_R(1.0);
  const GP_REAL h10 = t3 - GP_R(2.0) * t2 + t;
  const GP_REAL h01 = GP_R(3.0) * t2 - GP_R(2.0) * t3;
  const GP_REAL h11 = t3 - t2;
  const GP_REAL g00 = GP_R(6.0) * t2 - GP_R(6.0) * t; /* first derivatives */
  const GP_REAL g10 = GP_R(3.0) * t2 - GP_R(4.0) * t + GP_R(1.0);
  const GP_REAL g01 = GP_R(6.0) * t - GP_R(6.0) * t2;
  const GP_REAL g11 = GP_R(3.0) * t2 - GP_R(2.0) * t;
  const GP_REAL s00 = GP_R(12.0) * t - GP_R(6.0); /* second derivatives */
  const GP_REAL s10 = GP_R(6.0) * t - GP_R(4.0);
  const GP_REAL s01 = GP_R(6.0) - GP_R(12.0) * t;
  const GP_REAL s11 = GP_R(6.0) * t - GP_R(2.0);
  const gp_vec3 p0 = gp_get3(rec, GP_E_V0), p1 = gp_get3(rec, GP_E_V1);
  const gp_vec3 m0 = gp_get3(rec, GP_E_M0), m1 = gp_get3(rec, GP_E_M1);
  gp_vec3 C = gp_scale(p0, h00), D = gp_scale(p0, g00), S = gp_scale(p0, s00);
  C = gp_madd(gp_madd(gp_madd(C, p1, h01), m0, h10), m1, h11);
  D = gp_madd(gp_madd(gp_madd(D, p1, g01), m0, g10), m1, g11);
  S = gp_madd(gp_madd(gp_madd(S, p1, s01), m0, s10), m1, s11);
  *c = gp_dv(C, D);
  *cp = gp_dv(D, S);
}

/* Length of the edge's chord |V1 - V0|, computed once per edge and evaluation and passed to
 * gp_edge_normal and gp_cross_tangent. */
GP_FN_INLINE GP_REAL gp_edge_length(const GP_REAL* rec) {
  return gp_len(gp_sub(gp_get3(rec, GP_E_V1), gp_get3(rec, GP_E_V0)));
}

/* Unit surface normal along the edge, n_c(t) (Eq. 10, normalised), with its t-derivative.
 * cp = (C', C''); L = gp_edge_length. The guarded end tangents (gp_edge_tangents) make it N_k at
 * t = 0 and N_{k+1} at t = 1; in between it is not turned towards the interpolated normal (such a
 * turn flips it where it is perpendicular to that normal, and tore patches: design page,
 * Robustness 1). */
GP_FN_INLINE gp_dvec3 gp_edge_normal(const GP_REAL* rec, GP_REAL t, gp_dvec3 cp, GP_REAL L, GP_STATUS* st) {
  const gp_vec3 e = gp_sub(gp_get3(rec, GP_E_V1), gp_get3(rec, GP_E_V0));
  const gp_dvec3 nt = gp_dlerp(gp_get3(rec, GP_E_N0), gp_get3(rec, GP_E_N1), t);
  const gp_dvec3 ce = gp_dv(e, gp_zero3());
  const gp_dvec3 raw = gp_dcross(cp, gp_dcross(nt, ce));
  /* where |raw| > tiny L^2 >= 0, |raw| > 0 and the unit vector is defined; elsewhere the
   * fallback below replaces it */
  const GP_REAL lraw = gp_len(raw.v);
  gp_dvec3 n = gp_dunit_len(raw, lraw);
  GP_STATUS sraw = 0u;
  const GP_MASK flat = !(lraw > GP_TINY * L * L);
  if (GP_ANY(flat)) { /* normal along the edge or opposite normals: interpolated normal, else N_k */
    GP_STATUS sfb = GP_ST_EDGE_NORMAL;
    const gp_dvec3 fb = gp_dunit_or(nt, gp_dv(gp_get3(rec, GP_E_N0), gp_zero3()), GP_TINY, &sfb, GP_ST_EDGE_NORMAL);
    n = gp_dsel(flat, fb, n);
    sraw = GP_SEL(flat, sfb, sraw);
  }
  *st |= sraw;
  return n;
}

/* Inward direction used where a cross-tangent construction step is undefined: unit
 * n_c x C' (zero, with GP_ST_CROSS_TANGENT in *ist, where that too is undefined, e.g. on a
 * zero-length edge). Computed only for the lanes that need it. */
GP_FN gp_dvec3 gp_edge_inward(gp_dvec3 nc, gp_dvec3 cp, GP_REAL scale, GP_STATUS* ist) {
  return gp_dunit_or(gp_dcross(nc, cp), gp_dv(gp_zero3(), gp_zero3()), GP_TINY * scale, ist, GP_ST_CROSS_TANGENT);
}

/* unit(a), or gp_edge_inward where |a| <= tiny (GP_ST_CROSS_TANGENT and the inward
 * direction's own bits in *st there). */
GP_FN_INLINE gp_dvec3 gp_unit_or_inward(gp_dvec3 a, GP_REAL tiny, gp_dvec3 nc, gp_dvec3 cp, GP_REAL scale, GP_STATUS* st) {
  const GP_REAL l = gp_len(a.v);
  const GP_MASK ok = l > tiny;
  gp_dvec3 u = gp_dunit_len(a, l);
  if (GP_ANY(!ok)) {
    GP_STATUS ist = 0u;
    const gp_dvec3 in = gp_edge_inward(nc, cp, scale, &ist);
    u = gp_dsel(ok, u, in);
    *st |= GP_SEL(ok, (GP_STATUS)0u, (GP_STATUS)GP_ST_CROSS_TANGENT | ist);
  }
  return u;
}

/* Below this length (times the record's largest length for t_c) a cross-tangent direction
 * that turns over is turned through a direction across its path (gp_turn_past_zero). */
#undef GP_TURN_EPS
#define GP_TURN_EPS GP_R(1.0e-2)

/* The rare path of gp_turn_past_zero (|a|^2 = l2 < eps^2 on some lane). GP_FN, not GP_FN_INLINE:
 * forced into every edge of every evaluation it made the tracking step 15% slower; where it is
 * inlined is left to the compiler, since forcing it out of line (noinline) was slower too
 * (performance log, twenty-second session). */
GP_FN gp_dvec3 gp_turn_past_zero_near(gp_dvec3 a, GP_REAL l2, GP_REAL eps, gp_dvec3 nc, gp_dvec3 cp, gp_vec3 a0,
                                      gp_vec3 a1) {
  const GP_REAL l = GP_SQRT(l2);
  const gp_vec3 span = gp_sub(a1, a0);
  const GP_REAL ls = gp_len(span);
  const GP_MASK near = l < eps && ls > GP_R(0.0);
  const gp_vec3 u = gp_scale(span, GP_R(1.0) / ls);
  const gp_dvec3 b0 = gp_dv(gp_cross(nc.v, u), gp_cross(nc.d, u));
  const gp_dvec3 b = gp_dsel(gp_dot(b0.v, gp_cross(nc.v, cp.v)) < GP_R(0.0), gp_dneg(b0), b0);
  /* (eps - |a|)^2 / eps and its derivative -2 (eps - |a|) / eps a.a'/|a| (0 where |a| = 0) */
  const GP_REAL e = eps - l;
  const gp_dreal m = gp_dr(e * e / eps, GP_SEL(l > GP_R(0.0), GP_R(-2.0) * e / eps * gp_dot(a.v, a.d) / l, GP_R(0.0)));
  return gp_dsel(near, gp_dadd(a, gp_dmul(m, b)), a);
}

/* Where a direction field a(t) in the tangent plane of n_c (t_c of Eq. 13, or the corrected q
 * projected) turns over along the edge, from a0 at t = 0 to a1 at t = 1, it passes through zero
 * and its unit vector flips: the patch tears (pmp/L.off's reflex corner, tetris.obj's straight
 * corners: the surface jumped 0.5 m and 0.13 m across a line of constant t_k). Where |a| < eps this
 * adds ((eps - |a|)^2 / eps) b, b = n_c x unit(a1 - a0) turned inward (b . (n_c x C') >= 0), so
 * that the direction turns through b instead (design page, Robustness 4), with a continuous
 * derivative: the push and its derivative vanish where it starts (|a| = eps). A push of
 * (eps - |a|) b, as before, made the derivative jump there, a crease in the patch (pmp/L.off's
 * folded hexagon: dG/dxi 0.6 -> 31 m per domain unit, the normal turned over) that the Newton
 * refinement crawled along to its iteration cap. Unchanged where |a| >= eps, or where a1 - a0 has
 * no direction. cp = (C', C''). */
GP_FN_INLINE gp_dvec3 gp_turn_past_zero(gp_dvec3 a, GP_REAL eps, gp_dvec3 nc, gp_dvec3 cp, gp_vec3 a0, gp_vec3 a1) {
  const GP_REAL l2 = gp_dot(a.v, a.v);
  if (!GP_ANY(l2 < eps * eps)) return a; /* the common case */
  return gp_turn_past_zero_near(a, l2, eps, nc, cp, a0, a1);
}

/* The largest of the three lengths an edge record refers to (L = gp_edge_length): the scale of
 * its cross tangent's "tiny" and of Robustness 4's eps for t_c. */
GP_FN_INLINE GP_REAL gp_tangent_scale(const GP_REAL* rec, GP_REAL L) {
  return gp_max(L, gp_max(rec[GP_E_LP], rec[GP_E_LN]));
}

/* The cross tangent's length (1-t) L_prev + t L_next (Eq. 14) with its t-derivative. */
GP_FN_INLINE gp_dreal gp_tangent_length(const GP_REAL* rec, GP_REAL t) {
  return gp_dr((GP_R(1.0) - t) * rec[GP_E_LP] + t * rec[GP_E_LN], rec[GP_E_LN] - rec[GP_E_LP]);
}

/* The printed cross-tangent direction p(t) = unit(t_c(t)) (Eq. 11-13) with its t-derivative;
 * regular: turned where t_c vanishes (gp_turn_past_zero, a0 = V_{k-1} - V_k, a1 = V_{k+2} -
 * V_{k+1}: v_int at the ends; the corrected construction), else as printed. scale: the largest
 * length of the record. */
GP_FN_INLINE gp_dvec3 gp_printed_direction(const GP_REAL* rec, GP_REAL t, gp_dvec3 c, gp_dvec3 cp, gp_dvec3 nc,
                                           GP_REAL scale, int regular, GP_STATUS* st) {
  /* Eq. 11-13: v_int, n_int, t_c = n_c x (v_int x n_int) */
  const gp_dvec3 vint = gp_dsub(gp_dlerp(gp_get3(rec, GP_E_VP), gp_get3(rec, GP_E_VN), t), c);
  const gp_dvec3 nint = gp_dscale(gp_dadd(gp_dlerp(gp_get3(rec, GP_E_NP), gp_get3(rec, GP_E_NN), t), nc), GP_R(0.5));
  gp_dvec3 tc = gp_dcross(nc, gp_dcross(vint, nint));
  if (regular) {
    const gp_vec3 a0 = gp_sub(gp_get3(rec, GP_E_VP), gp_get3(rec, GP_E_V0));
    const gp_vec3 a1 = gp_sub(gp_get3(rec, GP_E_VN), gp_get3(rec, GP_E_V1));
    tc = gp_turn_past_zero(tc, GP_TURN_EPS * scale, nc, cp, a0, a1);
  }
  return gp_unit_or_inward(tc, GP_TINY * scale, nc, cp, scale, st);
}

/* Cross tangent T_k(t) with its t-derivative (Eq. 11-14 and the design page's variants).
 * c = (C, C'), cp = (C', C''), nc = n_c (dual), L = gp_edge_length. mode: GP_CT_*. Where a
 * step is undefined, the inward direction n_c x C' (gp_edge_inward) replaces it. */
GP_FN_INLINE gp_dvec3 gp_cross_tangent(const GP_REAL* rec, GP_REAL t, int mode, gp_dvec3 c, gp_dvec3 cp, gp_dvec3 nc,
                                GP_REAL L, GP_STATUS* st) {
  const GP_REAL scale = gp_tangent_scale(rec, L);
  const gp_dreal len = gp_tangent_length(rec, t);
  const gp_vec3 d0 = gp_get3(rec, GP_E_D0), d1 = gp_get3(rec, GP_E_D1);
  gp_dvec3 q;
  if (mode == GP_CT_BLEND) {
    q = gp_dlerp(d0, d1, t);
  } else {
    const gp_dvec3 p = gp_printed_direction(rec, t, c, cp, nc, scale, mode != GP_CT_PAPER, st);
    if (mode == GP_CT_PAPER) return gp_dmul(len, p); /* Eq. 14 as printed */
    /* correction: q(t) = p(t) + (1-t)(d0 - p(0)) + t(d1 - p(1)) */
    const gp_vec3 c0 = gp_sub(d0, gp_get3(rec, GP_E_P0)), c1 = gp_sub(d1, gp_get3(rec, GP_E_P1));
    q = gp_dadd(p, gp_dlerp(c0, c1, t));
  }
  /* project onto the tangent plane of n_c: q - (q.n_c) n_c, turned where it vanishes
   * (gp_turn_past_zero; q runs from d0 to d1) */
  const gp_dvec3 proj = gp_turn_past_zero(gp_dsub(q, gp_dmul(gp_ddot(q, nc), nc)), GP_TURN_EPS, nc, cp, d0, d1);
  return gp_dmul(len, gp_unit_or_inward(proj, GP_TINY, nc, cp, scale, st));
}

/* Unit end tangents (t_s, t_e) of the edge Va -> Vb (Eq. 8-9) with the design page's
 * degenerate fallback and backward-tangent guard. The same curve results from either
 * direction; the caller evaluates each edge in one canonical direction. */
GP_FN void gp_edge_tangents(gp_vec3 va, gp_vec3 vb, gp_vec3 na, gp_vec3 nb, gp_vec3* ts, gp_vec3* te, GP_STATUS* st) {
  const gp_vec3 e = gp_sub(vb, va);
  const GP_REAL L = gp_len(e);
  const GP_REAL span = gp_max(gp_len(va), gp_len(vb));
  const GP_MASK zero = !(L > GP_TINY * span) || !(L > GP_R(0.0));
  if (GP_ALL(zero)) {
    *st |= GP_ST_ZERO_EDGE;
    *ts = gp_zero3();
    *te = gp_zero3();
    return;
  }
  GP_STATUS s = 0u; /* bits of the lanes with an edge */
  const gp_vec3 eu = gp_scale(e, GP_R(1.0) / L);
  const gp_vec3 navg = gp_scale(gp_add(na, nb), GP_R(0.5));
  const gp_vec3 w = gp_cross(eu, navg);
  /* projections of the edge on the vertices' tangent planes: fallback and guard */
  const gp_vec3 pa = gp_unit_or(gp_madd(eu, na, -gp_dot(eu, na)), eu, GP_TINY, &s, GP_ST_EDGE_NORMAL);
  const gp_vec3 pb = gp_unit_or(gp_madd(eu, nb, -gp_dot(eu, nb)), eu, GP_TINY, &s, GP_ST_EDGE_NORMAL);
  GP_STATUS ignore = 0u;
  gp_vec3 a = gp_unit_or(gp_cross(na, w), pa, GP_TINY, &ignore, 1u);
  gp_vec3 b = gp_unit_or(gp_cross(nb, w), pb, GP_TINY, &ignore, 1u);
  const GP_MASK ga = gp_dot(a, e) <= GP_R(0.0), gb = gp_dot(b, e) <= GP_R(0.0);
  a = gp_sel3(ga, pa, a);
  b = gp_sel3(gb, pb, b);
  s |= GP_BITS(ga || gb, GP_ST_GUARD);
  *st |= GP_SEL(zero, (GP_STATUS)GP_ST_ZERO_EDGE, s);
  *ts = gp_sel3(zero, gp_zero3(), a);
  *te = gp_sel3(zero, gp_zero3(), b);
}

/* Fills the cross-tangent data (D0, D1, P0, P1, T0, T1, DT0, DT1) of one edge record whose
 * geometry fields are set. d0, d1 as on the design page. */
GP_FN void gp_finish_edge_record(GP_REAL* rec, gp_vec3 d0, gp_vec3 d1, int mode, GP_STATUS* st) {
  gp_put3(rec, GP_E_D0, d0);
  gp_put3(rec, GP_E_D1, d1);
  const GP_REAL L = gp_edge_length(rec);
  for (int end = 0; end < 2; ++end) { /* p(0), p(1): the printed direction (as the mode turns it) */
    const GP_REAL t = end ? GP_R(1.0) : GP_R(0.0);
    gp_dvec3 c, cp;
    gp_edge_curve(rec, t, &c, &cp);
    const gp_dvec3 nc = gp_edge_normal(rec, t, cp, L, st);
    const gp_dvec3 p = gp_printed_direction(rec, t, c, cp, nc, gp_tangent_scale(rec, L), mode == GP_CT_CORRECTED, st);
    const gp_dvec3 T = gp_dmul(gp_tangent_length(rec, t), p);
    const GP_REAL l = end ? rec[GP_E_LN] : rec[GP_E_LP];
    gp_put3(rec, end ? GP_E_P1 : GP_E_P0, gp_sel3(l > GP_R(0.0), gp_scale(T.v, GP_R(1.0) / l), gp_zero3()));
  }
  for (int end = 0; end < 2; ++end) { /* T(0), T(1) and exact dT/dt there (twists) */
    const GP_REAL t = end ? GP_R(1.0) : GP_R(0.0);
    gp_dvec3 c, cp;
    gp_edge_curve(rec, t, &c, &cp);
    const gp_dvec3 nc = gp_edge_normal(rec, t, cp, L, st);
    const gp_dvec3 T = gp_cross_tangent(rec, t, mode, c, cp, nc, L, st);
    gp_put3(rec, end ? GP_E_T1 : GP_E_T0, T.v);
    gp_put3(rec, end ? GP_E_DT1 : GP_E_DT0, T.d);
  }
}

/* True where some component of a and b differs (the lanes where two normals are not one). */
GP_FN GP_MASK gp_differs3(gp_vec3 a, gp_vec3 b) {
  return GP_FABS(a.x - b.x) > GP_R(0.0) || GP_FABS(a.y - b.y) > GP_R(0.0) || GP_FABS(a.z - b.z) > GP_R(0.0);
}

/* The unit tangent along the crease at one end of edge e: unit(n x p) (perpendicular to both
 * faces' normals there), turned to run along e. n x p and p x n differ only in sign, so both
 * faces of the edge get the same bits; where it is perpendicular to e, the sign of its first
 * nonzero component decides, again the same from both sides. */
GP_FN gp_vec3 gp_crease_direction(gp_vec3 c, GP_REAL len, gp_vec3 e) {
  const gp_vec3 u = gp_scale(c, GP_R(1.0) / len);
  const GP_REAL s = gp_dot(u, e);
  const GP_REAL first = GP_SEL(GP_FABS(u.x) > GP_R(0.0), u.x, GP_SEL(GP_FABS(u.y) > GP_R(0.0), u.y, u.z));
  const GP_MASK flip = s < GP_R(0.0) || (!(GP_FABS(s) > GP_R(0.0)) && first < GP_R(0.0));
  return gp_sel3(flip, gp_neg(u), u);
}

/* Unit end tangents (t_s, t_e) of an edge Va -> Vb that both of its faces build from the data they
 * share: na, nb are this face's normals at Va, Vb and pa, pb the other face's there (pa = na, pb = nb
 * on a boundary). Where the two faces' normals are one (bit for bit) at both ends, this is
 * gp_edge_tangents(va, vb, na, nb) exactly. Else, at a crease end (normals that differ, |n x p| >
 * tiny) the tangent runs along the crease, unit(n x p), in both faces' tangent planes, so that each
 * face's patch keeps its own normal there; at a smooth end (equal or parallel normals) the tangent is
 * gp_edge_tangents' of the shared normals unit(n + p). The host merges normals that are one up to
 * rounding (normals.h, kSameNormalAngle) before they get here. Every operation is symmetric in
 * (n, p) up to an exact sign, so the two faces build one curve, bit for bit: no gap along a crease
 * (docs/guide.md, Creases). Opposite normals
 * (n + p ~ 0 at an end that is no crease) set GP_ST_EDGE_NORMAL and take the edge's direction. */
GP_FN void gp_crease_edge_tangents(gp_vec3 va, gp_vec3 vb, gp_vec3 na, gp_vec3 nb, gp_vec3 pa, gp_vec3 pb,
                                   gp_vec3* ts, gp_vec3* te, GP_STATUS* st) {
  const GP_MASK sameA = !gp_differs3(na, pa), sameB = !gp_differs3(nb, pb);
  GP_STATUS sa = 0u, sb = 0u;
  const gp_vec3 ma = gp_sel3(sameA, na, gp_unit_or(gp_add(na, pa), gp_zero3(), GP_TINY, &sa, GP_ST_EDGE_NORMAL));
  const gp_vec3 mb = gp_sel3(sameB, nb, gp_unit_or(gp_add(nb, pb), gp_zero3(), GP_TINY, &sb, GP_ST_EDGE_NORMAL));
  gp_vec3 ra, rb;
  gp_edge_tangents(va, vb, ma, mb, &ra, &rb, st);
  const gp_vec3 e = gp_sub(vb, va);
  const gp_vec3 ca = gp_cross(na, pa), cb = gp_cross(nb, pb);
  const GP_REAL la = gp_len(ca), lb = gp_len(cb);
  const GP_MASK creaseA = la > GP_TINY, creaseB = lb > GP_TINY;
  /* a zero edge keeps gp_edge_tangents' zero tangents */
  const GP_MASK edge = gp_dot(ra, ra) > GP_R(0.0);
  *ts = gp_sel3(creaseA && edge, gp_crease_direction(ca, gp_max(la, GP_TINY), e), ra);
  *te = gp_sel3(creaseB && edge, gp_crease_direction(cb, gp_max(lb, GP_TINY), e), rb);
  *st |= GP_SEL(!sameA && !creaseA, sa, (GP_STATUS)0u) | GP_SEL(!sameB && !creaseB, sb, (GP_STATUS)0u);
}

/* The unit end tangents of the n edges of one polygon as gp_build_patch builds them: ts[k], te[k]
 * the directions of C_k'(0) at V_k and C_k'(1) at V_{k+1}, each edge evaluated from its lower
 * vertex id (so both faces of an edge get the same bits, up to an exact sign), from
 * gp_crease_edge_tangents where `creased` (PS, PE: the other faces' normals), else from
 * gp_edge_tangents (PS, PE unused). n in 3..GP_MAX_N. */
GP_FN void gp_patch_end_tangents(int n, const gp_vec3* V, const gp_vec3* N, const gp_vec3* PS, const gp_vec3* PE,
                                 int creased, const GP_VID* vid, gp_vec3* ts, gp_vec3* te, GP_STATUS* st) {
  for (int k = 0; k < n; ++k) {
    const int k1 = k + 1 == n ? 0 : k + 1;
    /* the edge from its lower vertex id; reversed, its tangents swap and change sign */
    const GP_MASK fwd = vid[k] <= vid[k1];
    const gp_vec3 va = gp_sel3(fwd, V[k], V[k1]), vb = gp_sel3(fwd, V[k1], V[k]);
    const gp_vec3 na = gp_sel3(fwd, N[k], N[k1]), nb = gp_sel3(fwd, N[k1], N[k]);
    gp_vec3 a, b;
    if (creased)
      gp_crease_edge_tangents(va, vb, na, nb, gp_sel3(fwd, PS[k], PE[k]), gp_sel3(fwd, PE[k], PS[k]), &a, &b, st);
    else
      gp_edge_tangents(va, vb, na, nb, &a, &b, st);
    ts[k] = gp_sel3(fwd, a, gp_neg(b));
    te[k] = gp_sel3(fwd, b, gp_neg(a));
  }
}

/* The body of gp_build_patch and gp_build_patch_creased, and the construction with given end
 * tangents: each edge's end tangents from gp_patch_end_tangents, replaced by TS[k], TE[k] where
 * those are given (TS != 0) and nonzero: unit directions of C_k'(0) at V_k and C_k'(1) at V_{k+1}
 * in the tangent planes there (the fold repair's untangled vertex fans; the face across edge k
 * passes the same two, negated and swapped, so both build one curve), then the records. Where
 * every TS[k], TE[k] is zero, the records are those of TS = 0 bit for bit. */
GP_FN GP_STATUS gp_build_patch_with(int n, const gp_vec3* V, const gp_vec3* N, const gp_vec3* PS, const gp_vec3* PE,
                                    int creased, const gp_vec3* TS, const gp_vec3* TE, const GP_VID* vid, int mode,
                                    GP_REAL* recs) {
  GP_STATUS st = 0u;
  if (n < 3 || n > GP_MAX_N) return GP_ST_TOO_MANY_SIDES;
  GP_MASK bad = !gp_finite3(V[0]) || !gp_finite3(N[0]);
  for (int k = 1; k < n; ++k) bad = bad || !gp_finite3(V[k]) || !gp_finite3(N[k]);
  if (GP_ALL(bad)) {
    for (int i = 0; i < n * GP_E_NFIELDS; ++i) recs[i] = GP_R(0.0); /* defined output */
    return GP_ST_NONFINITE;
  }
  gp_vec3 ts[GP_MAX_N], te[GP_MAX_N];
  gp_patch_end_tangents(n, V, N, PS, PE, creased, vid, ts, te, &st);
  if (TS) {
    for (int k = 0; k < n; ++k) {
      ts[k] = gp_sel3(gp_dot(TS[k], TS[k]) > GP_R(0.0), TS[k], ts[k]);
      te[k] = gp_sel3(gp_dot(TE[k], TE[k]) > GP_R(0.0), TE[k], te[k]);
    }
  }
  for (int k = 0; k < n; ++k) {
    const int km = k == 0 ? n - 1 : k - 1, k1 = k + 1 == n ? 0 : k + 1, k2 = k1 + 1 == n ? 0 : k1 + 1;
    GP_REAL* rec = recs + k * GP_E_NFIELDS;
    const GP_REAL L = gp_len(gp_sub(V[k1], V[k]));
    gp_put3(rec, GP_E_V0, V[k]);
    gp_put3(rec, GP_E_V1, V[k1]);
    gp_put3(rec, GP_E_M0, gp_scale(ts[k], L));
    gp_put3(rec, GP_E_M1, gp_scale(te[k], L));
    gp_put3(rec, GP_E_N0, N[k]);
    gp_put3(rec, GP_E_N1, N[k1]);
    gp_put3(rec, GP_E_VP, V[km]);
    gp_put3(rec, GP_E_VN, V[k2]);
    gp_put3(rec, GP_E_NP, N[km]);
    gp_put3(rec, GP_E_NN, N[k2]);
    rec[GP_E_LP] = gp_len(gp_sub(V[k], V[km]));
    rec[GP_E_LN] = gp_len(gp_sub(V[k2], V[k1]));
  }
  for (int k = 0; k < n; ++k) {
    const int km = k == 0 ? n - 1 : k - 1, k1 = k + 1 == n ? 0 : k + 1;
    gp_finish_edge_record(recs + k * GP_E_NFIELDS, gp_neg(te[km]), ts[k1], mode, &st);
  }
  if (GP_ANY(bad)) { /* lanes only: some lanes non-finite */
    for (int i = 0; i < n * GP_E_NFIELDS; ++i) recs[i] = GP_SEL(bad, GP_R(0.0), recs[i]);
    st = GP_SEL(bad, (GP_STATUS)GP_ST_NONFINITE, st);
  }
  return st;
}

/* Builds the n edge records of one polygon into recs (n * GP_E_NFIELDS, record-major).
 * V, N: n positions and unit normals, CCW from outside. vid: the global vertex ids, used
 * to evaluate each edge's end tangents in one canonical direction (lower id first) so that
 * both faces of an edge build the same curve. Returns the patch status bits. A lane with a
 * non-finite V or N gets zero records and GP_ST_NONFINITE alone. */
GP_FN GP_STATUS gp_build_patch(int n, const gp_vec3* V, const gp_vec3* N, const GP_VID* vid, int mode, GP_REAL* recs) {
  return gp_build_patch_with(n, V, N, N, N, 0, 0, 0, vid, mode, recs);
}

/* gp_build_patch for a polygon whose edges may be creases: PS[k], PE[k] are the unit normals that
 * the face across edge k has at V_k and V_{k+1} (N[k], N[k+1] where edge k has no neighbour).
 * Each edge's curve comes from gp_crease_edge_tangents, so both faces of a crease build the same
 * curve while each keeps its own normals N (and so its own tangent plane along the crease). Where
 * PS = N and PE = N[k+1] everywhere, the records equal gp_build_patch's bit for bit. */
GP_FN GP_STATUS gp_build_patch_creased(int n, const gp_vec3* V, const gp_vec3* N, const gp_vec3* PS, const gp_vec3* PE,
                                       const GP_VID* vid, int mode, GP_REAL* recs) {
  return gp_build_patch_with(n, V, N, PS, PE, 1, 0, 0, vid, mode, recs);
}
