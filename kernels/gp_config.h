/* SPDX-License-Identifier: Apache-2.0 */
/* Target mapping for the single-source patch math (gp_patch.h).
 *
 * gp_patch.h is restricted C: it compiles as OpenCL C 1.2 (kernels) and as C++ (host),
 * in float and in double. The includer defines, before including gp_patch.h:
 *   GP_REAL       float or double
 *   GP_IS_DOUBLE  0 or 1
 * This file holds what does not depend on the precision: storage class, math functions,
 * status bits, record layout. Model: OpenSubdiv osd/patchBasisTypes.h.
 *
 * Floating-point contraction is OFF on both sides (FP_CONTRACT here for OpenCL,
 * -ffp-contract=off for the C++ build), so every backend rounds the same expressions
 * the same way. Division and sqrt are correctly rounded on both (OpenCL requires it in double;
 * float programs ask for it where the device offers it), and the device takes the domain's cos
 * and sin from the host's table (GP_DT_PARAM below) and the refinement's sin(angle tolerance)
 * from the host (kernels/refine.cl): no math-library call is left to round differently.
 */
#ifndef GP_CONFIG_H
#define GP_CONFIG_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define GP_OPENCL 1
#pragma OPENCL FP_CONTRACT OFF
#define GP_FN static inline
#define GP_FN_INLINE static inline
#define GP_UNROLL
#define GP_SQRT(x) sqrt(x)
#define GP_COS(x) cos(x)
#define GP_SIN(x) sin(x)
#define GP_FABS(x) fabs(x)
#define GP_ATAN2(y, x) atan2(y, x)
/* address space of the cache arrays that gp_refine.h reads while it iterates */
#define GP_GLOBAL __global
/* The domain's constants (cos and sin of multiples of pi/n; gp_tables.h) come from the host's
 * table, uploaded flat (GP_DOMAIN_FLAT_OFFSET), so that the device rounds them as the host
 * does rather than through its own cos and sin (OpenCL allows either 4 ulp off; measured: 1 ulp
 * off in 1,154 of 8,370 double constants on an NVIDIA H200, 684 on PoCL). The functions that
 * read them take the table as a trailing parameter, GP_DT_PARAM; GP_DT_ARG passes it on, and
 * GP_DT_M(m) passes a refinement mesh's. On the host all three are empty. */
#define GP_DT_PARAM , __global const GP_REAL* gp_dt
#define GP_DT_ARG , gp_dt
#define GP_DT_M(m) , (m)->domainTable
typedef uint gp_uint;
#else
#include <cmath>
#define GP_FN static inline
/* the edge functions of the evaluation: inlined into it, so that a position-only evaluation
 * (gp_patch_eval_dom_d, deriv 0) drops their derivative parts and lanes stay in registers */
#define GP_FN_INLINE static inline __attribute__((always_inline))
/* before a short loop over a polygon's edges: unrolled completely where the edge count is a
 * constant (gp_patch_eval_dom_n); not before loops with the edge functions inlined in them (a
 * copy of those per edge: code too large for the instruction cache). OpenCL leaves it to the
 * device compiler */
#define GP_UNROLL _Pragma("GCC unroll 8")
/* C++: overloadable names, so that a lane type (host/gp_lanes-inl.h) or a counting type (bench/)
 * can stand in for GP_REAL and bring its own sqrt, fabs, cos, sin, found by argument-dependent
 * lookup. For float and double they are std::sqrt etc. */
#define GP_SQRT(x) gp_sqrt(x)
#define GP_COS(x) gp_cos(x)
#define GP_SIN(x) gp_sin(x)
#define GP_FABS(x) gp_fabs(x)
#define GP_ATAN2(y, x) std::atan2(y, x)
#define GP_GLOBAL
#define GP_DT_PARAM
#define GP_DT_ARG
#define GP_DT_M(m)
typedef unsigned int gp_uint;
static inline float gp_sqrt(float x) { return std::sqrt(x); }
static inline double gp_sqrt(double x) { return std::sqrt(x); }
static inline float gp_fabs(float x) { return std::fabs(x); }
static inline double gp_fabs(double x) { return std::fabs(x); }
static inline float gp_cos(float x) { return std::cos(x); }
static inline double gp_cos(double x) { return std::cos(x); }
static inline float gp_sin(float x) { return std::sin(x); }
static inline double gp_sin(double x) { return std::sin(x); }
#endif

/* Largest polygon the fixed-size private arrays hold. */
#define GP_MAX_N 64

/* Cross-tangent construction (design page, "Robustness"). */
#define GP_CT_CORRECTED 0 /* default: guard + corner-compatibility correction */
#define GP_CT_PAPER 1     /* Eq. 11-14 as printed */
#define GP_CT_BLEND 2     /* q(t) = (1-t) d0 + t d1, projected */

/* The evaluation mode (the `mode` of gp_patch_eval and the functions that take one): the
 * cross-tangent mode in the low byte, and GP_EVAL_AFFINE for a face with GP_ST_AFFINE
 * (gp_eval_mode). The construction takes the cross-tangent mode alone. */
