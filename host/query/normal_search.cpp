// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/normal_search.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/tangent_fans.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/query/surface_faults.h>

#include "embree_point_query.h"
#include "fault_verdict.h"
#include "gp_config.h"  // GP_ST_* status bits
#include "surface_tessellation.h"
#include "winding_rays.h"

namespace sf {
namespace {

/// A candidate normal within 10 degrees of one of its vertex's edges is not tried.
const double kEdgeCos = std::cos(10 * std::numbers::pi / 180);
/// A candidate whose patches gain one of these status bits is not kept.
constexpr uint32_t kNewStatus = GP_ST_DEGENERATE_MASK | GP_ST_BULGE;

Eigen::Vector3d vec3(const std::vector<double>& a, int i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }

/// A mirror symmetry of the cache's mesh: the reflection across a plane normal to `axis` (through
/// the box's centre) maps every vertex to a vertex (within 1e-9 of the diagonal), every face to a
/// face and every vertex normal (group of corners) to a vertex normal (within 1e-9): mate[g] is
/// the group that normal g maps to (g itself on the plane). axis -1: none found.
struct MirrorSymmetry {
  int axis = -1;
  std::vector<int> mate;
  Eigen::Vector3d reflect(Eigen::Vector3d v) const {  // a direction
    v[axis] = -v[axis];
    return v;
  }
};

MirrorSymmetry findMirrorSymmetry(const PatchCache& c, const std::vector<std::vector<int>>& groups) {
  MirrorSymmetry m;
  Eigen::Vector3d lo, hi;
  if (!referencedBox(c, lo, hi) || c.numVertices() == 0) return m;
  const double tol = 1e-9 * (hi - lo).norm();
  std::vector<Eigen::Vector3d> p(c.numVertices());
  for (int v = 0; v < c.numVertices(); ++v) p[v] = vec3(c.positions, v);
  const PointIndex index(p);
  std::vector<char> used(c.numVertices(), 0);
  for (const int32_t v : c.faceVertices) used[v] = 1;
  std::map<std::vector<int>, int> faceKey;  // a face's sorted vertices
  for (int f = 0; f < c.numFaces(); ++f) {
    std::vector<int> k(c.faceVertices.begin() + c.faceOffsets[f], c.faceVertices.begin() + c.faceOffsets[f + 1]);
    std::sort(k.begin(), k.end());
    faceKey.emplace(std::move(k), f);
  }
  for (int axis = 0; axis < 3; ++axis) {
    const double centre = 0.5 * (lo[axis] + hi[axis]);
    std::vector<int> mateVertex(c.numVertices(), -1);
    bool ok = true;
    for (int v = 0; v < c.numVertices() && ok; ++v) {
      if (!used[v]) continue;
      Eigen::Vector3d q = p[v];
      q[axis] = 2 * centre - q[axis];
      const int64_t w = index.nearest(q);
      ok = w >= 0 && used[w] && (p[w] - q).norm() <= tol;
      if (ok) mateVertex[v] = static_cast<int>(w);
    }
    for (int f = 0; f < c.numFaces() && ok; ++f) {
      std::vector<int> k;
      for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) k.push_back(mateVertex[c.faceVertices[s]]);
      std::sort(k.begin(), k.end());
      ok = faceKey.count(k) == 1;
    }
    if (!ok) continue;
    // the vertex normals: group g's normal, reflected, is the normal of a group at the mate vertex
    std::map<int, std::vector<int>> groupsAt;
    for (size_t g = 0; g < groups.size(); ++g) groupsAt[c.faceVertices[groups[g][0]]].push_back(static_cast<int>(g));
    MirrorSymmetry s;
    s.axis = axis;
    s.mate.assign(groups.size(), -1);
    for (size_t g = 0; g < groups.size() && ok; ++g) {
      const Eigen::Vector3d n = s.reflect(vec3(c.cornerNormals, groups[g][0]));
      for (const int h : groupsAt[mateVertex[c.faceVertices[groups[g][0]]]])
        if ((vec3(c.cornerNormals, groups[h][0]) - n).norm() <= 1e-9) s.mate[g] = h;
      ok = s.mate[g] >= 0;
    }
    if (ok) return s;
  }
  return m;
}

/// The unit vector a fraction t of the way from unit a to unit b along the great circle, at
/// most maxAngle (radians) from a.
Eigen::Vector3d turnTowards(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t, double maxAngle) {
  const Eigen::Vector3d side = b - a.dot(b) * a;
  if (side.norm() < 1e-12) return a;
  const double angle = std::min(t * std::atan2(side.norm(), a.dot(b)), maxAngle);
  return std::cos(angle) * a + std::sin(angle) * side.normalized();
}

/// The tessellation vertices of `faces` into box b.
void growByFaces(const UniformTessellation& u, const std::vector<int>& faces, Eigen::AlignedBox3d* b) {
  for (const int f : faces) {
    const int64_t first = u.faceFirstTri[f];
    if (first < 0) continue;
    for (size_t t = first; t < u.tri.size() && u.triFace[t] == f; ++t)
      for (const int32_t v : u.tri[t]) b->extend(u.vertex[v]);
  }
}

/// The fault area (m^2; 0 where Consistent or Degenerate) of triangle t of `u`, probed at offset
/// h (fault_verdict.h), with the winding numbers from the crossings of the scenes that make up the
/// surface (windingsAlongRay): split(back, dir, length, &near, &far, &clean) as
/// WindingRays::splitCrossings, crossings(q, k, &clean) as WindingRays::crossings.
template <class Split, class Crossings>
double faultArea(const UniformTessellation& u, size_t t, double h, Split&& split, Crossings&& crossings) {
  double area2 = 0;
  const SurfaceVerdict v = faultVerdict(
      u.vertex[u.tri[t][0]], u.vertex[u.tri[t][1]], u.vertex[u.tri[t][2]], h,
      [&](const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* atBack, int* atFront) {
        windingsAlongRay(back, dir, length, split, crossings, atBack, atFront);
      },
      &area2);
  return v != SurfaceVerdict::Consistent && v != SurfaceVerdict::Degenerate ? 0.5 * area2 : 0.0;
}

/// The triangles of the surface's uniform tessellation whose face is in `star` or that touch box b.
std::vector<size_t> touchedTriangles(const UniformTessellation& u, const std::vector<char>& inStar,
                                     const std::vector<Eigen::AlignedBox3d>& boxes) {
  std::vector<size_t> touched;
  for (size_t t = 0; t < u.tri.size(); ++t) {
    bool in = inStar[u.triFace[t]];
    for (size_t i = 0; i < boxes.size() && !in; ++i)
      in = boxes[i].contains(u.vertex[u.tri[t][0]]) || boxes[i].contains(u.vertex[u.tri[t][1]]) ||
           boxes[i].contains(u.vertex[u.tri[t][2]]);
    if (in) touched.push_back(t);
  }
  return touched;
}

/// Marks in *marked every face of `c` some of whose edge-curve end tangents differ between a and
/// b (each #C*6 as PatchCache::edgeTangents, or empty: none given).
void markFacesWithOtherEndTangents(const PatchCache& c, const std::vector<double>& a, const std::vector<double>& b,
                                   std::vector<char>* marked) {
  if (a.empty() && b.empty()) return;
  auto value = [](const std::vector<double>& t, size_t i) { return t.empty() ? 0.0 : t[i]; };
  for (int f = 0; f < c.numFaces(); ++f)
    for (size_t i = 6 * size_t(c.faceOffsets[f]); i < 6 * size_t(c.faceOffsets[f + 1]) && !(*marked)[f]; ++i)
      if (value(a, i) != value(b, i)) (*marked)[f] = 1;
}

/// True when face f's edge records (every field of every slot) have the same bits in a and b
/// (GP_E_NFIELDS * #C each, field-major as PatchCache::edgeDataD).
template <class T>
bool sameRecords(const PatchCache& c, const std::vector<T>& a, const std::vector<T>& b, int f) {
  const size_t C = c.faceVertices.size();
  for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s)
    for (size_t i = 0; i < GP_E_NFIELDS; ++i)
      if (std::memcmp(&a[i * C + size_t(s)], &b[i * C + size_t(s)], sizeof(T)) != 0) return false;
  return true;
}

