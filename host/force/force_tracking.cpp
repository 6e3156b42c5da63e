// SPDX-License-Identifier: Apache-2.0
// The patch method: Algorithm 1 of Wu et al. over PatchSurface (global query on the patches),
// PolygonScene (the paper's polygon start) and PatchRefiner (local refinement).
#include <smoothforce/force/force_tracking.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/query/patch_refine.h>

#include "force_tracking_detail.h"

namespace sf {

namespace detail {

void setContact(bool contact, const RefineResult& r, const Eigen::Vector3d& hip, const ForceOptions& options,
                PatchContactState& state, ForceSample& s) noexcept {
  const bool was = state.inContact;
  s.iterations = r.iterations;
  s.transitions = r.transitions;
  s.status |= r.status;
  if (contact) {
    state = PatchContactState{true, r.face, {r.xi, r.eta}, r.edge, hip, false};
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
    state.verify = false;
    if (was) s.status |= SF_TRACK_LEAVE;
  }
}

}  // namespace detail

bool markJump(const PolygonScene& scene, const Eigen::Vector3d& hip, PatchContactState& state) noexcept {
  if (!state.inContact) return state.verify = false;
  const double jump = kJumpDiagonals * scene.facets().extent();
  if ((hip - state.hip).squaredNorm() > jump * jump) state.verify = true;
  return state.verify;
}

using detail::lazyGlobalStep;
using detail::setContact;

namespace {

/// *hint = the patch point r ended at, where r is usable; untouched otherwise (or hint null).
void rememberIn(PatchStepHint* hint, const RefineResult& r) noexcept {
  if (hint && usableRefinement(r)) *hint = PatchStepHint{r.face, Eigen::Vector2d(r.xi, r.eta), r.scp};
}

/// Ends a global step on the patch surface: contact when the HIP is inside it.
void finishGlobalStep(const PatchSurface& surface, const Eigen::Vector3d& hip, const PatchNearest& q,
                      const ForceOptions& options, PatchContactState& state, ForceSample& s,
                      int windingVerdict = -2) noexcept {
  RefineResult scp;
  const bool inside = insidePatchSurface(surface, hip, q, &scp, windingVerdict);
  if (inside) s.status |= SF_TRACK_INSIDE;
  setContact(inside, scp, hip, options, state, s);
}

/// The end of a tracking step whose refinement r left the contact (the HIP not below r): the
/// global query on the surface decides, as at an out-of-contact step (no patch work where the
/// HIP is outside the closed surface beyond every error band); inside, the contact holds at the
/// query's SCP (no SF_TRACK_LEAVE or SF_TRACK_ENTER), outside it ends.
/// The global query at `hip` from a tracking step's refinement r (leaveOrHold, insideAfterJump):
/// r, where usable, hints insideByWinding's band test and is the candidate search's first
/// refinement (its seed). windingVerdict() runs the band test (SF_TRACK_GLOBAL in s), nearest()
/// the candidate search bounded by what the band test found.
struct GlobalQueryFrom {
  const PatchSurface& surface;
  const Eigen::Vector3d& hip;
  const RefineResult& r;
  bool from = usableRefinement(r);
  double reach = std::numeric_limits<double>::infinity();
  int reachFace = -1;

