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
      if (buildPatchEdges(cache, f, recs) & GP_ST_NOT_BUILT) continue;
      gpd::gp_vec3 lo, hi;
      gpd::gp_patch_box(n, recs, &lo, &hi);
      PatchBox& b = boxes[f];
      b.lo = Eigen::Vector3d(lo.x, lo.y, lo.z);
      b.hi = Eigen::Vector3d(hi.x, hi.y, hi.z);
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
