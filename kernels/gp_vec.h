/* SPDX-License-Identifier: Apache-2.0 */
/* 3-vectors and forward-mode dual numbers (value + derivative) in restricted C.
 * Part of the single-source patch math; included once per precision by gp_patch.h
 * (no include guard on purpose). Requires GP_REAL and GP_IS_DOUBLE.
 *
 * Lanes. The math is written without branches on per-point data, so that GP_REAL may also be
 * a SIMD lane type (one point, or one face, per lane; host/patch/gp_lanes-inl.h): a condition on
 * data is a GP_MASK, a choice is GP_SEL(mask, a, b) (both sides computed), status bits are set
 * with GP_BITS(mask, bits). Branches on uniform values (n, k, mode) stay ordinary C. With
 * GP_LANES, the macros below come from the includer's lane types (gp_instantiate.h); otherwise
 * they are the scalar ones:
 *   GP_SREAL           the scalar real of the lanes (tables, uniform constants)
 *   GP_MASK            the type of a comparison of GP_REALs; &&, ||, ! combine masks
 *   GP_STATUS          status bits per lane (gp_uint for scalars)
 *   GP_VID             a vertex id per lane (int for scalars); <= gives a GP_MASK
 *   GP_SEL(m, a, b)    per lane: m ? a : b, for GP_REAL and GP_STATUS
 *   GP_ANY(m), GP_ALL(m)  uniform: some lane / every lane of m is set (skips rare work)
 * Every lane computes exactly the operations a scalar evaluation of its point computes, so
 * a lane result is bit-identical to the scalar result (contraction is off everywhere). */

/* (a C++ instantiation undefines them again when it ends: gp_instantiate.h) */
#ifndef GP_LANES
#define GP_SREAL GP_REAL
#define GP_MASK int
#define GP_STATUS gp_uint
#define GP_VID int
#define GP_SEL(m, a, b) ((m) ? (a) : (b))
#define GP_ANY(m) (m)
#define GP_ALL(m) (m)
#endif
/* bits where m holds, else none */
#undef GP_BITS
#define GP_BITS(m, bits) GP_SEL(m, (GP_STATUS)(bits), (GP_STATUS)0u)

#undef GP_R
#undef GP_EPS
#undef GP_BIG
#if GP_IS_DOUBLE
#define GP_R(x) ((GP_REAL)(x))
#define GP_EPS ((GP_REAL)2.220446049250313e-16)
#define GP_BIG GP_R(1.0e300)
#else
#ifdef GP_OPENCL
#define GP_R(x) (x##f)
#else
#define GP_R(x) ((GP_REAL)(x))
#endif
#define GP_EPS GP_R(1.1920929e-7)
#define GP_BIG GP_R(1.0e37)
#endif
/* Relative size below which a vector counts as zero when normalising. */
#undef GP_TINY
#define GP_TINY (GP_R(64.0) * GP_EPS)

typedef struct {
  GP_REAL x, y, z;
} gp_vec3;
/* A vector-valued function of one parameter at a point: value v and derivative d. */
typedef struct {
  gp_vec3 v, d;
} gp_dvec3;
typedef struct {
  GP_REAL v, d;
} gp_dreal;

