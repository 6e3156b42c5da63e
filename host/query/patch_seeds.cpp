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
  std::vector<int32_t> qf;
  std::vector<double> qx, qy;
  std::vector<Eigen::Vector2d> dom;
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & GP_ST_NOT_BUILT) continue;
    dom.clear();
    domainRingPoints(cache.faceSize(f), level, dom);
    for (const Eigen::Vector2d& X : dom) {
      qf.push_back(f);
      qx.push_back(X.x());
      qy.push_back(X.y());
    }
  }
  std::vector<PatchPoint> pts(qf.size());
  evaluatePatches(cache, qf.data(), qx.data(), qy.data(), qf.size(), pts.data(), Backend::Tbb);
  std::vector<Eigen::Vector3d> pos;
  for (size_t i = 0; i < pts.size(); ++i) {
    if ((pts[i].status & GP_ST_NOT_A_PATCH_POINT) || !pts[i].pos.allFinite()) continue;
    pos.push_back(pts[i].pos);
    face_.push_back(qf[i]);
    dom_.emplace_back(qx[i], qy[i]);
  }
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
