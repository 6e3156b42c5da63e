// SPDX-License-Identifier: Apache-2.0
// Property tests of the independent reference patch (tests/reference/) against the design
// page /work/shared/design/gregory-patch.md: interpolation, boundary curves, cross-tangent
// identities, exact derivatives, the page's sphere numbers, and G1 across shared edges.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include "gregory_reference.h"
#include "ref_sampling.h"
#include "ref_shapes.h"

using namespace sf::ref;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr CrossTangent kModes[] = {CrossTangent::Corrected, CrossTangent::Paper, CrossTangent::Blend};

const char* modeName(CrossTangent m) {
  return m == CrossTangent::Corrected ? "corrected" : m == CrossTangent::Paper ? "paper" : "blend";
}

struct NamedMesh {
  std::string name;
  RefMesh mesh;
};

std::vector<NamedMesh> regularShapes() {
  return {{"cube", refUnitSphereCube()}, {"icosahedron", refIcosahedron()}, {"dodecahedron", refDodecahedron()}};
}

/// Jittered polytopes: vertices moved up to 0.1-0.15, normals tilted 10 degrees.
std::vector<NamedMesh> irregularShapes() {
  return {{"jittered cube 1", refJitteredPolytope(1, 0, 0.1, 10.0)},
          {"jittered cube 7", refJitteredPolytope(7, 0, 0.15, 10.0)},
          {"jittered icosahedron 3", refJitteredPolytope(3, 1, 0.1, 10.0)}};
}

std::vector<NamedMesh> allShapes() {
  auto all = regularShapes();
  for (auto& s : irregularShapes()) all.push_back(s);
  all.push_back({"twisted strip", refTwistedStrip()});
  return all;
}

double diameter(const RefPatch& p) {
  double d = 0;
  for (const auto& a : p.V)
    for (const auto& b : p.V) d = std::max(d, (a - b).norm());
  return d;
}

int numFaces(const RefMesh& m) { return static_cast<int>(m.faces.size()); }
int sides(const RefPatch& p) { return static_cast<int>(p.V.size()); }

}  // namespace

// ------------------------------------------------------------------ shapes

TEST(ReferenceShapes, ClosedOutwardUnitNormals) {
  for (const auto& [name, m] : allShapes()) {
    SCOPED_TRACE(name);
    const auto nb = refEdgeNeighbours(m);
    const bool closed = name != "twisted strip";
    for (int f = 0; f < numFaces(m); ++f) {
      const auto& F = m.faces[f];
      Eigen::Vector3d newell = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
      for (size_t k = 0; k < F.size(); ++k) {
        newell += m.positions[F[k]].cross(m.positions[F[(k + 1) % F.size()]]);
        c += m.positions[F[k]];
        if (closed) {
          EXPECT_GE(nb[f][k].face, 0);
        }
      }
      if (closed) {
        EXPECT_GT(newell.dot(c), 0.0) << "face " << f << " not CCW from outside";
      }
    }
    for (const auto& n : m.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-15);
  }
  EXPECT_EQ(numFaces(refUnitSphereCube()), 6);
  EXPECT_EQ(numFaces(refIcosahedron()), 20);
  EXPECT_EQ(numFaces(refDodecahedron()), 12);
  EXPECT_EQ(refDodecahedron().positions.size(), 20u);
}

// ------------------------------------------------------------------ edge curve, n_c

