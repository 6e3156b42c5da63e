// The patch method: Algorithm 1 of Wu et al. over PatchSurface (global query on the patches),
// PolygonScene (the paper's polygon start) and PatchRefiner (local refinement).
#include <smoothforce/force/force_tracking.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/query/patch_refine.h>

#include "force_tracking_detail.h"

namespace sf {

void validateForceOptions(const ForceOptions& o) {
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness))
    throw InputError("stiffness must be a finite value > 0 N/m, got " + std::to_string(o.stiffness));
  validateRefineOptions(o);
}

PatchSurfaceOptions patchSurfaceOptions(const ForceOptions& o) {
  PatchSurfaceOptions so;
  so.level = o.tessellationLevel;
  return so;
}

namespace detail {

bool usable(const RefineResult& r) noexcept {
  return !(r.status & SF_TRACK_DEGENERATE) && r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
}

void setContact(bool contact, const RefineResult& r, const Eigen::Vector3d& hip, const ForceOptions& options,
                PatchContactState& state, ForceSample& s) noexcept {
  const bool was = state.inContact;
  s.iterations = r.iterations;
  s.transitions = r.transitions;
  s.status |= r.status;
  if (contact) {
    state = PatchContactState{true, r.face, {r.xi, r.eta}, r.edge};
    s.contact = true;
    s.scp = r.scp;
    s.normal = r.normal;
    s.face = r.face;
    s.xi = r.xi;
    s.eta = r.eta;
    s.force = options.stiffness * (r.scp - hip);
    if (!was) s.status |= SF_TRACK_ENTER;
  } else {
    state.inContact = false;
    if (was) s.status |= SF_TRACK_LEAVE;
  }
}

}  // namespace detail

using detail::lazyGlobalStep;
using detail::setContact;
using detail::usable;

namespace {

/// A refined point on the other side than the nearest one, within this factor of its distance,
/// makes the side of the nearest point doubtful (overlapping or folded patches).
constexpr double kConflict = 3.0;

/// Ends a global step on the patch surface: contact when the HIP is inside it.
void finishGlobalStep(const PatchSurface& surface, const Eigen::Vector3d& hip, const PatchNearest& q,
                      const ForceOptions& options, PatchContactState& state, ForceSample& s,
                      int windingVerdict = -2) noexcept {
  RefineResult scp;
  const bool inside = insidePatchSurface(surface, hip, q, &scp, windingVerdict);
  if (inside) s.status |= SF_TRACK_INSIDE;
  setContact(inside, scp, hip, options, state, s);
}

class PatchTracker final : public ForceRenderer {
 public:
  PatchTracker(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
               const ForceOptions& options, std::shared_ptr<const PatchSurface> surface)
      : cache_(std::move(cache)),
        scene_(std::move(scene)),
        options_(options),
        lazy_(hasPatchData(*cache_) ? nullptr : std::make_unique<LazyPatches>(cache_, options.patchCapacity)),
        refiner_(*cache_, lazy_.get()) {
    int maxN = 3;
    for (int f = 0; f < cache_->numFaces(); ++f) maxN = std::max(maxN, cache_->faceSize(f));
    lambda_.resize(maxN);
    if (options_.initialGuess == InitialGuess::Surface && lazy_)
      lazySurface_ = std::make_unique<LazyPatchSurface>(*cache_, scene_->facets());
    if (options_.initialGuess == InitialGuess::Surface && !lazy_) {
      if (surface && &surface->cache() != cache_.get())
        throw InputError("makePatchForceRenderer: the patch surface must be built from the same cache");
      surface_ =
          surface ? std::move(surface) : std::make_shared<const PatchSurface>(*cache_, patchSurfaceOptions(options_));
    }
  }

  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    if (lazySurface_ && !state_.inContact && hip.allFinite()) {  // patches built lazily: faces chosen by their boxes
      s.scp = hip;
      s.status = SF_TRACK_GLOBAL;
      lazyGlobalStep(*lazySurface_, *scene_, *cache_, refiner_, hip, options_, lambda_.data(), state_, s);
      return s;
    }
    PatchStepStart start;
    // the patch point the last step ended at bounds the distance (the candidates stay the same)
    const double reach =
        lastPoint_.allFinite() ? (hip - lastPoint_).norm() : std::numeric_limits<double>::infinity();
    if (!beginPatchStep(*scene_, surface_.get(), *cache_, hip, state_, lambda_.data(), start, s, false, reach))
      return s;
    if (start.global && surface_) {  // the whole global query here: every candidate it may need
      const PatchNearest q = nearestOnPatches(*surface_, refiner_, hip, options_, nullptr, start.reach);
      if (q.candidates == 0) s.status |= SF_TRACK_NO_POLYGON;
      finishGlobalStep(*surface_, hip, q, options_, state_, s, start.windingVerdict);
      remember(q.nearest);
      return s;
    }
    // in contact: the next step from the SCP the refiner found last (its evaluation reused)
    const RefineResult r = start.global
                               ? refiner_.refine(hip, start.face, start.X.x(), start.X.y(), options_, start.edge)
                               : refiner_.refineNext(hip, start.face, start.X.x(), start.X.y(), options_, start.edge);
    finishPatchStep(*scene_, surface_.get(), refiner_, hip, start, r, options_, state_, s);
    remember(r);
    return s;
  }

