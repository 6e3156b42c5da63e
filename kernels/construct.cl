/* SPDX-License-Identifier: Apache-2.0 */
/* Patch construction: one work-item per face (gp_build_patch + gp_patch_quality).
 *
 * The host compiles: defines (GP_REAL, GP_IS_DOUBLE, GP_EMBEDDED) + gp_config.h, gp_vec.h,
 * gp_edge.h, gp_eval.h + this file (host/opencl_backend.cpp). Standalone (clang syntax
 * check, -I kernels) the include below pulls in the same headers.
 * Fills exactly what host/patch_build.cpp fills: records field-major
 * edgeData[i * numSlots + slot], faceStatus[f], faceBulge[f]. */
#if GP_IS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#ifndef GP_EMBEDDED
#include "gp_patch.h"
#endif

/* numFaces: #F. numSlots: #C. mode: GP_CT_*.
 * positions: #V*3, cornerNormals: #C*3 (unit), faceOffsets: #F+1, faceVertices: #C.
 * across: #C*2, for slot c (edge k of its face): the corners of the face across the edge at V_k
 * and V_{k+1} (the face's own corners without a neighbour; host acrossCorners). A face whose
 * normals differ from the face across somewhere has a crease (gp_build_patch_with, creased).
 * edgeData: GP_E_NFIELDS*#C (out), faceStatus, faceBulge: #F (out).
 * domainTable: GP_DOMAIN_FLAT_SIZE, the host's domain constants (gp_tables.h).
 * tangents: #C*6 where hasTangents (else unread): for slot c the unit directions of C'(0) and
 * C'(1) the fold repair gives (host tangent_fans.h), zeros where the construction's own stay. */
__kernel void gp_construct(const int numFaces, const int numSlots, const int mode, __global const GP_REAL* positions,
                           __global const GP_REAL* cornerNormals, __global const int* faceOffsets,
                           __global const int* faceVertices, __global const int* across, __global GP_REAL* edgeData, __global uint* faceStatus,
                           __global float* faceBulge, __global const GP_REAL* domainTable,
                           __global const GP_REAL* tangents, const int hasTangents) {
  const int f = (int)get_global_id(0);
  if (f >= numFaces) return;
  const int first = faceOffsets[f], n = faceOffsets[f + 1] - first;
  if (n < 3 || n > GP_MAX_N) {
    /* not built: records stay zero, as in a freshly prepared cache */
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < GP_E_NFIELDS; ++i) edgeData[(size_t)i * numSlots + first + k] = GP_R(0.0);
    faceStatus[f] = GP_ST_TOO_MANY_SIDES;
    faceBulge[f] = 0.0f;
    return;
  }
  gp_vec3 V[GP_MAX_N], N[GP_MAX_N];
  int vid[GP_MAX_N];
  GP_REAL recs[GP_MAX_N * GP_E_NFIELDS];
  for (int k = 0; k < n; ++k) {
    const int v = faceVertices[first + k];
    const int c = first + k;
    vid[k] = v;
    V[k] = gp_v3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    N[k] = gp_v3(cornerNormals[3 * c], cornerNormals[3 * c + 1], cornerNormals[3 * c + 2]);
  }
  gp_vec3 PS[GP_MAX_N], PE[GP_MAX_N];
  int creased = 0;
  for (int k = 0; k < n; ++k) {
    const int a = across[2 * (first + k)], b = across[2 * (first + k) + 1];
    PS[k] = gp_v3(cornerNormals[3 * a], cornerNormals[3 * a + 1], cornerNormals[3 * a + 2]);
    PE[k] = gp_v3(cornerNormals[3 * b], cornerNormals[3 * b + 1], cornerNormals[3 * b + 2]);
    const int k1 = k + 1 == n ? 0 : k + 1;
    creased |= gp_differs3(PS[k], N[k]) || gp_differs3(PE[k], N[k1]);
  }
  gp_vec3 TS[GP_MAX_N], TE[GP_MAX_N];
  int turned = 0;
  for (int k = 0; k < n && hasTangents; ++k) {
    __global const GP_REAL* t = tangents + 6 * (size_t)(first + k);
    TS[k] = gp_v3(t[0], t[1], t[2]);
    TE[k] = gp_v3(t[3], t[4], t[5]);
    turned |= gp_dot(TS[k], TS[k]) > GP_R(0.0) || gp_dot(TE[k], TE[k]) > GP_R(0.0);
  }
  gp_uint st = gp_build_patch_with(n, V, N, PS, PE, creased, turned ? TS : 0, turned ? TE : 0, vid, mode, recs);
  GP_REAL bulge = GP_R(0.0);
  if (st & GP_ST_NOT_BUILT) {
    /* gp_build_patch wrote nothing: store zeros rather than stale private memory */
    for (int j = 0; j < n * GP_E_NFIELDS; ++j) recs[j] = GP_R(0.0);
  } else {
    st |= gp_patch_quality(n, recs, mode, &bulge, domainTable);
  }
  faceStatus[f] = st;
  faceBulge[f] = (float)bulge;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < GP_E_NFIELDS; ++i) edgeData[(size_t)i * numSlots + first + k] = recs[k * GP_E_NFIELDS + i];
}
