// The patch method: Algorithm 1 of Wu et al. over PolygonScene (global) and PatchRefiner (local).
#include <smoothforce/force/force_tracking.h>

#include <cmath>
#include <string>

#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_seeds.h>

namespace sf {

void validateForceOptions(const ForceOptions& o) {
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness))
    throw InputError("stiffness must be a finite value > 0 N/m, got " + std::to_string(o.stiffness));
  validateRefineOptions(o);
}

namespace {

class PatchTracker final : public ForceRenderer {
 public:
  PatchTracker(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
               const ForceOptions& options)
      : cache_(std::move(cache)),
        scene_(std::move(scene)),
        options_(options),
        lazy_(hasPatchData(*cache_) ? nullptr : std::make_unique<LazyPatches>(cache_, options.patchCapacity)),
        refiner_(*cache_, lazy_.get()) {
    int maxN = 3;
    for (int f = 0; f < cache_->numFaces(); ++f) maxN = std::max(maxN, cache_->faceSize(f));
    lambda_.resize(maxN);
    if (options_.initialGuess == InitialGuess::Tessellation) {
      if (lazy_)  // the tessellation would build every patch, which lazy construction avoids
        throw InputError("initial guess 'tessellation' needs prebuilt patches (a cache, not a mesh built lazily)");
      seeds_ = std::make_unique<PatchSeeds>(*cache_, options_.tessellationLevel);
    }
  }

  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    PatchStepStart start;
    if (!beginPatchStep(*scene_, *cache_, hip, state_, lambda_.data(), start, s, seeds_.get())) return s;
    const RefineResult r = refiner_.refine(hip, start.face, start.X.x(), start.X.y(), options_);
    finishPatchStep(*scene_, hip, start, r, options_.stiffness, state_, s);
    return s;
  }

  void reset() noexcept override { state_.inContact = false; }
  int patchesBuilt() const noexcept override { return lazy_ ? lazy_->constructions() : cache_->numFaces(); }

 private:
  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;
  ForceOptions options_;
  std::unique_ptr<LazyPatches> lazy_;  ///< patches built on demand when the cache is a skeleton
  PatchRefiner refiner_;
  std::unique_ptr<PatchSeeds> seeds_;  ///< InitialGuess::Tessellation only
  std::vector<double> lambda_;
  PatchContactState state_;
};

}  // namespace

bool beginPatchStep(const PolygonScene& scene, const PatchCache& cache, const Eigen::Vector3d& hip,
                    PatchContactState& state, double* lambda, PatchStepStart& start, ForceSample& s,
                    const PatchSeeds* seeds) noexcept {
  s = ForceSample{};
  s.scp = hip;
  start = PatchStepStart{};
  if (!hip.allFinite()) {
    state.inContact = false;
    s.status = SF_TRACK_BAD_HIP;
    return false;
  }
  if (state.inContact) {
    start.face = state.face;
    start.X = state.X;
    start.edge = state.edge;
    return true;
  }
  s.status |= SF_TRACK_GLOBAL;
  if (seeds) {  // global query on the tessellation: the vertex carries its (face, xi, eta)
    const PatchSeed seed = seeds->nearest(hip);
    if (seed.face < 0) {
      s.status |= SF_TRACK_NO_POLYGON;
      return false;
    }
    start.global = true;
    start.face = seed.face;
    start.X = seed.X;
    return true;  // facet -1: no polygon point to fall back on
  }
  const NearestPolygonPoint np = scene.nearest(hip);
  if (np.face < 0) {
    s.status |= SF_TRACK_NO_POLYGON;
    return false;
  }
  start.global = true;
  start.face = np.face;
  start.facet = np.facet;
  start.polygonPoint = np.point;
  start.X = polygonToDomain(scene.facets(), cache, np.face, np.point, lambda);
  return true;
}

void finishPatchStep(const PolygonScene& scene, const Eigen::Vector3d& hip, const PatchStepStart& start, RefineResult r,
                     double stiffness, PatchContactState& state, ForceSample& s) noexcept {
  const bool was = state.inContact;
  if (start.global && start.facet >= 0 && (r.status & SF_TRACK_DEGENERATE)) {  // no patch here: the polygon itself is the surface
    r.scp = start.polygonPoint;
    r.normal = scene.facets().facetNormal[start.facet];
    r.face = start.face;
    r.edge = -1;
    r.xi = start.X.x();
    r.eta = start.X.y();
  }
  s.iterations = r.iterations;
  s.transitions = r.transitions;
  s.status |= r.status;
  const bool usable = r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
  if (usable && (hip - r.scp).dot(r.normal) < 0) {
    state = PatchContactState{true, r.face, {r.xi, r.eta}, r.edge};
    s.contact = true;
    s.scp = r.scp;
    s.normal = r.normal;
    s.face = r.face;
    s.xi = r.xi;
    s.eta = r.eta;
    s.force = stiffness * (r.scp - hip);
    if (!was) s.status |= SF_TRACK_ENTER;
  } else {
    state.inContact = false;
    if (was) s.status |= SF_TRACK_LEAVE;
  }
}

std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options) {
  validateForceOptions(options);
  return std::make_unique<PatchTracker>(std::move(cache), std::move(scene), options);
}

}  // namespace sf