  int windingVerdict(ForceSample& s) noexcept {
    s.status |= SF_TRACK_GLOBAL;
    return insideByWinding(surface, hip, &reach, &reachFace, from ? r.face : -1, Eigen::Vector2d(r.xi, r.eta),
                           from ? r.scp : Eigen::Vector3d::Constant(NAN));
  }
  PatchNearest nearest(PatchRefiner& refiner, const ForceOptions& options) const noexcept {
    SurfaceCandidate start;
    start.face = r.face;
    start.X = Eigen::Vector2d(r.xi, r.eta);
    return nearestOnPatches(surface, refiner, hip, options, from ? &r : nullptr, reach, from ? &start : nullptr,
                            reachFace);
  }
};

void leaveOrHold(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& hip, const RefineResult& r,
                 const ForceOptions& options, PatchContactState& state, ForceSample& s, PatchStepHint* next) noexcept {
  GlobalQueryFrom g{surface, hip, r};
  const int verdict = g.windingVerdict(s);
  if (verdict == 0) {
    rememberIn(next, r);
    setContact(false, r, hip, options, state, s);
    return;
  }
  const PatchNearest q = g.nearest(refiner, options);
  finishGlobalStep(surface, hip, q, options, state, s, verdict);
  rememberIn(next, q.nearest);
}

/// Whether a HIP that jumped while its tracked contact holds (r: this step's refinement, the
/// HIP below it) is inside the surface: the global query's verdict, as at a contact start
/// (insideByWinding beyond the error bands, else nearestOnPatches from r and insidePatchSurface).
bool insideAfterJump(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                     const RefineResult& r, const ForceOptions& options, ForceSample& s) noexcept {
  GlobalQueryFrom g{surface, hip, r};
  const int verdict = g.windingVerdict(s);
  if (verdict >= 0) return verdict == 1;
  return insidePatchSurface(surface, hip, g.nearest(refiner, options), nullptr, verdict);
}

class PatchTracker final : public ForceRenderer {
 public:
  PatchTracker(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
               const ForceOptions& options, std::shared_ptr<const PatchSurface> surface,
               const detail::SharedLazyParts& shared = {})
      : cache_(std::move(cache)),
        scene_(std::move(scene)),
        options_(options),
        seedOptions_(options),
        lazy_(hasPatchData(*cache_) ? nullptr
              : shared.patches      ? shared.patches
                                    : std::make_shared<LazyPatches>(cache_, options.patchCapacity)),
        refiner_(*cache_, lazy_.get()) {
    seedOptions_.maxIterations = 0;  // a seed is evaluated, not refined
    int maxN = 3;
    for (int f = 0; f < cache_->numFaces(); ++f) maxN = std::max(maxN, cache_->faceSize(f));
    lambda_.resize(maxN);
    // the patch surface's index (surface_index, force_method.h): the boxes on a skeleton, or where
    // asked for and no tessellated surface is given; else (auto too) the tessellation
    const bool bounds = lazy_ || (options_.surfaceIndex == SurfaceIndex::Bounds && !surface);
    if (options_.initialGuess == InitialGuess::Surface && bounds) {
      lazySurface_ = shared.surface ? shared.surface : detail::makeBoundsIndex(*cache_, *scene_);
    }
    if (options_.initialGuess == InitialGuess::Surface && !bounds) {
      if (surface && &surface->cache() != cache_.get())
        throw InputError("makePatchForceRenderer: the patch surface must be built from the same cache");
      surface_ =
          surface ? std::move(surface) : std::make_shared<const PatchSurface>(*cache_, patchSurfaceOptions(options_));
    }
  }

  ForceSample step(const Eigen::Vector3d& hip) noexcept override {
    ForceSample s;
    if (lazySurface_ && state_.inContact && lazySurface_->farBeyond(hip)) {
      state_.inContact = false;  // no contact holds that far out (beginPatchStep, prebuilt)
      s.status |= SF_TRACK_LEAVE;
    }
    if (lazySurface_ && !state_.inContact && inCoordinateRange(hip)) {  // patches built lazily: faces chosen by their boxes
      s.scp = hip;
      s.status |= SF_TRACK_GLOBAL;
      lazyGlobalStep(*lazySurface_, *scene_, *cache_, refiner_, hip, options_, lambda_.data(), state_, s);
      return s;
    }
    PatchStepStart start;
    // the patch point the last step ended at (or resetNear's) seeds the global query on the
    // surface and bounds its candidate search; without one the query runs whole here
    const bool seeded = surface_ && hint_.face >= 0 && hint_.seed && options_.refine == RefineMethod::Newton;
    if (!beginPatchStep(*scene_, surface_.get(), *cache_, hip, state_, lambda_.data(), start, s, seeded, hint_)) {
      // a HIP the queries do not take resets the renderer: the next step starts afresh, not
      // from the seed the step before it left
      if (s.status & SF_TRACK_BAD_HIP) reset();
      return s;
    }
    if (start.global && surface_ && !start.seeded) {  // the whole global query: every candidate it may need
      const PatchNearest q =
          nearestOnPatches(*surface_, refiner_, hip, options_, nullptr, start.reach, nullptr, start.reachFace);
      if (q.candidates == 0) s.status |= SF_TRACK_NO_POLYGON;
      finishGlobalStep(*surface_, hip, q, options_, state_, s, start.windingVerdict);
      remember(q.nearest);
      return s;
    }
    // in contact: the next step from the SCP the refiner found last (its evaluation reused); a
    // seed is only evaluated (no iteration): it stands in for a candidate only where it is a
    // minimum already (refineCandidates), and bounds the candidate search in any case
    const RefineResult r = start.global
                               ? refiner_.refine(hip, start.face, start.X.x(), start.X.y(),
                                                 start.seeded ? seedOptions_ : options_, start.edge)
                               : refiner_.refineNext(hip, start.face, start.X.x(), start.X.y(), options_, start.edge);
    const bool jumped = state_.verify && !surface_;  // with a surface finishPatchStep asks it
    finishPatchStep(*scene_, surface_.get(), refiner_, hip, start, r, options_, state_, s, &hint_);
    const bool jumpedOut = jumped && state_.inContact && !start.global && !insideAfterJump(hip);
    if (jumpedOut) {
      // the HIP jumped out of the object (no surface to ask in finishPatchStep): the contact ends
      const ForceSample tracked = s;
      s = ForceSample{};
      s.scp = hip;
      s.iterations = tracked.iterations;
      s.transitions = tracked.transitions;
      s.status = (tracked.status & ~SF_TRACK_ENTER) | SF_TRACK_GLOBAL | SF_TRACK_LEAVE;
      state_.inContact = false;
    }
    state_.verify = false;
    if (lazySurface_ && !start.global && !state_.inContact && !jumpedOut) {
      // a tracked contact ends only where the global query would not start one (leaveOrHold)
      state_.inContact = true;
      s.status = (s.status & ~SF_TRACK_LEAVE) | SF_TRACK_GLOBAL;
      lazyGlobalStep(*lazySurface_, *scene_, *cache_, refiner_, hip, options_, lambda_.data(), state_, s);
    }
    return s;
  }

