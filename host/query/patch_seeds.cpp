// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/patch_seeds.h>

#include <algorithm>
#include <string>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/point_index.h>
#include "gp_config.h"

namespace sf {

namespace {
/// Seeds are moved 0.1% towards the domain centre: Newton refinement (double caches) started
/// exactly on a domain edge or corner often crawled to the iteration cap (12 of 300 quad-sphere
/// HIPs in the trade-off study, error ~1% of the diagonal; none from the inset start).
constexpr double kSeedInset = 0.999;
}  // namespace

PatchSeeds::PatchSeeds(const PatchCache& cache, int level) {
  if (level < 1 || level > 64)
    throw InputError("tessellation level of the initial guess: expected 1..64, got " + std::to_string(level));
  // the ring points a bounded batch at a time (no array of every point's evaluation: 760 MB for
  // a 70k-face mesh at level 8); the same points in the same order
  const std::vector<int32_t> faces = builtFaces(cache);
  const BatchEvaluator evaluate = [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    evaluatePatches(cache, f, x, y, n, out, Backend::Tbb);
  };
  std::vector<Eigen::Vector3d> pos;
  visitRingPoints(cache, level, faces.data(), faces.size(), evaluate,
                  [&](size_t i, const Eigen::Vector2d* X, const PatchPoint* pts, size_t m) {
                    for (size_t v = 0; v < m; ++v) {
                      if ((pts[v].status & GP_ST_NOT_A_PATCH_POINT) || !pts[v].pos.allFinite()) continue;
                      pos.push_back(pts[v].pos);
                      face_.push_back(faces[i]);
                      dom_.push_back(X[v]);
                    }
                  });
  index_ = std::make_unique<PointIndex>(std::move(pos));
}

PatchSeeds::~PatchSeeds() = default;

PatchSeed PatchSeeds::nearest(const Eigen::Vector3d& q) const noexcept {
  PatchSeed s;
  knn(q, 1, &s);
  return s;
}

size_t PatchSeeds::knn(const Eigen::Vector3d& q, size_t k, PatchSeed* out) const noexcept {
  uint32_t idx[64];
  double d2[64];
  if (!q.allFinite()) return 0;
  const size_t found = index_->knn(q, std::min<size_t>(k, 64), idx, d2);
  for (size_t i = 0; i < found; ++i) out[i] = {face_[idx[i]], kSeedInset * dom_[idx[i]], index_->point(idx[i])};
  return found;
}

}  // namespace sf
