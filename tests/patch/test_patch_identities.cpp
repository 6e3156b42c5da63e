// SPDX-License-Identifier: Apache-2.0
// Unit/property tests of the production patch math (kernels/gp_patch.h through the cache):
// corner interpolation, boundary = edge curve, cross-tangent end identities, derivatives.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include "patch_test_support.h"

namespace sf {
namespace {

using test::cacheFromShape;

std::vector<ref::RefMesh> shapes() {
  return {ref::refUnitSphereCube(), ref::refIcosahedron(), ref::refDodecahedron(),
          ref::refJitteredPolytope(7, 0, 0.12, 12.0), ref::refJitteredPolytope(11, 1, 0.08, 10.0)};
}

TEST(PatchIdentities, CornersInterpolateVertices) {
  for (const auto& shape : shapes()) {
    const PatchCache c = cacheFromShape(shape);
    for (int f = 0; f < c.numFaces(); ++f)
      for (int k = 0; k < c.faceSize(f); ++k) {
        const Eigen::Vector2d x = domainCorner(c.faceSize(f), k);
        const PatchPoint p = evaluatePatch(c, f, x.x(), x.y());
        const Eigen::Vector3d v = shape.positions[shape.faces[f][k]];
        EXPECT_LT((p.pos - v).norm(), 1e-14) << "face " << f << " corner " << k;
        EXPECT_EQ(p.status & GP_ST_DEGENERATE_MASK, 0u);
      }
  }
}

TEST(PatchIdentities, BoundaryIsTheEdgeCurve) {
  for (const auto& shape : shapes()) {
    const PatchCache c = cacheFromShape(shape);
    for (int f = 0; f < c.numFaces(); ++f) {
      const int n = c.faceSize(f);
      double recs[GP_MAX_N * GP_E_NFIELDS];
      gatherRecords(c, f, recs);
      for (int k = 0; k < n; ++k)
        for (double s : {0.1, 0.37, 0.5, 0.81}) {
          const Eigen::Vector2d x = test::edgePoint(n, k, s, 0.0);
          const PatchPoint p = evaluatePatch(c, f, x.x(), x.y());
          gpd::gp_dvec3 cv, cp;
          gpd::gp_edge_curve(recs + k * GP_E_NFIELDS, s, &cv, &cp);
          EXPECT_LT((p.pos - Eigen::Vector3d(cv.v.x, cv.v.y, cv.v.z)).norm(), 1e-13) << "face " << f << " edge " << k;
        }
    }
  }
}

// T_k(0) = -C_{k-1}'(1) (pointing away from V_k) and T_k(1) = C_{k+1}'(0): Eq. 1's
// compatibility, which the corrected construction guarantees.
TEST(PatchIdentities, CrossTangentEndsMatchNeighbouringCurves) {
  for (auto mode : {CrossTangentMode::Corrected, CrossTangentMode::Blend}) {
    for (const auto& shape : shapes()) {
      const PatchCache c = cacheFromShape(shape, mode);
      for (int f = 0; f < c.numFaces(); ++f) {
        const int n = c.faceSize(f);
        double recs[GP_MAX_N * GP_E_NFIELDS];
        gatherRecords(c, f, recs);
        for (int k = 0; k < n; ++k) {
          const double* rk = recs + k * GP_E_NFIELDS;
          const double* rm = recs + ((k + n - 1) % n) * GP_E_NFIELDS;
          const double* rp = recs + ((k + 1) % n) * GP_E_NFIELDS;
          gpd::gp_dvec3 cv, cp;
          gpd::gp_edge_curve(rm, 1.0, &cv, &cp);
          const gpd::gp_vec3 t0 = gpd::gp_get3(rk, GP_E_T0), t1 = gpd::gp_get3(rk, GP_E_T1);
          EXPECT_LT(gpd::gp_len(gpd::gp_add(t0, cv.d)), 1e-13) << "T_k(0), face " << f << " edge " << k;
          gpd::gp_edge_curve(rp, 0.0, &cv, &cp);
          EXPECT_LT(gpd::gp_len(gpd::gp_sub(t1, cv.d)), 1e-13) << "T_k(1), face " << f << " edge " << k;
        }
      }
    }
  }
}

// The edge normal n_c(t) of Eq. 10 is the vertex normal at both ends of every edge of every
// bundled mesh: the guard (Robustness 1) keeps the end tangents forward and in the vertices'
// tangent planes, so n_c needs no orientation rule of its own (one, n_c . N(t) >= 0 at every t,
// turned n_c over inside edges and tore patches; test_patch_continuity.cpp). Checked against the
// records' unit normals N_k, N_{k+1}; every edge of every face, counted.
TEST(PatchIdentities, EdgeNormalIsTheVertexNormalAtBothEndsOfEveryEdge) {
  size_t ends = 0;
  double worst = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    size_t meshEnds = 0;
    for (int f = 0; f < c.numFaces(); ++f) {
      if (c.faceStatus[f] & GP_ST_NOT_BUILT) continue;
      double recs[GP_MAX_N * GP_E_NFIELDS];
      gatherRecords(c, f, recs);
      for (int k = 0; k < c.faceSize(f); ++k) {
        const double* rk = recs + k * GP_E_NFIELDS;
        const double L = gpd::gp_edge_length(rk);
        if (!(L > 0)) continue;  // a zero-length edge has no edge normal of its own
        for (int end = 0; end < 2; ++end) {
          gpd::gp_dvec3 cv, cp;
          gpd::gp_edge_curve(rk, end, &cv, &cp);
          uint32_t st = 0;
          const gpd::gp_vec3 nc = gpd::gp_edge_normal(rk, end, cp, L, &st).v;
          const gpd::gp_vec3 N = gpd::gp_get3(rk, end ? GP_E_N1 : GP_E_N0);
          const double gap = gpd::gp_len(gpd::gp_sub(nc, N));
          worst = std::max(worst, gap);
          EXPECT_LT(gap, 1e-12) << "face " << f << " edge " << k << " end " << end;
          ++meshEnds;
        }
      }
    }
    EXPECT_GT(meshEnds, 0u);
    ends += meshEnds;
  }
  std::printf("%zu edge ends, largest |n_c - N| %.3g\n", ends, worst);
  EXPECT_GT(ends, size_t(1'000'000));
}

// dG/dxi, dG/deta are exact: they agree with central differences to O(h^2).
TEST(PatchIdentities, DerivativesMatchFiniteDifferences) {
  const PatchCache c = cacheFromShape(ref::refJitteredPolytope(3, 0, 0.12, 15.0));
  const double h = 1e-6;
  for (int f = 0; f < c.numFaces(); ++f)
    for (const auto& x : {Eigen::Vector2d(0.1, -0.2), Eigen::Vector2d(-0.3, 0.25), Eigen::Vector2d(0.5, 0.1)}) {
      const PatchPoint p = evaluatePatch(c, f, x.x(), x.y());
      const Eigen::Vector3d fx =
          (evaluatePatch(c, f, x.x() + h, x.y()).pos - evaluatePatch(c, f, x.x() - h, x.y()).pos) / (2 * h);
      const Eigen::Vector3d fy =
          (evaluatePatch(c, f, x.x(), x.y() + h).pos - evaluatePatch(c, f, x.x(), x.y() - h).pos) / (2 * h);
      EXPECT_LT((p.dxi - fx).norm(), 1e-7 * (1 + fx.norm())) << "face " << f;
      EXPECT_LT((p.deta - fy).norm(), 1e-7 * (1 + fy.norm())) << "face " << f;
      EXPECT_NEAR(p.normal.norm(), 1.0, 1e-14);
    }
}

// The design page's independently checked numbers: max |r - 1| of the patches vs the flat faces.
TEST(PatchIdentities, PlatonicSolidsOnTheUnitSphere) {
  struct Case {
    ref::RefMesh m;
    double expect;
  };
  for (const Case& cs : {Case{ref::refUnitSphereCube(), 0.104}, Case{ref::refIcosahedron(), 0.038},
                         Case{ref::refDodecahedron(), 0.064}}) {
    const PatchCache c = cacheFromShape(cs.m);
    double worst = 0;
    for (int f = 0; f < c.numFaces(); ++f) {
      const int n = c.faceSize(f);
      for (int r = 0; r <= 24; ++r)
        for (int k = 0; k < n; ++k)
          for (int j = 0; j <= 8; ++j) {
            const Eigen::Vector2d x = (r / 24.0) * test::edgePoint(n, k, j / 8.0, 0.0);
            worst = std::max(worst, std::abs(evaluatePatch(c, f, x.x(), x.y()).pos.norm() - 1.0));
          }
    }
    EXPECT_NEAR(worst, cs.expect, 0.0015);
  }
}

// The position-only evaluation (gp_patch_eval_dom_d with deriv 0, which the quality check's
// bulge samples use) gives the full evaluation's position bit for bit, and its status but for
// GP_ST_SINGULAR (a normal's flag): so the fold and bulge every cache reports are unchanged.
// Every face of the reference shapes and of three shared meshes (triangles to hexagons), double
// and float records, at every quality sample (3 rings x 5 steps per edge) and 16 random points.
template <class R>
void checkPositionOnly(const PatchCache& c, size_t& points) {
  const int mode = static_cast<int>(c.options.crossTangent);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    R recs[GP_MAX_N * GP_E_NFIELDS];
    gatherRecords(c, f, recs);
    std::vector<Eigen::Vector2d> X;
    for (int k = 0; k < n; ++k)
      for (int i = 0; i <= 4; ++i)
        for (double ring : {1.0 - 1e-3, 0.66, 0.33}) {
          const Eigen::Vector2d a = domainCorner(n, k), b = domainCorner(n, k + 1);
          X.push_back(ring * ((1 - i / 4.0) * a + (i / 4.0) * b));
        }
    for (int j = 0; j < 16; ++j) X.push_back(0.7 * Eigen::Vector2d(u(rng), u(rng)));
    for (const Eigen::Vector2d& x : X) {
      const auto g = Gp<R>::evalDom(Gp<R>::domain(n), recs, mode, R(x.x()), R(x.y()));
      const auto p = Gp<R>::evalDomPosition(Gp<R>::domain(n), recs, mode, R(x.x()), R(x.y()));
      ++points;
      ASSERT_TRUE(g.pos.x == p.pos.x && g.pos.y == p.pos.y && g.pos.z == p.pos.z) << "face " << f << " at " << x.transpose();
      ASSERT_EQ(g.status & ~GP_ST_SINGULAR, p.status) << "face " << f;
    }
  }
}

TEST(PatchIdentities, PositionOnlyEvaluationIsTheFullEvaluationsPosition) {
  std::vector<PatchCache> caches;
  for (const auto& shape : shapes()) caches.push_back(cacheFromShape(shape));
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/hexaSphere.off",
                          "keenan_crane/spot_quadrangulated.obj"})
    for (Precision p : {Precision::Double, Precision::Float})
      caches.push_back(test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, p));
  size_t points = 0, faces = 0;
  for (const PatchCache& c : caches) {
    faces += c.numFaces();
    if (c.options.precision == Precision::Float)
      checkPositionOnly<float>(c, points);
    else
      checkPositionOnly<double>(c, points);
  }
  EXPECT_GT(faces, 6000u);
  EXPECT_GT(points, 20u * faces);
  std::printf("  %zu faces, %zu points: the position-only evaluation's positions are the full one's\n", faces, points);
}

}  // namespace
}  // namespace sf