TEST(ReferenceEdge, CurveEndsReversalAndDerivative) {
  for (const auto& [name, m] : allShapes()) {
    SCOPED_TRACE(name);
    const auto nb = refEdgeNeighbours(m);
    for (int f = 0; f < numFaces(m); ++f) {
      const RefPatch p = refFacePatch(m, f);
      const int n = sides(p);
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d A = p.V[k], B = p.V[(k + 1) % n];
        const double L = (B - A).norm();
        EXPECT_LT((refEdgeCurve(p, k, 0) - A).norm(), 1e-15 * L);
        EXPECT_LT((refEdgeCurve(p, k, 1) - B).norm(), 1e-15 * L);
        // Hermite: |C'(0)| = |C'(1)| = L, in the vertices' tangent planes.
        EXPECT_NEAR(refEdgeCurveDerivative(p, k, 0).norm(), L, 1e-14 * L);
        EXPECT_NEAR(refEdgeCurveDerivative(p, k, 1).norm(), L, 1e-14 * L);
        EXPECT_NEAR(refEdgeCurveDerivative(p, k, 0).dot(p.N[k]), 0, 1e-14 * L);
        EXPECT_NEAR(refEdgeCurveDerivative(p, k, 1).dot(p.N[(k + 1) % n]), 0, 1e-14 * L);
        for (double s : {0.0, 0.2, 0.5, 0.9, 1.0}) {
          const double h = 1e-6, t = std::clamp(s, h, 1 - h);
          const Eigen::Vector3d fd = (refEdgeCurve(p, k, t + h) - refEdgeCurve(p, k, t - h)) / (2 * h);
          EXPECT_LT((refEdgeCurveDerivative(p, k, t) - fd).norm(), 1e-8 * L);
          const Eigen::Vector3d nc = refEdgeNormal(p, k, s);
          EXPECT_NEAR(nc.norm(), 1.0, 1e-14);
          EXPECT_NEAR(nc.dot(refEdgeCurveDerivative(p, k, s)), 0.0, 1e-13 * L);
          if (nb[f][k].face < 0) continue;  // same curve and n_c from the other face
          const RefPatch q = refFacePatch(m, nb[f][k].face);
          EXPECT_LT((refEdgeCurve(q, nb[f][k].edge, 1 - s) - refEdgeCurve(p, k, s)).norm(), 1e-14 * L);
          EXPECT_LT((refEdgeNormal(q, nb[f][k].edge, 1 - s) - nc).norm(), 1e-13);
        }
        EXPECT_LT((refEdgeNormal(p, k, 0) - p.N[k]).norm(), 1e-13);  // n_c(0) = +N_k
        EXPECT_LT((refEdgeNormal(p, k, 1) - p.N[(k + 1) % n]).norm(), 1e-13);
      }
    }
  }
}

TEST(ReferenceEdge, GuardFiresOnlyOnTheTwistedStrip) {
  for (const auto& [name, m] : allShapes()) {
    int fired = 0;
    for (int f = 0; f < numFaces(m); ++f)
      for (int k = 0; k < static_cast<int>(m.faces[f].size()); ++k)
        fired += refEdgeGuardMask(refFacePatch(m, f), k) != 0;
    EXPECT_EQ(fired, name == "twisted strip" ? 2 : 0) << name;
  }
  // V4 -> V5 is edge 0 of face 3 (guarded start) and edge 2 of face 1 (guarded end).
  const RefMesh s = refTwistedStrip();
  EXPECT_EQ(refEdgeGuardMask(refFacePatch(s, 3), 0), 1);
  EXPECT_EQ(refEdgeGuardMask(refFacePatch(s, 1), 2), 2);
}

// ------------------------------------------------------------------ cross tangents (check 3)

TEST(ReferenceCrossTangent, EndsMatchNeighbouringEdgeCurves) {
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : {CrossTangent::Corrected, CrossTangent::Blend}) {
      SCOPED_TRACE(name + " " + modeName(mode));
      for (int f = 0; f < numFaces(m); ++f) {
        const RefPatch p = refFacePatch(m, f, mode);
        const int n = sides(p);
        for (int k = 0; k < n; ++k) {
          const double tol = 1e-13 * diameter(p);
          // T_k(0) = -C_{k-1}'(1), T_k(1) = C_{k+1}'(0)
          EXPECT_LT((refCrossTangent(p, k, 0) + refEdgeCurveDerivative(p, (k + n - 1) % n, 1)).norm(), tol);
          EXPECT_LT((refCrossTangent(p, k, 1) - refEdgeCurveDerivative(p, (k + 1) % n, 0)).norm(), tol);
          for (double t : {0.0, 0.3, 0.7, 1.0})  // T_k lies in the plane normal to n_c
            EXPECT_NEAR(refCrossTangent(p, k, t).dot(refEdgeNormal(p, k, t)), 0.0, tol);
        }
      }
    }
}

