// The patch method: Algorithm 1 of Wu et al. over PolygonScene (global) and PatchRefiner (local).
#include "force_tracking.h"

#include <cmath>
#include <string>

#include "embree_scene.h"
#include "mean_value.h"
#include "patch_refine.h"
#include "patch_seeds.h"

namespace sf {

void validateForceOptions(const ForceOptions& o) {
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness))
    throw InputError("stiffness must be a finite value > 0 N/m, got " + std::to_string(o.stiffness));
  if (!(o.angleTolerance > 0) || !std::isfinite(o.angleTolerance))
    throw InputError("angleTolerance must be a finite value > 0 rad, got " + std::to_string(o.angleTolerance));
  if (o.maxIterations < 1) throw InputError("maxIterations must be >= 1, got " + std::to_string(o.maxIterations));
  if (o.tessellationLevel < 1 || o.tessellationLevel > 64)
    throw InputError("tessellationLevel must be in 1..64, got " + std::to_string(o.tessellationLevel));
}

namespace {

class PatchTracker final : public ForceRenderer {
 public:
  PatchTracker(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
               const ForceOptions& options)
      : cache_(std::move(cache)), scene_(std::move(scene)), options_(options), refiner_(*cache_) {
    int maxN = 3;
    for (int f = 0; f < cache_->numFaces(); ++f) maxN = std::max(maxN, cache_->faceSize(f));
    lambda_.resize(maxN);
    if (options_.initialGuess == InitialGuess::Tessellation)
      seeds_ = std::make_unique<PatchSeeds>(*cache_, options_.tessellationLevel);
  }

  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    s.scp = hip;
    if (!hip.allFinite()) {
      inContact_ = false;
      s.status = SF_TRACK_BAD_HIP;
      return s;
    }
    const bool was = inContact_;
    RefineResult r;
    if (!was && seeds_) {  // global query on the tessellation: the vertex carries its (face, xi, eta)
      s.status |= SF_TRACK_GLOBAL;
      const PatchSeed seed = seeds_->nearest(hip);
      if (seed.face < 0) {
        s.status |= SF_TRACK_NO_POLYGON;
        return s;
      }
      r = refiner_.refine(hip, seed.face, seed.X.x(), seed.X.y(), options_);
    } else if (!was) {
      s.status |= SF_TRACK_GLOBAL;
      const NearestPolygonPoint np = scene_->nearest(hip);
      if (np.face < 0) {
        s.status |= SF_TRACK_NO_POLYGON;
        return s;
      }
      const Eigen::Vector2d X = polygonToDomain(scene_->facets(), *cache_, np.face, np.point, lambda_.data());
      r = refiner_.refine(hip, np.face, X.x(), X.y(), options_);
      if (r.status & SF_TRACK_DEGENERATE) {  // no patch here: the polygon itself is the surface
        r.scp = np.point;
        r.normal = scene_->facets().facetNormal[np.facet];
        r.face = np.face;
        r.xi = X.x();
        r.eta = X.y();
      }
    } else {
      r = refiner_.refine(hip, face_, X_.x(), X_.y(), options_);
    }
    s.iterations = r.iterations;
    s.transitions = r.transitions;
    s.status |= r.status;
    const bool usable = r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
    if (usable && (hip - r.scp).dot(r.normal) < 0) {
      inContact_ = true;
      face_ = r.face;
      X_ = {r.xi, r.eta};
      s.contact = true;
      s.scp = r.scp;
      s.normal = r.normal;
      s.face = r.face;
      s.xi = r.xi;
      s.eta = r.eta;
      s.force = options_.stiffness * (r.scp - hip);
      if (!was) s.status |= SF_TRACK_ENTER;
    } else {
      inContact_ = false;
      if (was) s.status |= SF_TRACK_LEAVE;
    }
    return s;
  }

  void reset() noexcept override { inContact_ = false; }
  int patchesBuilt() const noexcept override { return cache_->numFaces(); }

 private:
  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;
  ForceOptions options_;
  PatchRefiner refiner_;
  std::unique_ptr<PatchSeeds> seeds_;  ///< InitialGuess::Tessellation only
  std::vector<double> lambda_;
  bool inContact_ = false;
  int face_ = -1;
  Eigen::Vector2d X_{0, 0};
};

}  // namespace

std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options) {
  validateForceOptions(options);
  return std::make_unique<PatchTracker>(std::move(cache), std::move(scene), options);
}

}  // namespace sf
