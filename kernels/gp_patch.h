/* SPDX-License-Identifier: Apache-2.0 */
/* The n-sided Gregory patch: the one definition of the patch math.
 *
 * Restricted C that compiles as OpenCL C 1.2 and as C++, in float and in double.
 * The includer defines GP_REAL (float|double) and GP_IS_DOUBLE (0|1) first; C++ includes it
 * once per precision inside a namespace through gp_instantiate.h, OpenCL once per program build.
 * No include guard on purpose. Source: Wu, Leung, Wang, Wang, Zhang, "Smooth Force Rendering
 * on Coarse Polygonal Meshes" (Sections 2.2, 3), with shared/design/gregory-patch.md.
 *
 * Shared functions work on private memory only; kernels (kernels/NAME.cl) and host code do
 * the loads and stores of the cache arrays.
 */
/* order matters: each part uses the ones before it */
// clang-format off
#include "gp_config.h"
#include "gp_vec.h"
#include "gp_tables.h"
#include "gp_edge.h"
#include "gp_eval.h"
// clang-format on