TEST(ReferenceCrossTangent, PaperEqualsCorrectedWhereCompatible) {
  for (const auto& [name, m] : allShapes()) {
    if (name == "twisted strip") continue;
    SCOPED_TRACE(name);
    for (int f = 0; f < numFaces(m); ++f) {
      const RefPatch c = refFacePatch(m, f, CrossTangent::Corrected);
      const RefPatch p = refFacePatch(m, f, CrossTangent::Paper);
      for (int k = 0; k < sides(c); ++k)
        for (double t : {0.0, 0.25, 0.5, 1.0})
          EXPECT_LT((refCrossTangent(c, k, t) - refCrossTangent(p, k, t)).norm(), 1e-13 * diameter(c));
    }
  }
}

TEST(ReferenceCrossTangent, PaperIsIncompatibleAtTheGuardedVertex) {
  // Face 1 = (V1, V2, V5, V4): its edge 2 (V5 -> V4) arrives at V4 along the guarded t_e,
  // so the printed T_3(0) cannot equal -C_2'(1) there; corrected does.
  const RefMesh s = refTwistedStrip();
  const RefPatch paper = refFacePatch(s, 1, CrossTangent::Paper);
  const Eigen::Vector3d want = -refEdgeCurveDerivative(paper, 2, 1);
  const Eigen::Vector3d got = refCrossTangent(paper, 3, 0);
  const double angle = std::acos(want.normalized().dot(got.normalized())) / kDeg;
  std::printf("[twisted strip] paper T_3(0) vs -C_2'(1): %.2f degrees apart\n", angle);
  EXPECT_GT(angle, 30.0);
  const RefPatch corr = refFacePatch(s, 1, CrossTangent::Corrected);
  EXPECT_LT((refCrossTangent(corr, 3, 0) - want).norm(), 1e-13);
}

TEST(ReferenceCrossTangent, DerivativeMatchesFiniteDifference) {
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes) {
      SCOPED_TRACE(name + " " + modeName(mode));
      const RefPatch p = refFacePatch(m, 0, mode);
      for (int k = 0; k < sides(p); ++k)
        for (double t : {0.0, 0.4, 1.0}) {
          const double h = 1e-6, tc = std::clamp(t, h, 1 - h);
          const Eigen::Vector3d fd = (refCrossTangent(p, k, tc + h) - refCrossTangent(p, k, tc - h)) / (2 * h);
          const Eigen::Vector3d d = refCrossTangentDerivative(p, k, tc);
          EXPECT_LT((d - fd).norm(), 1e-7 * (1 + d.norm()) * diameter(p));
        }
    }
}

// ------------------------------------------------------------------ patch (checks 1, 2, 4)

TEST(ReferencePatch, CornersInterpolate) {
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes)
      for (int f = 0; f < numFaces(m); ++f) {
        const RefPatch p = refFacePatch(m, f, mode);
        const RefPatchEvaluator ev(p);
        for (int k = 0; k < sides(p); ++k) {
          const Eigen::Vector2d C = refDomainCorner(sides(p), k);
          EXPECT_LT((ev.evaluate(C.x(), C.y()).pos - p.V[k]).norm(), 1e-14 * diameter(p))
              << name << " " << modeName(mode) << " face " << f << " corner " << k;
        }
      }
}

TEST(ReferencePatch, BoundaryIsTheEdgeCurve) {
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes)
      for (int f = 0; f < numFaces(m); ++f) {
        const RefPatch p = refFacePatch(m, f, mode);
        const RefPatchEvaluator ev(p);
        for (int k = 0; k < sides(p); ++k)
          for (double s : {0.0, 0.01, 0.25, 0.5, 0.8, 0.999, 1.0}) {
            const Eigen::Vector2d X = refDomainEdgePoint(sides(p), k, s, 0.0);
            EXPECT_LT((ev.position(X.x(), X.y()) - refEdgeCurve(p, k, s)).norm(), 1e-13 * diameter(p))
                << name << " " << modeName(mode) << " face " << f << " edge " << k << " s " << s;
          }
      }
}

