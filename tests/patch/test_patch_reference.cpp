// SPDX-License-Identifier: Apache-2.0
// Cross-check: the production patch math (kernels/gp_patch.h, double and float, serial and
// TBB) against the independent double-precision reference (tests/reference/), on in-code
// shapes and real meshes, in every cross-tangent mode.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "gregory_reference.h"
#include "reference_patch_support.h"
#include "patch_test_support.h"

namespace sf {
namespace {

ref::CrossTangent refMode(CrossTangentMode m) {
  return m == CrossTangentMode::Paper   ? ref::CrossTangent::Paper
         : m == CrossTangentMode::Blend ? ref::CrossTangent::Blend
                                        : ref::CrossTangent::Corrected;
}

/// Random points uniform in the n-gon domain plus its corners, edge points and centre.
std::vector<Eigen::Vector2d> domainSamples(int n, std::mt19937& rng, int count) {
  std::vector<Eigen::Vector2d> pts{Eigen::Vector2d::Zero()};
  for (int k = 0; k < n; ++k) {
    pts.push_back(domainCorner(n, k));
    pts.push_back(test::edgePoint(n, k, 0.3, 0.0));
  }
  std::uniform_real_distribution<double> u(-1, 1);
  while (static_cast<int>(pts.size()) < count) {
    const Eigen::Vector2d x(u(rng), u(rng));
    if (insideDomain(n, x.x(), x.y())) pts.push_back(x);
  }
  return pts;
}

struct Diff {
  double pos = 0, deriv = 0, normal = 0;
  int compared = 0, flagged = 0;
};

/// Angle between unit vectors, accurate for tiny angles (acos is not: it bottoms out at 2e-8).
double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

/// The patch of a face with GP_ST_AFFINE (a flat triangle with straight edges and its plane's
/// normals, markAffineTriangles): the affine map of the domain triangle onto V_0 V_1 V_2 at x, from
/// the corners alone.
ref::RefEval affineReference(const ref::RefPatch& rp, const Eigen::Vector2d& x) {
  const Eigen::Vector2d a = domainCorner(3, 0);
  Eigen::Matrix2d T;
  T << domainCorner(3, 1) - a, domainCorner(3, 2) - a;
  const Eigen::Matrix2d Ti = T.inverse();
  const Eigen::Vector2d l = Ti * (x - a);
  const Eigen::Vector3d e1 = rp.V[1] - rp.V[0], e2 = rp.V[2] - rp.V[0];
  ref::RefEval r;
  r.pos = rp.V[0] + l.x() * e1 + l.y() * e2;
  r.dxi = Ti(0, 0) * e1 + Ti(1, 0) * e2;
  r.deta = Ti(0, 1) * e1 + Ti(1, 1) * e2;
  r.normal = r.dxi.cross(r.deta).normalized();
  return r;
}

/// Max differences between the cache's patches and the reference, relative to each face's size
/// (a face marked GP_ST_AFFINE against its affine map).
Diff compare(const PatchCache& c, CrossTangentMode mode, int samples) {
  std::mt19937 rng(5);
  Diff d;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    const ref::RefPatch rp = test::referencePatchOf(c, f, refMode(mode));
    double size = 0;
    for (int k = 0; k < n; ++k) size = std::max(size, (rp.V[k] - rp.V[(k + 1) % n]).norm());
    const ref::RefPatchEvaluator ev(rp);
    for (const Eigen::Vector2d& x : domainSamples(n, rng, samples)) {
      const PatchPoint p = evaluatePatch(c, f, x.x(), x.y());
      // Points where the construction itself is singular (e.g. the cross tangent of an edge
      // between two collinear neighbours vanishes at t = 1/2) carry a status and a fallback
      // value that the reference need not share: they are counted, not compared.
      if (p.status & (GP_ST_DEGENERATE_MASK | GP_ST_SINGULAR)) {
        ++d.flagged;
        continue;
      }
      ++d.compared;
      const ref::RefEval r = (c.faceStatus[f] & GP_ST_AFFINE) ? affineReference(rp, x) : ev.evaluate(x.x(), x.y());
      d.pos = std::max(d.pos, (p.pos - r.pos).norm() / size);
      d.deriv = std::max(d.deriv, std::max((p.dxi - r.dxi).norm(), (p.deta - r.deta).norm()) / size);
      // the normal is as well conditioned as the tangent frame: skip nearly parallel dG/dxi, dG/deta
      // and faces that fold (non-convex or strongly bent cages), where the normal turns over
      if (!(p.status & GP_ST_FOLD) && angle(p.dxi, p.deta) > 1e-3 && angle(p.dxi, p.deta) < M_PI - 1e-3)
        d.normal = std::max(d.normal, angle(p.normal, r.normal));
    }
  }
  return d;
}

const CrossTangentMode kModes[] = {CrossTangentMode::Corrected, CrossTangentMode::Paper, CrossTangentMode::Blend};

TEST(PatchVsReference, ShapesDouble) {
  for (auto mode : kModes)
    for (const auto& shape :
         {ref::refUnitSphereCube(), ref::refDodecahedron(), ref::refJitteredPolytope(4, 0, 0.12, 12),
          ref::refJitteredPolytope(8, 1, 0.1, 10), ref::refTwistedStrip()}) {
      const Diff d = compare(test::cacheFromShape(shape, mode), mode, 40);
      EXPECT_EQ(d.flagged, 0) << toString(mode);
      EXPECT_LT(d.pos, 1e-13) << toString(mode);
      EXPECT_LT(d.deriv, 1e-12) << toString(mode);
      EXPECT_LT(d.normal, 1e-10) << toString(mode);
    }
}

// Real cages, every face. The normal bound is looser near folds, where the normal turns fast.
TEST(PatchVsReference, RealMeshesDouble) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/hexaSphere.off",
                          "geomview/snub_dodecahedron.off", "polygon_laplacian/tetris.obj", "pmp/hole_capsule.off"})
    for (auto mode : kModes) {
      const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), mode);
      const Diff d = compare(c, mode, 12);
      // tetris.obj: planar non-convex n-gons with straight (180 degree) corners, where the
      // cross tangent is singular by construction; elsewhere hardly any point is flagged.
      if (std::string(rel).find("tetris") == std::string::npos) {
        EXPECT_LT(d.flagged, d.compared / 20) << rel;
      }
      EXPECT_GT(d.compared, 0) << rel;
      EXPECT_LT(d.pos, 1e-12) << rel << " " << toString(mode);
      EXPECT_LT(d.deriv, 1e-10) << rel << " " << toString(mode);
      EXPECT_LT(d.normal, 1e-8) << rel << " " << toString(mode);
    }
}

TEST(PatchVsReference, FloatWithinStatedBound) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"),
                                           CrossTangentMode::Corrected, Precision::Float);
  const Diff d = compare(c, CrossTangentMode::Corrected, 12);
  std::printf(
      "float vs reference on the spot cage: position %.3g, derivatives %.3g (of the face size), normal %.3g rad\n",
      d.pos, d.deriv, d.normal);
  // Stated float bound: positions within 2e-5 and derivatives within 1e-4 of the face size.
  EXPECT_LT(d.pos, 2e-5);
  EXPECT_LT(d.deriv, 1e-4);
}

TEST(PatchVsReference, TbbConstructionEqualsSerial) {
  const auto shape = ref::refJitteredPolytope(9, 0, 0.1, 10);
  const PatchCache a = test::cacheFromShape(shape, CrossTangentMode::Corrected, Precision::Double, Backend::Serial);
  const PatchCache b = test::cacheFromShape(shape, CrossTangentMode::Corrected, Precision::Double, Backend::Tbb);
  EXPECT_EQ(a.edgeDataD, b.edgeDataD);
  EXPECT_EQ(a.faceStatus, b.faceStatus);
}

}  // namespace
}  // namespace sf
