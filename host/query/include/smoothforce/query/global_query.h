// SPDX-License-Identifier: Apache-2.0
// The global contact query on the patch surface (Algorithm 1, lines 1-3): the nearest patch
// point to a HIP over every patch that can hold it, and whether the HIP is inside the surface.
// One definition for every caller: the patch method's tracker (force/), the sweep's probers on
// the CPU and with OpenCL refinement, and the batch surface query (surface_query.h).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

#include <smoothforce/base/status.h>  // SF_TRACK_* bits
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/refine_options.h>

namespace sf {

/// The PatchSurface options for these refinement (or force) options (level = tessellationLevel,
/// 0: chosen).
PatchSurfaceOptions patchSurfaceOptions(const RefineOptions& options);

/// A refined point that can carry a contact: not degenerate, finite, with a unit normal.
bool usableRefinement(const RefineResult& r) noexcept;

/// Whether the HIP (m), off the surface, lies in the tangent plane of the refined point r (within
/// 1e-9 rad), where rounding picks its side: r is then no interior nearest point (there HIP - SCP
/// runs along the normal) but one on the patch's boundary, on a crease curve, level with r's sheet
/// (a valley's corner), and r's side does not tell inside from outside.
bool levelWithTangentPlane(const RefineResult& r, const Eigen::Vector3d& hip) noexcept;

/// Keeps the tighter of two bounds on a point's distance to the patch surface (m; each with the
/// face of the patch point it is measured to, -1: unknown): the one whose candidate search
/// starts at the smaller radius (PatchSurface::searchRadius).
void tighterReach(const PatchSurface& surface, double r, int face, double& reach, int& reachFace) noexcept;

/// What the global query on the patch surface found (nearestOnPatches, refineCandidates).
struct PatchNearest {
  RefineResult nearest;       ///< the nearest refined point (SF_TRACK_DEGENERATE, face -1: none)
  RefineResult nearestBelow;  ///< the nearest refined point with the HIP below its tangent plane
  bool anyBelow = false;      ///< some refined point has (HIP - SCP) . n < 0
  bool anyAbove = false;      ///< some refined point has (HIP - SCP) . n >= 0
  double nearestAbove = std::numeric_limits<double>::infinity();  ///< m, the nearest such
  double minLower = 0;  ///< m, the smallest candidate lower bound (> 0: outside every error band)
  int candidates = 0, refined = 0;
};

/// Adds the refinements of `more` (a later batch of candidates of the same query) to q: the
/// nearest points kept where nearer (ties: q's), the flags and counts combined.
void mergeNearest(PatchNearest& q, const PatchNearest& more) noexcept;

/// Refines the candidates c[0..n) (sorted by lower bound: PatchSurface::candidates, or lazy
/// cells) whose lower bound is below the nearest distance found so far, skipping a start within
/// `spacing` (domain units) of an earlier start or result on the same face; with a surface, such
/// a skipped start is evaluated once the others are refined, and refined where the patch there
/// is nearer than every point found (another minimum within `spacing`). The order: with a
/// surface, by the distance to the candidate's triangle (ties as given), so that the triangle
/// under the HIP's foot point comes before a neighbour whose wider error bound put it first by
/// lower bound; without one (cells, no distance), as given, stopping at the first lower bound not
/// below the nearest distance. first, when given, is
/// a refinement already done: from c[0] when firstStart is null (the OpenCL sweep), else from
/// firstStart's (face, X) (a seed: PatchStepHint); a seed stands in for the first candidate
/// refined whose start lies within `spacing` of the seed's on the same face, when it converged
/// at its start to a strict local minimum (RefineResult::startMinimum) over that candidate's
/// own triangle (surface->overTriangle) no farther than the patch can be there (the
/// candidate's distance plus error bound); otherwise that candidate's refinement runs (the
/// candidates refined are those of the query without a seed) and first's point still counts
/// where it converged nearer than all of theirs and apart from them (more than 4 sin
/// (angleTolerance) times its distance), as does such a first that no candidate's turn reached;
/// the result is otherwise that of the query without a seed. surface: the
/// candidates' (null: a seed never stands in). Refinements that end degenerate are skipped.
/// Never throws or allocates.
PatchNearest refineCandidates(const SurfaceCandidate* c, int n, double spacing, PatchRefiner& refiner,
                              const Eigen::Vector3d& hip, const RefineOptions& options,
                              const RefineResult* first = nullptr, const SurfaceCandidate* firstStart = nullptr,
                              const PatchSurface* surface = nullptr) noexcept;

/// The most candidate batches (of PatchSurface::kMaxCandidates) nearestOnPatches refines.
/// The 28 bundled meshes need at most 23 (tests/query/test_global_query.cpp); patches that bulge
/// hundreds of face sizes (normals that disagree with the geometry) give nearly every triangle a
/// lower bound below the nearest distance, and this bounds a query's time there.
inline constexpr int kMaxCandidateBatches = 64;

/// The global nearest point of the patches to `hip` (m): PatchSurface::candidates, then
/// refineCandidates; where the candidate buffer is full and its last lower bound is below the
/// nearest distance found, the next candidates in turn (PatchSurface::candidates' `after`), so
/// that no candidate that could be nearer is left out, up to kMaxCandidateBatches batches.
/// Never throws or allocates.
/// first, firstStart: as in refineCandidates (a refinement already done; with firstStart, its
/// distance also bounds the candidate search).
/// reach, reachFace: an upper bound (m) of the HIP's distance to the patch surface when known
/// (the distance to a patch point, and that point's face or -1): PatchSurface::candidates
/// searches less; the candidates are the same.
PatchNearest nearestOnPatches(const PatchSurface& surface, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                              const RefineOptions& options, const RefineResult* first = nullptr,
                              double reach = std::numeric_limits<double>::infinity(),
                              const SurfaceCandidate* firstStart = nullptr, int reachFace = -1) noexcept;

/// Whether `hip` is inside the patch surface (Algorithm 1, line 3), from its global query, and
/// the SCP to start contact at (*scp). Closed surface (PatchSurface::closed): the winding number
/// of the tessellation (>= 1) where it is reliable (the HIP outside every triangle's error band),
/// and where the side is in doubt (a refined point within 3 times the nearest distance sees the
/// other side: overlapping or folded patches); otherwise the side of the nearest point's tangent
/// plane ((HIP - SCP) . n < 0). Inside, the SCP is the nearest refined point the HIP is below
/// (else the nearest). Open surface: "inside" is the side the normals point away from, within the
/// surface's reach: the nearest point is not held on a boundary edge and (HIP - SCP) . n < 0.
/// windingVerdict: insideByWinding(surface, hip) when the caller has it already (-2: not yet).
bool insidePatchSurface(const PatchSurface& surface, const Eigen::Vector3d& hip, const PatchNearest& q,
                        RefineResult* scp, int windingVerdict = -2) noexcept;

/// The part of insidePatchSurface that needs no refined point: on a closed surface with `hip`
/// outside every error band of the tessellation, the winding number decides alone (1 inside,
/// 0 outside); -1 otherwise (within a band, an open or empty surface: the global query decides). An
/// out-of-contact step with verdict 0 needs no patch work at all: no candidates, no refinement.
/// reach, reachFace, when given and the HIP is within a band: an upper bound (m) of its distance
/// to the patch surface and the face it is measured to (PatchSurface::inErrorBand); untouched
/// otherwise. hintFace, hintX, hintPoint: a patch point near the HIP, when known
/// (PatchSurface::inErrorBand).
int insideByWinding(
    const PatchSurface& surface, const Eigen::Vector3d& hip, double* reach = nullptr, int* reachFace = nullptr,
    int hintFace = -1, const Eigen::Vector2d& hintX = Eigen::Vector2d::Zero(),
    const Eigen::Vector3d& hintPoint = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())) noexcept;

/// The contact verdict on an open surface, which has no inside: the HIP below the nearest point
/// and on its normal line (a foot point: the angle between HIP - SCP and the normal within
/// kOpenFootSine), and that point not held on a boundary or fold edge. Where the nearest point
/// is not a foot point (a boundary, a fold edge or a corner, e.g. a double-sided sheet's rim: a
/// HIP 2 m beside a 1 m sheet was "below" one of its sides and got 1 kN of contact), its side
/// says nothing: no force rather than a guessed side. On a G1 surface every nearest point off
/// its boundary and folds is a foot point.
inline constexpr double kOpenFootSine = 1e-3;
inline bool openInside(const RefineResult& nearest, const Eigen::Vector3d& hip) noexcept {
  const Eigen::Vector3d r = hip - nearest.scp;
  return r.dot(nearest.normal) < 0 && r.cross(nearest.normal).norm() <= kOpenFootSine * r.norm() &&
         !(nearest.status & (SF_TRACK_BOUNDARY | SF_TRACK_FOLD_EDGE));
}

}  // namespace sf