#define GP_CT_MASK 0xff
#define GP_EVAL_AFFINE 0x100

/* Status bits: per patch (construction) and per evaluation. */
#define GP_ST_GUARD 0x1u            /* a backward end tangent was replaced (guard 1) */
#define GP_ST_ZERO_EDGE 0x2u        /* an edge of (near) zero length */
#define GP_ST_EDGE_NORMAL 0x4u      /* n_c or an end tangent undefined; fallback used */
#define GP_ST_CROSS_TANGENT 0x8u    /* cross tangent undefined; fallback used */
#define GP_ST_FOLD 0x10u            /* patch normal opposite to n_c near an edge */
#define GP_ST_BULGE 0x20u           /* surface leaves the face box by > 0.5 face diameters */
#define GP_ST_OUTSIDE 0x40u         /* evaluation point outside the domain */
#define GP_ST_SINGULAR 0x80u        /* dG/dxi x dG/deta vanishes; normal is a fallback */
#define GP_ST_TOO_MANY_SIDES 0x100u /* n > GP_MAX_N or n < 3: not built */
#define GP_ST_NONFINITE 0x200u      /* non-finite input */
/* position, derivatives and normal from the refinement's quadratic model at this point, not
 * from an evaluation (gp_refine_options.modelFinal) */
#define GP_ST_MODEL_POINT 0x400u
/* construction: a flat triangle whose corner normals are all its plane's and whose edge curves
 * lie in it, built by the default construction (fold repair on) where its map is proven regular:
 * its patch is the affine map of the domain triangle plus each curved edge's deviation from its
 * chord (gp_patch_eval_affine3), which has the same boundary and tangent plane */
#define GP_ST_AFFINE 0x800u
/* the bits of a face that has no patch (not built: its records are zeros, not evaluable) */
#define GP_ST_NOT_BUILT (GP_ST_TOO_MANY_SIDES | GP_ST_NONFINITE)
#define GP_ST_DEGENERATE_MASK (GP_ST_ZERO_EDGE | GP_ST_EDGE_NORMAL | GP_ST_CROSS_TANGENT | GP_ST_NOT_BUILT)
/* an evaluation that is not a point of the patch with its normal: outside the domain, a fallback
 * normal, or no patch */
#define GP_ST_NOT_A_PATCH_POINT (GP_ST_OUTSIDE | GP_ST_SINGULAR | GP_ST_NOT_BUILT)

/* Refinement status bits (gp_refine.h); equal to the host's SF_TRACK_* (force_tracking.h),
 * above the GP_ST_* bits, which a refinement result carries too. */
#define GP_TRACK_CONVERGED 0x10000u  /* the angle tolerance was met */
#define GP_TRACK_MAX_ITER 0x20000u   /* the iteration limit was hit */
#define GP_TRACK_STALLED 0x40000u    /* the step shrank to nothing before the tolerance */
#define GP_TRACK_BOUNDARY 0x80000u   /* iterate held on a boundary / non-manifold edge */
#define GP_TRACK_DEGENERATE 0x100000u /* start patch not evaluable (or non-finite input) */
#define GP_TRACK_FOLD_EDGE 0x10000000u /* iterate held on a patch edge where the surface turns back (fold, valley crease) */

/* Per-edge record: everything evaluation needs about edge k of a face (edge V_k -> V_{k+1}).
 * Offsets of 3-vectors unless noted. Stored field-major in the cache (struct of arrays). */
#define GP_E_V0 0   /* V_k */
#define GP_E_V1 3   /* V_{k+1} */
#define GP_E_M0 6   /* L t_s: Hermite start tangent (Eq. 6-9, guarded) */
#define GP_E_M1 9   /* L t_e: Hermite end tangent */
#define GP_E_N0 12  /* N_k */
#define GP_E_N1 15  /* N_{k+1} */
#define GP_E_VP 18  /* V_{k-1} */
#define GP_E_VN 21  /* V_{k+2} */
#define GP_E_NP 24  /* N_{k-1} */
#define GP_E_NN 27  /* N_{k+2} */
#define GP_E_D0 30  /* d0: unit tangent of edge k-1 arriving at V_k, reversed */
#define GP_E_D1 33  /* d1: unit tangent of edge k+1 leaving V_{k+1} */
#define GP_E_P0 36  /* p(0): printed cross-tangent direction at t = 0 */
#define GP_E_P1 39  /* p(1) */
#define GP_E_T0 42  /* T_k(0) */
#define GP_E_T1 45  /* T_k(1) */
#define GP_E_DT0 48 /* dT_k/dt at 0 (twist source, exact) */
#define GP_E_DT1 51 /* dT_k/dt at 1 */
#define GP_E_LP 54  /* scalar: L_prev = |V_k - V_{k-1}| */
#define GP_E_LN 55  /* scalar: L_next = |V_{k+2} - V_{k+1}| */
#define GP_E_NFIELDS 56

#endif /* GP_CONFIG_H */
