// SPDX-License-Identifier: Apache-2.0
// Boxes of whole patches from their edge records (kernels/gp_bound.h).
#include <smoothforce/patch/patch_bounds.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include <smoothforce/patch/detail/gp_math.h>

namespace sf {

std::vector<PatchBox> patchBoxes(const PatchCache& cache) {
  std::vector<PatchBox> boxes(cache.numFaces());
  const double rel = cache.options.precision == Precision::Double ? 1e-9 : 1e-5;
  tbb::parallel_for(tbb::blocked_range<int>(0, cache.numFaces(), 64), [&](const tbb::blocked_range<int>& range) {
    double recs[GP_MAX_N * GP_E_NFIELDS];
    for (int f = range.begin(); f < range.end(); ++f) {
      const int n = cache.faceSize(f), first = cache.faceOffsets[f];
      const uint32_t st = buildPatchEdges(cache, f, recs);
      if (st & GP_ST_NOT_BUILT) continue;
      PatchBox& b = boxes[f];
      if (st & GP_ST_AFFINE) {  // the affine map plus each edge's deviation from its chord, blended
        // in with a weight in [0, 1]: that deviation's Bezier control points are 0, (M0 - E) / 3,
        // (E - M1) / 3, 0 (gp_patch_eval_affine3); the affine part lies in the triangle's box
        b.lo = b.hi = Eigen::Vector3d(recs[GP_E_V0], recs[GP_E_V0 + 1], recs[GP_E_V0 + 2]);
        Eigen::Vector3d dlo = Eigen::Vector3d::Zero(), dhi = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
          const double* r = recs + k * GP_E_NFIELDS;
          const Eigen::Vector3d v0(r[GP_E_V0], r[GP_E_V0 + 1], r[GP_E_V0 + 2]),
              e = Eigen::Vector3d(r[GP_E_V1], r[GP_E_V1 + 1], r[GP_E_V1 + 2]) - v0,
              p1 = (Eigen::Vector3d(r[GP_E_M0], r[GP_E_M0 + 1], r[GP_E_M0 + 2]) - e) / 3.0,
              p2 = (e - Eigen::Vector3d(r[GP_E_M1], r[GP_E_M1 + 1], r[GP_E_M1 + 2])) / 3.0;
          b.lo = b.lo.cwiseMin(v0);
          b.hi = b.hi.cwiseMax(v0);
          dlo += p1.cwiseMin(p2).cwiseMin(Eigen::Vector3d::Zero());
          dhi += p1.cwiseMax(p2).cwiseMax(Eigen::Vector3d::Zero());
        }
        b.lo += dlo;
        b.hi += dhi;
      } else {
        gpd::gp_vec3 lo, hi;
        gpd::gp_patch_box(n, recs, &lo, &hi);
        b.lo = Eigen::Vector3d(lo.x, lo.y, lo.z);
        b.hi = Eigen::Vector3d(hi.x, hi.y, hi.z);
      }
      for (int k = 0; k < n; ++k) {  // the polygon's vertices (the box of r_k holds them already)
        const Eigen::Vector3d v =
            Eigen::Map<const Eigen::Vector3d>(&cache.positions[3 * cache.faceVertices[first + k]]);
        b.lo = b.lo.cwiseMin(v);
        b.hi = b.hi.cwiseMax(v);
      }
      if (!(b.lo.allFinite() && b.hi.allFinite())) continue;
      const double pad = rel * ((b.hi - b.lo).norm() + b.lo.cwiseAbs().cwiseMax(b.hi.cwiseAbs()).norm());
      b.lo.array() -= pad;
      b.hi.array() += pad;
      b.valid = true;
    }
  });
  return boxes;
}

}  // namespace sf
