/* SPDX-License-Identifier: Apache-2.0 */
/* Geometry of the regular n-gon domain (design page, "Domain and blending"; Eq. 3) as the
 * nearest-point refinement uses it: edge normals, the inside test, the first edge a segment
 * leaves through, and the position along a domain edge that Eq. 15 carries across.
 * Part of the single-source patch math; include after gp_eval.h (gp_domain_corner). No
 * include guard on purpose (one copy per precision). */

/* cos(pi/n): the distance from the centre to every domain edge. Unit outward normal
 * m_k = (cos (2k+1) pi/n, sin (2k+1) pi/n) of domain edge k (C_k -> C_{k+1}). On the host both
 * come from the domain table (gp_tables.h: the same formulas, evaluated once; OpenCL reads the
 * host's, GP_DT_PARAM). */
#if defined(GP_DOMAIN_TABLE)
GP_FN GP_REAL gp_dom_apothem(int n) { return GP_DOMAIN_TABLE(n)->apothem; }
GP_FN void gp_dom_normal(int n, int k, GP_REAL* mx, GP_REAL* my) {
  *mx = GP_DOMAIN_TABLE(n)->mx[k];
  *my = GP_DOMAIN_TABLE(n)->my[k];
}
#elif defined(GP_OPENCL)
GP_FN GP_REAL gp_dom_apothem(int n GP_DT_PARAM) { return gp_dt[GP_DOMAIN_FLAT_OFFSET(n)]; }
GP_FN void gp_dom_normal(int n, int k, GP_REAL* mx, GP_REAL* my GP_DT_PARAM) {
  *mx = gp_dt[GP_DOMAIN_FLAT_OFFSET(n) + 1 + 4 * k];
  *my = gp_dt[GP_DOMAIN_FLAT_OFFSET(n) + 2 + 4 * k];
}
#else
GP_FN GP_REAL gp_dom_apothem(int n) { return gp_domain_calc_apothem(n); }
GP_FN void gp_dom_normal(int n, int k, GP_REAL* mx, GP_REAL* my) { gp_domain_calc_normal(n, k, mx, my); }
#endif

/* max_k X . m_k and its edge k: X is inside the domain iff this is <= cos(pi/n). */
GP_FN GP_REAL gp_dom_edge_max(int n, GP_REAL x, GP_REAL y, int* k GP_DT_PARAM) {
  GP_REAL best = -GP_BIG;
  *k = 0;
  for (int j = 0; j < n; ++j) {
    GP_REAL mx, my;
    gp_dom_normal(n, j, &mx, &my GP_DT_ARG);
    const GP_REAL v = x * mx + y * my;
    if (v > best) {
      best = v;
      *k = j;
    }
  }
  return best;
}

GP_FN int gp_dom_inside(int n, GP_REAL x, GP_REAL y GP_DT_PARAM) {
  int k;
  return gp_dom_edge_max(n, x, y, &k GP_DT_ARG) <= gp_dom_apothem(n GP_DT_ARG);
}

/* Scales a point outside the domain back onto its boundary along the ray from the origin. */
GP_FN void gp_dom_clamp(int n, GP_REAL* x, GP_REAL* y GP_DT_PARAM) {
  int k;
  const GP_REAL mx = gp_dom_edge_max(n, *x, *y, &k GP_DT_ARG), c = gp_dom_apothem(n GP_DT_ARG);
  if (mx > c) {
    *x = *x * (c / mx);
    *y = *y * (c / mx);
  }
}

/* The segment X + tau d (tau in [0, 1]) from X in the domain: returns the smallest tau at which
 * it reaches a domain edge it moves out through, and that edge in *k; 1 + (something) when it
 * stays inside (returns a value > 1, *k = -1). A point on edge k moving outward gives 0. */
GP_FN GP_REAL gp_dom_exit(int n, GP_REAL x, GP_REAL y, GP_REAL dx, GP_REAL dy, int* k GP_DT_PARAM) {
  const GP_REAL c = gp_dom_apothem(n GP_DT_ARG);
  GP_REAL best = GP_R(2.0);
  *k = -1;
  for (int j = 0; j < n; ++j) {
    GP_REAL mx, my;
    gp_dom_normal(n, j, &mx, &my GP_DT_ARG);
    const GP_REAL out = dx * mx + dy * my; /* speed towards edge j's line */
    if (!(out > GP_R(0.0))) continue;
    GP_REAL tau = (c - (x * mx + y * my)) / out;
    if (tau < GP_R(0.0)) tau = GP_R(0.0);
    if (tau < best) {
      best = tau;
      *k = j;
    }
  }
  return best;
}

/* Position of X along domain edge k as a fraction from C_k (0) to C_{k+1} (1), clamped. On the
 * edge this is the edge curve's parameter t (u_k = d_{k-1} / (d_{k-1} + d_{k+1}) is linear
 * along a side of the regular polygon), so Eq. 15's I1 = C_i + (1 - t) (C_{i+1} - C_i) on the
 * neighbour is the same surface point. */
GP_FN GP_REAL gp_dom_edge_param(int n, int k, GP_REAL x, GP_REAL y GP_DT_PARAM) {
  GP_REAL ax, ay, bx, by;
  gp_domain_corner(n, k, &ax, &ay GP_DT_ARG);
  gp_domain_corner(n, (k + 1) % n, &bx, &by GP_DT_ARG);
  const GP_REAL ex = bx - ax, ey = by - ay;
  GP_REAL t = ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey);
  return t < GP_R(0.0) ? GP_R(0.0) : (t > GP_R(1.0) ? GP_R(1.0) : t);
}

/* The point at fraction t from C_k to C_{k+1} on domain edge k. */
GP_FN void gp_dom_edge_point(int n, int k, GP_REAL t, GP_REAL* x, GP_REAL* y GP_DT_PARAM) {
  GP_REAL ax, ay, bx, by;
  gp_domain_corner(n, k, &ax, &ay GP_DT_ARG);
  gp_domain_corner(n, (k + 1) % n, &bx, &by GP_DT_ARG);
  *x = ax + t * (bx - ax);
  *y = ay + t * (by - ay);
}

/* Moves X a hair towards the centre when it lies on (or within 1e-9 of) a domain corner: at a
 * vertex of the mesh the step's exit edge is ambiguous and the patch's Jacobian is degenerate. */
GP_FN void gp_dom_off_corner(int n, GP_REAL* x, GP_REAL* y) {
  const GP_REAL r2 = *x * *x + *y * *y;
  if (r2 < GP_R(1.0) - GP_R(2.0e-9)) return; /* the corners are the points of the unit circle */
  const GP_REAL s = GP_R(1.0) - GP_R(1.0e-6);
  *x = *x * s;
  *y = *y * s;
  (void)n;
}

/* Moves X inward so that an eps-disc around it fits in the domain (for finite differences). */
GP_FN void gp_dom_interior(int n, GP_REAL* x, GP_REAL* y, GP_REAL eps GP_DT_PARAM) {
  int k;
  const GP_REAL dmin = gp_dom_apothem(n GP_DT_ARG) - gp_dom_edge_max(n, *x, *y, &k GP_DT_ARG);
  if (dmin > GP_R(2.0) * eps) return;
  const GP_REAL r = GP_SQRT(*x * *x + *y * *y); /* >= cos(pi/n) - 2 eps > 0.4 near the boundary */
  const GP_REAL s = GP_R(1.0) - GP_R(3.0) * eps / r;
  *x = *x * s;
  *y = *y * s;
}