  void reset() noexcept override {
    state_ = PatchContactState{};
    hint_ = PatchStepHint{};
  }
  void resetNear(int face, double xi, double eta) noexcept override {
    reset();
    if (face >= 0 && face < cache_->numFaces() && std::isfinite(xi) && std::isfinite(eta)) {
      hint_.face = face;
      hint_.X = Eigen::Vector2d(xi, eta);
    }
  }
  int patchesBuilt() const noexcept override { return lazy_ ? lazy_->constructions() : cache_->numFaces(); }
  const void* patchStore() const noexcept override {
    return lazy_ ? static_cast<const void*>(lazy_.get()) : static_cast<const void*>(cache_.get());
  }

 private:
  void remember(const RefineResult& r) noexcept { rememberIn(&hint_, r); }

  /// The contact-start verdict at `hip` without a prebuilt surface, on a scratch state: the lazy
  /// global step, or the polygon start (Section 4.1).
  bool insideAfterJump(const Eigen::Vector3d& hip) noexcept {
    PatchContactState scratch;
    ForceSample g;
    g.scp = hip;
    if (lazySurface_) {
      lazyGlobalStep(*lazySurface_, *scene_, *cache_, refiner_, hip, options_, lambda_.data(), scratch, g);
      return g.contact;
    }
    PatchStepStart start;
    if (!beginPatchStep(*scene_, nullptr, *cache_, hip, scratch, lambda_.data(), start, g)) return false;
    const RefineResult r = refiner_.refine(hip, start.face, start.X.x(), start.X.y(), options_, start.edge);
    finishPatchStep(*scene_, nullptr, refiner_, hip, start, r, options_, scratch, g);
    return g.contact;
  }

