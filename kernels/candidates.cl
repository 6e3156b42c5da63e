/* SPDX-License-Identifier: Apache-2.0 */
/* The patch surface's candidate search (PatchSurface::candidates) for a batch of queries: one
 * work-item per query walks a BVH over the adaptive tessellation's triangles, whose boxes are
 * grown by each triangle's error bound (host/opencl/opencl_candidates.cpp builds it), and keeps
 * the triangles whose lower bound (exact distance - error bound, gp_closest.h) is at most the
 * smallest (distance + error bound) seen; of those, the first `cap` in (lower bound, triangle)
 * order. A box is skipped only where its distance from the query exceeds that smallest upper
 * bound, so every triangle that can be a candidate is visited: the same set as the host's,
 * whatever order the walk takes.
 *
 * Always double. Compiled with gp_config.h and gp_closest.h before it
 * (host/opencl/opencl_program.cpp); standalone (clang syntax check, -I kernels) the include
 * below pulls them in. */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#ifndef GP_EMBEDDED
#include "gp_closest.h"
#endif

/* The most candidates a query keeps, and the walk's stack (a median-split BVH of 4 million
 * triangles is 21 levels deep; the walk holds at most one sibling per level). */
#define GP_CAND_MAX 64
#define GP_CAND_STACK 64

/* distance (m) from q to box k of nodeBox (6 per node: lower x, y, z, upper x, y, z) */
static inline double gp_cand_box_distance(__global const double* nodeBox, int k, const double* q) {
  double s = 0;
  int a;
  for (a = 0; a < 3; ++a) {
    const double lo = nodeBox[6 * k + a] - q[a], hi = q[a] - nodeBox[6 * k + 3 + a];
    const double g = lo > 0 ? lo : (hi > 0 ? hi : 0);
    s += g * g;
  }
  return sqrt(s);
}

/* count: N queries. cap: candidates kept per query, 1..GP_CAND_MAX.
 * nodeBox: 6 per node (m). nodeFirst, nodeCount: per node; a leaf (count > 0) holds triangles
 * [first, first + count) of the triangle arrays, an inner node (count 0) has children first and
 * first + 1. Node 0 is the root.
 * triCorner: 9 per triangle, its corners (m). triError: its error bound (m). triId: its index in
 * PatchSurface::pointTriangles().
 * queries: 3*N, q x, y, z per query (m).
 * outCount: N, the candidates found (at most cap), or -1 where the walk's stack overflowed (the
 * host searches). outTotal: one int, 0 on entry: the ids written. outOffset: N, where query i's
 * ids start in outId. outId: cap*N room, each query's candidates' triangle indices together, in
 * (lower bound, index) order; the queries' blocks in any order. */
__kernel void gp_candidates(const int count, const int cap, __global const double* nodeBox,
                            __global const int* nodeFirst, __global const int* nodeCount,
                            __global const double* triCorner, __global const double* triError,
                            __global const int* triId, __global const double* queries, __global int* outCount,
                            volatile __global int* outTotal, __global int* outOffset, __global int* outId) {
  const int i = (int)get_global_id(0);
  double q[3], a[3], b[3], c[3];
  double lower[GP_CAND_MAX];
  int id[GP_CAND_MAX];
  int stack[GP_CAND_STACK];
  double bound = INFINITY; /* the smallest (distance + error bound) seen */
  int n = 0, sp = 0, k, j, m, overflow = 0;
  if (i >= count) return;
  for (k = 0; k < 3; ++k) q[k] = queries[3 * i + k];
  stack[sp++] = 0;
  while (sp > 0) {
    const int node = stack[--sp];
    if (gp_cand_box_distance(nodeBox, node, q) > bound) continue;
    if (nodeCount[node] > 0) {
      const int first = nodeFirst[node], last = first + nodeCount[node];
      for (j = first; j < last; ++j) {
        double u, v, w, d, e, lo;
        for (k = 0; k < 3; ++k) {
          a[k] = triCorner[9 * j + k];
          b[k] = triCorner[9 * j + 3 + k];
          c[k] = triCorner[9 * j + 6 + k];
        }
        d = sqrt(gp_closest_on_triangle(q, a, b, c, &u, &v, &w));
        e = triError[j];
        if (!(d - e <= bound)) continue;
        lo = d - e;
        if (n < cap) {
          lower[n] = lo;
          id[n] = triId[j];
          ++n;
        } else { /* full: replace the last in (lower bound, index) order, if after this one */
          int worst = 0;
          for (m = 1; m < n; ++m)
            if (lower[m] > lower[worst] || (lower[m] == lower[worst] && id[m] > id[worst])) worst = m;
          if (lo < lower[worst] || (lo == lower[worst] && triId[j] < id[worst])) {
            lower[worst] = lo;
            id[worst] = triId[j];
          }
        }
        if (d + e < bound) bound = d + e;
      }
    } else if (sp + 2 > GP_CAND_STACK) {
      overflow = 1;
      break;
    } else { /* the nearer child first */
      const int l = nodeFirst[node], r = l + 1;
      const double dl = gp_cand_box_distance(nodeBox, l, q), dr = gp_cand_box_distance(nodeBox, r, q);
      if (dl <= dr) {
        stack[sp++] = r;
        stack[sp++] = l;
      } else {
        stack[sp++] = l;
        stack[sp++] = r;
      }
    }
  }
  if (overflow) {
    outCount[i] = -1;
    outOffset[i] = 0;
    return;
  }
  /* keep those whose lower bound is within the final bound, sorted */
  m = 0;
  for (j = 0; j < n; ++j)
    if (lower[j] <= bound) {
      lower[m] = lower[j];
      id[m] = id[j];
      ++m;
    }
  for (j = 1; j < m; ++j) {
    const double lj = lower[j];
    const int ij = id[j];
    k = j - 1;
    while (k >= 0 && (lower[k] > lj || (lower[k] == lj && id[k] > ij))) {
      lower[k + 1] = lower[k];
      id[k + 1] = id[k];
      --k;
    }
    lower[k + 1] = lj;
    id[k + 1] = ij;
  }
  outCount[i] = m;
  k = m > 0 ? atomic_add(outTotal, m) : 0;
  outOffset[i] = k;
  for (j = 0; j < m; ++j) outId[k + j] = id[j];
}
