// SPDX-License-Identifier: Apache-2.0
// Mean value coordinates, the polygon facets' exact queries and the Embree scene against
// brute force (paper 4.1).
#include <gtest/gtest.h>

#include <numbers>
#include <random>
#include <thread>

#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/mean_value.h>
#include "patch_test_support.h"

namespace sf {
namespace {

std::vector<Eigen::Vector2d> regular(int n, double r = 1.0) {
  std::vector<Eigen::Vector2d> p;
  for (int k = 0; k < n; ++k) p.emplace_back(r * std::cos(2 * M_PI * k / n), r * std::sin(2 * M_PI * k / n));
  return p;
}
std::vector<Eigen::Vector2d> lShape() {  // non-convex, counter-clockwise
  return {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
}

TEST(MeanValue, ReproducesVerticesExactly) {
  for (const auto& poly : {regular(3), regular(4), regular(7), lShape()}) {
    const int n = static_cast<int>(poly.size());
    std::vector<double> l(n);
    for (int i = 0; i < n; ++i) {
      meanValueCoordinates(poly.data(), n, poly[i], l.data());
      for (int j = 0; j < n; ++j) EXPECT_EQ(l[j], i == j ? 1.0 : 0.0);
    }
  }
}

TEST(MeanValue, ReproducesLinearFunctionsInsideAndOnEdges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 2);
  for (const auto& poly : {regular(3), regular(5), regular(8), lShape()}) {
    const int n = static_cast<int>(poly.size());
    std::vector<double> l(n);
    auto check = [&](const Eigen::Vector2d& x) {
      meanValueCoordinates(poly.data(), n, x, l.data());
      Eigen::Vector2d sum(0, 0);
      double w = 0, lin = 0;
      for (int k = 0; k < n; ++k) {
        ASSERT_TRUE(std::isfinite(l[k]));
        sum += l[k] * poly[k];
        w += l[k];
        lin += l[k] * (3 * poly[k].x() - 2 * poly[k].y() + 0.5);
      }
      EXPECT_NEAR(w, 1.0, 1e-12);
      EXPECT_NEAR((sum - x).norm(), 0.0, 1e-12);
      EXPECT_NEAR(lin, 3 * x.x() - 2 * x.y() + 0.5, 1e-11);
    };
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector2d x(u(rng), u(rng));
      if (insidePolygon2d(poly.data(), n, x)) check(x);
    }
    for (int k = 0; k < n; ++k)  // exactly on the edges: linear interpolation, no NaN
      for (double s : {0.5, 1e-9, 0.3}) {
        const Eigen::Vector2d x = poly[k] + s * (poly[(k + 1) % n] - poly[k]);
        check(x);
        meanValueCoordinates(poly.data(), n, x, l.data());
        EXPECT_NEAR(l[k], 1 - s, 1e-12);
        EXPECT_NEAR(l[(k + 1) % n], s, 1e-12);
      }
  }
}

TEST(MeanValue, PolygonPointToDomain) {
  const PatchCache c = test::cacheFromShape(ref::refDodecahedron());
  const PolygonFacets pf = buildPolygonFacets(c);
  std::vector<double> l(8);
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    for (int k = 0; k < n; ++k) {  // vertices map to their domain corners, edge midpoints to edge midpoints
      const int v = c.faceVertices[c.faceOffsets[f] + k], w = c.faceVertices[c.faceOffsets[f] + (k + 1) % n];
      const Eigen::Vector3d V(&c.positions[3 * v]), W(&c.positions[3 * w]);
      EXPECT_NEAR((polygonToDomain(pf, c, f, V, l.data()) - domainCorner(n, k)).norm(), 0, 1e-12);
      const Eigen::Vector2d mid = 0.5 * (domainCorner(n, k) + domainCorner(n, (k + 1) % n));
      EXPECT_NEAR((polygonToDomain(pf, c, f, 0.5 * (V + W), l.data()) - mid).norm(), 0, 1e-12);
    }
    EXPECT_NEAR(polygonToDomain(pf, c, f, pf.faceCentroid[f], l.data()).norm(), 0, 1e-12);  // regular face
  }
}

// A face's diameter: exact (all pairs of corners) up to 256 corners, its corners' box diagonal
// beyond (a face of 10^6 corners took hours in the pairwise loop): single flat n-gons of radius
// 1, n = 3 .. 64 and 200, 257, 1000, 10000.
TEST(EmbreeFacets, FaceDiameterExactUpTo256CornersThenTheBoxDiagonal) {
  int checked = 0;
  for (int n : {3, 4, 5, 7, 16, 64, 200, 257, 1000, 10000}) {
    ref::RefMesh m;
    for (const Eigen::Vector2d& p : regular(n)) m.positions.emplace_back(p.x(), p.y(), 0);
    m.faces.emplace_back();
    for (int k = 0; k < n; ++k) m.faces[0].push_back(k);
    m.normals.assign(n, Eigen::Vector3d::UnitZ());
    const PatchCache c = test::cacheFromShape(m);
    const PolygonFacets pf = buildPolygonFacets(c);
    double exact = 0;
    Eigen::Vector3d lo = m.positions[0], hi = lo;
    for (int a = 0; a < n; ++a) {
      lo = lo.cwiseMin(m.positions[a]);
      hi = hi.cwiseMax(m.positions[a]);
      for (int b = a + 1; b < n; ++b) exact = std::max(exact, (m.positions[a] - m.positions[b]).norm());
    }
    EXPECT_EQ(pf.faceDiameter[0], n <= 256 ? exact : (hi - lo).norm()) << n;
    EXPECT_LE(exact, pf.faceDiameter[0]) << n;
    ++checked;
  }
  EXPECT_EQ(checked, 10);
}