TEST(ReferencePatch, BoundaryNormalIsTheEdgeNormal) {
  // On domain edge k the tangent plane is span(C_k', T_k), i.e. normal to n_c (Eq. 1 holds
  // for corrected and blend everywhere, for paper where it is compatible); at corner k it is
  // span(C_k'(0), C_{k-1}'(1)), normal to N_k. Exact derivatives on the boundary.
  double worst = 0;
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes) {
      if (mode == CrossTangent::Paper && name == "twisted strip") continue;
      for (int f = 0; f < numFaces(m); ++f) {
        const RefPatch p = refFacePatch(m, f, mode);
        const RefPatchEvaluator ev(p);
        const int n = sides(p);
        for (int k = 0; k < n; ++k)
          for (double s : {0.0, 0.3, 0.5, 0.9}) {
            const Eigen::Vector2d X = refDomainEdgePoint(n, k, s, 0.0);
            const Eigen::Vector3d nG = ev.evaluate(X.x(), X.y()).normal;
            const Eigen::Vector3d nc = refEdgeNormal(p, k, s);  // = N_k at s = 0
            worst = std::max(worst, refTangentPlaneAngle(nG, nc));
            EXPECT_LT(refTangentPlaneAngle(nG, nc), 1e-10)
                << name << " " << modeName(mode) << " face " << f << " edge " << k << " s " << s;
            EXPECT_GT(nG.dot(nc), 0.0) << "patch normal against n_c: " << name;
          }
      }
    }
  std::printf("[boundary] worst angle patch normal vs n_c on the boundary = %.2e rad\n", worst);
}

TEST(ReferencePatch, DerivativesMatchCentralDifferences) {
  std::mt19937 g(11);
  auto u01 = [&] { return g() / 4294967296.0; };
  double worst = 0;
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes)
      for (int f = 0; f < numFaces(m); f += 2) {
        const RefPatch p = refFacePatch(m, f, mode);
        const RefPatchEvaluator ev(p);
        const int n = sides(p);
        for (int i = 0; i < 20; ++i) {  // random points of the fan triangles, inset a little
          double a = u01(), b = u01();
          if (a + b > 1) a = 1 - a, b = 1 - b;
          const int k = static_cast<int>(u01() * n);
          const Eigen::Vector2d X = 0.98 * (a * refDomainCorner(n, k) + b * refDomainCorner(n, k + 1));
          const double h = 1e-6;
          const RefEval e = ev.evaluate(X.x(), X.y());
          const Eigen::Vector3d fx = (ev.position(X.x() + h, X.y()) - ev.position(X.x() - h, X.y())) / (2 * h);
          const Eigen::Vector3d fy = (ev.position(X.x(), X.y() + h) - ev.position(X.x(), X.y() - h)) / (2 * h);
          const double scale = std::max(e.dxi.norm(), e.deta.norm());
          const double err = std::max((e.dxi - fx).norm(), (e.deta - fy).norm()) / scale;
          worst = std::max(worst, err);
          EXPECT_LT(err, 1e-7) << name << " " << modeName(mode) << " face " << f;
          EXPECT_LT((e.pos - ev.position(X.x(), X.y())).norm(), 1e-15 * diameter(p));
        }
      }
  std::printf("[derivatives] worst relative |complex step - central difference| = %.2e\n", worst);
}

