// SPDX-License-Identifier: Apache-2.0
// How far one surface lies from another: a patch surface from another patch surface (the same
// mesh under two constructions) or from polygons (a dense mesh of the same shape).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// What a cache stands for in measureSurfaceDistance: its patch surface (the cache must be
/// prebuilt), or its base polygons (a dense mesh; a skeleton will do): each polygon flat to
/// rounding as itself, every other one as the fan of triangles (centroid, V_k, V_k+1), flat
/// polygons with a reflex corner cut into convex pieces first (the same point set).
enum class DistanceSurface { Patches, Polygons };

/// "patches" or "polygons" (the Python and C keyword `to`). Throws InputError
/// "to: expected patches|polygons, got '...'".
DistanceSurface parseDistanceSurface(const std::string& text);

/// One direction of measureSurfaceDistance: from every sample of one surface to the nearest
/// point of the other.
struct DistanceDirection {
  double max = 0;                          ///< fraction of the diagonal
  double mean = 0;                         ///< fraction of the diagonal
  size_t points = 0;                       ///< samples measured
  int worstFace = -1;                      ///< face (of the sampled surface) of the farthest sample
  Eigen::Vector3d worstPoint{0, 0, 0};     ///< m, that sample
};

/// Both directions, in fractions of `diagonal`.
struct SurfaceDistance {
  double diagonal = 0;      ///< m: boundingDiagonal(a), its referenced vertices' box
  int levelA = 0, levelB = 0;  ///< the sample levels used (sampleLevel)
  DistanceDirection aToB;   ///< from a's samples to b
  DistanceDirection bToA;   ///< from b's samples to a
};

/// Samples per surface at most (about; 4 million points are about 100 MB of coordinates).
inline constexpr double kMaxDistanceSamples = 4e6;

/// The level measureSurfaceDistance samples c at: `level`, lowered (to 1 at least) until c's
/// samples stay within kMaxDistanceSamples, so that a dense mesh of millions of polygons is
/// measured in bounded memory.
int sampleLevel(const PatchCache& c, int level);

/// The samples measureSurfaceDistance takes of `c` as `as` stands for it: x, y, z per point (m)
/// and the face each lies on.
struct SurfaceSamples {
  std::vector<double> xyz;  ///< 3 per point
  std::vector<int> face;    ///< per point
  size_t size() const { return face.size(); }
};
SurfaceSamples sampleSurface(const PatchCache& c, DistanceSurface as, int level);

/// The distance (m) from each of points[0, 3 count) to the surface `to` stands for (`as`):
/// its nearest patch point (SurfaceQuery) or polygon point (PolygonScene). NaN for a point
/// without one (not finite, or beyond the coordinate range). Parallel (threads <= 0: all cores).
std::vector<double> distancesToSurface(const PatchCache& to, DistanceSurface as, const double* points, size_t count,
                                       int threads = 0);

/// The two one-sided distances between a and b, each as what it stands for (`aAs`, `bAs`).
/// Samples (at sampleLevel(c, level) each): a patch surface's level-L ring points of every built patch (tessellate.h:
/// 1 + n L (L+1) / 2 per n-gon); polygons' points on the same rings over each polygon's fan
/// triangles from its centroid. Nearest points: on a patch surface the global nearest-point
/// query (SurfaceQuery, exact to the refinement's tolerances); on polygons the exact nearest
/// point (PolygonScene over the facets above). Their max is the two-sided Hausdorff distance of the samples, a lower
/// bound of the surfaces' that converges as L grows. Throws InputError for a level outside
/// [1, 64] or a patch surface whose cache has no patch data, and when a sample has no nearest
/// point (a non-finite sample or an empty surface).
SurfaceDistance measureSurfaceDistance(const PatchCache& a, DistanceSurface aAs, const PatchCache& b,
                                       DistanceSurface bAs, int level = 8, int threads = 0);

}  // namespace sf
