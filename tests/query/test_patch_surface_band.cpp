// SPDX-License-Identifier: Apache-2.0
// The error band test's hint (PatchSurface::inErrorBand with a patch point near the query): the
// uniform triangle over a domain point is found from the ring layout (uniformTriangleAt), and a
// hinted band test gives the BVH query's verdict for every query, with a right or a wrong hint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep_reference.h>
#include "patch_test_support.h"
#include "surface_tessellation.h"

namespace sf {
namespace {

/// Barycentric coordinates of X in the domain triangle (a, b, c); the smallest of the three.
double minBarycentric(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                      const Eigen::Vector2d& X) {
  auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) { return p.x() * q.y() - p.y() * q.x(); };
  const double area = cross(b - a, c - a);
  const double l0 = cross(b - X, c - X) / area, l1 = cross(c - X, a - X) / area;
  return std::min({l0, l1, 1 - l0 - l1});
}

// Every triangle's centroid maps to that triangle (so the index arithmetic is the layout's), and
// every vertex of the tessellation, every point of a random set and points just outside the
// domain map to a triangle of their face holding them (outside: the nearest one's edge, within
// the overshoot): triangles, pentagons, hexagons, open meshes, levels 1 to 12.
TEST(UniformTriangleAt, HoldsEveryPointOfEveryFace) {
  const char* meshes[] = {"geomview/dodecahedron.off",        "geomview/snub_dodecahedron.off",
                          "polygon_laplacian/hexaSphere.off", "keenan_crane/spot_control_mesh.obj",
                          "polygon_laplacian/L-plane.obj",    "pmp/hole_capsule.off"};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  for (const char* rel : meshes) {
    const PatchCache c = test::cacheFromFile(test::sharedMesh(rel));
    for (int L : {1, 2, 5, 12}) {
      const UniformTessellation u = tessellateUniform(c, L);
      ASSERT_EQ(u.faceFirstTri.size(), size_t(c.numFaces())) << rel;
      size_t centroids = 0, vertices = 0, random = 0, outside = 0, held = 0;
      for (size_t t = 0; t < u.tri.size(); ++t) {
        const auto& tr = u.tri[t];
        const Eigen::Vector2d g = (u.domain[tr[0]] + u.domain[tr[1]] + u.domain[tr[2]]) / 3;
        centroids += uniformTriangleAt(u, c, u.triFace[t], g) == int64_t(t);
      }
      auto check = [&](int f, const Eigen::Vector2d& X, double slack) {
        const int64_t t = uniformTriangleAt(u, c, f, X);
        if (t < 0 || u.triFace[t] != f) return false;
        const auto& tr = u.tri[t];
        return minBarycentric(u.domain[tr[0]], u.domain[tr[1]], u.domain[tr[2]], X) >= -slack;
      };
      for (int f = 0; f < c.numFaces(); ++f) {
        if (u.faceFirstTri[f] < 0) continue;
        const int n = c.faceSize(f);
        std::vector<Eigen::Vector2d> ring;
        domainRingPoints(n, L, ring);
        for (const Eigen::Vector2d& X : ring) vertices += check(f, X, 1e-9);
        for (int i = 0; i < 40; ++i) {
          const Eigen::Vector2d X(U(rng), U(rng));
          if (!insideDomain(n, X.x(), X.y(), 0)) continue;
          ++random;
          held += check(f, X, 1e-9);
        }
        for (int k = 0; k < n; ++k) {  // 1e-9 beyond each corner and edge midpoint
          const Eigen::Vector2d C = domainCorner(n, k), M = 0.5 * (C + domainCorner(n, (k + 1) % n));
          outside += check(f, C * (1 + 1e-9), 1e-6) + check(f, M * (1 + 1e-9), 1e-6);
        }
      }
      int64_t triangles = 0, ringVertices = 0, corners = 0;
      for (int f = 0; f < c.numFaces(); ++f)
        if (u.faceFirstTri[f] >= 0) {
          triangles += int64_t(c.faceSize(f)) * L * L;
          ringVertices += 1 + int64_t(c.faceSize(f)) * L * (L + 1) / 2;
          corners += 2 * c.faceSize(f);
        }
      EXPECT_EQ(int64_t(u.tri.size()), triangles) << rel << " L " << L;
      EXPECT_EQ(int64_t(centroids), triangles) << rel << " L " << L;
      EXPECT_EQ(int64_t(vertices), ringVertices) << rel << " L " << L;
      EXPECT_EQ(held, random) << rel << " L " << L;
      EXPECT_GT(random, size_t(10 * c.numFaces())) << rel;
      EXPECT_EQ(int64_t(outside), corners) << rel << " L " << L;
    }
    // no triangle: a face out of range, a non-finite point
    const UniformTessellation u = tessellateUniform(c, 3);
    EXPECT_EQ(uniformTriangleAt(u, c, -1, Eigen::Vector2d::Zero()), -1);
    EXPECT_EQ(uniformTriangleAt(u, c, c.numFaces(), Eigen::Vector2d::Zero()), -1);
    EXPECT_EQ(uniformTriangleAt(u, c, 0, Eigen::Vector2d(std::nan(""), 0)), -1);
  }
}

// inErrorBand with a hint answers as without one for every query: HIPs on each face's normal
// lines at depths from 1e-7 to 1e-2 of the diagonal on both sides (many inside a band, many not),
// hinted with the patch point they were offset from (its position unknown, and known: the distance
// rule that skips the hint's triangle), with the same domain point on another face, and with a
// point of the same face far off; where the hinted test finds a band, its reach bounds
// the distance to the nearest patch point (the global query's) from above.
TEST(PatchSurfaceBand, HintKeepsTheVerdict) {
  const char* meshes[] = {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off",
                          "polygon_laplacian/hexaSphere.off", "geomview/snub_dodecahedron.off"};
  for (const char* rel : meshes) {
    const PatchCache c = test::cacheFromFile(test::sharedMesh(rel));
    const PatchSurface surface(c);
    PatchRefiner refiner(c);
    const ForceOptions opt;
    const double diag = boundingDiagonal(c);
    size_t hips = 0, same = 0, inBand = 0, reachOk = 0, hintedBand = 0;
    for (int f = 0; f < c.numFaces(); ++f) {
      const int n = c.faceSize(f);
      const Eigen::Vector2d Xs[] = {Eigen::Vector2d::Zero(), 0.5 * domainCorner(n, 0),
                                    0.3 * domainCorner(n, 1) + 0.6 * domainCorner(n, 2),
                                    0.999 * domainCorner(n, n - 1)};
      for (const Eigen::Vector2d& X : Xs) {
        const PatchPoint p = evaluatePatch(c, f, X.x(), X.y());
        for (double d : {-1e-2, -1e-3, -1e-4, -1e-5, -1e-7, 0.0, 1e-7, 1e-5, 1e-4, 1e-3, 1e-2}) {
          const Eigen::Vector3d hip = p.pos + d * diag * p.normal;
          ++hips;
          double r0 = -1, r1 = -1, r2 = -1, r3 = -1, r4 = -1;
          int f0 = -2, f1 = -2, f2 = -2, f3 = -2, f4 = -2;
          const bool b0 = surface.inErrorBand(hip, &r0, &f0);
          const bool b1 = surface.inErrorBand(hip, &r1, &f1, f, X);
          const bool b2 = surface.inErrorBand(hip, &r2, &f2, (f + c.numFaces() / 2) % c.numFaces(), X);
          const bool b3 = surface.inErrorBand(hip, &r3, &f3, f, -X);
          const bool b4 = surface.inErrorBand(hip, &r4, &f4, f, X, p.pos);  // the hint's point known too
          same += b0 == b1 && b0 == b2 && b0 == b3 && b0 == b4 && (b1 || (r1 == -1 && f1 == -2));
          inBand += b0;
          if (b1) {
            hintedBand += f1 == f;
            const double nearest = nearestOnPatches(surface, refiner, hip, opt).nearest.distance;
            reachOk += r1 >= nearest - 1e-12 * diag && r1 < std::numeric_limits<double>::infinity();
          }
        }
      }
    }
    EXPECT_EQ(same, hips) << rel;
    EXPECT_EQ(reachOk, inBand) << rel;
    EXPECT_EQ(hips, size_t(44) * c.numFaces()) << rel;
    EXPECT_GT(inBand, hips / 4) << rel;  // both verdicts well represented
    EXPECT_LT(inBand, hips * 9 / 10) << rel;
    EXPECT_GT(hintedBand, inBand / 2) << rel;  // most bands found on the hint's face
    std::printf("  %s: %zu HIPs, %zu in a band (%zu on the hint's face), the same verdict for all\n", rel, hips, inBand,
                hintedBand);
  }
}

// The one BVH that serves the candidate search and the band test answers as a scan of every
// triangle: HIPs on the normal lines of patch points at depths from 1e-6 to 1e-2 of the diagonal
// on both sides, on meshes whose adaptive tessellation splits many uniform triangles (the
// quad-sphere), some (the spot cage) and none (the dodecahedron at its level). inErrorBand holds
// exactly where some uniform triangle lies within its error bound, and candidates() lists exactly
// the adaptive triangles whose lower bound is at most the smallest (distance + bound), in (lower
// bound, index) order, with the records candidateOf gives. Every triangle the adaptive
// tessellation kept whole is its uniform triangle, error bound and all, and the pieces and the
// triangles kept whole cover each face's domain once.
TEST(PatchSurfaceBand, SharedBvhAnswersAsAScanOfEveryTriangle) {
  const char* meshes[] = {"polygon_laplacian/quad-sphere.off", "keenan_crane/spot_control_mesh.obj",
                          "geomview/dodecahedron.off"};
  for (const char* rel : meshes) {
    const PatchCache c = test::cacheFromFile(test::sharedMesh(rel));
    const PatchSurface surface(c);
    const UniformTessellation& u = surface.uniform();
    const AdaptiveTessellation& a = surface.adaptive();
    const double diag = boundingDiagonal(c);
    ASSERT_EQ(a.size(), surface.numPointTriangles());
    // the triangles kept whole, and the domain area each face's triangles cover
    size_t whole = 0;
    std::vector<int> uses(u.tri.size(), 0);
    std::vector<double> area(c.numFaces(), 0.0), uniformArea(c.numFaces(), 0.0);
    auto domainArea = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
      const Eigen::Vector2d e = q - p, f = r - p;
      return 0.5 * std::abs(e.x() * f.y() - e.y() * f.x());
    };
    for (size_t t = 0; t < a.size(); ++t) {
      const SurfaceTriangle s = adaptiveTriangle(u, a, t);
      area[s.face] += domainArea(s.X[0], s.X[1], s.X[2]);
      if (a.ref[t] < 0) continue;
      ++whole;
      const int32_t r = a.ref[t];
      ++uses[r];
      bool same = s.face == u.triFace[r] && s.error == u.error[r] + a.pad;
      for (int k = 0; k < 3; ++k) same = same && s.P[k] == u.vertex[u.tri[r][k]] && s.X[k] == u.domain[u.tri[r][k]];
      EXPECT_TRUE(same) << rel << " triangle " << t;
    }
    for (size_t t = 0; t < u.tri.size(); ++t) {
      EXPECT_LE(uses[t], 1) << rel << " uniform triangle " << t;
      uniformArea[u.triFace[t]] += domainArea(u.domain[u.tri[t][0]], u.domain[u.tri[t][1]], u.domain[u.tri[t][2]]);
    }
    for (int f = 0; f < c.numFaces(); ++f) EXPECT_NEAR(area[f], uniformArea[f], 1e-12) << rel << " face " << f;

    size_t hips = 0, bandSame = 0, inBand = 0, listSame = 0, listed = 0;
    for (int f = 0; f < c.numFaces(); f += std::max(1, c.numFaces() / 24)) {
      const int n = c.faceSize(f);
      for (const Eigen::Vector2d& X : {Eigen::Vector2d(0.1, -0.05), Eigen::Vector2d(0.7 * domainCorner(n, 1))}) {
        const PatchPoint p = evaluatePatch(c, f, X.x(), X.y());
        for (double d : {-1e-2, -1e-3, -1e-4, -1e-6, 1e-6, 1e-4, 1e-3, 1e-2}) {
          const Eigen::Vector3d q = p.pos + d * diag * p.normal;
          ++hips;
          // the band, by a scan of the uniform triangles (the sweep reference's point-triangle distance, not the
          // query's; a triangle within 1e-12 of the diagonal of its bound's edge may go either way)
          bool within = false, near = false;
          for (size_t t = 0; t < u.tri.size() && !within; ++t) {
            const double e =
                u.error[t] -
                (closestPointOnTriangle(q, u.vertex[u.tri[t][0]], u.vertex[u.tri[t][1]], u.vertex[u.tri[t][2]]) - q)
                    .norm();
            within = e > 1e-12 * diag;
            near = near || std::abs(e) <= 1e-12 * diag;
          }
          const bool band = surface.inErrorBand(q);
          bandSame += band == within || (near && !within);
          inBand += band;
          // the candidates, by a scan of the adaptive triangles
          std::vector<SurfaceCandidate> scan(a.size());
          double bound = std::numeric_limits<double>::infinity();
          for (size_t t = 0; t < a.size(); ++t) {
            scan[t] = surface.candidateOf(q, static_cast<int>(t));
            bound = std::min(bound, scan[t].distance + (scan[t].distance - scan[t].lower));
          }
          std::vector<SurfaceCandidate> want;
          for (const SurfaceCandidate& x : scan)
            if (x.lower <= bound) want.push_back(x);
          std::sort(want.begin(), want.end(),
                    [](const SurfaceCandidate& x, const SurfaceCandidate& y) { return candidateBefore(x, y); });
          if (want.size() > PatchSurface::kMaxCandidates) want.resize(PatchSurface::kMaxCandidates);
          CandidateBuffer<> got;
          const size_t m = surface.candidates(q, got.data(), got.size());
          bool same = m == want.size();
          for (size_t i = 0; same && i < m; ++i)
            same = got[i].triangle == want[i].triangle && got[i].face == want[i].face && got[i].X == want[i].X &&
                   got[i].distance == want[i].distance && got[i].lower == want[i].lower;
          listSame += same;
          listed += m;
        }
      }
    }
    EXPECT_EQ(bandSame, hips) << rel;
    EXPECT_EQ(listSame, hips) << rel;
    EXPECT_GT(inBand, hips / 8) << rel;  // both verdicts represented
    EXPECT_LT(inBand, hips) << rel;
    EXPECT_GE(hips, size_t(8 * 12)) << rel;
    std::printf(
        "  %s: %zu adaptive triangles (%zu kept whole of %zu uniform), %zu HIPs, %zu in a band, %zu candidates; "
        "band and candidates as the scans for all\n",
        rel, a.size(), whole, u.tri.size(), hips, inBand, listed);
  }
}

}  // namespace
}  // namespace sf
