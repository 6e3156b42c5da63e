// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/global_query.h>

#include <smoothforce/patch/patch_eval.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sf {

namespace {

/// A refined point on the other side than the nearest one, within this factor of its distance,
/// makes the side of the nearest point doubtful (overlapping or folded patches).
constexpr double kConflict = 3.0;

}  // namespace

PatchSurfaceOptions patchSurfaceOptions(const RefineOptions& o) {
  PatchSurfaceOptions so;
  so.level = o.tessellationLevel;
  return so;
}

bool usableRefinement(const RefineResult& r) noexcept {
  return !(r.status & SF_TRACK_DEGENERATE) && r.scp.allFinite() && r.normal.allFinite() && r.normal.squaredNorm() > 0.5;
}

bool levelWithTangentPlane(const RefineResult& r, const Eigen::Vector3d& hip) noexcept {
  const Eigen::Vector3d toHip = hip - r.scp;
  return toHip.squaredNorm() > 0 && std::abs(toHip.dot(r.normal)) <= 1e-9 * toHip.norm();
}

void tighterReach(const PatchSurface& surface, double r, int face, double& reach, int& reachFace) noexcept {
  if (surface.searchRadius(r, face) < surface.searchRadius(reach, reachFace)) {
    reach = r;
    reachFace = face;
  }
}

void mergeNearest(PatchNearest& q, const PatchNearest& more) noexcept {
  if (more.nearest.distance < q.nearest.distance) q.nearest = more.nearest;
  if (more.nearestBelow.distance < q.nearestBelow.distance) q.nearestBelow = more.nearestBelow;
  q.anyBelow = q.anyBelow || more.anyBelow;
  q.anyAbove = q.anyAbove || more.anyAbove;
  q.nearestAbove = std::min(q.nearestAbove, more.nearestAbove);
  q.minLower = std::min(q.minLower, more.minLower);
  q.candidates += more.candidates;
  q.refined += more.refined;
}

namespace {

/// The starts of candidates c[skipped[0..n)] whose lower bound is below `nearest` evaluated on
/// the patch (distance to hip, infinite where the start is no patch point), then those nearer
/// than `nearest` refined through `take`,
/// nearest start first, while they stay nearer than the nearest found (`nearest`, updated by
/// take). simd: the refiner's SIMD evaluator reads the cache's records in place (a prebuilt double
/// cache); otherwise the starts are evaluated one at a time through the refiner (float records).
template <class Take>
void refineSkipped(const SurfaceCandidate* c, int* skipped, int n, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                   const RefineOptions& options, Take& take, const double& nearest, bool simd) noexcept {
  FacePointEvaluator* ev = simd ? refiner.pointEvaluator() : nullptr;
  int kept = 0;  // those whose lower bound is still below the nearest found
  for (int k = 0; k < n; ++k)
    if (c[skipped[k]].lower < nearest) skipped[kept++] = skipped[k];
  n = kept;
  double dist[PatchSurface::kMaxCandidates];
  bool done[PatchSurface::kMaxCandidates] = {};
  for (int a = 0; a < n; ++a) {
    if (done[a]) continue;
    const int f = c[skipped[a]].face;
    int at[16], m = 0;
    double xi[16], eta[16];
    for (int b = a; b < n && m < 16; ++b)
      if (!done[b] && c[skipped[b]].face == f) {
        done[b] = true;
        at[m] = b;
        xi[m] = c[skipped[b]].X.x();
        eta[m++] = c[skipped[b]].X.y();
      }
    PatchPoint p[16];
    const bool evaluable = refiner.evaluable(f);
    if (evaluable && ev)
      ev->evaluate(f, xi, eta, m, p);
    else if (evaluable)  // float records: one at a time through the refiner's own buffer
      for (int k = 0; k < m; ++k) p[k] = refiner.eval(f, Eigen::Vector2d(xi[k], eta[k]));
    for (int k = 0; k < m; ++k)
      dist[at[k]] =
          evaluable && !(p[k].status & (SF_ST_OUTSIDE | SF_ST_TOO_MANY_SIDES | SF_ST_NONFINITE)) && p[k].pos.allFinite()
              ? (p[k].pos - hip).norm()
              : std::numeric_limits<double>::infinity();
  }
  for (int k = 1; k < n; ++k)  // by start distance (insertion sort: a handful)
    for (int j = k; j > 0 && dist[j - 1] > dist[j]; --j) {
      std::swap(dist[j - 1], dist[j]);
      std::swap(skipped[j - 1], skipped[j]);
    }
  for (int k = 0; k < n && dist[k] < nearest; ++k) {
    const SurfaceCandidate& s = c[skipped[k]];
    take(s.face, s.X, refiner.refine(hip, s.face, s.X.x(), s.X.y(), options));
  }
}

}  // namespace

