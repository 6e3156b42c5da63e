// SPDX-License-Identifier: Apache-2.0
// Stability at the extremes, patch level: each knob swept to its limit on
// meshes built in code, float and double, CPU backends. Every case must stay finite
// (positions, derivatives, normals), interpolate its corners, keep its boundary on the edge
// curves and give unit normals within the bounds of test_extremes_support.h; the status
// word must report the degradation the case causes. Set SF_EXTREMES_REPORT=1 to print the
// measured values (one row per case).
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "ref_shapes.h"
#include "test_extremes_support.h"

namespace sf::extreme {
namespace {

CornerMesh fromRef(const ref::RefMesh& r) {
  CornerMesh m;
  m.mesh.positions = r.positions;
  for (const auto& f : r.faces) {
    std::vector<Vec3> n;
    for (int v : f) n.push_back(r.normals[v]);
    m.face(std::vector<int32_t>(f.begin(), f.end()), n);
  }
  return m;
}

/// A generic mesh: irregular non-planar quads with tilted normals, off the origin.
CornerMesh generic() {
  CornerMesh m = fromRef(ref::refJitteredPolytope(5, 0, 0.15, 15.0));
  for (Vec3& p : m.mesh.positions) p += Vec3(0.3, -0.2, 0.1);
  return m;
}

const Vec3 kZ(0, 0, 1);

// ---- scale ------------------------------------------------------------------------------

/// Largest |G(sM) - s G(M)| / (s scale), derivatives likewise, normals absolute; status equal.
struct ScaleErr {
  double pos = 0, deriv = 0, normal = 0;
  int statusDiff = 0;
  bool finite = true;
};
ScaleErr scaleError(const CornerMesh& m, double s, Precision p) {
  const PatchCache a = build(m, p), b = build(scaled(m, s), p);
  const double scale = meshScale(a);
  ScaleErr e;
  for (int f = 0; f < a.numFaces(); ++f) {
    EXPECT_EQ(a.faceStatus[f], b.faceStatus[f]) << "face " << f << " scale " << s;
    for (const Sample& q : samples(a.faceSize(f))) {
      const PatchPoint pa = evaluatePatch(a, f, q.x.x(), q.x.y()), pb = evaluatePatch(b, f, q.x.x(), q.x.y());
      e.finite = e.finite && finite(pa) && finite(pb);
      const double d = std::max(pa.dxi.norm(), pa.deta.norm());
      e.pos = std::max(e.pos, (pb.pos - s * pa.pos).norm() / (s * scale));
      e.deriv = std::max({e.deriv, (pb.dxi - s * pa.dxi).norm() / (s * d), (pb.deta - s * pa.deta).norm() / (s * d)});
      e.normal = std::max(e.normal, (pb.normal - pa.normal).norm());
      e.statusDiff += pa.status != pb.status;
    }
  }
  if (std::getenv("SF_EXTREMES_REPORT"))
    std::printf("| scale %-8g %-6s | pos %.1e | deriv %.1e | normal %.1e | status diffs %d |\n", s, toString(p), e.pos,
                e.deriv, e.normal, e.statusDiff);
  return e;
}

// Power-of-two scales commute with every rounding (no cos/sin touches positions): the
// surface scales bit for bit. Decimal scales round the input (s * x is inexact), and that
// relative perturbation of ~1 ulp per coordinate is all that remains.
TEST(ExtremePatch, SurfaceScalesExactly) {
  for (const CornerMesh& m : {generic(), fromRef(ref::refDodecahedron())})
    for (Precision p : kBoth) {
      for (double s : {std::ldexp(1.0, -20), std::ldexp(1.0, 20)}) {
        const ScaleErr e = scaleError(m, s, p);
        EXPECT_TRUE(e.finite);
        EXPECT_EQ(e.pos, 0.0);
        EXPECT_EQ(e.deriv, 0.0);
        EXPECT_EQ(e.normal, 0.0);
        EXPECT_EQ(e.statusDiff, 0);
      }
      const double tol = p == Precision::Double ? 1e-14 : 1e-5;
      for (double s : {1e-6, 1e6}) {
        const ScaleErr e = scaleError(m, s, p);
        EXPECT_TRUE(e.finite);
        EXPECT_LE(e.pos, tol) << "scale " << s;
        EXPECT_LE(e.deriv, tol) << "scale " << s;
        EXPECT_LE(e.normal, tol) << "scale " << s;
        EXPECT_EQ(e.statusDiff, 0);
      }
      for (double s : {1e-6, 1e6})
        check("scaled x" + num(s) + (m.mesh.numFaces() == 12 ? " dodecahedron" : " polytope"), build(scaled(m, s), p));
    }
}

// How far the scale goes before the status word reports degradation (measured on this
// polytope in quarter-decade steps): float is clean from ~1e-9 to ~5e9, double from ~3e-81
// to ~1e77. Below, squared norms of L^2-sized cross products (|G_xi x G_eta|, gp_edge_normal's
// |C' x (n x e)|) go subnormal: at 1e-10 the float unit normal is off by 2e-5 with no status
// bit, from ~1e-11 EDGE_NORMAL is set. Above, they overflow: n_c becomes 0 and
// CROSS_TANGENT is set; beyond |V|^2 overflowing (float ~1.8e19, double ~1e154) the outputs
// are no longer finite.
TEST(ExtremePatch, ScaleRangeWithoutDegradation) {
  const CornerMesh m = generic();
  for (Precision p : kBoth)
    for (double s : p == Precision::Float ? std::vector<double>{1e-9, 1e9} : std::vector<double>{1e-75, 1e75}) {
      const ScaleErr e = scaleError(m, s, p);
      EXPECT_TRUE(e.finite);
      EXPECT_LE(std::max({e.pos, e.deriv, e.normal}), p == Precision::Double ? 1e-14 : 1e-5) << s;
      const Sweep r = check("polytope x" + num(s), build(scaled(m, s), p));
      EXPECT_EQ(r.status, 0u) << s << ": " << bits(r.status);
    }
}

// ---- thin, short, collinear -----------------------------------------------------------------

TEST(ExtremePatch, SliverAndNeedlePolygons) {
  const double a = 1e-6;  // aspect ratio 1e6
  const std::vector<std::pair<std::string, std::vector<Vec3>>> shapes = {
      {"sliver triangle", {{0, 0, 0}, {1, 0, 0}, {0.5, a, 0}}},
      {"needle triangle", {{0, 0, 0}, {a, 0, 0}, {0.5 * a, 1, 0}}},
      {"sliver quad", {{0, 0, 0}, {1, 0, 0}, {1, a, 0}, {0, a, 0}}},
      {"sliver hexagon", {{0, 0, 0}, {0.3, -a, 0}, {0.7, -a, 0}, {1, 0, 0}, {0.7, a, 0}, {0.3, a, 0}}},
  };
  for (Precision p : kBoth)
    for (const auto& [name, V] : shapes) {
      // flat: the patch must stay in the polygon's plane
      check(name + " flat", build(polygon(V, kZ), p), kZ, 0);
      // normals tilted 30 degrees away from the centroid: a curved, still finite patch
      Vec3 c = Vec3::Zero();
      for (const Vec3& v : V) c += v / V.size();
      std::vector<Vec3> N;
      for (const Vec3& v : V) N.push_back(ref::refTiltToward(kZ, v - c, 30));
      check(name + " tilted", build(polygon(V, N), p));
    }
}

TEST(ExtremePatch, ZeroAndNearZeroEdges) {
  for (Precision p : kBoth) {
    // V1 == V2 exactly (distinct vertex ids): flagged, still finite
    const std::vector<Vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Sweep z = check("zero-length edge", build(polygon(quad, kZ), p), kZ, 0);
    EXPECT_TRUE(z.faceStatus & GP_ST_ZERO_EDGE);
    // 1e-12 of the face size: below float resolution (flagged); double builds the edge
    for (double rel : {1e-12, 1e-9}) {
      const std::vector<Vec3> q = {{0, 0, 0}, {1, 0, 0}, {1, rel, 0}, {0, 1, 0}};
      const Sweep r = check("edge " + num(rel), build(polygon(q, kZ), p), kZ, 0);
      if (p == Precision::Float && rel == 1e-12) {
        EXPECT_TRUE(r.faceStatus & GP_ST_ZERO_EDGE);
      }
    }
    // a triangle collapsed to a point, and one at the origin (no scale at all)
    for (const Vec3& at : {Vec3(1, 2, 3), Vec3(0, 0, 0)}) {
      const Sweep r = check("point triangle", build(polygon({at, at, at}, kZ), p));
      EXPECT_TRUE(r.faceStatus & GP_ST_ZERO_EDGE);
    }
  }
}

TEST(ExtremePatch, CollinearCorners) {
  for (Precision p : kBoth) {
    // a 180-degree corner at V1: the Jacobian is rank-deficient there
    const Sweep a =
        check("quad, 3 collinear", build(polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}}, kZ), p), kZ, 0);
    EXPECT_TRUE(a.status & GP_ST_SINGULAR);
    check("pentagon, 3 collinear", build(polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2.5, 1, 0}, {0, 1, 0}}, kZ), p), kZ,
          0);
    // a triangle with all three corners on a line: zero area
    const Sweep t = check("collinear triangle", build(polygon({{0, 0, 0}, {1, 0, 0}, {3, 0, 0}}, kZ), p));
    EXPECT_TRUE(t.status & GP_ST_SINGULAR);
  }
}