GP_FN gp_vec3 gp_v3(GP_REAL x, GP_REAL y, GP_REAL z) {
  gp_vec3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
GP_FN gp_vec3 gp_zero3(void) { return gp_v3(GP_R(0.0), GP_R(0.0), GP_R(0.0)); }
GP_FN gp_vec3 gp_add(gp_vec3 a, gp_vec3 b) { return gp_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
GP_FN gp_vec3 gp_sub(gp_vec3 a, gp_vec3 b) { return gp_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
GP_FN gp_vec3 gp_scale(gp_vec3 a, GP_REAL s) { return gp_v3(a.x * s, a.y * s, a.z * s); }
GP_FN gp_vec3 gp_neg(gp_vec3 a) { return gp_v3(-a.x, -a.y, -a.z); }
GP_FN GP_REAL gp_dot(gp_vec3 a, gp_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
GP_FN gp_vec3 gp_cross(gp_vec3 a, gp_vec3 b) {
  return gp_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
GP_FN GP_REAL gp_len(gp_vec3 a) { return GP_SQRT(gp_dot(a, a)); }
/* a + s b */
GP_FN gp_vec3 gp_madd(gp_vec3 a, gp_vec3 b, GP_REAL s) { return gp_v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
/* (1-t) a + t b */
GP_FN gp_vec3 gp_lerp(gp_vec3 a, gp_vec3 b, GP_REAL t) {
  const GP_REAL s = GP_R(1.0) - t;
  return gp_v3(s * a.x + t * b.x, s * a.y + t * b.y, s * a.z + t * b.z);
}
/* a > b ? a : b (a NaN b gives b), a < b ? a : b */
GP_FN GP_REAL gp_max(GP_REAL a, GP_REAL b) { return GP_SEL(a > b, a, b); }
GP_FN GP_REAL gp_min(GP_REAL a, GP_REAL b) { return GP_SEL(a < b, a, b); }
/* per lane m ? a : b */
GP_FN gp_vec3 gp_sel3(GP_MASK m, gp_vec3 a, gp_vec3 b) {
  return gp_v3(GP_SEL(m, a.x, b.x), GP_SEL(m, a.y, b.y), GP_SEL(m, a.z, b.z));
}
GP_FN GP_MASK gp_finite3(gp_vec3 a) {
  /* NaN fails every comparison; Inf exceeds the largest finite value. */
  return GP_FABS(a.x) <= GP_BIG && GP_FABS(a.y) <= GP_BIG && GP_FABS(a.z) <= GP_BIG;
}

/* unit(a), or `fallback` with `bit` set in *st when |a| <= tiny. */
GP_FN gp_vec3 gp_unit_or(gp_vec3 a, gp_vec3 fallback, GP_REAL tiny, GP_STATUS* st, GP_STATUS bit) {
  const GP_REAL l = gp_len(a);
  const GP_MASK ok = l > tiny;
  *st |= GP_SEL(ok, (GP_STATUS)0u, bit);
  return gp_sel3(ok, gp_scale(a, GP_R(1.0) / l), fallback);
}

/* Reads the 3-vector at field offset `off` of a record. */
GP_FN gp_vec3 gp_get3(const GP_REAL* rec, int off) { return gp_v3(rec[off], rec[off + 1], rec[off + 2]); }
GP_FN void gp_put3(GP_REAL* rec, int off, gp_vec3 a) {
  rec[off] = a.x;
  rec[off + 1] = a.y;
  rec[off + 2] = a.z;
}

/* ---- dual numbers: exact first derivatives by forward-mode differentiation ---- */
GP_FN gp_dvec3 gp_dv(gp_vec3 v, gp_vec3 d) {
  gp_dvec3 r;
  r.v = v;
  r.d = d;
  return r;
}
GP_FN gp_dreal gp_dr(GP_REAL v, GP_REAL d) {
  gp_dreal r;
  r.v = v;
  r.d = d;
  return r;
}
GP_FN gp_dvec3 gp_dsel(GP_MASK m, gp_dvec3 a, gp_dvec3 b) { return gp_dv(gp_sel3(m, a.v, b.v), gp_sel3(m, a.d, b.d)); }
GP_FN gp_dvec3 gp_dadd(gp_dvec3 a, gp_dvec3 b) { return gp_dv(gp_add(a.v, b.v), gp_add(a.d, b.d)); }
GP_FN gp_dvec3 gp_dsub(gp_dvec3 a, gp_dvec3 b) { return gp_dv(gp_sub(a.v, b.v), gp_sub(a.d, b.d)); }
GP_FN gp_dvec3 gp_dneg(gp_dvec3 a) { return gp_dv(gp_neg(a.v), gp_neg(a.d)); }
GP_FN gp_dvec3 gp_dscale(gp_dvec3 a, GP_REAL s) { return gp_dv(gp_scale(a.v, s), gp_scale(a.d, s)); }
/* s a for a dual scalar s */
GP_FN gp_dvec3 gp_dmul(gp_dreal s, gp_dvec3 a) {
  return gp_dv(gp_scale(a.v, s.v), gp_add(gp_scale(a.v, s.d), gp_scale(a.d, s.v)));
}
GP_FN gp_dreal gp_ddot(gp_dvec3 a, gp_dvec3 b) { return gp_dr(gp_dot(a.v, b.v), gp_dot(a.d, b.v) + gp_dot(a.v, b.d)); }
GP_FN gp_dvec3 gp_dcross(gp_dvec3 a, gp_dvec3 b) {
  return gp_dv(gp_cross(a.v, b.v), gp_add(gp_cross(a.d, b.v), gp_cross(a.v, b.d)));
}
/* (1-t) a + t b for constant a, b: derivative b - a. */
GP_FN gp_dvec3 gp_dlerp(gp_vec3 a, gp_vec3 b, GP_REAL t) { return gp_dv(gp_lerp(a, b, t), gp_sub(b, a)); }
/* unit(a) with derivative (a' - u (u.a')) / |a|, given l = |a.v| (lanes with l = 0 get
 * non-finite values: the caller selects them away). */
GP_FN gp_dvec3 gp_dunit_len(gp_dvec3 a, GP_REAL l) {
  const GP_REAL il = GP_R(1.0) / l;
  const gp_vec3 u = gp_scale(a.v, il);
  return gp_dv(u, gp_scale(gp_madd(a.d, u, -gp_dot(u, a.d)), il));
}
/* unit(a) with derivative, or the fallback (bit set) when |a| <= tiny. */
GP_FN gp_dvec3 gp_dunit_or(gp_dvec3 a, gp_dvec3 fallback, GP_REAL tiny, GP_STATUS* st, GP_STATUS bit) {
  const GP_REAL l = gp_len(a.v);
  const GP_MASK ok = l > tiny;
  *st |= GP_SEL(ok, (GP_STATUS)0u, bit);
  return gp_dsel(ok, gp_dunit_len(a, l), fallback);
}
