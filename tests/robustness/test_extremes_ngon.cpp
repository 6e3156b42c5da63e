// SPDX-License-Identifier: Apache-2.0
// Stability at the extremes, polygon size: every n from 3 to GP_MAX_N = 64,
// regular and irregular, planar and not, float and double; n = 65 is reported as not built.
#include <gtest/gtest.h>

#include <random>

#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include "patch_test_support.h"
#include "ref_shapes.h"
#include "test_extremes_support.h"

namespace sf::extreme {
namespace {

const Vec3 kZ(0, 0, 1);

std::vector<Vec3> regular(int n, double r = 1) {
  std::vector<Vec3> V;
  for (int k = 0; k < n; ++k) V.emplace_back(r * std::cos(2 * M_PI * k / n), r * std::sin(2 * M_PI * k / n), 0);
  return V;
}

/// Normals of a spherical cap through the polygon: tilted `deg` away from the centre.
std::vector<Vec3> dome(const std::vector<Vec3>& V, double deg) {
  std::vector<Vec3> N;
  for (const Vec3& v : V) N.push_back(ref::refTiltToward(kZ, v, deg));
  return N;
}

/// An irregular, non-planar, still star-shaped n-gon: angles jittered by up to 0.4 of a
/// step, radii in [0.5, 1.5], heights in [-0.2, 0.2]; normals of a 25-degree dome, each
/// tilted by up to 15 more degrees in a random direction.
CornerMesh irregular(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> V, N;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * (k + 0.4 * u(rng)) / n, r = 1 + 0.5 * u(rng);
    V.emplace_back(r * std::cos(a), r * std::sin(a), 0.2 * u(rng));
  }
  for (const Vec3& n0 : dome(V, 25)) N.push_back(ref::refTiltToward(n0, Vec3(u(rng), u(rng), u(rng)), 15 * u(rng)));
  return polygon(V, N);
}

TEST(ExtremeNgon, EveryNFrom3To64) {
  Sweep worst[2];
  for (int n = 3; n <= GP_MAX_N; ++n)
    for (Precision p : kBoth) {
      const std::string tag = "n=" + std::to_string(n);
      // planar with face normals: the patch is the flat polygon's plane (a triangle's: its affine map)
      const Sweep a = check(tag + " regular flat", build(polygon(regular(n), kZ), p), kZ, 0, false);
      EXPECT_EQ(a.faceStatus, n == 3 ? GP_ST_AFFINE : 0u) << tag;
      const Sweep b =
          check(tag + " regular dome", build(polygon(regular(n), dome(regular(n), 30)), p), Vec3::Zero(), 0, false);
      EXPECT_EQ(b.faceStatus & GP_ST_DEGENERATE_MASK, 0u) << tag;
      const Sweep c = check(tag + " irregular", build(irregular(n, 100 + n), p), Vec3::Zero(), 0, false);
      EXPECT_EQ(c.faceStatus & GP_ST_TOO_MANY_SIDES, 0u) << tag;
      Sweep& w = worst[p == Precision::Float];
      for (const Sweep* s : {&a, &b, &c}) {
        w.corner = std::max(w.corner, s->corner);
        w.edge = std::max(w.edge, s->edge);
        w.unit = std::max(w.unit, s->unit);
        w.plane = std::max(w.plane, s->plane);
        w.points += s->points;
        w.maxN = std::max(w.maxN, s->maxN);
        w.faceStatus |= s->faceStatus;
        w.status |= s->status;
      }
    }
  report("all n = 3..64", Precision::Double, worst[0]);
  report("all n = 3..64", Precision::Float, worst[1]);
}

// A closed 64-gon prism (two 64-gon caps, 64 quads) with angle-weighted normals: built
// everywhere and G1 across every edge, the caps' 64-gon patches included.
TEST(ExtremeNgon, ClosedPrismWith64GonCaps) {
  const int n = GP_MAX_N;
  CornerMesh m;
  for (int ring = 0; ring < 2; ++ring)
    for (const Vec3& v : regular(n)) m.mesh.positions.push_back(v + Vec3(0, 0, ring ? 0.5 : -0.5));
  std::vector<int32_t> bottom, top;
  for (int k = 0; k < n; ++k) {
    bottom.push_back(n - 1 - k);
    top.push_back(n + k);
  }
  m.mesh.addFace(bottom);
  m.mesh.addFace(top);
  for (int k = 0; k < n; ++k) m.mesh.addFace({k, (k + 1) % n, n + (k + 1) % n, n + k});
  m.normals = cornerNormals(m.mesh, NormalMode::Angle);
  for (Precision p : kBoth) {
    const PatchCache c = build(m, p, CrossTangentMode::Corrected, Backend::Tbb);
    const Sweep s = check("64-gon prism", c);
    EXPECT_EQ(s.faceStatus & GP_ST_DEGENERATE_MASK, 0u);
    if (p == Precision::Double) {
      // tangent planes agree 1e-5 inside (the jump shrinks tenfold per decade); on the edge
      // both patches are the same curve
      const test::G1Stats g = test::measureG1(c, 1e-5, 3), on = test::measureG1(c, 0, 3);
      EXPECT_LT(g.maxAngle, 1e-3) << "worst face " << g.worstFace;  // radians
      EXPECT_LT(on.maxGap, 1e-14);
      if (std::getenv("SF_EXTREMES_REPORT"))
        std::printf("| 64-gon prism: tangent-plane jump 1e-5 inside %.2e rad, gap on the edge %.1e |\n", g.maxAngle,
                    on.maxGap);
    }
  }
}

// n = 65 (and far beyond) is not built: status GP_ST_TOO_MANY_SIDES, records zero,
// evaluation gives that status and zeros; the other faces of the mesh are built as usual.
TEST(ExtremeNgon, MoreThan64SidesIsReportedNotBuilt) {
  for (int n : {GP_MAX_N + 1, 1000}) {
    CornerMesh m;
    for (int ring = 0; ring < 2; ++ring)
      for (const Vec3& v : regular(n)) m.mesh.positions.push_back(v + Vec3(0, 0, ring ? 0.5 : -0.5));
    std::vector<int32_t> top;
    for (int k = 0; k < n; ++k) top.push_back(n + k);
    m.mesh.addFace(top);
    for (int k = 0; k < n; ++k) m.mesh.addFace({k, (k + 1) % n, n + (k + 1) % n, n + k});
    m.normals = cornerNormals(m.mesh, NormalMode::Angle);
    for (Precision p : kBoth)
      for (Backend b : {Backend::Serial, Backend::Tbb}) {
        const PatchCache c = build(m, p, CrossTangentMode::Corrected, b);
        EXPECT_EQ(c.faceStatus[0], GP_ST_TOO_MANY_SIDES);
        EXPECT_EQ(c.faceBulge[0], 0.f);
        for (int f = 1; f < c.numFaces(); ++f) EXPECT_EQ(c.faceStatus[f] & GP_ST_DEGENERATE_MASK, 0u) << f;
        const size_t ns = c.numSlots();
        for (int i = 0; i < GP_E_NFIELDS; ++i)
          for (int k = 0; k < n; ++k) {
            const double v = p == Precision::Double ? c.edgeDataD[i * ns + k] : c.edgeDataF[i * ns + k];
            ASSERT_EQ(v, 0.0) << "field " << i << " corner " << k;
          }
        for (const Vec2& x : {Vec2(0, 0), Vec2(domainCorner(n, 3)), Vec2(0.3, -0.2)}) {
          const PatchPoint q = evaluatePatch(c, 0, x.x(), x.y());
          EXPECT_EQ(q.status, GP_ST_TOO_MANY_SIDES);
          EXPECT_TRUE(q.pos.isZero(0) && q.dxi.isZero(0) && q.deta.isZero(0) && q.normal.isZero(0));
        }
        const PatchStatusSummary sum = summarizePatchStatus(c);
        EXPECT_EQ(sum.notBuilt, 1);
        EXPECT_EQ(sum.degenerateFaces, std::vector<int>{0});
        check("n=" + std::to_string(n) + " mesh, other faces", c);
      }
  }
  // the shared math itself refuses n outside [3, GP_MAX_N] before touching its arrays
  gpd::gp_vec3 V[3] = {}, N[3] = {};
  int vid[3] = {0, 1, 2};
  double recs[3 * GP_E_NFIELDS] = {};
  EXPECT_EQ(gpd::gp_build_patch(GP_MAX_N + 1, V, N, vid, GP_CT_CORRECTED, recs), GP_ST_TOO_MANY_SIDES);
  EXPECT_EQ(gpd::gp_build_patch(2, V, N, vid, GP_CT_CORRECTED, recs), GP_ST_TOO_MANY_SIDES);
  EXPECT_EQ(gpd::gp_patch_eval(GP_MAX_N + 1, recs, GP_CT_CORRECTED, 0, 0).status, GP_ST_TOO_MANY_SIDES);
}

}  // namespace
}  // namespace sf::extreme