TEST(ReferencePatch, BoundaryDerivativesMatchOneSidedDifferences) {
  // On domain edges and corners the complex step runs partly outside the domain. Compare
  // its derivative along an inward (or along-the-boundary) direction w with the one-sided
  // difference (-3 G(X) + 4 G(X + h w) - G(X + 2h w)) / 2h.
  double worst = 0;
  for (const auto& [name, m] : allShapes())
    for (CrossTangent mode : kModes)
      for (int f = 0; f < numFaces(m); ++f) {
        const RefPatchEvaluator ev(refFacePatch(m, f, mode));
        const int n = ev.size();
        for (int k = 0; k < n; ++k)
          for (double s : {0.0, 0.5, 0.8}) {
            const Eigen::Vector2d X = refDomainEdgePoint(n, k, s, 0.0);
            std::vector<Eigen::Vector2d> dirs{-X.normalized()};     // towards the centre
            if (s > 0) dirs.push_back(-refDomainEdgeNormal(n, k));  // across edge k
            if (s == 0)                                             // at corner k, along edges k and k-1
              for (int o : {1, n - 1}) dirs.push_back((refDomainCorner(n, k + o) - X).normalized());
            for (const Eigen::Vector2d& w : dirs) {
              const double h = 1e-6;
              const RefEval e = ev.evaluate(X.x(), X.y());
              const Eigen::Vector3d d = w.x() * e.dxi + w.y() * e.deta;
              auto G = [&](double t) { return ev.position(X.x() + t * w.x(), X.y() + t * w.y()); };
              const Eigen::Vector3d fd = (-3 * G(0) + 4 * G(h) - G(2 * h)) / (2 * h);
              const double err = (d - fd).norm() / std::max(e.dxi.norm(), e.deta.norm());
              worst = std::max(worst, err);
              EXPECT_LT(err, 1e-7) << name << " " << modeName(mode) << " face " << f << " edge " << k << " s " << s;
            }
          }
      }
  std::printf("[derivatives] worst relative error on the boundary (one-sided) = %.2e\n", worst);
}

TEST(ReferencePatch, NormalPointsOutwardOnTheSphereShapes) {
  for (const auto& [name, m] : regularShapes())
    for (int f = 0; f < numFaces(m); ++f) {
      const RefPatchEvaluator ev(refFacePatch(m, f));
      for (const auto& X : refDomainSamples(ev.size(), 6)) {
        const RefEval e = ev.evaluate(X.x(), X.y());
        EXPECT_GT(e.normal.dot(e.pos.normalized()), 0.9) << name << " face " << f;
      }
    }
}

TEST(ReferencePatch, RejectsFewerThanThreeVertices) {
  RefPatch p;
  p.V = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()};
  p.N = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()};
  EXPECT_THROW(refEvaluate(p, 0, 0), std::invalid_argument);
}

// ------------------------------------------------------------------ sphere numbers (check 5)

namespace {

// Fan grid 60: 5,673 (triangle), 7,564 (quad), 9,455 (pentagon) samples per face. The page
// quotes three decimals (+-0.0005). The maximum sits at the face centres (asserted), which
// the grid contains exactly, so sampling cannot lower it; 0.001 covers the rounding.
void expectSphere(const RefMesh& m, const char* name, double patch, double flat) {
  for (CrossTangent mode : kModes) {
    const RefSphereDeviation d = refSphereDeviation(m, mode, 60);
    std::printf("[sphere] %-12s %-9s max|r-1| patch %.6f (face centre %.6f), flat %.6f\n", name, modeName(mode),
                d.patch, d.centre, d.flat);
    EXPECT_NEAR(d.flat, flat, 0.001);
    if (mode == CrossTangent::Blend) continue;  // the page's numbers are for the default
    EXPECT_NEAR(d.patch, patch, 0.001) << modeName(mode);
    EXPECT_NEAR(d.patch, d.centre, 1e-12) << "maximum not at a face centre";
  }
}

}  // namespace

TEST(ReferenceSphere, CubeDeviation) { expectSphere(refUnitSphereCube(), "cube", 0.104, 0.423); }
TEST(ReferenceSphere, IcosahedronDeviation) { expectSphere(refIcosahedron(), "icosahedron", 0.038, 0.205); }
TEST(ReferenceSphere, DodecahedronDeviation) { expectSphere(refDodecahedron(), "dodecahedron", 0.064, 0.205); }

// ------------------------------------------------------------------ G1 (check 6)

