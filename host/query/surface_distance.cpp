// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/surface_distance.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/mesh/polygon_split.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/polygon_facets.h>
#include <smoothforce/query/surface_query.h>

namespace sf {
namespace {

void add(SurfaceSamples& s, const Eigen::Vector3d& p, int f) {
  s.xyz.insert(s.xyz.end(), {p.x(), p.y(), p.z()});
  s.face.push_back(f);
}

/// c's polygons, the flat non-convex ones cut into convex pieces (splitBadCorners: the same
/// point set), so that every piece is the fan of triangles from its centroid or, flat to
/// rounding, that polygon itself; source[piece] = c's face.
struct PolygonPieces {
  PatchCache pieces;  ///< a skeleton: positions, faces and adjacency
  std::vector<int32_t> source;
};

PolygonPieces polygonPieces(const PatchCache& c) {
  PolygonMesh m = cacheBaseMesh(c);
  m.faceSource.clear();  // the pieces' sources are c's faces
  std::vector<Eigen::Vector3d> normals(c.numSlots(), Eigen::Vector3d::UnitZ());
  if (c.cornerNormals.size() == 3 * normals.size())
    for (size_t k = 0; k < normals.size(); ++k)
      normals[k] = {c.cornerNormals[3 * k], c.cornerNormals[3 * k + 1], c.cornerNormals[3 * k + 2]};
  splitBadCorners(m, &normals);
  PatchOptions o = c.options;
  o.foldRepair = FoldRepairMode::Off;
  return {preparePatchCache(m, normals, o, c.meshHash, /*allocatePatches=*/false), std::move(m.faceSource)};
}

SurfaceSamples patchSamples(const PatchCache& c, int level) {
  SurfaceSamples s;
  const std::vector<int32_t> faces = builtFaces(c);
  visitRingPoints(
      c, level, faces.data(), faces.size(),
      [&c](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
        evaluatePatches(c, f, x, y, n, out, Backend::Tbb);
      },
      [&](size_t i, const Eigen::Vector2d*, const PatchPoint* points, size_t m) {
        for (size_t k = 0; k < m; ++k) add(s, points[k].pos, faces[i]);
      });
  return s;
}

Eigen::Vector3d position(const PatchCache& c, int v) {
  return {c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]};
}

/// Each polygon's fan triangles (centroid, V_k, V_k+1) sampled like a ring tessellation: the
/// centroid, then rings r = 1..L, each fan triangle's outer side split in r.
SurfaceSamples polygonSamples(const PolygonPieces& p, int level) {
  const PatchCache& c = p.pieces;
  const std::vector<int32_t>& source = p.source;
  SurfaceSamples s;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int first = c.faceOffsets[f], n = c.faceOffsets[f + 1] - first;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) centre += position(c, c.faceVertices[first + k]) / n;
    add(s, centre, source[f]);
    for (int r = 1; r <= level; ++r)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d a = position(c, c.faceVertices[first + k]),
                              b = position(c, c.faceVertices[first + (k + 1) % n]);
        for (int j = 0; j < r; ++j) {
          const double t = static_cast<double>(r) / level, u = static_cast<double>(j) / r;
          add(s, centre + t * ((1 - u) * a + u * b - centre), source[f]);
        }
      }
  }
  return s;
}

/// Distances (m) from points[0, 3 count) to the polygon pieces, exact (PolygonScene); NaN for a
/// point that is not finite.
std::vector<double> polygonDistances(const PolygonPieces& p, const double* points, size_t count, int threads) {
  std::vector<double> d(count, 0);
  const PolygonScene scene(p.pieces, kWatertightPlanarTolerance);
  auto run = [&] {
    tbb::parallel_for(size_t{0}, count, [&](size_t i) {
      const Eigen::Vector3d q(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
      d[i] = q.allFinite() ? scene.nearest(q).distance : std::numeric_limits<double>::quiet_NaN();
    });
  };
  if (threads > 0)
    tbb::task_arena(threads).execute(run);
  else
    run();
  return d;
}

/// The global nearest-point query of the patch surface of `to` (prebuilt).
std::unique_ptr<const SurfaceQuery> patchQuery(const PatchCache& to) {
  if (!hasPatchData(to))
    throw InputError("surface distance: a patch surface needs a prebuilt cache (this one is a skeleton)");
  return std::make_unique<const SurfaceQuery>(std::shared_ptr<const PatchCache>(std::shared_ptr<void>(), &to));
}

/// Distances (m) from points[0, 3 count) to a patch surface, by its global nearest-point query;
/// NaN where it has no answer.
std::vector<double> patchDistances(const SurfaceQuery& query, const double* points, size_t count, int threads) {
  std::vector<double> d(count, 0);
  constexpr size_t kChunk = size_t{1} << 16;  // bounds the answers held at once
  std::vector<SurfaceQueryResult> out(std::min(count, kChunk));
  for (size_t first = 0; first < count; first += kChunk) {
    const size_t m = std::min(kChunk, count - first);
    query.query(points + 3 * first, m, out.data(), threads);
    for (size_t i = 0; i < m; ++i) d[first + i] = std::fabs(out[i].signedDistance);
  }
  return d;
}

/// The aggregates of the distances d (m) of the samples `from`, in fractions of `diagonal`.
DistanceDirection summarize(const SurfaceSamples& from, const std::vector<double>& d, double diagonal) {
  DistanceDirection out;
  out.points = from.size();
  double sum = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (!std::isfinite(d[i]))
      throw InputError("surface distance: a sample of face " + std::to_string(from.face[i]) +
                       " has no nearest point on the other surface");
    sum += d[i];
    if (d[i] > out.max || out.worstFace < 0) {
      out.max = d[i];
      out.worstFace = from.face[i];
      out.worstPoint = {from.xyz[3 * i], from.xyz[3 * i + 1], from.xyz[3 * i + 2]};
    }
  }
  out.mean = d.empty() ? 0 : sum / static_cast<double>(d.size());
  out.max /= diagonal;
  out.mean /= diagonal;
  return out;
}

}  // namespace

