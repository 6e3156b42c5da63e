// The patch method's global query on a skeleton cache: faces chosen by their patch boxes,
// patches built only where they can hold the nearest point (force_tracking_detail.h).
#include <algorithm>
#include <limits>

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
/// The most refinement starts one step considers (the polygon start and the nearest cells).
constexpr int kMaxCandidates = 512;

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
  const double upper = usable(first) ? first.distance : std::numeric_limits<double>::infinity();
  FaceDistance near[LazyPatchSurface::kMaxFaces];
  const size_t m = surface.facesWithin(hip, upper, near, LazyPatchSurface::kMaxFaces);
  int n = 1;  // c[1..n): the cells below the upper bound, sorted by lower bound, the lowest kMaxCandidates kept
  for (size_t i = 0; i < m; ++i) {
    const int f = near[i].face;
    // the sector boxes first: most faces whose a-priori box is near stop here
    if (!surface.sectors(f)) continue;
    double faceLower = std::numeric_limits<double>::infinity();
    for (int k = 0; k < cache.faceSize(f); ++k) faceLower = std::min(faceLower, surface.sectorDistance(f, k, hip));
    if (!(std::max(near[i].distance, faceLower) < upper)) continue;
    const int cells = surface.cells(f);
    for (int j = 0; j < cells; ++j) {
      const double lower = std::max(near[i].distance, surface.cellDistance(f, j, hip));
      if (!(lower < upper) || (n == kMaxCandidates && lower >= c[n - 1].lower)) continue;
      int at = n < kMaxCandidates ? n++ : n - 1;
      for (; at > 1 && c[at - 1].lower > lower; --at) c[at] = c[at - 1];
      c[at] = SurfaceCandidate{};
      c[at].face = f;
      c[at].X = surface.cellStart(f, j, hip);
      c[at].lower = lower;
    }
  }
  const PatchNearest q = refineCandidates(c.data(), n, kStartSpacing, refiner, hip, options, &first);
  bool inside = false;
  RefineResult scp = q.nearest;
  if (usable(q.nearest)) {
    const bool below = (hip - q.nearest.scp).dot(q.nearest.normal) < 0;
    // held on a fold edge of a closed mesh, the point has two sides by itself: the base polygons'
    // inside test decides (a sheet about as near on the other side is left to the nearest point:
    // on the spot cage's folds the polygons disagree with the patches more often than not)
    const bool conflict = q.nearest.status & SF_TRACK_FOLD_EDGE;
    if (far && closed)
      inside = true;
    else if (closed)
      inside = conflict ? scene.contains(hip, Eigen::Vector3d::Zero()) : below;
    else  // open: no inside; only the side of a point off every boundary and fold edge (openInside)
      inside = openInside(q.nearest, hip);
    if (inside && q.anyBelow) scp = q.nearestBelow;
  }
  if (inside) s.status |= SF_TRACK_INSIDE;
  setContact(inside, scp, hip, options, state, s);
}

}  // namespace sf::detail
