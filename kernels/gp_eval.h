/* Domain, blending and evaluation of the n-sided Gregory patch (Eq. 1-5), with exact first
 * derivatives, and the per-patch quality measures (fold, bulge).
 * Part of gp_patch.h; no include guard on purpose. */

/* Domain corner C_k = (cos 2 pi k/n, sin 2 pi k/n) of the regular n-gon. */
GP_FN void gp_domain_corner(int n, int k, GP_REAL* xi, GP_REAL* eta) {
  const GP_REAL a = GP_R(2.0) * GP_R(3.14159265358979323846) * (GP_REAL)k / (GP_REAL)n;
  *xi = GP_COS(a);
  *eta = GP_SIN(a);
}

/* Fills d_k(X) = cos(pi/n) - X . m_k and the unit edge normals m_k (Eq. 3). Returns the
 * smallest d_k before clamping; d_k are clamped at 0 so that points on the boundary that
 * rounding put a hair outside evaluate as on it. */
GP_FN GP_REAL gp_domain_distances(int n, GP_REAL xi, GP_REAL eta, GP_REAL* d, GP_REAL* mx, GP_REAL* my) {
  const GP_REAL pin = GP_R(3.14159265358979323846) / (GP_REAL)n;
  const GP_REAL c = GP_COS(pin);
  GP_REAL dmin = GP_R(1.0);
  for (int k = 0; k < n; ++k) {
    const GP_REAL a = (GP_REAL)(2 * k + 1) * pin;
    mx[k] = GP_COS(a);
    my[k] = GP_SIN(a);
    d[k] = c - (xi * mx[k] + eta * my[k]);
    if (d[k] < dmin) dmin = d[k];
    if (d[k] < GP_R(0.0)) d[k] = GP_R(0.0);
  }
  return dmin;
}

/* Tolerance on d_k below zero for a point still counted as inside the domain. */
#undef GP_DOMAIN_TOL
#define GP_DOMAIN_TOL (GP_R(1024.0) * GP_EPS)

/* The result of one patch evaluation. */
typedef struct {
  gp_vec3 pos, dxi, deta, normal; /* G, dG/dxi, dG/deta, unit normal */
  gp_uint status;                 /* GP_ST_* bits */
} gp_eval_result;

/* Evaluates G(X) = sum_k w_k(X) r_k(u_k(X), v_k(X)) (Eq. 2-5) and its exact first
 * derivatives at X = (xi, eta) in the domain of an n-gon. recs: the patch's n edge records
 * (record-major, private memory). Points outside the domain return GP_ST_OUTSIDE and zeros. */
