/* SPDX-License-Identifier: Apache-2.0 */
/* The closest point of a triangle to a point, in double: the exact distance that the patch
 * surface's candidate search computes for each tessellation triangle it visits, on the host
 * (host/query/patch_surface.cpp) and on an OpenCL device (kernels/candidates.cl). One definition,
 * so that both round every operation alike (contraction off, gp_config.h) and find the same
 * candidates. Ericson, Real-Time Collision Detection (2005), section 5.1.5.
 *
 * Always double: an OpenCL program that includes it enables cl_khr_fp64. */
#ifndef GP_CLOSEST_H
#define GP_CLOSEST_H

#include "gp_config.h"

/* x . y of two 3-vectors, summed left to right */
GP_FN double gp_cl_dot3(const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

/* Sets (u, v, w) and returns |u a + v b + w c - p|^2. */
GP_FN double gp_cl_at(const double* p, const double* a, const double* b, const double* c, double uu, double vv,
                      double ww, double* u, double* v, double* w) {
  double s = 0;
  int k;
  *u = uu;
  *v = vv;
  *w = ww;
  for (k = 0; k < 3; ++k) {
    const double x = uu * a[k] + vv * b[k] + ww * c[k] - p[k];
    s = k == 0 ? x * x : s + x * x;
  }
  return s;
}

/* Closest point of triangle abc (3-vectors, m) to p: returns the squared distance (m^2) and the
 * barycentric weights (u, v, w) of the closest point u a + v b + w c. A degenerate triangle gives
 * the closest point of its edges or corners; non-finite input gives non-finite output. */
GP_FN double gp_closest_on_triangle(const double* p, const double* a, const double* b, const double* c, double* u,
                                    double* v, double* w) {
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  double d1, d2, d3, d4, d5, d6, vc, vb, va, t, denom, vv, ww;
  int k;
  for (k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
  }
  d1 = gp_cl_dot3(ab, ap);
  d2 = gp_cl_dot3(ac, ap);
  if (d1 <= 0 && d2 <= 0) return gp_cl_at(p, a, b, c, 1, 0, 0, u, v, w);
  for (k = 0; k < 3; ++k) bp[k] = p[k] - b[k];
  d3 = gp_cl_dot3(ab, bp);
  d4 = gp_cl_dot3(ac, bp);
  if (d3 >= 0 && d4 <= d3) return gp_cl_at(p, a, b, c, 0, 1, 0, u, v, w);
  vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    t = d1 / (d1 - d3);
    return gp_cl_at(p, a, b, c, 1 - t, t, 0, u, v, w);
  }
  for (k = 0; k < 3; ++k) cp[k] = p[k] - c[k];
  d5 = gp_cl_dot3(ab, cp);
  d6 = gp_cl_dot3(ac, cp);
  if (d6 >= 0 && d5 <= d6) return gp_cl_at(p, a, b, c, 0, 0, 1, u, v, w);
  vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    t = d2 / (d2 - d6);
    return gp_cl_at(p, a, b, c, 1 - t, 0, t, u, v, w);
  }
  va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return gp_cl_at(p, a, b, c, 0, 1 - t, t, u, v, w);
  }
  denom = 1 / (va + vb + vc);
  vv = vb * denom;
  ww = vc * denom;
  return gp_cl_at(p, a, b, c, 1 - vv - ww, vv, ww, u, v, w);
}

#endif /* GP_CLOSEST_H */
