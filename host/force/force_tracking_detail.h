// SPDX-License-Identifier: Apache-2.0
// Private to the force module: the pieces of a patch step shared by the tracker's global
// queries (force_tracking.cpp on a prebuilt cache, force_lazy.cpp on a skeleton).
#pragma once

#include <Eigen/Geometry>

#include <smoothforce/force/force_tracking.h>

namespace sf {

class LazyPatchSurface;
class LazyPatches;
class PolygonScene;

namespace detail {

/// The lazy parts of patch trackers over one skeleton that step on one thread (SharedGeometry):
/// the patch store and its surface (built from the trackers' shared PolygonScene's facets).
/// Null: the tracker makes its own.
struct SharedLazyParts {
  std::shared_ptr<LazyPatches> patches;
  std::shared_ptr<LazyPatchSurface> surface;
};

/// The boxes of the bounds index (LazyPatchSurface) over `cache`, on the facets of the renderers'
/// PolygonScene; on a prebuilt cache every cell computed now, so that no servo step computes one
/// (a skeleton's cells follow the patches built on demand). Throws as LazyPatchSurface's
/// constructor.
std::shared_ptr<LazyPatchSurface> makeBoundsIndex(const PatchCache& cache, const PolygonScene& scene);

/// makePatchForceRenderer with the lazy parts given (shared_geometry.cpp).
std::unique_ptr<ForceRenderer> makeSharedPatchRenderer(std::shared_ptr<const PatchCache> cache,
                                                       std::shared_ptr<const PolygonScene> scene,
                                                       const ForceOptions& options,
                                                       std::shared_ptr<const PatchSurface> surface,
                                                       const SharedLazyParts& lazy);

/// A tracking step's refinement r, or a nearer point on another sheet where r's face touches a
/// crease (crease_sheets.cpp): across its crease edges and around its corners where creases meet,
/// each sheet whose tangent plane the HIP is below within 4 tracked distances is refined from
/// there, and a nearer converged point below which the HIP lies wins. Never throws or allocates.
RefineResult nearerAcrossCreases(const PolygonScene& scene, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                                 const RefineResult& r, const ForceOptions& options) noexcept;

/// Whether the HIP is below the other side's tangent plane at an SCP held on a crease edge
/// (r.edge): under a valley the HIP is below at least one of the two sides.
bool belowOtherSide(const PatchCache& cache, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                    const RefineResult& r) noexcept;

/// The inside verdict of a HIP whose nearest point r is held on a crease edge (r.edge, a fold
/// edge of the refinement: the crease curve itself is nearest), from the two sides' tangent
/// planes there: 1 below both, 0 above both; where they disagree, 1 at a valley (the other
/// sheet rises above r's tangent plane just past the crease: the solid is the union of the two
/// half spaces there) and 0 at a ridge (their intersection); -1 where r is not held on a crease
/// edge. Never throws or allocates.
int creaseSidesVerdict(const PatchCache& cache, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                       const RefineResult& r) noexcept;

/// Ends a step: contact at SCP r (F = k (SCP - HIP)) or none; keeps the contact state.
void setContact(bool contact, const RefineResult& r, const Eigen::Vector3d& hip, const ForceOptions& options,
                PatchContactState& state, ForceSample& s) noexcept;

/// The global query of an out-of-contact patch step on a skeleton whose patches are built
/// lazily (Algorithm 1, lines 1-3), ending the step (state, s). The HIP is finite and s has
/// SF_TRACK_GLOBAL set. lambda: scratch for the largest face's size.
/// - Outside every a-priori box of a closed mesh, or outside the swept boxes of the faces whose
///   a-priori box holds the HIP (LazyPatchSurface::inAnySweptBox), the base polygons' inside test decides
///   (PolygonScene::contains; lazy_surface.h says why it equals the patch surface's there);
///   outside: no patch work at all (no patch built, no refinement).
/// - Otherwise the polygon start (nearest polygon point, mean value coordinates, refinement)
///   gives an upper bound U of the nearest distance; every cell (LazyPatchSurface::cells) of
///   every face whose box (LazyPatchSurface::faceBox) is within U of the HIP is a candidate, its lower bound the
///   larger of the face's and the cell's box distance, its start the cell's point under the HIP (cellStart);
///   refineCandidates refines them in order of lower bound until the next is not below the
///   nearest distance found (only those faces' patches are built). The faces come in batches of
///   LazyPatchSurface::kMaxFaces (box distance order), their cells in batches of 511 (lower
///   bound order); the next batch is taken while the last of a full one is below the nearest
///   distance found (at most 64 face batches of 16 cell batches each).
/// - Contact when the HIP is inside: by the polygons outside those boxes; else on the side the
///   nearest refined point's normal points away from (an open mesh: and not held on a boundary
///   edge), except where the nearest point is held on a fold edge of a closed mesh (two sides by
///   itself), where the base polygons' inside test decides (a heuristic there: exact only
///   outside those boxes). The SCP is the nearest refined point the HIP is below.
void lazyGlobalStep(LazyPatchSurface& surface, const PolygonScene& scene, const PatchCache& cache,
                    PatchRefiner& refiner, const Eigen::Vector3d& hip, const ForceOptions& options, double* lambda,
                    PatchContactState& state, ForceSample& s) noexcept;

}  // namespace detail
}  // namespace sf
