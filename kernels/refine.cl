/* SPDX-License-Identifier: Apache-2.0 */
/* Batch refinement: one work-item per HIP runs gp_refine_newton or the paper's descent
 * gp_refine_descent (gp_refine.h), as host/query/patch_refine.cpp does on the CPU.
 *
 * Compiled like construct.cl (see there), with gp_domain.h, gp_refine.h and gp_descent.h after
 * gp_eval.h (host/opencl/opencl_program.cpp). Standalone (clang syntax check, -I kernels) the includes below
 * pull in the same headers. */
#if GP_IS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#ifndef GP_EMBEDDED
#include "gp_patch.h"
#include "gp_domain.h"
#include "gp_refine.h"
#include "gp_descent.h"
#endif

/* numFaces: #F. numSlots: #C. mode: GP_CT_*. count: N HIPs. maxIterations >= 1.
 * angleTolerance: rad. positionTolerance: m. modelFinal: gp_refine_options.modelFinal (0 or 1).
 * descent: 0 Newton, 1 the paper's descent (RefineMethod::PaperDescent).
 * scale: bounding-box diagonal, m.
 * faceOffsets: #F+1. edgeData: GP_E_NFIELDS*#C, field-major. faceStatus: #F. slotTwin: #C.
 * hips: 3*N component-major (hips[c * N + q], m). qFace, qXi, qEta, qEdge: N (start; qEdge
 * the domain edge the start is held on, -1 for none). qIterations: N, the query's iteration
 * limit (>= 0; 0: the start evaluated and tested only, a seed), or -1: maxIterations.
 * outReal: 8*N component-major: 0..2 SCP (m), 3..5 unit normal, 6 xi, 7 eta.
 * outInt: 5*N component-major: 0 face, 1 held edge (-1: none), 2 iterations, 3 transitions,
 * 4 startMinimum.
 * outStatus: N, GP_TRACK_* | GP_ST_*.
 * sinAngleTolerance: sin(angleTolerance) as the host rounds it. domainTable: GP_DOMAIN_FLAT_SIZE,
 * the host's domain constants (gp_tables.h). */
__kernel void gp_refine(const int numFaces, const int numSlots, const int mode, const int count,
                        const int maxIterations, const GP_REAL angleTolerance, const GP_REAL positionTolerance,
                        const int modelFinal, const int descent, const GP_REAL scale,
                        __global const int* faceOffsets, __global const GP_REAL* edgeData,
                        __global const uint* faceStatus, __global const int* slotTwin, __global const GP_REAL* hips,
                        __global const int* qFace, __global const GP_REAL* qXi, __global const GP_REAL* qEta,
                        __global const int* qEdge, __global const int* qIterations, __global GP_REAL* outReal,
                        __global int* outInt, __global uint* outStatus, const GP_REAL sinAngleTolerance,
                        __global const GP_REAL* domainTable) {
  const int q = (int)get_global_id(0);
  if (q >= count) return;
  const size_t m = (size_t)count;
  gp_refine_mesh mesh;
  mesh.faceOffsets = faceOffsets;
  mesh.edgeData = edgeData;
  mesh.faceStatus = faceStatus;
  mesh.slotTwin = slotTwin;
  mesh.slotFace = 0;
  mesh.numFaces = numFaces;
  mesh.numSlots = numSlots;
  mesh.mode = mode;
  mesh.scale = scale;
  mesh.floatRecords = !GP_IS_DOUBLE; /* the records are in the program's precision */
  mesh.domainTable = domainTable;
  gp_refine_work work;
  work.loaded = -1;
  work.sinOf = angleTolerance; /* the host's sine: gp_rf_begin takes it instead of computing one */
  work.sinAngle = sinAngleTolerance;
  const gp_vec3 hip = gp_v3(hips[q], hips[m + q], hips[2 * m + q]);
  gp_refine_options opt;
  opt.maxIterations = qIterations[q] >= 0 ? qIterations[q] : maxIterations;
  opt.angleTol = angleTolerance;
  opt.positionTol = positionTolerance;
  opt.modelFinal = modelFinal;
  const gp_refine_result r = descent ? gp_refine_descent(&mesh, &work, hip, qFace[q], qXi[q], qEta[q], qEdge[q], &opt)
                                     : gp_refine_newton(&mesh, &work, hip, qFace[q], qXi[q], qEta[q], qEdge[q], &opt);
  outReal[q] = r.scp.x;
  outReal[m + q] = r.scp.y;
  outReal[2 * m + q] = r.scp.z;
  outReal[3 * m + q] = r.normal.x;
  outReal[4 * m + q] = r.normal.y;
  outReal[5 * m + q] = r.normal.z;
  outReal[6 * m + q] = r.xi;
  outReal[7 * m + q] = r.eta;
  outInt[q] = r.face;
  outInt[m + q] = r.edge;
  outInt[2 * m + q] = r.iterations;
  outInt[3 * m + q] = r.transitions;
  outInt[4 * m + q] = r.startMinimum;
  outStatus[q] = r.status;
}