TEST(EmbreeFacets, NearestOnPlanarPolygonIsAnalytic) {
  // the unit-sphere cube's faces are planar squares: nearest = clamp in the face frame
  const PatchCache c = test::cacheFromShape(ref::refUnitSphereCube());
  const PolygonFacets pf = buildPolygonFacets(c);
  ASSERT_EQ(pf.numFacets(), 6);
  const double h = 1 / std::sqrt(3.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 2 + u(rng));  // the z = +h face
    int f = -1;
    for (int g = 0; g < 6; ++g)
      if (pf.faceNormal[g].z() > 0.99) f = g;
    Eigen::Vector3d best;
    double d2 = 1e300;
    int facet = -1;
    ASSERT_TRUE(nearestOnFace(pf, f, p, best, d2, facet));
    const Eigen::Vector3d expect(std::clamp(p.x(), -h, h), std::clamp(p.y(), -h, h), h);
    EXPECT_NEAR((best - expect).norm(), 0, 1e-14);
    EXPECT_NEAR(std::sqrt(d2), (p - expect).norm(), 1e-14);
  }
}

void expectNearestMatchesBruteForce(const PatchCache& c, int samples) {
  const PolygonScene scene(c);
  const PolygonFacets& pf = scene.facets();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 1.3);
  const Eigen::Vector3d lo = pf.boxMin, ext = pf.boxMax - pf.boxMin;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector3d p = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(ext);
    Eigen::Vector3d best;
    double d2 = std::numeric_limits<double>::infinity();
    int facet = -1;
    for (int f = 0; f < c.numFaces(); ++f) nearestOnFace(pf, f, p, best, d2, facet);
    const NearestPolygonPoint q = scene.nearest(p);
    ASSERT_GE(q.face, 0);
    EXPECT_NEAR(q.distance, std::sqrt(d2), 1e-13 * pf.extent()) << "sample " << i;
    EXPECT_NEAR((q.point - p).norm(), q.distance, 1e-14 * pf.extent());
    if (facet == q.facet) {
      EXPECT_EQ((q.point - best).norm(), 0.0);
    }
  }
}

TEST(EmbreeScene, NearestMatchesBruteForceSpotCage) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const PolygonFacets pf = buildPolygonFacets(c);
  int fans = 0;
  for (int f = 0; f < c.numFaces(); ++f) fans += pf.isFan(f);
  EXPECT_GT(fans, 0);  // the spot cage has strongly non-planar faces
  EXPECT_LT(fans, c.numFaces());
  expectNearestMatchesBruteForce(c, 2000);
}

TEST(EmbreeScene, NearestMatchesBruteForceQuadSphere) {
  expectNearestMatchesBruteForce(test::cacheFromFile(test::sharedMesh("polygon_laplacian/quad-sphere.off")), 2000);
}

TEST(EmbreeScene, ConcurrentQueriesAgree) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("polygon_laplacian/quad-sphere.off"));
  const PolygonScene scene(c);
  std::vector<Eigen::Vector3d> pts;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 4000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  std::vector<double> a(pts.size()), b(pts.size());
  std::thread t1([&] {
    for (size_t i = 0; i < pts.size(); ++i) a[i] = scene.nearest(pts[i]).distance;
  });
  std::thread t2([&] {
    for (size_t i = 0; i < pts.size(); ++i) b[i] = scene.nearest(pts[pts.size() - 1 - i]).distance;
  });
  t1.join();
  t2.join();
  for (size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(a[i], b[pts.size() - 1 - i]);
}

TEST(EmbreeScene, FirstEntryFindsFrontSideCrossingsOnly) {
  const PatchCache c = test::cacheFromShape(ref::refUnitSphereCube());
  const PolygonScene scene(c);
  const double h = 1 / std::sqrt(3.0);
  const Eigen::Vector3d out(0.1, 0.2, 2), in(0.1, 0.2, 0);
  const PolygonCrossing e = scene.firstEntry(out, in);
  ASSERT_GE(e.face, 0);
  EXPECT_NEAR(e.t, (2 - h) / 2, 1e-15);
  EXPECT_NEAR((e.point - Eigen::Vector3d(0.1, 0.2, h)).norm(), 0, 1e-15);
  EXPECT_GT(scene.facets().faceNormal[e.face].z(), 0.99);
  EXPECT_LT(scene.firstEntry(in, out).face, 0);                            // leaving is not entering
  EXPECT_LT(scene.firstEntry(out, Eigen::Vector3d(0.1, 0.2, 1)).face, 0);  // stops short
  EXPECT_LT(scene.firstEntry(out, in, &e.facet, 1).face, 0);               // excluded
  // through the whole cube: the first entry is the near face
  const PolygonCrossing t = scene.firstEntry(Eigen::Vector3d(3, 0.1, 0.2), Eigen::Vector3d(-3, 0.1, 0.2));
  ASSERT_GE(t.face, 0);
  EXPECT_GT(scene.facets().faceNormal[t.face].x(), 0.99);
  // a segment starting on the face (the god-object's proxy) enters at t = 0
  const PolygonCrossing z = scene.firstEntry(Eigen::Vector3d(0.3, 0.3, h), Eigen::Vector3d(0.35, 0.3, h - 0.1));
  ASSERT_GE(z.face, 0);
  EXPECT_EQ(z.t, 0.0);
}

}  // namespace
}  // namespace sf