DistanceSurface parseDistanceSurface(const std::string& text) {
  if (text == "patches") return DistanceSurface::Patches;
  if (text == "polygons") return DistanceSurface::Polygons;
  throw InputError("to: expected patches|polygons, got '" + text + "'");
}

SurfaceSamples sampleSurface(const PatchCache& c, DistanceSurface as, int level) {
  if (level < 1 || level > 64) throw InputError("surface distance: level " + std::to_string(level) + " outside 1..64");
  return as == DistanceSurface::Patches ? patchSamples(c, level) : polygonSamples(polygonPieces(c), level);
}

std::vector<double> distancesToSurface(const PatchCache& to, DistanceSurface as, const double* points, size_t count,
                                       int threads) {
  return as == DistanceSurface::Patches ? patchDistances(*patchQuery(to), points, count, threads)
                                        : polygonDistances(polygonPieces(to), points, count, threads);
}

int sampleLevel(const PatchCache& c, int level) {
  long corners = 0;
  for (int f = 0; f < c.numFaces(); ++f) corners += c.faceSize(f);
  // a level-L sample set holds about corners L (L + 1) / 2 + faces points
  while (level > 1 && static_cast<double>(corners) * level * (level + 1) / 2 + c.numFaces() > kMaxDistanceSamples)
    --level;
  return level;
}

SurfaceDistance measureSurfaceDistance(const PatchCache& a, DistanceSurface aAs, const PatchCache& b,
                                       DistanceSurface bAs, int level, int threads) {
  if (level < 1 || level > 64) throw InputError("surface distance: level " + std::to_string(level) + " outside 1..64");
  for (const auto& [c, as] : {std::pair{&a, aAs}, std::pair{&b, bAs}})
    if (as == DistanceSurface::Patches && !hasPatchData(*c))
      throw InputError("surface distance: a patch surface needs a prebuilt cache (this one is a skeleton)");
  SurfaceDistance r;
  r.diagonal = boundingDiagonal(a);
  if (!(r.diagonal > 0) || !std::isfinite(r.diagonal))
    throw InputError("surface distance: the first surface has no extent");
  r.levelA = sampleLevel(a, level);
  r.levelB = sampleLevel(b, level);
  // each polygon surface cut into its pieces once, for its samples and for its distances
  std::optional<PolygonPieces> piecesA, piecesB;
  if (aAs == DistanceSurface::Polygons) piecesA = polygonPieces(a);
  if (bAs == DistanceSurface::Polygons) piecesB = polygonPieces(b);
  auto samples = [](const PatchCache& c, const std::optional<PolygonPieces>& p, int l) {
    return p ? polygonSamples(*p, l) : patchSamples(c, l);
  };
  // a patch surface's query is built where it is needed and dropped after, but one surface
  // measured against itself builds it once for both directions
  const bool same = &a == &b && aAs == DistanceSurface::Patches && bAs == DistanceSurface::Patches;
  std::unique_ptr<const SurfaceQuery> shared;
  auto distances = [&](const PatchCache& c, const std::optional<PolygonPieces>& p, const SurfaceSamples& s) {
    if (p) return polygonDistances(*p, s.xyz.data(), s.size(), threads);
    if (!same) return patchDistances(*patchQuery(c), s.xyz.data(), s.size(), threads);
    if (!shared) shared = patchQuery(c);
    return patchDistances(*shared, s.xyz.data(), s.size(), threads);
  };
  {  // one sample set held at a time
    const SurfaceSamples sa = samples(a, piecesA, r.levelA);
    r.aToB = summarize(sa, distances(b, piecesB, sa), r.diagonal);
  }
  const SurfaceSamples sb = samples(b, piecesB, r.levelB);
  r.bToA = summarize(sb, distances(a, piecesA, sb), r.diagonal);
  return r;
}

}  // namespace sf
