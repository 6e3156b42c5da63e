// SPDX-License-Identifier: Apache-2.0
// Boxes that hold whole patches, computed without building or evaluating them: what the lazy
// global query uses to decide which patches can hold the nearest point.
#pragma once

#include <Eigen/Core>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// An axis-aligned box (m) that holds a face's whole patch and its base polygon.
struct PatchBox {
  Eigen::Vector3d lo{0, 0, 0}, hi{0, 0, 0};
  bool valid = false;  ///< false for a face without a patch (n outside 3..GP_MAX_N, non-finite input)

  /// Distance from p to the box (0 inside), m.
  double distance(const Eigen::Vector3d& p) const { return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm(); }
  /// Distance from p to the farthest point of the box, m: an upper bound of the distance from
  /// p to the nearest point of the patch inside.
  double farthest(const Eigen::Vector3d& p) const { return (p - lo).cwiseAbs().cwiseMax((p - hi).cwiseAbs()).norm(); }
};

/// The box of every face's patch (#F), from its vertices and normals alone: the face's edge
/// records (Eq. 6-14, buildPatchEdges: no quality sampling, no patch evaluation) bounded by
/// gp_patch_box (kernels/gp_bound.h: the patch is a convex combination of its corner
/// interpolators, each bounded term by term; for a triangle marked GP_ST_AFFINE instead the
/// triangle's box plus the box of its edges' deviations from their chords, each blended in with a
/// weight in [0, 1]), joined with the polygon's vertices, and widened
/// by 1e-9 (double caches) or 1e-5 (float) of the face's extent plus its distance from the
/// origin for rounding. Works on a skeleton
/// (preparePatchSkeleton) as on a built cache; the float patches of a float cache differ from
/// the double records bounded here by rounding only. oneTBB over faces. Never throws for
/// geometry.
std::vector<PatchBox> patchBoxes(const PatchCache& cache);

}  // namespace sf