  std::shared_ptr<const PatchCache> cache_;
  std::shared_ptr<const PolygonScene> scene_;
  ForceOptions options_;
  ForceOptions seedOptions_;  ///< options_ with no iteration: a seed's evaluation and tests only
  std::shared_ptr<LazyPatches> lazy_;  ///< patches built on demand when the cache is a skeleton
  PatchRefiner refiner_;
  std::shared_ptr<const PatchSurface> surface_;    ///< InitialGuess::Surface, SurfaceIndex::Tessellation
  std::shared_ptr<LazyPatchSurface> lazySurface_;  ///< InitialGuess::Surface, SurfaceIndex::Bounds or lazy patches
  std::vector<double> lambda_;
  PatchContactState state_;
  /// the patch point the last refining step ended at (or resetNear's; face -1: none): seeds the
  /// next global query and bounds its candidate search
  PatchStepHint hint_;
};

}  // namespace

bool beginPatchStep(const PolygonScene& scene, const PatchSurface* surface, const PatchCache& cache,
                    const Eigen::Vector3d& hip, PatchContactState& state, double* lambda, PatchStepStart& start,
                    ForceSample& s, bool firstCandidate, const PatchStepHint& hint, CandidateList* list) noexcept {
  s = ForceSample{};
  s.scp = hip;
  start = PatchStepStart{};
  if (!inCoordinateRange(hip)) {  // not finite, or beyond the queries' range
    state.inContact = false;
    s.status = SF_TRACK_BAD_HIP;
    return false;
  }
  markJump(scene, hip, state);
  if (state.inContact && surface && surface->farBeyond(hip)) {
    // farther from the surface's box than its size: the contact ends, whatever tracking would
    // find (from 1e14 m away its refinement stalled at a point the HIP was "below"); nearer, a
    // HIP pushed through a thin part keeps its contact (no pop-through)
    state.inContact = false;
    s.status |= SF_TRACK_LEAVE;
  }
  if (state.inContact) {
    start.face = state.face;
    start.X = state.X;
    start.edge = state.edge;
    return true;
  }
  s.status |= SF_TRACK_GLOBAL;
  if (surface) {  // the global query on the patch surface
    const bool onFace = hint.face >= 0 && hint.face < cache.numFaces();
    // the band test tries the uniform triangle under the hint first
    start.windingVerdict = insideByWinding(*surface, hip, &start.reach, &start.reachFace, onFace ? hint.face : -1,
                                           hint.X, hint.point);
    if (start.windingVerdict == 0) {  // outside the closed surface beyond every error band: no patch work
      state.inContact = false;
      return false;
    }
    const bool hinted = onFace && hint.seed;
    if (hint.point.allFinite())
      tighterReach(*surface, (hip - hint.point).norm(), onFace ? hint.face : -1, start.reach, start.reachFace);
    start.global = true;
    if (!firstCandidate) return true;  // the caller runs the whole global query
    // the hint or the first candidate starts the refinement (with a list: every candidate, kept
    // for the finish). Seeded, the finish searches, bounded by the seed's refinement: nearer than
    // the hint's point, so fewer triangles are visited than a search bounded by the hint's.
    const bool keep = list && list->c && list->capacity >= 2;
    if (keep) list->count = 0;
    if (hinted) {
      start.seeded = true;
      start.face = hint.face;
      start.X = hint.X;
      start.candidate.face = hint.face;
      start.candidate.X = hint.X;
      return true;
    }
    const size_t found = keep ? surface->candidates(hip, list->c, static_cast<size_t>(list->capacity), start.reach,
                                                    start.reachFace)
                              : surface->candidates(hip, &start.candidate, 1, start.reach, start.reachFace);
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
                     PatchStepHint* next, const CandidateList* list) noexcept {
  if (start.global && start.candidate.face >= 0 && surface) {  // the rest of the global query on the patches
    // r started at the first candidate, or at the hint (its start is then not among the candidates)
    const SurfaceCandidate* from = start.seeded ? &start.candidate : nullptr;
    const bool whole = list && list->c && list->count > 0 && list->count < list->capacity;
    const PatchNearest q =
        whole ? refineCandidates(list->c, list->count, surface->spacing(), refiner, hip, options, &r, from, surface)
              : nearestOnPatches(*surface, refiner, hip, options, &r, start.reach, from, start.reachFace);
    if (start.seeded && q.candidates == 0) s.status |= SF_TRACK_NO_POLYGON;
    finishGlobalStep(*surface, hip, q, options, state, s, start.windingVerdict);
    rememberIn(next, q.nearest);
    return;
  }
  if (!start.global && state.inContact) r = detail::nearerAcrossCreases(scene, refiner, hip, r, options);
  rememberIn(next, r);
  if (start.global && start.facet >= 0 && (r.status & SF_TRACK_DEGENERATE)) {  // no patch here: the polygon
    r.scp = start.polygonPoint;
    r.normal = scene.facets().facetNormal[start.facet];
    r.face = start.face;
    r.edge = -1;
    r.xi = start.X.x();
    r.eta = start.X.y();
  }
  const bool ok = r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
  bool below = ok && (hip - r.scp).dot(r.normal) < 0;
  if (ok && !below && !start.global && state.inContact) below = detail::belowOtherSide(scene.cache(), refiner, hip, r);
  if (!below && state.inContact && surface && !start.global) {
    // a tracked contact ends only where the global query would not start one: inside a surface
    // fault the refinement can slide to a nearer sheet the HIP is above while the HIP is inside
    // the surface (the next step's global query entered again: the force switched on and off at
    // half the servo rate). The query runs only on such a step, from the point r ended at.
    leaveOrHold(*surface, refiner, hip, r, options, state, s, next);
    return;
  }
  if (below && state.verify && surface && !start.global) {
    // the HIP jumped: the tracked contact holds only where the HIP is inside
    state.verify = false;
    if (!insideAfterJump(*surface, refiner, hip, r, options, s)) below = false;
  }
  setContact(below, r, hip, options, state, s);
}

std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options,
                                                      std::shared_ptr<const PatchSurface> surface) {
  return detail::makeSharedPatchRenderer(std::move(cache), std::move(scene), options, std::move(surface), {});
}

namespace detail {
std::unique_ptr<ForceRenderer> makeSharedPatchRenderer(std::shared_ptr<const PatchCache> cache,
                                                       std::shared_ptr<const PolygonScene> scene,
                                                       const ForceOptions& options,
                                                       std::shared_ptr<const PatchSurface> surface,
                                                       const SharedLazyParts& lazy) {
  validateForceOptions(options);
  return std::make_unique<PatchTracker>(std::move(cache), std::move(scene), options, std::move(surface), lazy);
}
}  // namespace detail

}  // namespace sf