  void reset() noexcept override {
    state_.inContact = false;
    lastPoint_.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  int patchesBuilt() const noexcept override { return lazy_ ? lazy_->constructions() : cache_->numFaces(); }

 private:
  void remember(const RefineResult& r) noexcept {
    if (usable(r)) lastPoint_ = r.scp;
  }

  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;
  ForceOptions options_;
  std::unique_ptr<LazyPatches> lazy_;  ///< patches built on demand when the cache is a skeleton
  PatchRefiner refiner_;
  std::shared_ptr<const PatchSurface> surface_;    ///< InitialGuess::Surface with prebuilt patches
  std::unique_ptr<LazyPatchSurface> lazySurface_;  ///< InitialGuess::Surface with lazy patches
  std::vector<double> lambda_;
  PatchContactState state_;
  /// m, the patch point the last refining step ended at (NaN: none): bounds the next global
  /// query's search radius
  Eigen::Vector3d lastPoint_{Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())};
};

}  // namespace

PatchNearest refineCandidates(const SurfaceCandidate* c, int n, double spacing, PatchRefiner& refiner,
                              const Eigen::Vector3d& hip, const ForceOptions& options,
                              const RefineResult* first) noexcept {
  PatchNearest q;
  q.nearest.status = q.nearestBelow.status = SF_TRACK_DEGENERATE;
  q.nearest.distance = q.nearestBelow.distance = std::numeric_limits<double>::infinity();
  q.candidates = n;
  q.minLower = n > 0 ? c[0].lower : std::numeric_limits<double>::infinity();
  constexpr int kSeen = 64;
  int seenFace[2 * kSeen];
  Eigen::Vector2d seenX[2 * kSeen];
  int seen = 0;
  auto near = [&](int f, const Eigen::Vector2d& X) {
    for (int j = 0; j < seen; ++j)
      if (seenFace[j] == f && (seenX[j] - X).norm() < spacing) return true;
    return false;
  };
  for (int i = 0; i < n; ++i) {
    if (c[i].lower >= q.nearest.distance) break;
    if (near(c[i].face, c[i].X)) continue;
    const RefineResult r = i == 0 && first ? *first : refiner.refine(hip, c[i].face, c[i].X.x(), c[i].X.y(), options);
    ++q.refined;
    if (seen + 2 <= 2 * kSeen) {
      seenFace[seen] = c[i].face;
      seenX[seen++] = c[i].X;
      seenFace[seen] = r.face;
      seenX[seen++] = Eigen::Vector2d(r.xi, r.eta);
    }
    if (!usable(r)) continue;
    const bool below = (hip - r.scp).dot(r.normal) < 0;
    (below ? q.anyBelow : q.anyAbove) = true;
    if (!below) q.nearestAbove = std::min(q.nearestAbove, r.distance);
    if (r.distance < q.nearest.distance) q.nearest = r;
    if (below && r.distance < q.nearestBelow.distance) q.nearestBelow = r;
  }
  return q;
}

PatchNearest nearestOnPatches(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                              const ForceOptions& options, const RefineResult* first, double reach) noexcept {
  SurfaceCandidate c[PatchSurface::kMaxCandidates];
  const int n = static_cast<int>(surface.candidates(hip, c, PatchSurface::kMaxCandidates, reach));
  return refineCandidates(c, n, surface.spacing(), refiner, hip, options, first);
}

int insideByWinding(const PatchSurface& surface, const Eigen::Vector3d& hip, double* reach) noexcept {
  if (!surface.closed() || surface.numTriangles() == 0 || surface.inErrorBand(hip, reach)) return -1;
  return surface.winding(hip) >= 1 ? 1 : 0;
}

