// SPDX-License-Identifier: Apache-2.0
// Patch construction on the CPU with options: backend, threads and SIMD target.
#pragma once

#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_simd.h>

namespace sf {

/// Options of constructPatches.
struct BuildOptions {
  Backend backend = Backend::Tbb;      ///< Serial (the calling thread) or Tbb
  int threads = 0;                     ///< Tbb worker limit (<= 0: oneTBB's default), in a task_arena
  SimdTarget simd = SimdTarget::Auto;  ///< instruction set (patch_simd.h); every one gives the same bits
};

/// Builds every patch and its quality as constructPatches(cache, backend, threads) does (that
/// one is this with SimdTarget::Auto). With a SIMD target, faces of one size are built side by
/// side, one per lane: records, status and bulge are bit-identical to Scalar's (the quality
/// uses the same 15 samples per edge). Throws std::invalid_argument for Backend::OpenCL, a
/// target this CPU or build lacks, or a skeleton cache (no patch arrays).
void constructPatches(PatchCache& cache, const BuildOptions& options);

/// Builds the patches of `faces` only (face ids, each at most once), bit-identical to what
/// constructPatches builds for them; every other face keeps its records, status and bulge. The
/// edge tangents are refreshed for the whole mesh from the current corner normals (vertex fans,
/// tangent_fans.h), so the caller must list every face whose inputs changed since its patch was
/// built: its corners' positions or normals, or an end tangent of one of its edges (a turned
/// normal can change the fan, and so the end tangents, at a neighbouring vertex). For callers
/// that change a few normals and rebuild many times (the normal search). Throws
/// std::invalid_argument as constructPatches does, and for a face id out of range or repeated.
void constructPatchesOf(PatchCache& cache, const std::vector<int>& faces, const BuildOptions& options);

/// The tolerances of markAffineTriangles in a double and a float cache (isAffineTriangle).
inline constexpr double kAffineTriangleTolerance = 1e-9, kAffineTriangleToleranceFloat = 1e-5;

/// For a triangle's built records (3 x GP_E_NFIELDS, record-major) that are a flat triangle whose
/// patch the default construction takes as its affine map plus its edges' deviations from their
/// chords (kernels/gp_eval.h, gp_patch_eval_affine3), a proven lower bound > 0 on the cosine
/// between that map's normal and the plane's over the whole domain; else 0. Such a triangle has
/// every corner normal equal to the unit normal of V_0 V_1 V_2 (right-handed; within `tolerance`)
/// and that normal defined (twice the area above `tolerance` times the longest edge squared),
/// every end tangent in that plane (within `tolerance` of its edge's length) and running along its
/// edge (positive along the chord), and a map proven regular: det(A + P) > 0 in the plane, A the
/// affine map's Jacobian and P the part of the curved edges' deviations, bounded over the domain
/// from the deviations' directions against A (a straight edge adds nothing: the affine map's
/// margin is 1 up to the tangents' tolerance). 0 for n != 3. The default tolerance is the default
/// construction's for records of that precision.
double affineTriangleMargin(int n, const double* recs, double tolerance = kAffineTriangleTolerance);
double affineTriangleMargin(int n, const float* recs, double tolerance = kAffineTriangleToleranceFloat);

/// affineTriangleMargin > 0: the triangles markAffineTriangles marks.
bool isAffineTriangle(int n, const double* recs, double tolerance = kAffineTriangleTolerance);
bool isAffineTriangle(int n, const float* recs, double tolerance = kAffineTriangleToleranceFloat);

/// The default construction's treatment of flat triangles (fold repair on; nothing with
/// FoldRepairMode::Off): every built triangle of `faces` (null: all) whose records pass
/// isAffineTriangle (its default tolerance) gets GP_ST_AFFINE, so that every evaluation takes its
/// patch as the affine map of the domain triangle plus its curved edges' deviations from their
/// chords (kernels/gp_eval.h, gp_patch_eval_affine3: the same boundary and tangent plane, regular),
/// and its quality bits and bulge measured again on that map. The Gregory patch of such a triangle
/// folds in its own plane where the triangle is thin or obtuse (docs/fold-levers.md).
/// constructPatches, constructPatchesOf, the lazy construction and the OpenCL construction apply
/// it; a triangle already marked is left as it is. Throws std::invalid_argument for a skeleton
/// cache.
void markAffineTriangles(PatchCache& cache, const std::vector<int>* faces = nullptr);

}  // namespace sf
