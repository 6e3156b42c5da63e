// SPDX-License-Identifier: Apache-2.0
// LazyPatchSurface (lazy_surface.h): its cell, sector and swept boxes hold their patches (checked against dense
// sampling of every patch of the smaller meshes in shared/meshes and 600 random patches of each
// larger one), its a-priori box queries agree with brute force, and it needs no built patch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/query/lazy_surface.h>
#include "patch_test_support.h"

namespace sf {
namespace {

/// Samples of every patch of `faces` (10 rings x 11 points per edge, and the centre) that lie
/// outside every cell, sector and swept box of their face; points: how many were sampled.
struct Containment {
  long points = 0, outside = 0, sectorOutside = 0, sweptOutside = 0, faceBoxOutside = 0;
  long sweptCellOutside = 0;  ///< patch points, or their fan-triangle points, outside their sector's swept cell boxes
  long faceBoxesBeyondApriori = 0;  ///< face boxes not inside their a-priori box
  double worst = 0;  ///< farthest outside a cell box, over the a-priori box diagonal
};
Containment containment(const PatchCache& c, const PolygonFacets& facets, LazyPatchSurface& surface,
                        const std::vector<int>& faces) {
  Containment r;
  constexpr int kRings = 10, kPerEdge = 11;
  for (int f : faces) {
    const int n = c.faceSize(f);
    if (n > GP_MAX_N) continue;
    const int cells = surface.cells(f);
    EXPECT_TRUE(surface.sectors(f)) << "face " << f;
    EXPECT_EQ(cells, LazyPatchSurface::kCellsPerSector * n) << "face " << f;
    const double diameter = (surface.aprioriBox(f).hi - surface.aprioriBox(f).lo).norm();
    const PatchBox& box = surface.faceBox(f);
    r.faceBoxesBeyondApriori += !((box.lo.array() >= surface.aprioriBox(f).lo.array()).all() &&
                                  (box.hi.array() <= surface.aprioriBox(f).hi.array()).all());
    for (int ring = 0; ring <= kRings; ++ring)
      for (int k = 0; k < (ring == 0 ? 1 : n); ++k)
        for (int j = 0; j < (ring == 0 ? 1 : kPerEdge); ++j) {
          const Eigen::Vector2d x = (double(ring) / kRings) * test::edgePoint(n, k, double(j) / kPerEdge, 0.0);
          const Eigen::Vector3d p = evaluatePatch(c, f, x.x(), x.y()).pos;
          ++r.points;
          double d = 1e300;  // to the nearest cell box: 0 when one holds p
          for (int i = 0; i < cells; ++i) d = std::min(d, surface.cellDistance(f, i, p));
          if (d > 0) {
            ++r.outside;
            r.worst = std::max(r.worst, d / diameter);
          }
          double swept = 1e300, sector = 1e300;  // to the nearest swept and sector box of the face
          for (int k = 0; k < n; ++k) {
            swept = std::min(swept, surface.sweptDistance(f, k, p));
            sector = std::min(sector, surface.sectorDistance(f, k, p));
          }
          r.sweptOutside += swept > 0;
          if (ring > 0) {  // the sector of edge k: the patch point and its fan-triangle point (the
                           // sector mapped linearly onto (centroid, V_k, V_k+1)) in one of its swept cells
            const double rho = double(ring) / kRings, t = double(j) / kPerEdge;
            const Eigen::Vector3d v0 = Eigen::Vector3d::Map(&c.positions[3 * c.faceVertices[c.faceOffsets[f] + k]]);
            const Eigen::Vector3d v1 =
                Eigen::Vector3d::Map(&c.positions[3 * c.faceVertices[c.faceOffsets[f] + (k + 1) % n]]);
            const Eigen::Vector3d centroid = facets.faceCentroid[f];
            const Eigen::Vector3d fan = centroid + rho * (v0 + t * (v1 - v0) - centroid);
            double dp = 1e300, df = 1e300;
            for (int i = 0; i < LazyPatchSurface::kCellsPerSector; ++i) {
              dp = std::min(dp, surface.sweptCellDistance(f, LazyPatchSurface::kCellsPerSector * k + i, p));
              df = std::min(df, surface.sweptCellDistance(f, LazyPatchSurface::kCellsPerSector * k + i, fan));
            }
            r.sweptCellOutside += dp > 0 || df > 0;
          }
          r.faceBoxOutside += box.distance(p) > 0;
          r.sectorOutside += sector > 0;
        }
  }
  return r;
}

TEST(LazySurface, CellBoxesHoldTheirPatches) {
  int meshes = 0;
  long checked = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    const PolygonFacets facets = buildPolygonFacets(c);
    LazyPatchSurface surface(c, facets);
    std::vector<int> faces(c.numFaces());
    for (int f = 0; f < c.numFaces(); ++f) faces[f] = f;
    if (faces.size() > 600) {
      std::shuffle(faces.begin(), faces.end(), std::mt19937(20261122));
      faces.resize(600);
    }
    const Containment r = containment(c, facets, surface, faces);
    std::printf(
        "  %-50s %5zu patches, %8ld samples: %ld outside every cell box, %ld every sector box, %ld every swept box, "
        "%ld the face box, %ld their swept cells\n",
        std::filesystem::path(path).lexically_relative(SF_SHARED_MESHES).string().c_str(), faces.size(), r.points,
        r.outside, r.sectorOutside, r.sweptOutside, r.faceBoxOutside, r.sweptCellOutside);
    EXPECT_EQ(r.outside, 0) << "worst " << r.worst << " of the a-priori box diagonal";
    EXPECT_EQ(r.sweptOutside, 0);
    EXPECT_EQ(r.sectorOutside, 0);
    EXPECT_EQ(r.faceBoxOutside, 0);
    EXPECT_EQ(r.faceBoxesBeyondApriori, 0);
    EXPECT_EQ(r.sweptCellOutside, 0);
    EXPECT_EQ(surface.sampledFaces(), static_cast<int>(faces.size()));
    checked += r.points;
    ++meshes;
  }
  EXPECT_GE(meshes, 20);
  EXPECT_GT(checked, 2'000'000);
}

// The same far from the origin, where the boxes' margins include the rounding of the
// coordinates: the spot cage and the quad-sphere moved by 1e4 ... 1e13 m along (1, 1, 1), every
// patch.
TEST(LazySurface, CellBoxesHoldTheirPatchesFarFromTheOrigin) {
  int runs = 0;
  long checked = 0;
  for (const char* name : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"})
    for (const double offset : {1e4, 1e6, 1e9, 1e11, 1e13}) {
      SCOPED_TRACE(std::string(name) + " moved by " + std::to_string(offset));
      PolygonMesh m = readMesh(std::string(SF_SHARED_MESHES) + "/" + name);
      for (Eigen::Vector3d& x : m.positions) x.array() += offset;
      PatchOptions o;
      const PatchCache c = buildPatchCache(loadMesh(std::move(m), 0, o), o, Backend::Tbb);
      const PolygonFacets facets = buildPolygonFacets(c);
      LazyPatchSurface surface(c, facets);
      std::vector<int> faces(c.numFaces());
      for (int f = 0; f < c.numFaces(); ++f) faces[f] = f;
      const Containment r = containment(c, facets, surface, faces);
      EXPECT_EQ(r.outside, 0) << "worst " << r.worst << " of the a-priori box diagonal";
      EXPECT_EQ(r.sweptOutside, 0);
      EXPECT_EQ(r.sectorOutside, 0);
      EXPECT_EQ(r.faceBoxOutside, 0);
      EXPECT_EQ(r.faceBoxesBeyondApriori, 0);
      EXPECT_EQ(r.sweptCellOutside, 0);
      checked += r.points;
      ++runs;
    }
  EXPECT_EQ(runs, 10);
  EXPECT_GT(checked, 100'000);
}

// facesWithin and inAnyBox against brute force over the face boxes, at 2,000 points around
// the spot cage and the quad-sphere, and facesWithin's batches (each after the last of the one
// before) against the brute-force list in (distance, face) order; computed on a skeleton
// (nothing built).
TEST(LazySurface, BoxQueriesAgreeWithBruteForce) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    const PatchCache skeleton = test::skeletonFromFile(test::sharedMesh(rel));
    ASSERT_FALSE(hasPatchData(skeleton));
    const PolygonFacets facets = buildPolygonFacets(skeleton);
    const LazyPatchSurface surface(skeleton, facets);
    EXPECT_TRUE(surface.closed());
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (int v = 0; v < skeleton.numVertices(); ++v) {
      lo = lo.cwiseMin(Eigen::Vector3d::Map(&skeleton.positions[3 * v]));
      hi = hi.cwiseMax(Eigen::Vector3d::Map(&skeleton.positions[3 * v]));
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    int inside = 0, truncated = 0, multiBatch = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d q = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
      const double radius = 0.05 * (hi - lo).norm() * (i % 5);
      std::vector<FaceDistance> brute;
      bool any = false;
      for (int f = 0; f < skeleton.numFaces(); ++f) {
        const double d = surface.faceBox(f).distance(q);
        any = any || d == 0;
        if (d <= radius) brute.push_back({f, d});
      }
      std::sort(brute.begin(), brute.end(), [](auto& a, auto& b) { return a.distance < b.distance; });
      FaceDistance out[LazyPatchSurface::kMaxFaces];
      size_t found = 0;
      const size_t n = surface.facesWithin(q, radius, out, 32, &found);
      ASSERT_EQ(found, brute.size()) << rel << " point " << i;
      ASSERT_EQ(n, std::min<size_t>(32, brute.size()));
      truncated += found > n;
      for (size_t k = 0; k < n; ++k) EXPECT_EQ(out[k].distance, brute[k].distance) << rel << " point " << i;
      // batches of 32, each after the last of the one before, give every face in (distance, face) order
      std::sort(brute.begin(), brute.end(), [](auto& a, auto& b) {
        return a.distance < b.distance || (a.distance == b.distance && a.face < b.face);
      });
      std::vector<FaceDistance> all;
      int batches = 0;
      for (const FaceDistance* after = nullptr;; ++batches) {
        size_t more = 0;
        const size_t m = surface.facesWithin(q, radius, out, 32, &more, after);
        all.insert(all.end(), out, out + m);
        if (more <= m || m == 0) break;
        after = &all.back();
      }
      // one batch: ties in distance as the BVH met them (the distances' order is checked above)
      if (batches == 0)
        std::sort(all.begin(), all.end(), [](auto& a, auto& b) {
          return a.distance < b.distance || (a.distance == b.distance && a.face < b.face);
        });
      multiBatch += batches > 0;
      ASSERT_EQ(all.size(), brute.size()) << rel << " point " << i;
      for (size_t k = 0; k < all.size(); ++k) {
        EXPECT_EQ(all[k].face, brute[k].face) << rel << " point " << i << " entry " << k;
        EXPECT_EQ(all[k].distance, brute[k].distance) << rel << " point " << i << " entry " << k;
      }
      EXPECT_EQ(surface.inAnyBox(q), any) << rel << " point " << i;
      inside += any;
    }
    EXPECT_GT(inside, 100) << rel;
    EXPECT_GT(truncated, 10) << rel;
    EXPECT_EQ(multiBatch, truncated) << rel;
  }
}

}  // namespace
}  // namespace sf
