/* SPDX-License-Identifier: Apache-2.0 */
/* The one prologue of a C++ instantiation of the single-source patch math: include it inside
 * the namespace that is to hold the instantiation (sf::gpd, a SIMD target's lanes, a counting
 * or an interval type). OpenCL needs none: it compiles gp_patch.h once per program, with
 * GP_REAL and GP_IS_DOUBLE given as build options. Model: OpenSubdiv osd/patchBasis.h.
 *
 * Define before including:
 *   GP_REAL          the real type: float, double, a SIMD lane, a counting or an interval type
 *   GP_IS_DOUBLE     1 when GP_REAL rounds as double, 0 as float (constants, tolerances)
 * and where wanted:
 *   GP_INST_FULL     1: also the patch's box and the nearest-point refinements (gp_bound.h,
 *                    gp_domain.h, gp_refine.h, gp_descent.h); else gp_patch.h alone
 *   GP_INST_TABLE    1: the domain reads the includer's table, a function of this namespace
 *                    `const gp_domain* gp_domain_table()` indexed by n (3..GP_MAX_N; gp_tables.h)
 *                    whose address and contents never change once it returns (it is declared
 *                    __attribute__((const)): the compiler may hoist it out of the domain loops)
 *   GP_LANES         1: GP_REAL holds lanes (gp_vec.h, "Lanes"), with GP_SREAL their scalar
 *                    real; the includer's namespace then provides the types gp_lane_mask (a
 *                    comparison of GP_REALs), gp_lane_status (status bits per lane) and
 *                    gp_lane_vid (a vertex id per lane) and the functions gp_sel(m, a, b),
 *                    gp_any(m), gp_all(m) (found by argument-dependent lookup or in scope)
 *   GP_INTERVAL      1: GP_REAL is an interval type (gp_eval.h's range-keeping forms)
 * Afterwards all of these are undefined again, and so are the lane macros (GP_SREAL, GP_MASK,
 * ... GP_ALL) that gp_vec.h gives a scalar instantiation: the next instantiation in the same
 * translation unit starts from nothing. No include guard on purpose. */

#ifdef GP_INST_TABLE
#define GP_DOMAIN_TABLE_DECLARE __attribute__((const)) const gp_domain* gp_domain_table()
#define GP_DOMAIN_TABLE(n) (gp_domain_table() + (n))
#endif
#ifdef GP_LANES
#define GP_MASK gp_lane_mask
#define GP_STATUS gp_lane_status
#define GP_VID gp_lane_vid
#define GP_SEL(m, a, b) gp_sel(m, a, b)
#define GP_ANY(m) gp_any(m)
#define GP_ALL(m) gp_all(m)
#endif

/* order matters: each part uses the ones before it */
// clang-format off
#include "gp_patch.h"
#ifdef GP_INST_FULL
#include "gp_bound.h"
#include "gp_domain.h"
#include "gp_refine.h"
#include "gp_descent.h"
#endif
// clang-format on

#undef GP_REAL
#undef GP_IS_DOUBLE
#undef GP_INST_FULL
#undef GP_INST_TABLE
#undef GP_DOMAIN_TABLE_DECLARE
#undef GP_DOMAIN_TABLE
#undef GP_LANES
#undef GP_INTERVAL
#undef GP_SREAL
#undef GP_MASK
#undef GP_STATUS
#undef GP_VID
#undef GP_SEL
#undef GP_ANY
#undef GP_ALL