/// Sum in index order: the same total, and so the same choice, for any thread count.
double sum(const std::vector<double>& a) {
  double s = 0;
  for (const double x : a) s += x;
  return s;
}

}  // namespace

NormalSearchReport finishFoldRepair(PatchCache& cache, Backend backend, int threads) {
  if (cache.options.foldRepair != FoldRepairMode::Search) return {};
  NormalSearchOptions o;
  o.backend = backend == Backend::Serial ? Backend::Serial : Backend::Tbb;
  o.threads = threads;
  return searchNormalsAgainstFaults(cache, o);
}

NormalSearchReport searchNormalsAgainstFaults(PatchCache& cache, const NormalSearchOptions& o) {
  if (!(o.maxRotationDeg > 0 && o.maxRotationDeg <= 90))
    throw std::invalid_argument("normal search: maxRotationDeg must be in (0, 90], got " +
                                std::to_string(o.maxRotationDeg));
  if (o.passes < 1 || o.passes > 16)
    throw std::invalid_argument("normal search: passes must be in 1..16, got " + std::to_string(o.passes));
  if (o.searchLevel < 0 || o.searchLevel > 64)
    throw std::invalid_argument("normal search: searchLevel must be in 0..64, got " + std::to_string(o.searchLevel));
  if (o.polishLevel < -1 || o.polishLevel > 64)
    throw std::invalid_argument("normal search: polishLevel must be -1 (none), 0 (chosen) or 1..64, got " +
                                std::to_string(o.polishLevel));
  if (o.polishLevel == 0 && o.polishTriangles < 1000)
    throw std::invalid_argument("normal search: polishTriangles must be at least 1000, got " +
                                std::to_string(o.polishTriangles));
  if (o.searchLevel == 0 && o.searchTriangles < 1000)
    throw std::invalid_argument("normal search: searchTriangles must be at least 1000, got " +
                                std::to_string(o.searchTriangles));
  if (o.backend == Backend::OpenCL)
    throw std::invalid_argument("normal search: candidates are built on the host (Serial or Tbb)");
  if (o.threads < 0)
    throw std::invalid_argument("normal search: threads must be >= 0, got " + std::to_string(o.threads));
  if (o.threads > 0 || o.backend == Backend::Serial) {
    NormalSearchOptions inner = o;  // oneTBB inside an arena of one thread is serial, with the same patches
    inner.threads = 0;
    inner.backend = Backend::Tbb;
    tbb::task_arena arena(o.backend == Backend::Serial ? 1 : o.threads);
    return arena.execute([&] { return searchNormalsAgainstFaults(cache, inner); });
  }
  if (!hasPatchData(cache)) throw std::invalid_argument("normal search: the cache has no patches built");
  const auto t0 = std::chrono::steady_clock::now();
  NormalSearchReport r;
  PatchSurfaceOptions fullOptions;
  fullOptions.windingOnly = true;
  double h = 0;  ///< m, the fault measure's probe offset
  {
    const PatchSurface full(cache, fullOptions);
    r.closed = full.closed();
    if (!r.closed) return r;
    h = surfaceProbeOffset(full);
    const SurfaceFaults f = measureSurfaceFaults(full);
    r.faultBefore = r.faultAfter = f.faultArea();
    r.totalArea = f.totalArea;
    r.searchLevel = o.searchLevel;
    if (r.searchLevel == 0) {  // triangles grow with the square of the level; never coarser than the measure's
      const double scale =
          std::sqrt(double(o.searchTriangles) / double(std::max<size_t>(1, full.uniform().tri.size())));
      r.searchLevel = std::clamp(std::max(full.level(), static_cast<int>(std::floor(full.level() * scale))), 1, 64);
    }
  }
  if (r.faultBefore == 0) return r;

  const std::vector<double> original = cache.cornerNormals;
  struct {
    std::vector<double> edgeDataD;
    std::vector<float> edgeDataF;
    std::vector<uint32_t> faceStatus;
  } const start{cache.edgeDataD, cache.edgeDataF, cache.faceStatus};  // the patches given, for the report
  const double maxAngle = o.maxRotationDeg * std::numbers::pi / 180;
  std::vector<int> faceOf(cache.numSlots());
  for (int f = 0; f < cache.numFaces(); ++f)
    for (int s = cache.faceOffsets[f]; s < cache.faceOffsets[f + 1]; ++s) faceOf[s] = f;
  const std::vector<std::vector<int>> groups = vertexNormalGroups(cache);
  const std::vector<std::vector<int>> facesAt = facesAtVertices(cache);
  const MirrorSymmetry symmetry = o.keepSymmetry ? findMirrorSymmetry(cache, groups) : MirrorSymmetry{};
  r.mirrorAxis = symmetry.axis;
  auto setNormal = [&](const std::vector<int>& slots, const Eigen::Vector3d& n) {
    for (const int s : slots)
      for (int i = 0; i < 3; ++i) cache.cornerNormals[3 * s + i] = n[i];
  };
  auto cornerNormal = [&](int s) {
    const int f = faceOf[s], n = cache.faceSize(f), k = s - cache.faceOffsets[f];
    const Eigen::Vector3d v = vec3(cache.positions, cache.faceVertices[s]);
    const Eigen::Vector3d next = vec3(cache.positions, cache.faceVertices[cache.faceOffsets[f] + (k + 1) % n]);
    const Eigen::Vector3d prev = vec3(cache.positions, cache.faceVertices[cache.faceOffsets[f] + (k + n - 1) % n]);
    const Eigen::Vector3d c = (next - v).cross(prev - v);
    return c.norm() > 0 ? Eigen::Vector3d(c.normalized()) : Eigen::Vector3d::Zero();
  };

  char embreeError[256] = {0};
  RTCDevice device = newEmbreeDevice(
      [](void* user, RTCError code, const char* str) {
        auto* e = static_cast<char*>(user);
        if (e[0] == 0) std::snprintf(e, 256, "Embree error %d: %s", int(code), str);
      },
      embreeError);
  const std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)> deviceOwner(device, rtcReleaseDevice);
  auto checkEmbree = [&] {
    if (embreeError[0]) throw std::runtime_error(std::string("normal search: ") + embreeError);
  };
  // The passes at one level. The search's surface: the uniform tessellation at that level, rays
  // only. A candidate changes the patches of the faces at its vertex (its star) alone, so the rest
  // is traced once per vertex, and each candidate tessellates and traces only its star again:
  // crossings of disjoint scenes with one origin add up to the whole's (winding_rays.h).
  // A move is kept where it lowers the fault area measured at that level by at least `share` of
  // the fault area on the faces it changes (0: by any amount beyond rounding); the fault area
  // (m^2) at that level before and after the passes in *before, *after.
  auto searchAt = [&](int level, int passes, double share, double* before, double* after) {
    UniformTessellation current = tessellateUniform(cache, level, /*errors=*/false);
    Eigen::AlignedBox3d all;
    for (const Eigen::Vector3d& p : current.vertex) all.extend(p);
    const Eigen::Vector3d origin = current.vertex.empty() ? Eigen::Vector3d::Zero() : localOrigin(all.min(), all.max());
    std::vector<double> triFault(current.tri.size(), 0.0);
    {
      const WindingRays whole(device, current, nullptr, origin);
      checkEmbree();
      tbb::parallel_for(size_t(0), current.tri.size(), [&](size_t t) {
        triFault[t] = faultArea(
            current, t, h,
            [&](const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* nearSum, int* farSum,
                bool* clean) { whole.splitCrossings(back, dir, length, nearSum, farSum, clean); },
            [&](const Eigen::Vector3d& q, int k, bool* clean) { return whole.crossings(q, k, clean); });
      });
    }
    std::vector<char> inStar(cache.numFaces(), 0);
    // the rest's crossings of the ray through both probes of each triangle off the star (before
    // and beyond the front probe), kept for the candidates of one vertex visit (stamp: the visit
    // that traced it)
    struct {
      std::vector<int32_t> stamp, nearSum, farSum;
      std::vector<uint8_t> clean;
    } restTraced;
    restTraced.stamp.assign(current.tri.size(), 0);
    restTraced.nearSum.assign(current.tri.size(), 0);
    restTraced.farSum.assign(current.tri.size(), 0);
    restTraced.clean.assign(current.tri.size(), 0);
    int32_t visit = 0;

    std::vector<double> faceFault(cache.numFaces(), 0.0);
    for (size_t t = 0; t < triFault.size(); ++t) faceFault[current.triFace[t]] += triFault[t];
    // A move: group g's normal turned to the best of its candidates, measured against the current
    // surface: the star's tessellation with it, and the fault area of every triangle it can change.
    struct Move {
      std::vector<size_t> groups;            ///< the group, and its mirror image where the mesh has one
      std::vector<Eigen::Vector3d> normals;  ///< theirs
      std::vector<int> star;
      std::unique_ptr<UniformTessellation> starTessellation;
      std::vector<size_t> touched;
      std::vector<double> fault;  ///< of touched, with the move
      double delta = 0;           ///< m^2, the change of the fault area
    };
    // the best candidate of group g (none where no candidate lowers the fault area); the cache's
    // normals and patches are left as they were
    auto evaluate = [&](size_t g) -> std::unique_ptr<Move> {
      // on a mirror-symmetric mesh a normal moves with its mirror image (one on the plane, with
      // itself: its candidates are made symmetric), so that the result keeps the symmetry
      const int mate = symmetry.axis >= 0 ? symmetry.mate[g] : -1;
      if (mate >= 0 && static_cast<size_t>(mate) < g) return nullptr;  // moved with its mate
      std::vector<size_t> moved{g};
      if (mate >= 0 && static_cast<size_t>(mate) != g) moved.push_back(static_cast<size_t>(mate));
      const std::vector<int>& slots = groups[g];
      // per moved group, the faces whose patches its normal changes: every face at its vertex (a
      // face with a crease edge there is built with the normals across it too)
      std::vector<std::vector<int>> stars;
      std::vector<int> star;  // all of them, once each
      bool faulted = false;
      for (const size_t m : moved) {
        stars.push_back(facesAt[cache.faceVertices[groups[m][0]]]);
        for (const int f : stars.back()) {
          star.push_back(f);
          faulted = faulted || faceFault[f] > 0;
        }
      }
      std::sort(star.begin(), star.end());
      star.erase(std::unique(star.begin(), star.end()), star.end());
      if (!faulted) return nullptr;
      const Eigen::Vector3d n0 = vec3(original, slots[0]), now = vec3(cache.cornerNormals, slots[0]);
      std::vector<Eigen::Vector3d> nowOf;
      for (const size_t m : moved) nowOf.push_back(vec3(cache.cornerNormals, groups[m][0]));
      std::vector<Eigen::Vector3d> towards;
      for (const int s : slots)
        if (const Eigen::Vector3d c = cornerNormal(s); c.squaredNorm() > 0) towards.push_back(c);
      if (towards.empty()) return nullptr;
      towards.push_back(minimaxDirection(towards, now));
      // the vertex's edges, as unit vectors away from it: a normal along one of them leaves that
      // edge's curve without a tangent direction (the design page's degenerate case)
      std::vector<Eigen::Vector3d> edges;
      for (const int s : slots) {
        const int f = faceOf[s], n = cache.faceSize(f), k = s - cache.faceOffsets[f];
        const Eigen::Vector3d v = vec3(cache.positions, cache.faceVertices[s]);
        for (const int j : {(k + 1) % n, (k + n - 1) % n})
          if (const Eigen::Vector3d e = vec3(cache.positions, cache.faceVertices[cache.faceOffsets[f] + j]) - v;
              e.norm() > 0)
            edges.push_back(e.normalized());
      }
      auto alongAnEdge = [&](const Eigen::Vector3d& n) {
        for (const Eigen::Vector3d& e : edges)
          if (std::abs(n.dot(e)) > kEdgeCos) return true;
        return false;
      };
      // the candidates: the normal (and its mirror image's) turned halfway and all the way
      // towards each direction, from the normal kept so far, clamped to the bound around the original
      std::vector<std::vector<Eigen::Vector3d>> candidates;
      for (const Eigen::Vector3d& d : towards)
        for (const double t : {0.5, 1.0}) {
          Eigen::Vector3d n = turnTowards(now, d, t, std::numbers::pi);
          if (std::acos(std::clamp(n.dot(n0), -1.0, 1.0)) > maxAngle) n = turnTowards(n0, n, 1.0, maxAngle);
          if (mate >= 0 && static_cast<size_t>(mate) == g) {  // on the plane: the symmetric part
            const Eigen::Vector3d sym = n + symmetry.reflect(n);
            if (sym.norm() < 1e-9) continue;
            n = sym.normalized();
          }
          if ((n - now).norm() < 1e-9 || alongAnEdge(n)) continue;
          candidates.push_back({n});
          if (moved.size() == 2) candidates.back().push_back(symmetry.reflect(n));
        }
      // Where the cache untangles vertex fans, a turned normal also turns the construction's own
      // directions of its edges at the neighbouring vertices (gp_edge_tangents uses both end
      // normals), and so can tangle or untangle their fans: every face whose end tangents some
      // candidate changes joins the star (with the moved vertex nearest to it, for the boxes).
      if (!candidates.empty() && cache.options.foldRepair != FoldRepairMode::Off) {
        const std::vector<double> nowTangents = cache.edgeTangents;
        std::vector<char> fanChanged(cache.numFaces(), 0);
        for (const std::vector<Eigen::Vector3d>& normals : candidates) {
          for (size_t i = 0; i < moved.size(); ++i) setNormal(groups[moved[i]], normals[i]);
          refreshEdgeTangents(cache);
          markFacesWithOtherEndTangents(cache, nowTangents, cache.edgeTangents, &fanChanged);
        }
        for (size_t i = 0; i < moved.size(); ++i) setNormal(groups[moved[i]], nowOf[i]);
        cache.edgeTangents = nowTangents;
        for (const int f : star) fanChanged[f] = 0;
        for (int f = 0; f < cache.numFaces(); ++f) {
          if (!fanChanged[f]) continue;
          star.push_back(f);
          size_t nearest = 0;
          const Eigen::Vector3d p = vec3(cache.positions, cache.faceVertices[cache.faceOffsets[f]]);
          for (size_t i = 1; i < moved.size(); ++i)
            if ((vec3(cache.positions, cache.faceVertices[groups[moved[i]][0]]) - p).squaredNorm() <
                (vec3(cache.positions, cache.faceVertices[groups[moved[nearest]][0]]) - p).squaredNorm())
              nearest = i;
          stars[nearest].push_back(f);
        }
        std::sort(star.begin(), star.end());
      }
      // the least decrease a move must bring: any beyond rounding, or `share` of the star's fault
      double threshold = 1e-12 * r.totalArea;
      if (share > 0) {
        double starFault = 0;
        for (const int f : star) starFault += faceFault[f];
        threshold = std::max(threshold, share * starFault);
      }
      for (const int f : star) inStar[f] = 1;
      std::vector<Eigen::AlignedBox3d> oldBoxes(moved.size());
      for (size_t i = 0; i < moved.size(); ++i) growByFaces(current, stars[i], &oldBoxes[i]);
      uint32_t starStatus = 0;
      for (const int f : star) starStatus |= cache.faceStatus[f];
      std::unique_ptr<WindingRays> rest;  // every triangle off the star, traced once for all candidates
      ++visit;
      std::unique_ptr<Move> best;
      // a candidate changes the patches of the star alone: the faces at the moved vertices, and
      // those whose end tangents the fans of its normals change
      BuildOptions build;
      build.backend = o.backend;
      for (const std::vector<Eigen::Vector3d>& normals : candidates) {
        for (size_t i = 0; i < moved.size(); ++i) setNormal(groups[moved[i]], normals[i]);
        constructPatchesOf(cache, star, build);
        uint32_t status = 0;
        for (const int f : star) status |= cache.faceStatus[f];
        if (status & ~starStatus & kNewStatus) continue;  // a degenerate edge or a bulge the normal made
        if (!rest) {
          std::vector<int64_t> off;
          off.reserve(current.tri.size());
          for (size_t i = 0; i < current.tri.size(); ++i)
            if (!inStar[current.triFace[i]]) off.push_back(static_cast<int64_t>(i));
          rest = std::make_unique<WindingRays>(device, current, &off, origin);
        }
        auto candidate =
            std::make_unique<UniformTessellation>(tessellateUniform(cache, level, /*errors=*/false, &star));
        const WindingRays starRays(device, *candidate, nullptr, origin);
        checkEmbree();
        ++r.evaluations;
        std::vector<Eigen::AlignedBox3d> boxes = oldBoxes;
        for (size_t i = 0; i < moved.size(); ++i) {
          growByFaces(*candidate, stars[i], &boxes[i]);
          boxes[i].min().array() -= 2 * h;
          boxes[i].max().array() += 2 * h;
        }
        std::vector<size_t> tt = touchedTriangles(current, inStar, boxes);
        // triangle i of the candidate surface: the star's from its own tessellation (the same
        // layout per face), the others from the current one
        auto corners = [&](size_t i) {
          const int f = current.triFace[i];
          if (!inStar[f]) return &current.tri[i];
          return &candidate->tri[size_t(candidate->faceFirstTri[f] + (int64_t(i) - current.faceFirstTri[f]))];
        };
        std::vector<double> fault(tt.size(), 0.0);
        tbb::parallel_for(size_t(0), tt.size(), [&](size_t j) {
          const size_t t = tt[j];
          const bool onStar = inStar[current.triFace[t]];
          const UniformTessellation& from = onStar ? *candidate : current;
          const size_t at = size_t(corners(t) - from.tri.data());
          fault[j] = faultArea(
              from, at, h,
              [&](const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* nearSum, int* farSum,
                  bool* clean) {
                // a triangle off the star keeps its probes for every candidate of this vertex, and so
                // the rest's crossings there
                if (onStar) {
                  rest->splitCrossings(back, dir, length, nearSum, farSum, clean);
                } else {
                  if (restTraced.stamp[t] != visit) {
                    int n = 0, f = 0;
                    bool c = true;
                    rest->splitCrossings(back, dir, length, &n, &f, &c);
                    restTraced.nearSum[t] = n;
                    restTraced.farSum[t] = f;
                    restTraced.clean[t] = c;
                    restTraced.stamp[t] = visit;
                  }
                  *nearSum += restTraced.nearSum[t];
                  *farSum += restTraced.farSum[t];
                  if (!restTraced.clean[t]) *clean = false;
                }
                starRays.splitCrossings(back, dir, length, nearSum, farSum, clean);
              },
              [&](const Eigen::Vector3d& q, int k, bool* clean) {
                return rest->crossings(q, k, clean) + starRays.crossings(q, k, clean);
              });
        });
        double before = 0;
        for (const size_t i : tt) before += triFault[i];
        if (const double delta = sum(fault) - before; delta < (best ? best->delta : -threshold)) {
          if (!best) best = std::make_unique<Move>();
          best->groups = moved;
          best->normals = normals;
          best->starTessellation = std::move(candidate);
          best->touched = std::move(tt);
          best->fault = std::move(fault);
          best->delta = delta;
        }
      }
      for (const int f : star) inStar[f] = 0;
      for (size_t i = 0; i < moved.size(); ++i) setNormal(groups[moved[i]], nowOf[i]);
      constructPatchesOf(cache, star, build);
      if (best) best->star = std::move(star);
      return best;
    };
    // makes move m on the cache's normals (patches not rebuilt), the current tessellation and the
    // fault areas
    auto apply = [&](const Move& m) {
      for (size_t i = 0; i < m.groups.size(); ++i) setNormal(groups[m.groups[i]], m.normals[i]);
      for (const int f : m.star) {  // the star's new vertices into the current tessellation
        const int64_t a = current.faceFirstTri[f], b = m.starTessellation->faceFirstTri[f];
        for (int64_t i = 0; a >= 0 && a + i < int64_t(current.tri.size()) && current.triFace[a + i] == f; ++i)
          for (int c = 0; c < 3; ++c)
            current.vertex[current.tri[a + i][c]] = m.starTessellation->vertex[m.starTessellation->tri[b + i][c]];
      }
      for (size_t i = 0; i < m.touched.size(); ++i) {
        const size_t t = m.touched[i];
        faceFault[current.triFace[t]] += m.fault[i] - triFault[t];
        triFault[t] = m.fault[i];
      }
    };
    *before = sum(triFault);
    for (int pass = 0; pass < passes; ++pass) {
      bool movedAny = false;
      for (size_t g = 0; g < groups.size(); ++g)
        if (const std::unique_ptr<Move> m = evaluate(g)) {
          apply(*m);
          constructPatches(cache, o.backend);
          movedAny = true;
        }
      if (!movedAny) break;
    }
    *after = sum(triFault);
  };
  double ignored = 0;
  searchAt(r.searchLevel, o.passes, 0.0, &ignored, &ignored);
  // A last pass at a finer level: folds and overlaps thinner than the search level's triangles
  // (on the spot cage, faces 35 and 125 crossing over the face between them), which its measure
  // cannot see. It keeps only moves that remove at least half the fault area on the faces they
  // change: the slivers left along the faults that the passes before took apart change with the
  // level by about as much as any turn lowers them (on the spot cage its other candidates
  // removed 0-12%), and would turn normals for nothing.
  r.polishLevel = std::max(0, o.polishLevel);
  if (o.polishLevel == 0) {  // 1.5 x the search level, within polishTriangles (n L^2 triangles per n-gon)
    int level = std::min(64, (3 * r.searchLevel + 1) / 2);
    while (level > r.searchLevel && double(cache.numSlots()) * level * level > double(o.polishTriangles)) --level;
    r.polishLevel = level > r.searchLevel ? level : 0;
  }
  if (r.polishLevel > 0) searchAt(r.polishLevel, 1, 0.5, &r.polishFaultBefore, &r.polishFaultAfter);

  {
    const PatchSurface full(cache, fullOptions);
    r.faultAfter = measureSurfaceFaults(full).faultArea();
  }
  if (!(r.faultAfter < r.faultBefore)) {
    cache.cornerNormals = original;
    constructPatches(cache, o.backend);
    r.faultAfter = r.faultBefore;
  } else {
    r.applied = true;
    if (cache.computedNormals.empty()) cache.computedNormals = original;  // a second search keeps the first's
    for (const std::vector<int>& slots : groups) {
      const Eigen::Vector3d n0 = vec3(original, slots[0]), n = vec3(cache.cornerNormals, slots[0]);
      if (n == n0) continue;
      r.changes.push_back(
          {cache.faceVertices[slots[0]], std::acos(std::clamp(n.dot(n0), -1.0, 1.0)) * 180 / std::numbers::pi, slots});
    }
    for (int f = 0; f < cache.numFaces(); ++f)
      if (cache.faceStatus[f] != start.faceStatus[f] ||
          (cache.options.precision == Precision::Double ? !sameRecords(cache, cache.edgeDataD, start.edgeDataD, f)
                                                        : !sameRecords(cache, cache.edgeDataF, start.edgeDataF, f)))
        r.changedFaces.push_back(f);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace sf
