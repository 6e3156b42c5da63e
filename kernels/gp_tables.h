/* SPDX-License-Identifier: Apache-2.0 */
/* The domain of an n-sided patch as data (design page, "Domain and blending"; Eq. 3): the
 * regular n-gon's corners C_k = (cos 2 pi k/n, sin 2 pi k/n), its unit edge normals
 * m_k = (cos (2k+1) pi/n, sin (2k+1) pi/n) and cos(pi/n), the distance from its centre to
 * every edge. Evaluation reads them from a gp_domain instead of calling cos/sin per point.
 *
 * Where they come from: the gp_domain_calc_* functions below are the one formula. The C++
 * host fills a table for n = 3..GP_MAX_N with them once, at first use (host/gp_tables.cpp),
 * and defines GP_DOMAIN_TABLE(n) to its entry (and GP_DOMAIN_TABLE_DECLARE to a declaration
 * of what that uses, placed after the gp_domain type). OpenCL reads the same values from the
 * host's table, uploaded flat (GP_DOMAIN_FLAT_OFFSET) and passed as the trailing parameter
 * GP_DT_PARAM (gp_config.h): the device's own cos and sin round differently. A C++ includer
 * without a table computes them where they are used.
 * Part of the single-source patch math (after gp_vec.h); no include guard on purpose. */

#ifndef GP_DOMAIN_FLAT_OFFSET
/* The flat domain table: for n = 3..GP_MAX_N, from GP_DOMAIN_FLAT_OFFSET(n) on, cos(pi/n) and
 * then (m_k.x, m_k.y, C_k.x, C_k.y) for k = 0..n-1; 4n + 1 numbers per n, GP_DOMAIN_FLAT_SIZE in
 * all. */
#define GP_DOMAIN_FLAT_OFFSET(n) (2 * (n) * (n) - (n) - 15)
#define GP_DOMAIN_FLAT_SIZE GP_DOMAIN_FLAT_OFFSET(GP_MAX_N + 1)
#endif

#ifndef GP_LANES
/* Domain of the regular n-gon, 3 <= n <= GP_MAX_N. Arrays: n entries used. */
typedef struct {
  int n;
  GP_REAL apothem;                    /* cos(pi/n) */
  GP_REAL mx[GP_MAX_N], my[GP_MAX_N]; /* unit outward normal m_k of edge C_k -> C_{k+1} */
  GP_REAL cx[GP_MAX_N], cy[GP_MAX_N]; /* corner C_k */
} gp_domain;

#ifdef GP_DOMAIN_TABLE_DECLARE
GP_DOMAIN_TABLE_DECLARE; /* the includer's table (see GP_DOMAIN_TABLE) */
#endif

/* cos(pi/n) */
GP_FN GP_REAL gp_domain_calc_apothem(int n) { return GP_COS(GP_R(3.14159265358979323846) / (GP_REAL)n); }
/* m_k */
GP_FN void gp_domain_calc_normal(int n, int k, GP_REAL* mx, GP_REAL* my) {
  const GP_REAL a = (GP_REAL)(2 * k + 1) * (GP_R(3.14159265358979323846) / (GP_REAL)n);
  *mx = GP_COS(a);
  *my = GP_SIN(a);
}
/* C_k */
GP_FN void gp_domain_calc_corner(int n, int k, GP_REAL* cx, GP_REAL* cy) {
  const GP_REAL a = GP_R(2.0) * GP_R(3.14159265358979323846) * (GP_REAL)k / (GP_REAL)n;
  *cx = GP_COS(a);
  *cy = GP_SIN(a);
}

/* Fills d for n sides (3 <= n <= GP_MAX_N); the corners only when `corners` is set. */
GP_FN void gp_domain_init(int n, gp_domain* d, int corners) {
  d->n = n;
  d->apothem = gp_domain_calc_apothem(n);
  for (int k = 0; k < n; ++k) {
    gp_domain_calc_normal(n, k, &d->mx[k], &d->my[k]);
    if (corners) gp_domain_calc_corner(n, k, &d->cx[k], &d->cy[k]);
  }
}

/* The domain of the n-gon: the host's table entry, or (OpenCL: from the flat table; a C++
 * includer without a table: computed) copied into *scratch, its corners only when `corners` is
 * set. */
GP_FN const gp_domain* gp_domain_of(int n, gp_domain* scratch, int corners GP_DT_PARAM) {
#if defined(GP_DOMAIN_TABLE)
  (void)scratch;
  (void)corners;
  return GP_DOMAIN_TABLE(n);
#elif defined(GP_OPENCL)
  GP_GLOBAL const GP_REAL* t = gp_dt + GP_DOMAIN_FLAT_OFFSET(n);
  scratch->n = n;
  scratch->apothem = t[0];
  for (int k = 0; k < n; ++k) {
    scratch->mx[k] = t[1 + 4 * k];
    scratch->my[k] = t[2 + 4 * k];
    if (corners) {
      scratch->cx[k] = t[3 + 4 * k];
      scratch->cy[k] = t[4 + 4 * k];
    }
  }
  return scratch;
#else
  gp_domain_init(n, scratch, corners);
  return scratch;
#endif
}

/* Domain corner C_k = (cos 2 pi k/n, sin 2 pi k/n) of the regular n-gon. */
GP_FN void gp_domain_corner(int n, int k, GP_REAL* xi, GP_REAL* eta GP_DT_PARAM) {
#if defined(GP_DOMAIN_TABLE)
  *xi = GP_DOMAIN_TABLE(n)->cx[k];
  *eta = GP_DOMAIN_TABLE(n)->cy[k];
#elif defined(GP_OPENCL)
  *xi = gp_dt[GP_DOMAIN_FLAT_OFFSET(n) + 3 + 4 * k];
  *eta = gp_dt[GP_DOMAIN_FLAT_OFFSET(n) + 4 + 4 * k];
#else
  gp_domain_calc_corner(n, k, xi, eta);
#endif
}
#endif /* GP_LANES: lane instantiations use the scalar gp_domain of their precision (gp_lanes-inl.h) */
