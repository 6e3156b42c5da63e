/* SPDX-License-Identifier: Apache-2.0 */
/* A box that holds a whole patch, from its edge records alone (no evaluation of the patch).
 * Source: Wu et al., Eq. 2-5 and 6-14, with shared/design/gregory-patch.md.
 *
 * G(X) = sum_k w_k(X) r_k(u_k, v_k) with w_k >= 0 and sum_k w_k = 1 (Eq. 3-5), and
 * u_k, v_k in [0, 1] inside the domain, so the patch lies in the smallest box holding the
 * boxes of the n corner interpolators r_k over [0, 1]^2. Each r_k (Eq. 2) is bounded term by
 * term, per coordinate:
 *   P(u) - V_k, Q(v) - V_k: the cubic Hermite edge curves (Eq. 6) lie in the hull of their
 *     Bezier control points V0, V0 + M0/3, V1 - M1/3, V1;
 *   v (T_P(u) - T_P(0)), u (T_Q(v) - T_Q(0)): |T_k(t)| <= max(L_prev, L_next) (Eq. 14 and
 *     the design page's variants: a length between L_prev and L_next times a unit vector, or
 *     zero), and v, u in [0, 1];
 *   u v (v a + u b) / (u + v): u v^2 / (u + v) and u^2 v / (u + v) lie in [0, 1/2] on [0, 1]^2.
 * The box is exact arithmetic's; callers add a margin for rounding. Part of the host's
 * instantiation of the patch math (host/patch detail/gp_math.h), after gp_patch.h; no include
 * guard on purpose. */

GP_FN gp_vec3 gp_vmin(gp_vec3 a, gp_vec3 b) { return gp_v3(gp_min(a.x, b.x), gp_min(a.y, b.y), gp_min(a.z, b.z)); }
GP_FN gp_vec3 gp_vmax(gp_vec3 a, gp_vec3 b) { return gp_v3(gp_max(a.x, b.x), gp_max(a.y, b.y), gp_max(a.z, b.z)); }

/* Adds the range of s c x over s in [0, 1] (per coordinate: [min(0, c x), max(0, c x)]) to
 * [*lo, *hi]. */
GP_FN void gp_box_add_scaled(gp_vec3 x, GP_REAL c, gp_vec3* lo, gp_vec3* hi) {
  const gp_vec3 s = gp_scale(x, c);
  *lo = gp_add(*lo, gp_vmin(s, gp_zero3()));
  *hi = gp_add(*hi, gp_vmax(s, gp_zero3()));
}

/* Box of the patch with edge records recs (n * GP_E_NFIELDS, record-major, 3 <= n <= GP_MAX_N)
 * into *lo, *hi. */
GP_FN void gp_patch_box(int n, const GP_REAL* recs, gp_vec3* lo, gp_vec3* hi) {
  gp_vec3 blo = gp_v3(GP_BIG, GP_BIG, GP_BIG), bhi = gp_neg(blo);
  const GP_REAL third = GP_R(1.0) / GP_R(3.0);
  for (int k = 0; k < n; ++k) {
    const int km = k == 0 ? n - 1 : k - 1;
    const GP_REAL* rk = recs + k * GP_E_NFIELDS;
    const GP_REAL* rm = recs + km * GP_E_NFIELDS;
    const gp_vec3 V = gp_get3(rk, GP_E_V0);
    /* P(u) - V_k: edge k's control points relative to V_k */
    const gp_vec3 e = gp_sub(gp_get3(rk, GP_E_V1), V);
    const gp_vec3 p1 = gp_scale(gp_get3(rk, GP_E_M0), third);
    const gp_vec3 p2 = gp_madd(e, gp_get3(rk, GP_E_M1), -third);
    /* Q(v) - V_k = C_{k-1}(1 - v) - V_k: edge k-1's control points relative to V_k (its end) */
    const gp_vec3 q0 = gp_sub(gp_get3(rm, GP_E_V0), V);
    const gp_vec3 q1 = gp_madd(q0, gp_get3(rm, GP_E_M0), third);
    const gp_vec3 q2 = gp_scale(gp_get3(rm, GP_E_M1), -third);
    gp_vec3 lo = gp_add(
        V, gp_add(gp_vmin(gp_vmin(gp_zero3(), p1), gp_vmin(p2, e)), gp_vmin(gp_vmin(gp_zero3(), q0), gp_vmin(q1, q2))));
    gp_vec3 hi = gp_add(
        V, gp_add(gp_vmax(gp_vmax(gp_zero3(), p1), gp_vmax(p2, e)), gp_vmax(gp_vmax(gp_zero3(), q0), gp_vmax(q1, q2))));
    /* v T_P(u) + u T_Q(v): each coordinate within the lengths */
    const GP_REAL l = gp_max(rk[GP_E_LP], rk[GP_E_LN]) + gp_max(rm[GP_E_LP], rm[GP_E_LN]);
    lo = gp_sub(lo, gp_v3(l, l, l));
    hi = gp_add(hi, gp_v3(l, l, l));
    /* - v T_P(0) - u T_Q(0), with T_P(0) = T_k(0), T_Q(0) = T_{k-1}(1) */
    gp_box_add_scaled(gp_get3(rk, GP_E_T0), GP_R(-1.0), &lo, &hi);
    gp_box_add_scaled(gp_get3(rm, GP_E_T1), GP_R(-1.0), &lo, &hi);
    /* twist term - (u v^2 a + u^2 v b) / (u + v), a = dT_k/dt(0), b = -dT_{k-1}/dt(1) */
    gp_box_add_scaled(gp_get3(rk, GP_E_DT0), GP_R(-0.5), &lo, &hi);
    gp_box_add_scaled(gp_get3(rm, GP_E_DT1), GP_R(0.5), &lo, &hi);
    blo = gp_vmin(blo, lo);
    bhi = gp_vmax(bhi, hi);
  }
  *lo = blo;
  *hi = bhi;
}
