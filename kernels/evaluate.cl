/* SPDX-License-Identifier: Apache-2.0 */
/* Batch evaluation: one work-item per query (face, xi, eta) -> gp_patch_eval.
 *
 * Compiled like construct.cl (see there). Matches host/patch_eval.cpp evaluatePatches:
 * a face index outside [0, #F) gives GP_ST_OUTSIDE and zeros; a face with n < 3 or
 * n > GP_MAX_N gives GP_ST_TOO_MANY_SIDES; otherwise status = eval bits | faceStatus[f]. */
#if GP_IS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#ifndef GP_EMBEDDED
#include "gp_patch.h"
#endif

/* numFaces: #F. numSlots: #C. mode: GP_CT_*. count: N queries.
 * faceOffsets: #F+1. edgeData: GP_E_NFIELDS*#C, field-major. faceStatus: #F.
 * qFace, qXi, qEta: N. out: 12*N, component-major: out[c * count + q] with c = 0..2 position,
 * 3..5 dG/dxi, 6..8 dG/deta, 9..11 unit normal. outStatus: N.
 * domainTable: GP_DOMAIN_FLAT_SIZE, the host's domain constants (gp_tables.h). */
__kernel void gp_evaluate(const int numFaces, const int numSlots, const int mode, const int count,
                          __global const int* faceOffsets, __global const GP_REAL* edgeData,
                          __global const uint* faceStatus, __global const int* qFace, __global const GP_REAL* qXi,
                          __global const GP_REAL* qEta, __global GP_REAL* out, __global uint* outStatus,
                          __global const GP_REAL* domainTable) {
  const int q = (int)get_global_id(0);
  if (q >= count) return;
  const int f = qFace[q];
  gp_eval_result r;
  r.pos = r.dxi = r.deta = r.normal = gp_zero3();
  if (f < 0 || f >= numFaces) {
    r.status = GP_ST_OUTSIDE;
  } else {
    const int first = faceOffsets[f], n = faceOffsets[f + 1] - first;
    if (n < 3 || n > GP_MAX_N) {
      r.status = GP_ST_TOO_MANY_SIDES;
    } else {
      GP_REAL recs[GP_MAX_N * GP_E_NFIELDS];
      for (int k = 0; k < n; ++k)
        for (int i = 0; i < GP_E_NFIELDS; ++i) recs[k * GP_E_NFIELDS + i] = edgeData[(size_t)i * numSlots + first + k];
      r = gp_patch_eval(n, recs, gp_eval_mode(mode, faceStatus[f]), qXi[q], qEta[q], domainTable);
      r.status |= faceStatus[f];
    }
  }
  const size_t m = (size_t)count;
  out[q] = r.pos.x;
  out[m + q] = r.pos.y;
  out[2 * m + q] = r.pos.z;
  out[3 * m + q] = r.dxi.x;
  out[4 * m + q] = r.dxi.y;
  out[5 * m + q] = r.dxi.z;
  out[6 * m + q] = r.deta.x;
  out[7 * m + q] = r.deta.y;
  out[8 * m + q] = r.deta.z;
  out[9 * m + q] = r.normal.x;
  out[10 * m + q] = r.normal.y;
  out[11 * m + q] = r.normal.z;
  outStatus[q] = r.status;
}