// ---- shape ------------------------------------------------------------------------------------

TEST(ExtremePatch, NonPlanarAndNonConvex) {
  for (Precision p : kBoth) {
    std::vector<Vec3> saddle, star, corner;
    for (int k = 0; k < 6; ++k) {
      const double t = 2 * M_PI * k / 6;
      saddle.emplace_back(std::cos(t), std::sin(t), k % 2 ? 0.8 : -0.8);
    }
    for (int k = 0; k < 10; ++k) {
      const double t = 2 * M_PI * k / 10, r = k % 2 ? 0.2 : 1.0;
      star.emplace_back(r * std::cos(t), r * std::sin(t), 0);
    }
    // per-corner normals of a non-planar polygon: the corner's own plane
    const auto cornerNormals = [](const std::vector<Vec3>& V) {
      std::vector<Vec3> N;
      const size_t n = V.size();
      for (size_t k = 0; k < n; ++k) {
        const Vec3 c = (V[(k + 1) % n] - V[k]).cross(V[(k + n - 1) % n] - V[k]);
        N.push_back(c.norm() > 0 ? c.normalized() : kZ);
      }
      return N;
    };
    check("saddle hexagon, +z normals", build(polygon(saddle, kZ), p));
    check("saddle hexagon, corner normals", build(polygon(saddle, cornerNormals(saddle)), p));
    check("tetrahedral quad", build(polygon({{0, 0, 0}, {1, 0, 1}, {1, 1, 0}, {0, 1, 1}}, kZ), p));
    check("star 10-gon", build(polygon(star, kZ), p), kZ, 0);
    check("L hexagon", build(polygon({{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}, kZ), p), kZ,
          0);
    check("arrowhead quad", build(polygon({{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {0.5, 1, 0}}, kZ), p), kZ, 0);
    check("bow-tie quad", build(polygon({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}, kZ), p), kZ, 0);
    // a polygon folded back on itself: corner normals flip from one half to the other
    corner = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, -1e-3}, {1, 0, -1e-3}, {0, 0, -1e-3}};
    check("folded hexagon", build(polygon(corner, cornerNormals(corner)), p));
  }
}