namespace {

/// Max tangent-plane jump (radians) over all shared edges at 1e-3, 1e-4, 1e-5 inside.
std::array<double, 3> jumps(const RefMesh& m, CrossTangent mode) {
  const RefEdgeJumpMeter meter(m, mode);
  return {meter.maxJump(1e-3), meter.maxJump(1e-4), meter.maxJump(1e-5)};
}

/// Directed edges (f, k) whose reversed edge belongs to another face, found here from the vertex
/// indices (independently of refEdgeNeighbours).
std::vector<std::pair<int, int>> sharedEdges(const RefMesh& m) {
  std::set<std::pair<int, int>> directed;
  for (const auto& F : m.faces)
    for (size_t k = 0; k < F.size(); ++k) directed.insert({F[k], F[(k + 1) % F.size()]});
  std::vector<std::pair<int, int>> out;
  for (int f = 0; f < numFaces(m); ++f)
    for (size_t k = 0; k < m.faces[f].size(); ++k)
      if (directed.count({m.faces[f][(k + 1) % m.faces[f].size()], m.faces[f][k]})) out.push_back({f, int(k)});
  return out;
}

/// G1 edge by edge: on every shared edge (`edges` of them, asserted) the tangent-plane angle
/// between the two patches at 1e-3, 1e-4, 1e-5 inside both domains is positive (two distinct
/// points of a curved surface: a meter that returns zeros fails) and shrinks at least fivefold
/// per decade (a G1 surface's shrinks tenfold, with the distance; a G0 jump stays).
void expectConverges(const std::string& name, const RefMesh& m, CrossTangent mode, int edges) {
  const RefEdgeJumpMeter meter(m, mode);
  const auto shared = sharedEdges(m);
  int measured = 0, positive = 0, shrinking = 0;
  double worst[3] = {0, 0, 0}, worstRatio = 0;
  for (const auto& [f, k] : shared) {
    const double j[3] = {meter.edgeJump(f, k, 1e-3), meter.edgeJump(f, k, 1e-4), meter.edgeJump(f, k, 1e-5)};
    ++measured;
    positive += j[0] > 0 && j[1] > 0 && j[2] > 0;
    const double ratio = std::max(j[1] / j[0], j[2] / j[1]);
    shrinking += ratio < 0.2;
    worstRatio = std::max(worstRatio, ratio);
    for (int i = 0; i < 3; ++i) worst[i] = std::max(worst[i], j[i]);
  }
  std::printf("[G1] %-22s %-9s %d edges: max %.3e %.3e %.3e deg, worst per-edge decade ratio %.3f\n", name.c_str(),
              modeName(mode), measured, worst[0] / kDeg, worst[1] / kDeg, worst[2] / kDeg, worstRatio);
  EXPECT_EQ(measured, edges) << name << " " << modeName(mode);
  EXPECT_EQ(positive, measured) << name << " " << modeName(mode);
  EXPECT_EQ(shrinking, measured) << name << " " << modeName(mode);
  // the meter's maximum over all edges is the maximum of the edges measured here
  const auto mj = jumps(m, mode);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(mj[i], worst[i]) << name << " " << modeName(mode) << " inset " << i;
}

/// Directed edges of a closed mesh: every corner starts one, and all are shared.
int corners(const RefMesh& m) {
  int n = 0;
  for (const auto& F : m.faces) n += static_cast<int>(F.size());
  return n;
}

}  // namespace

TEST(ReferenceG1, RegularShapesAllModes) {
  for (const auto& [name, m] : regularShapes())
    for (CrossTangent mode : kModes) expectConverges(name, m, mode, corners(m));
}

TEST(ReferenceG1, IrregularPolytopesAllModes) {
  // No guard fires here, so the printed construction is compatible and G1 as well.
  for (const auto& [name, m] : irregularShapes())
    for (CrossTangent mode : kModes) expectConverges(name, m, mode, corners(m));
}

TEST(ReferenceG1, PaperKeepsAJumpWhereTheGuardFires) {
  const RefMesh s = refTwistedStrip();
  constexpr int kStripShared = 8;  // a 2 x 2 grid of quads: 4 interior edges, each seen from both faces
  expectConverges("twisted strip", s, CrossTangent::Corrected, kStripShared);
  expectConverges("twisted strip", s, CrossTangent::Blend, kStripShared);
  const auto j = jumps(s, CrossTangent::Paper);
  std::printf("[G1] %-22s %-9s %.3e %.3e %.3e deg\n", "twisted strip", "paper", j[0] / kDeg, j[1] / kDeg, j[2] / kDeg);
  EXPECT_GT(j[2], 5 * kDeg);    // a jump of degrees ...
  EXPECT_GT(j[2] / j[0], 0.5);  // ... that does not shrink towards the edge
  EXPECT_GT(j[2] / j[1], 0.5);
}