bool insidePatchSurface(const PatchSurface& surface, const Eigen::Vector3d& hip, const PatchNearest& q,
                        RefineResult* scp, int windingVerdict) noexcept {
  if (scp) *scp = q.nearest;
  if (!usable(q.nearest)) return false;
  const bool below = (hip - q.nearest.scp).dot(q.nearest.normal) < 0;
  if (!surface.closed()) return below && !(q.nearest.status & SF_TRACK_BOUNDARY);
  // the side of the nearest point decides, unless the winding number is reliable here (outside every
  // error band) or a refined point about as near sees the other side (overlapping or folded patches)
  // (a nearest point held on a fold edge has two sides by itself: the two faces disagree there)
  const bool conflict = (q.nearest.status & SF_TRACK_FOLD_EDGE) ||
                        (below ? q.anyAbove && q.nearestAbove <= kConflict * q.nearest.distance
                               : q.anyBelow && q.nearestBelow.distance <= kConflict * q.nearest.distance);
  const int verdict = windingVerdict == -2 ? insideByWinding(surface, hip) : windingVerdict;
  const bool useWinding = conflict || verdict >= 0;
  const bool inside = useWinding ? (verdict >= 0 ? verdict == 1 : surface.winding(hip) >= 1) : below;
  if (inside && scp && q.anyBelow) *scp = q.nearestBelow;
  return inside;
}

bool beginPatchStep(const PolygonScene& scene, const PatchSurface* surface, const PatchCache& cache,
                    const Eigen::Vector3d& hip, PatchContactState& state, double* lambda, PatchStepStart& start,
                    ForceSample& s, bool firstCandidate, double reach, CandidateList* list) noexcept {
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
  if (surface) {  // the global query on the patch surface
    start.windingVerdict = insideByWinding(*surface, hip, &start.reach);
    if (start.windingVerdict == 0) {  // outside the closed surface beyond every error band: no patch work
      state.inContact = false;
      return false;
    }
    start.reach = std::min(start.reach, reach);
    start.global = true;
    if (!firstCandidate) return true;  // the caller runs the whole global query
    // its first candidate starts the refinement (with a list: every candidate, kept for the finish)
    const bool keep = list && list->c && list->capacity >= 2;
    const size_t found = keep ? surface->candidates(hip, list->c, static_cast<size_t>(list->capacity), start.reach)
                              : surface->candidates(hip, &start.candidate, 1, start.reach);
    if (keep) list->count = static_cast<int>(found);
    if (found == 0) {
      s.status |= SF_TRACK_NO_POLYGON;
      return false;
    }
    if (keep) start.candidate = list->c[0];
    start.face = start.candidate.face;
    start.X = start.candidate.X;
    return true;
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

void finishPatchStep(const PolygonScene& scene, const PatchSurface* surface, PatchRefiner& refiner,
                     const Eigen::Vector3d& hip, const PatchStepStart& start, RefineResult r,
                     const ForceOptions& options, PatchContactState& state, ForceSample& s,
                     Eigen::Vector3d* nearest, const CandidateList* list) noexcept {
  if (start.global && start.candidate.face >= 0 && surface) {  // the rest of the global query on the patches
    const bool whole = list && list->c && list->count > 0 && list->count < list->capacity;
    const PatchNearest q = whole ? refineCandidates(list->c, list->count, surface->spacing(), refiner, hip, options, &r)
                                 : nearestOnPatches(*surface, refiner, hip, options, &r, start.reach);
    finishGlobalStep(*surface, hip, q, options, state, s, start.windingVerdict);
    if (nearest && usable(q.nearest)) *nearest = q.nearest.scp;
    return;
  }
  if (nearest && usable(r)) *nearest = r.scp;
  if (start.global && start.facet >= 0 && (r.status & SF_TRACK_DEGENERATE)) {  // no patch here: the polygon
    r.scp = start.polygonPoint;
    r.normal = scene.facets().facetNormal[start.facet];
    r.face = start.face;
    r.edge = -1;
    r.xi = start.X.x();
    r.eta = start.X.y();
  }
  const bool ok = r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
  setContact(ok && (hip - r.scp).dot(r.normal) < 0, r, hip, options, state, s);
}

std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options,
                                                      std::shared_ptr<const PatchSurface> surface) {
  validateForceOptions(options);
  return std::make_unique<PatchTracker>(std::move(cache), std::move(scene), options, std::move(surface));
}

}  // namespace sf