// ---- normals ----------------------------------------------------------------------------------

TEST(ExtremePatch, NormalsAt89DegreesToTheFace) {
  const std::vector<Vec3> sq = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double deg : {89.0, 90.0})
    for (Precision p : kBoth)
      for (auto mode : {CrossTangentMode::Corrected, CrossTangentMode::Paper, CrossTangentMode::Blend}) {
        const std::string tag = std::to_string(int(deg)) + " deg " + toString(mode) + ", ";
        std::vector<Vec3> out, in, along, rnd;
        for (size_t k = 0; k < sq.size(); ++k) {
          out.push_back(ref::refTiltToward(kZ, sq[k], deg));
          in.push_back(ref::refTiltToward(kZ, -sq[k], deg));
          along.push_back(ref::refTiltToward(kZ, sq[(k + 1) % 4] - sq[k], deg));
          rnd.push_back(ref::refTiltToward(kZ, Vec3(u(rng), u(rng), 0), deg));
        }
        check(tag + "outward", build(polygon(sq, out), p, mode));
        check(tag + "inward", build(polygon(sq, in), p, mode));
        check(tag + "along edges", build(polygon(sq, along), p, mode));
        check(tag + "random", build(polygon(sq, rnd), p, mode));
        // Backward printed end tangent (design page, Robustness 1): with P the projection
        // across edge 0, t_s . e has the sign of P N0 . (P N0 + P N1). N0 leans 60 degrees
        // along the edge, N1 away across it: the guard must fire.
        std::vector<Vec3> twisted(4, kZ);
        twisted[0] = ref::refTiltToward(kZ, Vec3(0.5, std::sqrt(0.75), 0), deg);
        twisted[1] = ref::refTiltToward(kZ, Vec3(0, -1, 0), deg);
        const Sweep g = check(tag + "twisted pair", build(polygon(sq, twisted), p, mode));
        EXPECT_TRUE(g.faceStatus & GP_ST_GUARD) << tag;
      }
}

