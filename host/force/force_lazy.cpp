// SPDX-License-Identifier: Apache-2.0
// The patch method's global query on a skeleton cache: faces chosen by their patch boxes,
// patches built only where they can hold the nearest point (force_tracking_detail.h).
#include <algorithm>
#include <limits>

#include <smoothforce/base/status.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/query/patch_refine.h>

#include "force_tracking_detail.h"

namespace sf::detail {

namespace {

/// Starts on one face closer than this (domain units) to an earlier start or result are not
/// refined again. Small: a cell is 0.5 of a sector's ray long, and a result held on a fold edge
/// must not hide the cell beside it (on the spot cage that cell held the nearest point).
constexpr double kStartSpacing = 0.02;
/// The most refinement starts one batch holds (the polygon start and the nearest cells).
constexpr int kMaxCandidates = 512;
/// The most batches of faces (LazyPatchSurface::kMaxFaces each) one step takes, and of cells
/// (kMaxCandidates each) per batch of faces: they bound a step's time where patches that bulge
/// far beyond their faces put thousands of boxes within reach. On the bundled meshes a HIP 5% of
/// the diagonal deep takes up to 22 face batches and never a second cell batch
/// (tests/query/test_lazy_query.cpp, test_held_contact.cpp).
constexpr int kMaxFaceBatches = 64;
constexpr int kMaxCellBatches = 16;

/// The most cells a face has (LazyPatchSurface::cells: kCellsPerSector per corner).
constexpr int kMaxFaceCells = LazyPatchSurface::kCellsPerSector * SF_MAX_PATCH_SIDES;

/// Collects into c[from, n) the cells of the faces near[0, m) whose lower bound (the larger of
/// the face's box distance and the cell's) is below `bound`, after `after` in candidateBefore
/// order when given, the first kMaxCandidates - from in that order; returns n. *more: cells
/// qualified beyond those kept. A cell's `triangle` holds its place in the batch of faces (face
/// rank x kMaxFaceCells + cell), so that ties in lower bound come in the order of the faces' box
/// distances (nearest box first: the face most likely to hold the nearest point is refined first,
/// and its distance prunes the rest). A face's cells, computed on first use, are sampled on the
/// lent evaluator's SIMD lanes (the step's refiner's).
int collectCells(LazyPatchSurface& surface, const PatchCache& cache, const FaceDistance* near, size_t m,
                 const Eigen::Vector3d& hip, double bound, const SurfaceCandidate* after, SurfaceCandidate* c, int from,
                 bool* more, FacePointEvaluator* evaluator) noexcept {
  int n = from;
  *more = false;
  for (size_t i = 0; i < m; ++i) {
    const int f = near[i].face;
    // the sector boxes first: most faces whose box is near stop here
    if (!surface.sectors(f)) continue;
    double faceLower = std::numeric_limits<double>::infinity();
    for (int k = 0; k < cache.faceSize(f); ++k) faceLower = std::min(faceLower, surface.sectorDistance(f, k, hip));
    if (!(std::max(near[i].distance, faceLower) < bound)) continue;
    const int cells = surface.cells(f, evaluator);
    for (int j = 0; j < cells; ++j) {
      SurfaceCandidate e;
      e.face = f;
      e.triangle = static_cast<int>(i) * kMaxFaceCells + j;
      e.lower = std::max(near[i].distance, surface.cellDistance(f, j, hip));
      if (!(e.lower < bound) || (after && !candidateBefore(*after, e))) continue;
      if (n == kMaxCandidates) {
        *more = true;
        if (!candidateBefore(e, c[n - 1])) continue;
      }
      int at = n < kMaxCandidates ? n++ : n - 1;
      for (; at > from && candidateBefore(e, c[at - 1]); --at) c[at] = c[at - 1];
      e.X = surface.cellStart(f, j, hip);
      c[at] = e;
    }
  }
  return n;
}

}  // namespace

std::shared_ptr<LazyPatchSurface> makeBoundsIndex(const PatchCache& cache, const PolygonScene& scene) {
  auto surface = std::make_shared<LazyPatchSurface>(cache, scene.facets());
  if (hasPatchData(cache)) surface->computeAllCells();
  return surface;
}

namespace {
/// r with its edge set to the domain edge its point lies on (within 1e-9) where the refinement
/// left it unset (it sets it on boundary and fold edges only).
RefineResult heldOnDomainEdge(const PatchCache& cache, RefineResult r) noexcept {
  if (r.edge >= 0 || r.face < 0 || r.face >= cache.numFaces()) return r;
  const int n = cache.faceSize(r.face);
  if (n < 3 || insideDomain(n, r.xi, r.eta, -1e-9)) return r;
  int k = 0;
  domainEdgeMax(n, {r.xi, r.eta}, k);
  r.edge = k;
  return r;
}
}  // namespace

void lazyGlobalStep(LazyPatchSurface& surface, const PolygonScene& scene, const PatchCache& cache,
                    PatchRefiner& refiner, const Eigen::Vector3d& hip, const ForceOptions& options, double* lambda,
                    PatchContactState& state, ForceSample& s) noexcept {
  const bool far = !surface.inAnySweptBox(hip);  // no a-priori box holds the HIP, or no swept box of those
  const bool closed = surface.closed();
  if (far && closed && !scene.contains(hip, Eigen::Vector3d::Zero())) {  // outside, beyond every patch: no patch work
    setContact(false, RefineResult{}, hip, options, state, s);
    return;
  }
  const NearestPolygonPoint np = scene.nearest(hip);
  if (np.face < 0) {
    s.status |= SF_TRACK_NO_POLYGON;
    setContact(false, RefineResult{}, hip, options, state, s);
    return;
  }
  // the polygon start first: its refined point bounds the nearest distance from above
  CandidateBuffer<kMaxCandidates> c;
  c[0] = SurfaceCandidate{};
  c[0].face = np.face;
  c[0].X = polygonToDomain(scene.facets(), cache, np.face, np.point, lambda);
  c[0].lower = -1;
  const RefineResult first = refiner.refine(hip, c[0].face, c[0].X.x(), c[0].X.y(), options);
  const double upper = usableRefinement(first) ? first.distance : std::numeric_limits<double>::infinity();
  // the faces in batches of kMaxFaces (box distance order), each face batch's cells in batches of
  // kMaxCandidates (lower bound order), each batch refined in turn while what a full one left out
  // could still be nearer than the nearest point found (dense meshes put hundreds of face
  // boxes within reach); the first cell batch also holds the polygon start, c[0]
  PatchNearest q;
  bool started = false;
  FaceDistance near[LazyPatchSurface::kMaxFaces], lastFace;
  const FaceDistance* afterFace = nullptr;
  auto bound = [&] { return started ? std::min(upper, q.nearest.distance) : upper; };
  for (int faceBatch = 0; faceBatch < kMaxFaceBatches; ++faceBatch) {
    size_t found = 0;
    const size_t m = surface.facesWithin(hip, bound(), near, LazyPatchSurface::kMaxFaces, &found, afterFace);
    SurfaceCandidate lastCell;
    const SurfaceCandidate* afterCell = nullptr;
    for (int cellBatch = 0; cellBatch < kMaxCellBatches; ++cellBatch) {
      bool more = false;
      const int n = collectCells(surface, cache, near, m, hip, bound(), afterCell, c.data(), started ? 0 : 1, &more,
                                 refiner.pointEvaluator());
      const PatchNearest b =
          refineCandidates(c.data(), n, kStartSpacing, refiner, hip, options, started ? nullptr : &first);
      if (started)
        mergeNearest(q, b);
      else
        q = b;
      started = true;
      if (!more || !(c[n - 1].lower < q.nearest.distance)) break;
      lastCell = c[n - 1];
      afterCell = &lastCell;
    }
    if (found <= m || m == 0) break;
    lastFace = near[m - 1];
    afterFace = &lastFace;
    if (!(lastFace.distance < q.nearest.distance)) break;
  }
  bool inside = false;
  RefineResult scp = q.nearest;
  if (usableRefinement(q.nearest)) {
    const bool below = (hip - q.nearest.scp).dot(q.nearest.normal) < 0;
    // held on a fold edge of a closed mesh, the point has two sides by itself: on a crease curve
    // (a valley's, or a ridge's seen from outside) the two sides' tangent planes decide
    // (creaseSidesVerdict); elsewhere the base polygons' inside test decides (a sheet about as
    // near on the other side is left to the nearest point: on the spot cage's folds the polygons
    // disagree with the patches more often than not)
    const bool foldEdge = q.nearest.status & SF_TRACK_FOLD_EDGE;
    // a HIP level with its nearest point (on a crease curve) is on neither side of it: the
    // crease's two sides decide as on a fold edge (at a valley, level with one sheet and below
    // the other is inside)
    const bool level = levelWithTangentPlane(q.nearest, hip);
    const bool conflict = foldEdge || level;
    const int creaseVerdict =
        conflict && closed && !far ? creaseSidesVerdict(cache, refiner, hip, heldOnDomainEdge(cache, q.nearest)) : -1;
    if (far && closed)
      inside = true;
    else if (closed)
      inside = !conflict            ? below
               : creaseVerdict >= 0 ? creaseVerdict == 1
               : foldEdge           ? scene.contains(hip, Eigen::Vector3d::Zero())
                                    : below;
    else  // open: no inside; only the side of a point off every boundary and fold edge (openInside)
      inside = openInside(q.nearest, hip);
    // the SCP: the nearest point the HIP is below; a level nearest point is itself the nearest
    // (a refinement on the other sheet can stall along the crease short of it)
    if (inside && q.anyBelow && !level) scp = q.nearestBelow;
  }
  if (inside) s.status |= SF_TRACK_INSIDE;
  setContact(inside, scp, hip, options, state, s);
}

}  // namespace sf::detail