PatchNearest refineCandidates(const SurfaceCandidate* c, int n, double spacing, PatchRefiner& refiner,
                              const Eigen::Vector3d& hip, const RefineOptions& options,
                              const RefineResult* first, const SurfaceCandidate* firstStart,
                              const PatchSurface* surface) noexcept {
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
  auto account = [&](const RefineResult& r) {
    if (!usableRefinement(r)) return;
    const bool below = (hip - r.scp).dot(r.normal) < 0;
    (below ? q.anyBelow : q.anyAbove) = true;
    if (!below) q.nearestAbove = std::min(q.nearestAbove, r.distance);
    if (r.distance < q.nearest.distance) q.nearest = r;
    if (below && r.distance < q.nearestBelow.distance) q.nearestBelow = r;
  };
  auto take = [&](int f, const Eigen::Vector2d& X, const RefineResult& r) {
    ++q.refined;
    if (seen + 2 <= 2 * kSeen) {
      seenFace[seen] = f;
      seenX[seen++] = X;
      seenFace[seen] = r.face;
      seenX[seen++] = Eigen::Vector2d(r.xi, r.eta);
    }
    account(r);
  };
  // the refinement already done: from c[0]; or from a seed, which stands in for the first
  // candidate refined whose start lies within `spacing` of the seed's on the same face, only
  // where it converged at its start to a strict local minimum (RefineResult::startMinimum: a
  // seed that had to move, or sits at a saddle or maximum of the distance, may have left the
  // candidate's basin) over that candidate's own triangle (two minima within one small, nearly
  // flat triangle's region are what the error bounds exclude; within `spacing` they are not)
  // no farther than the patch can be there (its distance + error bound); otherwise the
  // candidate's own refinement runs: the candidates refined are those of the query without it.
  // The seed's point, a point of the patch surface like theirs, then still counts where it is
  // nearer than all of theirs (below): the candidate's refinement may have ended in another basin
  // (two minima of the distance within `spacing` on one face, which the skip of the candidates
  // beside it then never reaches).
  bool pending = first != nullptr, standIn = false;
  auto matches = [&](int i) {
    return firstStart ? c[i].face == firstStart->face && (c[i].X - firstStart->X).norm() < spacing : i == 0;
  };
  // the order: candidates of a PatchSurface by their triangle's distance (ties: as given), so that
  // the triangle under the HIP's foot point comes before a neighbour whose wider error bound
  // gave it a lower bound below its own (sorted by lower bound, that neighbour's refinement ran
  // first and a seed over the foot point's triangle could not stand in for it); others (cells,
  // no distance) by lower bound
  const bool byDistance = surface && n <= static_cast<int>(PatchSurface::kMaxCandidates);
  int order[PatchSurface::kMaxCandidates];
  for (int k = 0; byDistance && k < n; ++k) {  // insertion sort: a handful of candidates
    int at = k;
    for (; at > 0 && c[order[at - 1]].distance > c[k].distance; --at) order[at] = order[at - 1];
    order[at] = k;
  }
  int deferred[PatchSurface::kMaxCandidates];
  int nDeferred = 0;
  for (int k = 0; k < n; ++k) {
    const int i = byDistance ? order[k] : k;
    if (c[i].lower >= q.nearest.distance) {
      if (byDistance) continue;  // a later one may still have a lower bound below it
      break;
    }
    if (near(c[i].face, c[i].X)) {  // checked below, once every other candidate is refined
      if (surface && nDeferred < static_cast<int>(PatchSurface::kMaxCandidates)) deferred[nDeferred++] = i;
      continue;
    }
    if (pending && matches(i)) {
      pending = false;
      if (!firstStart) {
        take(c[i].face, c[i].X, *first);
        standIn = true;
        continue;
      }
      if (surface && first->startMinimum && first->distance <= 2 * c[i].distance - c[i].lower &&
          surface->overTriangle(c[i].triangle, first->face, Eigen::Vector2d(first->xi, first->eta))) {
        // the seed's own start, not the candidate's, marks the basin explored: the candidate's
        // point may lie in another basin the error bound allows over that triangle, which the
        // candidates beside it must still reach
        take(firstStart->face, firstStart->X, *first);
        standIn = true;
        continue;
      }
    }
    take(c[i].face, c[i].X, refiner.refine(hip, c[i].face, c[i].X.x(), c[i].X.y(), options));
  }
  // a candidate skipped as within `spacing` of a start or result refined is taken for the same
  // basin, unless the patch at its own start is nearer than every point found: the refinement
  // only descends, so from there it ends nearer still, in a basin not yet explored (two minima
  // of the distance within `spacing` on one face). Its start is evaluated to tell, 16 points of a
  // face at a time on the refiner's SIMD evaluator, and those nearer are refined, nearest first.
  if (nDeferred > 0)
    refineSkipped(c, deferred, nDeferred, refiner, hip, options, take, q.nearest.distance,
                  surface->cache().options.precision == Precision::Double);
  // a converged point nearer than every candidate's and not theirs (apart by more than the
  // refinement's tolerance: a seed that did not converge, or converged to the same point, leaves
  // the result of the query without a seed)
  if (first && !standIn && usableRefinement(*first) && (first->status & SF_TRACK_CONVERGED) &&
      first->distance < q.nearest.distance &&
      !((first->scp - q.nearest.scp).norm() <= 4 * std::sin(options.angleTolerance) * first->distance))
    account(*first);
  return q;
}