GP_FN gp_eval_result gp_patch_eval(int n, const GP_REAL* recs, int mode, GP_REAL xi, GP_REAL eta) {
  gp_eval_result out;
  out.pos = out.dxi = out.deta = out.normal = gp_zero3();
  out.status = 0u;
  if (n < 3 || n > GP_MAX_N) {
    out.status = GP_ST_TOO_MANY_SIDES;
    return out;
  }
  GP_REAL d[GP_MAX_N], mx[GP_MAX_N], my[GP_MAX_N];
  /* the domain lies in the unit disc; this also rejects NaN and Inf */
  if (!(GP_FABS(xi) <= GP_R(1.5) && GP_FABS(eta) <= GP_R(1.5)) ||
      gp_domain_distances(n, xi, eta, d, mx, my) < -GP_DOMAIN_TOL) {
    out.status = GP_ST_OUTSIDE;
    return out;
  }
  /* u_k = d_{k-1} / (d_{k-1} + d_{k+1}) is also 1 - v_{k+1}: one edge parameter t_k per edge
   * serves corners k and k+1. Gradients: grad d_j = -m_j. */
  GP_REAL t[GP_MAX_N], tx[GP_MAX_N], ty[GP_MAX_N];
  for (int k = 0; k < n; ++k) {
    const int km = (k + n - 1) % n, kp = (k + 1) % n;
    const GP_REAL den = d[km] + d[kp];
    if (den > GP_R(0.0)) {
      const GP_REAL id2 = GP_R(1.0) / (den * den);
      t[k] = d[km] / den;
      /* d(a/(a+b)) = (b da - a db) / (a+b)^2 */
      tx[k] = (d[kp] * -mx[km] - d[km] * -mx[kp]) * id2;
      ty[k] = (d[kp] * -my[km] - d[km] * -my[kp]) * id2;
    } else { /* only where both corners using this edge have zero weight */
      t[k] = tx[k] = ty[k] = GP_R(0.0);
    }
  }
  /* W_k = prod_{j != k-1, k} d_j^2 and its gradient; S = sum W (Eq. 5). */
  GP_REAL W[GP_MAX_N], Wx[GP_MAX_N], Wy[GP_MAX_N];
  GP_REAL S = GP_R(0.0), Sx = GP_R(0.0), Sy = GP_R(0.0);
  for (int k = 0; k < n; ++k) {
    GP_REAL w = GP_R(1.0), wx = GP_R(0.0), wy = GP_R(0.0);
    for (int i = 1; i <= n - 2; ++i) {
      const int j = (k + i) % n;
      const GP_REAL f = d[j] * d[j];
      wx = wx * f + w * GP_R(2.0) * d[j] * -mx[j];
      wy = wy * f + w * GP_R(2.0) * d[j] * -my[j];
      w = w * f;
    }
    W[k] = w;
    Wx[k] = wx;
    Wy[k] = wy;
    S += w;
    Sx += wx;
    Sy += wy;
  }
  /* Edge k at t_k: C, C', T, T' (needed when corner k or k+1 has weight). */
  gp_vec3 C[GP_MAX_N], Cd[GP_MAX_N], T[GP_MAX_N], Td[GP_MAX_N];
  for (int k = 0; k < n; ++k) {
    const int kp = (k + 1) % n;
    if (W[k] > GP_R(0.0) || W[kp] > GP_R(0.0)) {
      const GP_REAL* rec = recs + k * GP_E_NFIELDS;
      gp_dvec3 c, cp;
      gp_edge_curve(rec, t[k], &c, &cp);
      const gp_dvec3 nc = gp_edge_normal(rec, t[k], cp, &out.status);
      const gp_dvec3 tt = gp_cross_tangent(rec, t[k], mode, c, cp, nc, &out.status);
      C[k] = c.v;
      Cd[k] = c.d;
      T[k] = tt.v;
      Td[k] = tt.d;
    } else {
      C[k] = Cd[k] = T[k] = Td[k] = gp_zero3();
    }
  }
  const GP_REAL iS = GP_R(1.0) / S;
  gp_vec3 nfb = gp_zero3(); /* fallback normal: weighted vertex normals */
  for (int k = 0; k < n; ++k) {
    if (!(W[k] > GP_R(0.0))) continue;
    const int km = (k + n - 1) % n;
    const GP_REAL* rk = recs + k * GP_E_NFIELDS;
    const GP_REAL* rm = recs + km * GP_E_NFIELDS;
    /* corner interpolator r_k(u, v) (Eq. 2): P(u) = C_k(u), Q(v) = C_{k-1}(1 - v) */
    const GP_REAL u = t[k], v = GP_R(1.0) - t[km];
    const GP_REAL ux = tx[k], uy = ty[k], vx = -tx[km], vy = -ty[km];
    const gp_vec3 tp0 = gp_get3(rk, GP_E_T0), tq0 = gp_get3(rm, GP_E_T1);
    const gp_vec3 a = gp_get3(rk, GP_E_DT0);         /* T_P'(0) = dT_k/dt(0) */
    const gp_vec3 b = gp_neg(gp_get3(rm, GP_E_DT1)); /* T_Q'(0) = -dT_{k-1}/dt(1) */
    const gp_vec3 dTP = gp_sub(T[k], tp0), dTQ = gp_sub(T[km], tq0);
    gp_vec3 r = gp_sub(gp_add(C[k], C[km]), gp_get3(rk, GP_E_V0));
    r = gp_madd(gp_madd(r, dTP, v), dTQ, u);
    gp_vec3 ru = gp_madd(gp_add(Cd[k], dTQ), Td[k], v);    /* P' + v T_P' + (T_Q - T_Q(0)) */
    gp_vec3 rv = gp_madd(gp_sub(dTP, Cd[km]), Td[km], -u); /* Q' + (T_P - T_P(0)) + u T_Q' */
    const GP_REAL s = u + v;
    if (s > GP_R(0.0)) { /* - u v (v a + u b) / (u + v), and its partials */
      const GP_REAL is = GP_R(1.0) / s, is2 = is * is;
      r = gp_sub(r, gp_scale(gp_add(gp_scale(a, u * v * v), gp_scale(b, u * u * v)), is));
      ru = gp_sub(ru, gp_scale(gp_add(gp_scale(a, v * v * v), gp_scale(b, u * v * (u + GP_R(2.0) * v))), is2));
      rv = gp_sub(rv, gp_scale(gp_add(gp_scale(a, u * v * (GP_R(2.0) * u + v)), gp_scale(b, u * u * u)), is2));
    }
    const GP_REAL w = W[k] * iS;
    const GP_REAL wx = (Wx[k] - w * Sx) * iS, wy = (Wy[k] - w * Sy) * iS;
    out.pos = gp_madd(out.pos, r, w);
    out.dxi = gp_madd(gp_madd(out.dxi, r, wx), gp_add(gp_scale(ru, ux), gp_scale(rv, vx)), w);
    out.deta = gp_madd(gp_madd(out.deta, r, wy), gp_add(gp_scale(ru, uy), gp_scale(rv, vy)), w);
    nfb = gp_madd(nfb, gp_get3(rk, GP_E_N0), w);
  }
  const gp_vec3 nn = gp_cross(out.dxi, out.deta);
  /* rank-deficient Jacobian (e.g. at a 180-degree corner): the normal is noise, flag it */
  const GP_REAL jmax = gp_max(gp_len(out.dxi), gp_len(out.deta));
  const GP_REAL scale = jmax * jmax;
  gp_uint sst = 0u;
  out.normal =
      gp_unit_or(nn, gp_unit_or(nfb, gp_get3(recs, GP_E_N0), GP_TINY, &sst, 0u), GP_TINY * scale, &sst, GP_ST_SINGULAR);
  out.status |= sst;
  return out;
}

