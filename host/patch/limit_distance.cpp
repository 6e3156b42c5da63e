// SPDX-License-Identifier: Apache-2.0
// Two-sided distance between a cage's patch surface and its Catmull-Clark limit surface.
#include <smoothforce/patch/limit_distance.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/mesh/cage_limit.h>
#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>

namespace sf {

namespace {

/// Squared distance from p to triangle (a, b, c): the closest point by Voronoi regions
/// (Ericson, Real-Time Collision Detection, 5.1.5).
double pointTriangleDist2(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).squaredNorm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).squaredNorm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).squaredNorm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).squaredNorm();
}

/// Points and triangles of one tessellation, grouped by face.
struct ByFace {
  std::vector<std::vector<int32_t>> points, triangles;
};

ByFace groupByFace(int numFaces, const std::vector<std::array<int32_t, 3>>& triangles,
                   const std::vector<int32_t>& face) {
  ByFace g;
  g.points.resize(numFaces);
  g.triangles.resize(numFaces);
  for (size_t t = 0; t < triangles.size(); ++t) {
    g.triangles[face[t]].push_back(static_cast<int32_t>(t));
    for (int32_t v : triangles[t]) g.points[face[t]].push_back(v);
  }
  for (auto& p : g.points) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
  }
  return g;
}

}  // namespace

LimitDistance measureLimitDistance(const PatchCache& cache, const LoadedMesh& loaded, int level, int approxLevel) {
  if (loaded.cagePositions.empty())
    throw std::invalid_argument("measureLimitDistance: the mesh was not loaded with a cage");
  if (loaded.mesh.faceOffsets != cache.faceOffsets || loaded.mesh.faceVertices != cache.faceVertices)
    throw std::invalid_argument("measureLimitDistance: the cache was not built from this mesh");
  // the cage's limit surface is that of its faces as read: a fold repair cut leaves other faces
  if (!loaded.split.splitFaces.empty() || !loaded.split.fannedFaces.empty())
    throw InputError("limit distance: the fold repair cut faces of the cage (--fold-repair off measures it)");
  if (loaded.mesh.positions.size() != loaded.cagePositions.size())
    throw std::invalid_argument("measureLimitDistance: the cage has not one position per vertex of the mesh");
  if (level < 1 || level > 64) throw InputError("limit distance: level " + std::to_string(level) + " outside 1..64");
  PolygonMesh cage = loaded.mesh;
  cage.positions = loaded.cagePositions;
  const LimitTessellation limit = tessellateLimitSurface(cage, loaded.report, level, approxLevel);
  const TriangleMesh patch = tessellatePatches(
      cache, level, [&cache](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
        evaluatePatches(cache, f, x, y, n, out, Backend::Tbb);
      });
  const int nf = cache.numFaces();
  const ByFace pg = groupByFace(nf, patch.triangles, patch.face);
  const ByFace lg = groupByFace(nf, limit.triangles, limit.face);

  // faces sharing a vertex with each face
  const std::vector<std::vector<int>> vertexFaces = facesAtVertices(cache);

  struct PerFace {
    double maxPL = 0, sumPL = 0, maxLP = 0, sumLP = 0;
    size_t nP = 0, nL = 0;
    bool measured = false;
  };
  std::vector<PerFace> per(nf);
  tbb::parallel_for(0, nf, [&](int f) {
    if (pg.triangles[f].empty() || lg.triangles[f].empty()) return;
    std::vector<int> ring;
    for (int c = cache.faceOffsets[f]; c < cache.faceOffsets[f + 1]; ++c)
      ring.insert(ring.end(), vertexFaces[cache.faceVertices[c]].begin(), vertexFaces[cache.faceVertices[c]].end());
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    // nearest distance from point p to the triangles of `g` on the ring's faces
    auto nearest = [&](const Eigen::Vector3d& p, const ByFace& g, const std::vector<Eigen::Vector3d>& pos,
                       const std::vector<std::array<int32_t, 3>>& tris) {
      double best = std::numeric_limits<double>::infinity();
      for (int h : ring)
        for (int32_t t : g.triangles[h])
          best = std::min(best, pointTriangleDist2(p, pos[tris[t][0]], pos[tris[t][1]], pos[tris[t][2]]));
      return std::sqrt(best);
    };
    PerFace& r = per[f];
    r.measured = true;
    for (int32_t v : pg.points[f]) {
      const double d = nearest(patch.positions[v], lg, limit.positions, limit.triangles);
      r.maxPL = std::max(r.maxPL, d);
      r.sumPL += d;
      ++r.nP;
    }
    for (int32_t v : lg.points[f]) {
      const double d = nearest(limit.positions[v], pg, patch.positions, patch.triangles);
      r.maxLP = std::max(r.maxLP, d);
      r.sumLP += d;
      ++r.nL;
    }
  });

  LimitDistance out;
  out.diagonal = boundingDiagonal(cache);
  double sumPL = 0, sumLP = 0, worst = -1;
  for (int f = 0; f < nf; ++f) {
    const PerFace& r = per[f];
    if (!r.measured) continue;
    ++out.facesMeasured;
    out.maxPatchToLimit = std::max(out.maxPatchToLimit, r.maxPL);
    out.maxLimitToPatch = std::max(out.maxLimitToPatch, r.maxLP);
    sumPL += r.sumPL;
    sumLP += r.sumLP;
    out.patchPoints += r.nP;
    out.limitPoints += r.nL;
    if (std::max(r.maxPL, r.maxLP) > worst) {
      worst = std::max(r.maxPL, r.maxLP);
      out.worstFace = f;
    }
  }
  const double d = out.diagonal > 0 ? out.diagonal : 1;
  out.meanPatchToLimit = out.patchPoints ? sumPL / out.patchPoints / d : 0;
  out.meanLimitToPatch = out.limitPoints ? sumLP / out.limitPoints / d : 0;
  out.maxPatchToLimit /= d;
  out.maxLimitToPatch /= d;
  return out;
}

}  // namespace sf