PatchNearest nearestOnPatches(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                              const RefineOptions& options, const RefineResult* first, double reach,
                              const SurfaceCandidate* firstStart, int reachFace) noexcept {
  if (first && firstStart && usableRefinement(*first)) tighterReach(surface, first->distance, first->face, reach, reachFace);
  CandidateBuffer<> c;
  int n = static_cast<int>(surface.candidates(hip, c.data(), c.size(), reach, reachFace));
  PatchNearest q = refineCandidates(c.data(), n, surface.spacing(), refiner, hip, options, first, firstStart, &surface);
  // a full buffer holds the candidates of lowest lower bound; those it left out matter where their
  // lower bounds (at least the last one's) are below the nearest distance found: the next ones,
  // refined in turn, until none is (a bulging patch's wide error bounds can crowd the buffer), at
  // most kMaxCandidateBatches batches in all
  for (int batch = 1;
       batch < kMaxCandidateBatches && n == static_cast<int>(c.size()) && c[n - 1].lower < q.nearest.distance;
       ++batch) {
    const SurfaceCandidate last = c[n - 1];
    if (usableRefinement(q.nearest)) tighterReach(surface, q.nearest.distance, q.nearest.face, reach, reachFace);
    n = static_cast<int>(surface.candidates(hip, c.data(), c.size(), reach, reachFace, &last));
    mergeNearest(q,
                 refineCandidates(c.data(), n, surface.spacing(), refiner, hip, options, nullptr, nullptr, &surface));
  }
  return q;
}

int insideByWinding(const PatchSurface& surface, const Eigen::Vector3d& hip, double* reach, int* reachFace,
                    int hintFace, const Eigen::Vector2d& hintX, const Eigen::Vector3d& hintPoint) noexcept {
  if (!surface.closed() || surface.numTriangles() == 0 ||
      surface.inErrorBand(hip, reach, reachFace, hintFace, hintX, hintPoint))
    return -1;
  return surface.winding(hip) >= 1 ? 1 : 0;
}

bool insidePatchSurface(const PatchSurface& surface, const Eigen::Vector3d& hip, const PatchNearest& q,
                        RefineResult* scp, int windingVerdict) noexcept {
  if (scp) *scp = q.nearest;
  if (!usableRefinement(q.nearest)) return false;
  const bool below = (hip - q.nearest.scp).dot(q.nearest.normal) < 0;
  if (!surface.closed()) return openInside(q.nearest, hip);
  // the side of the nearest point decides, unless the winding number is reliable here (outside every
  // error band) or a refined point about as near sees the other side (overlapping or folded patches)
  // (a nearest point held on a fold edge has two sides by itself: the two faces disagree there)
  const bool conflict = (q.nearest.status & SF_TRACK_FOLD_EDGE) ||
                        (below ? q.anyAbove && q.nearestAbove <= kConflict * q.nearest.distance
                               : q.anyBelow && q.nearestBelow.distance <= kConflict * q.nearest.distance);
  const int verdict = windingVerdict == -2 ? insideByWinding(surface, hip) : windingVerdict;
  const bool useWinding = conflict || verdict >= 0;
  const bool inside = useWinding ? (verdict >= 0 ? verdict == 1 : surface.winding(hip) >= 1) : below;
  // the SCP: the nearest point the HIP is below; a nearest point level with the HIP (on a valley's
  // crease) is itself the nearest (a refinement on the other sheet can stall along the crease
  // short of it)
  if (inside && scp && q.anyBelow && !levelWithTangentPlane(q.nearest, hip)) *scp = q.nearestBelow;
  return inside;
}

}  // namespace sf
