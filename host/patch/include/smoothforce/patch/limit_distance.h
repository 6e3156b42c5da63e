// SPDX-License-Identifier: Apache-2.0
// How far a cage's patch surface lies from the cage's Catmull-Clark limit surface.
#pragma once

#include <cstddef>

#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Two-sided distance between the patch surface and the limit surface, in fractions of the
/// bounding-box diagonal of the cache's base mesh (the limit positions).
/// patchToLimit: from every vertex of the patches' level-L ring tessellation (tessellate.h) to
/// the nearest point of the limit surface's triangles (tessellateLimitSurface, rate L);
/// limitToPatch: from every limit-tessellation point to the nearest point of the patches'
/// triangles. Each point is compared with the triangles of its own face and of every face
/// sharing a vertex with it (exact point-triangle distances, brute force), so each value is an
/// upper bound of the distance to the whole other tessellation. Both tessellations are piecewise
/// linear: their own deviation from the smooth surfaces (second order in 1/L) is included.
struct LimitDistance {
  double diagonal = 0;                               ///< m
  double maxPatchToLimit = 0, meanPatchToLimit = 0;  ///< fractions of the diagonal
  double maxLimitToPatch = 0, meanLimitToPatch = 0;  ///< fractions of the diagonal
  int worstFace = -1;                                ///< face of the largest of the two maxima
  size_t patchPoints = 0, limitPoints = 0;
  int facesMeasured = 0;  ///< faces with a built patch and a limit surface
};

/// Measures the distance for a cache built from `loaded` with CageMode::CatmullClark (the limit
/// surface is that of loaded.cagePositions on loaded.mesh's faces; faces are matched by index).
/// level: 1..64. approxLevel: Bfr's approximation level of irregular regions (1..10). Throws
/// std::invalid_argument when `loaded` holds no cage or its faces differ from the cache's,
/// InputError for a level out of range or a cage whose faces the fold repair cut (the limit
/// surface is that of the faces as read; --fold-repair off measures it).
LimitDistance measureLimitDistance(const PatchCache& cache, const LoadedMesh& loaded, int level = 16,
                                   int approxLevel = 8);

}  // namespace sf