TEST(ExtremePatch, OppositeNormals) {
  for (Precision p : kBoth) {
    // the two ends of edge 0 have opposite normals: n_avg = 0 and n_c(1/2) is undefined
    const std::vector<Vec3> sq = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Sweep a = check("opposite ends of an edge", build(polygon(sq, {kZ, -kZ, kZ, kZ}), p));
    EXPECT_TRUE(a.status & GP_ST_EDGE_NORMAL);
    // opposite normals across a shared edge: face 0 has +z at V1, V2, face 1 has -z there
    CornerMesh two;
    two.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    two.face({0, 1, 2, 3}, {kZ, kZ, kZ, kZ});
    two.face({1, 4, 5, 2}, {-kZ, kZ, kZ, -kZ});
    check("opposite across an edge", build(two, p));
    // every normal opposite to the face: the patch folds over and says so
    const Sweep f = check("all normals reversed", build(polygon(sq, -kZ), p), kZ, 0);
    EXPECT_TRUE(f.faceStatus & GP_ST_FOLD);
  }
}

// ---- where it is evaluated ------------------------------------------------------------------

TEST(ExtremePatch, EvaluationOutsideTheDomain) {
  const double inf = std::numeric_limits<double>::infinity(), big = std::numeric_limits<double>::max();
  for (Precision p : kBoth)
    for (int n : {3, 4, 7, 64}) {
      std::vector<Vec3> V;
      for (int k = 0; k < n; ++k) V.emplace_back(std::cos(2 * M_PI * k / n), std::sin(2 * M_PI * k / n), 0);
      const PatchCache c = build(polygon(V, kZ), p);
      const Vec2 c0 = domainCorner(n, 0), m0 = 0.5 * (c0 + domainCorner(n, 1));
      for (const Vec2& x : {Vec2(c0 * (1 + 1e-3)), Vec2(m0 * (1 + 1e-3)), Vec2(10, 0), Vec2(-3, 7), Vec2(1e30, -1e30),
                            Vec2(big, big), Vec2(-big, 0), Vec2(inf, 0), Vec2(0, -inf), Vec2(inf, -inf)}) {
        const PatchPoint q = evaluatePatch(c, 0, x.x(), x.y());
        EXPECT_TRUE(q.status & GP_ST_OUTSIDE) << "n " << n << " at " << x.transpose();
        EXPECT_TRUE(q.pos.isZero(0) && q.dxi.isZero(0) && q.deta.isZero(0) && q.normal.isZero(0));
      }
      // rounding a hair outside (1e-15) still counts as on the boundary
      const PatchPoint e = evaluatePatch(c, 0, c0.x() * (1 + 1e-15), c0.y());
      EXPECT_FALSE(e.status & GP_ST_OUTSIDE);
      EXPECT_TRUE(finite(e));
    }
}

// A NaN domain point is not inside the domain: the evaluation says GP_ST_OUTSIDE and returns
// finite zeros, never a finite point that is not on the patch (a domain test written with `<`
// alone is false for NaN and would go on; gp_patch_eval's bound test is written to reject it).
TEST(ExtremePatch, NanDomainPointIsOutside) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Precision p : kBoth) {
    const PatchCache c = build(polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, kZ), p);
    for (const Vec2& x : {Vec2(nan, 0), Vec2(0, nan), Vec2(nan, nan)}) {
      const PatchPoint q = evaluatePatch(c, 0, x.x(), x.y());
      EXPECT_TRUE(q.status & GP_ST_OUTSIDE) << x.transpose() << " status " << bits(q.status);
      EXPECT_TRUE(finite(q)) << x.transpose();
    }
  }
}

}  // namespace
}  // namespace sf::extreme