/* Quality of one built patch (design page, "Robustness"): fold = the patch normal opposite
 * to n_c at points 1e-3 inside an edge; bulge = the largest distance of sampled surface
 * points outside the face's bounding box over the face diameter. Returns GP_ST_FOLD and/or
 * GP_ST_BULGE (bulge > 0.5); the bulge value goes to *bulge. */
GP_FN gp_uint gp_patch_quality(int n, const GP_REAL* recs, int mode, GP_REAL* bulge) {
  gp_uint st = 0u;
  gp_vec3 lo = gp_get3(recs, GP_E_V0), hi = lo;
  GP_REAL diam = GP_R(0.0);
  for (int k = 0; k < n; ++k) {
    const gp_vec3 p = gp_get3(recs + k * GP_E_NFIELDS, GP_E_V0);
    lo = gp_v3(p.x < lo.x ? p.x : lo.x, p.y < lo.y ? p.y : lo.y, p.z < lo.z ? p.z : lo.z);
    hi = gp_v3(p.x > hi.x ? p.x : hi.x, p.y > hi.y ? p.y : hi.y, p.z > hi.z ? p.z : hi.z);
    for (int j = 0; j < k; ++j) diam = gp_max(diam, gp_len(gp_sub(p, gp_get3(recs + j * GP_E_NFIELDS, GP_E_V0))));
  }
  GP_REAL worst = GP_R(0.0);
  const GP_REAL inset = GP_R(1.0e-3);
  const int steps = 4;
  for (int k = 0; k < n; ++k) {
    GP_REAL ax, ay, bx, by;
    gp_domain_corner(n, k, &ax, &ay);
    gp_domain_corner(n, (k + 1) % n, &bx, &by);
    for (int i = 0; i <= steps; ++i) {
      for (int ring = 0; ring < 3; ++ring) {
        /* points on the segment from the centre towards the edge: near the edge and inside */
        const GP_REAL s = (GP_REAL)i / (GP_REAL)steps;
        const GP_REAL f = ring == 0 ? GP_R(1.0) - inset : (ring == 1 ? GP_R(0.66) : GP_R(0.33));
        const GP_REAL px = f * ((GP_R(1.0) - s) * ax + s * bx), py = f * ((GP_R(1.0) - s) * ay + s * by);
        const gp_eval_result g = gp_patch_eval(n, recs, mode, px, py);
        const gp_vec3 q = g.pos;
        GP_REAL out = GP_R(0.0);
        out = gp_max(out, gp_max(lo.x - q.x, q.x - hi.x));
        out = gp_max(out, gp_max(lo.y - q.y, q.y - hi.y));
        out = gp_max(out, gp_max(lo.z - q.z, q.z - hi.z));
        worst = gp_max(worst, out);
        if (ring == 0 && i > 0 && i < steps) {
          gp_dvec3 c, cp;
          gp_uint ignore = 0u;
          gp_edge_curve(recs + k * GP_E_NFIELDS, s, &c, &cp);
          const gp_dvec3 nc = gp_edge_normal(recs + k * GP_E_NFIELDS, s, cp, &ignore);
          if (gp_dot(nc.v, g.normal) < GP_R(0.0)) st |= GP_ST_FOLD;
        }
      }
    }
  }
  *bulge = diam > GP_R(0.0) ? worst / diam : GP_R(0.0);
  if (*bulge > GP_R(0.5)) st |= GP_ST_BULGE;
  return st;
}
