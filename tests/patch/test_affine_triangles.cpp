// SPDX-License-Identifier: Apache-2.0
// Flat triangles whose corner normals are all their plane's: the default construction (fold
// repair on) takes each patch as the triangle's affine map plus its curved edges' deviations from
// their chords (GP_ST_AFFINE, markAffineTriangles), which the Gregory patch of a thin or obtuse
// such triangle is not: it folds in its own plane (docs/fold-levers.md). Checked on slabs whose
// top and bottom are strips of thin, skewed triangles and on plates with a round hole (a crease
// curve through the rim's vertices), against the design page's construction on the same files.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_bounds.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>

#include "patch_test_support.h"
#include "test_hostile_support.h"

namespace sf {
namespace {

/// A slab [0, m dx] x [0, w] x [0, h] whose top and bottom are strips of triangles between the
/// rows y = 0 and y = w of m + 1 vertices each, the row y = 0 `skew` vertices ahead: thin, obtuse
/// triangles (apex up to skew dx beyond its base); the four sides are quads.
std::string skewedSlabObj(int m, int skew, double dx, double w, double h) {
  std::string s;
  auto vertex = [&](double x, double y, double z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", x, y, z);
    s += buf;
  };
  // vertex ids (1-based): row r (0: y = 0, 1: y = w) at level l (0 bottom, 1 top), index i
  auto id = [&](int l, int r, int i) { return 1 + (l * 2 + r) * (m + 1) + i; };
  for (int l = 0; l < 2; ++l)
    for (int r = 0; r < 2; ++r)
      for (int i = 0; i <= m; ++i) vertex(i * dx, r * w, l * h);
  auto face = [&](std::vector<int> f, bool flip) {
    if (flip) std::reverse(f.begin(), f.end());
    s += "f";
    for (int v : f) s += " " + std::to_string(v);
    s += "\n";
  };
  for (int l = 0; l < 2; ++l) {
    const bool flip = l == 0;  // the bottom faces down
    // a monotone path over the two rows: row 0 runs `skew` vertices ahead of row 1
    int a = 0, b = 0;
    while (a < m || b < m) {
      const bool advanceA = a < m && (a - b < skew || b == m);
      if (advanceA) {
        face({id(l, 0, a), id(l, 0, a + 1), id(l, 1, b)}, flip);
        ++a;
      } else {
        face({id(l, 1, b), id(l, 0, a), id(l, 1, b + 1)}, flip);
        ++b;
      }
    }
  }
  for (int i = 0; i < m; ++i) {
    face({id(0, 0, i), id(0, 0, i + 1), id(1, 0, i + 1), id(1, 0, i)}, false);  // y = 0
    face({id(0, 1, i + 1), id(0, 1, i), id(1, 1, i), id(1, 1, i + 1)}, false);  // y = w
  }
  face({id(0, 1, 0), id(0, 0, 0), id(1, 0, 0), id(1, 1, 0)}, false);  // x = 0
  face({id(0, 0, m), id(0, 1, m), id(1, 1, m), id(1, 0, m)}, false);  // x = m dx
  return s;
}

struct Slab {
  const char* name;
  int m, skew;
  double dx, w;
};
const Slab kSlabs[] = {
    {"thin skewed strip", 12, 5, 0.1, 0.05},
    {"obtuse strip", 10, 3, 0.2, 0.1},
    {"long thin strip", 20, 8, 0.05, 0.02},
};

PatchCache slabCache(const std::string& path, FoldRepairMode repair, Precision precision = Precision::Double) {
  PatchOptions o;
  o.creases.angleDeg = 30;
  o.foldRepair = repair;
  o.precision = precision;
  return buildPatchCache(loadMesh(path, o), o, Backend::Tbb);
}

/// The affine map of face f's triangle at domain point X, from its vertices and the domain's
/// corners: an independent computation of what the patch must be.
Eigen::Vector3d affinePoint(const PatchCache& c, int f, const Eigen::Vector2d& X) {
  Eigen::Vector3d V[3];
  for (int k = 0; k < 3; ++k) V[k] = Eigen::Vector3d(&c.positions[3 * size_t(c.faceVertices[c.faceOffsets[f] + k])]);
  const Eigen::Vector2d a = domainCorner(3, 0), b = domainCorner(3, 1), d = domainCorner(3, 2);
  Eigen::Matrix2d T;
  T << b - a, d - a;
  const Eigen::Vector2d l = T.inverse() * (X - a);
  return V[0] + l.x() * (V[1] - V[0]) + l.y() * (V[2] - V[0]);
}

/// How many of the points (faces[q], xs[q], ys[q]) target t's batch evaluation gives with the
/// scalar path's bits (position, derivatives, normal, status).
size_t sameAsScalar(const PatchCache& c, SimdTarget t, const std::vector<int32_t>& faces, const std::vector<double>& xs,
                    const std::vector<double>& ys) {
  EvalOptions eo;
  eo.simd = t;
  std::vector<PatchPoint> out(faces.size());
  PatchEvaluator(c, eo).evaluate(faces.data(), xs.data(), ys.data(), faces.size(), out.data());
  size_t same = 0;
  for (size_t q = 0; q < faces.size(); ++q) {
    const PatchPoint p = evaluatePatch(c, faces[q], xs[q], ys[q]);
    same += out[q].pos == p.pos && out[q].dxi == p.dxi && out[q].deta == p.deta && out[q].normal == p.normal &&
            out[q].status == p.status;
  }
  return same;
}

/// Face f of `b` has the patch of face f of `a`, bit for bit (the same size and records).
bool samePatch(const PatchCache& a, const PatchCache& b, int f) {
  if (a.faceSize(f) != b.faceSize(f)) return false;
  std::vector<double> x(size_t(a.faceSize(f)) * GP_E_NFIELDS), y(x.size());
  gatherRecords(a, f, x.data());
  gatherRecords(b, f, y.data());
  return x == y;
}

}  // namespace

// Every top and bottom triangle of the slabs: the design page's construction proves some of them
// folded, the default one marks every one affine, proves every patch of the slab fold-free and
// leaves no fault; the records are the construction's, bit for bit, in both.
TEST(AffineTriangles, FlatStraightTrianglesAreTheirAffineMapAndNeverFold) {
  hostile::TempDir dir("sf_affine");
  int foldedOff = 0, affine = 0, strips = 0;
  for (const Slab& sl : kSlabs) {
    const std::string path = (dir.path / (std::string(sl.name) + ".obj")).string();
    std::ofstream(path) << skewedSlabObj(sl.m, sl.skew, sl.dx, sl.w, 0.3);
    PatchCache off = slabCache(path, FoldRepairMode::Off), on = slabCache(path, FoldRepairMode::On);
    ASSERT_EQ(off.numFaces(), on.numFaces()) << sl.name;  // nothing to cut: the same faces
    const int triangles = 2 * 2 * sl.m;                   // top and bottom, 2 m each
    strips += triangles;
    int marked = 0;
    for (int f = 0; f < on.numFaces(); ++f) {
      EXPECT_EQ(off.faceStatus[f] & GP_ST_AFFINE, 0u) << sl.name << " face " << f;
      EXPECT_EQ(bool(on.faceStatus[f] & GP_ST_AFFINE), on.faceSize(f) == 3) << sl.name << " face " << f;
      marked += (on.faceStatus[f] & GP_ST_AFFINE) != 0;
      EXPECT_TRUE(samePatch(off, on, f)) << sl.name << " face " << f;
    }
    EXPECT_EQ(marked, triangles) << sl.name;
    affine += marked;
    CertificateOptions budget;  // the design page's patches: enough to prove folds, not to decide every patch
    budget.maxCells = budget.triangleMaxCells = 3000;
    budget.regularity = false;
    const CertificateSummary co = certifyPatches(off, 0, budget);
    foldedOff += co.folded;
    const CertificateSummary cs = certifyPatches(on);
    EXPECT_EQ(cs.certified, on.numFaces())
        << sl.name << " uncertified " << ::testing::PrintToString(cs.uncertifiedFaces);
    const SurfaceFaults faults = measureSurfaceFaults(PatchSurface(on));
    EXPECT_TRUE(faults.closed) << sl.name;
    EXPECT_EQ(faults.faultArea(), 0.0) << sl.name;
    // every edge of an affine patch: its neighbour's patch at the same edge points (closed), and
    // off the creases the same tangent plane (G1)
    double gap = 0, turn = 0;
    int edges = 0, smooth = 0;
    for (int f = 0; f < on.numFaces(); ++f) {
      if (!(on.faceStatus[f] & GP_ST_AFFINE)) continue;
      for (int k = 0; k < 3; ++k) {
        const int twin = on.slotTwin[on.faceOffsets[f] + k];
        ASSERT_GE(twin, 0);
        const int g = slotFace(on.faceOffsets, twin), i = twin - on.faceOffsets[g], m = on.faceSize(g);
        const bool crease = isCreaseEdge(on, f, k);
        ++edges;
        smooth += !crease;
        for (int j = 1; j <= 9; ++j) {
          const Eigen::Vector2d xf = test::edgePoint(3, k, j / 10.0, 0), xg = test::edgePoint(m, i, 1 - j / 10.0, 0);
          const PatchPoint pf = evaluatePatch(on, f, xf.x(), xf.y()), pg = evaluatePatch(on, g, xg.x(), xg.y());
          gap = std::max(gap, (pf.pos - pg.pos).norm());
          if (!crease) turn = std::max(turn, std::atan2(pf.normal.cross(pg.normal).norm(), pf.normal.dot(pg.normal)));
        }
      }
    }
    EXPECT_EQ(edges, 3 * triangles) << sl.name;
    EXPECT_GT(smooth, 0) << sl.name;
    EXPECT_LT(gap, 1e-14) << sl.name;
    EXPECT_LT(turn, 1e-12) << sl.name;
    std::printf(
        "%-18s %3d faces, %3d affine; design page's construction: %2d proven folded; default: %d certified, "
        "fault area %g of %g; edges of affine patches: %d (%d smooth), gap %.2g m, tangent planes %.2g rad "
        "apart\n",
        sl.name, on.numFaces(), marked, co.folded, cs.certified, faults.faultArea(), faults.totalArea, edges, smooth,
        gap, turn);
  }
  EXPECT_EQ(affine, strips);
  EXPECT_GT(foldedOff, 0);  // the inputs fold under the design page's construction
}

// The patch of every affine face is the triangle's affine map at every point of a domain grid,
// with its derivatives and the plane's normal, on the scalar path, every SIMD target's batch
// evaluation (the same bits) and a float cache; the cache file keeps the mark, and a file whose
// mark names a triangle that is not one is refused.
TEST(AffineTriangles, EveryPathEvaluatesTheAffineMap) {
  hostile::TempDir dir("sf_affine_eval");
  const Slab& sl = kSlabs[0];
  const std::string path = (dir.path / "slab.obj").string();
  std::ofstream(path) << skewedSlabObj(sl.m, sl.skew, sl.dx, sl.w, 0.3);
  const PatchCache c = slabCache(path, FoldRepairMode::On), cf = slabCache(path, FoldRepairMode::On, Precision::Float);
  std::vector<int32_t> faces;
  std::vector<double> xs, ys;
  int points = 0;
  double worst = 0, worstFloat = 0, worstDerivative = 0;
  for (int f = 0; f < c.numFaces(); ++f) {
    if (!(c.faceStatus[f] & GP_ST_AFFINE)) continue;
    EXPECT_TRUE(cf.faceStatus[f] & GP_ST_AFFINE) << f;
    const double scale = (Eigen::Vector3d(&c.positions[3 * size_t(c.faceVertices[c.faceOffsets[f]])])).norm() + 1;
    for (int i = 0; i <= 12; ++i)
      for (int j = 0; i + j <= 12; ++j) {  // barycentric grid, corners and edges included
        const Eigen::Vector2d a = domainCorner(3, 0), b = domainCorner(3, 1), d = domainCorner(3, 2);
        const Eigen::Vector2d X = a + (i / 12.0) * (b - a) + (j / 12.0) * (d - a);
        const PatchPoint p = evaluatePatch(c, f, X.x(), X.y());
        ASSERT_FALSE(p.status & GP_ST_NOT_A_PATCH_POINT) << f;
        EXPECT_TRUE(p.status & GP_ST_AFFINE);
        worst = std::max(worst, (p.pos - affinePoint(c, f, X)).norm() / scale);
        const double h = 1e-6;
        const Eigen::Vector3d fx = (affinePoint(c, f, X + Eigen::Vector2d(h, 0)) - affinePoint(c, f, X)) / h;
        const Eigen::Vector3d fy = (affinePoint(c, f, X + Eigen::Vector2d(0, h)) - affinePoint(c, f, X)) / h;
        worstDerivative = std::max({worstDerivative, (p.dxi - fx).norm(), (p.deta - fy).norm()});
        EXPECT_NEAR(std::abs(p.normal.z()), 1.0, 1e-15) << f;  // the slab's top and bottom lie in z = const
        worstFloat = std::max(worstFloat, (evaluatePatch(cf, f, X.x(), X.y()).pos - p.pos).norm() / scale);
        faces.push_back(f);
        xs.push_back(X.x());
        ys.push_back(X.y());
        ++points;
      }
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_LT(worstDerivative, 1e-8);
  EXPECT_LT(worstFloat, 1e-6);
  for (SimdTarget t : supportedSimdTargets())
    EXPECT_EQ(sameAsScalar(c, t, faces, xs, ys), size_t(points)) << toString(t);
  std::printf("affine faces: %d points; position %.2g, derivatives %.2g off the affine map, float %.2g\n", points,
              worst, worstDerivative, worstFloat);
  EXPECT_GT(points, 40 * 91);

  // the file keeps the mark; a mark forged on a quad is refused
  const std::string file = (dir.path / "slab.sfcache").string();
  writePatchCache(c, file);
  const PatchCache back = readPatchCache(file);
  EXPECT_EQ(back.faceStatus, c.faceStatus);
  int quad = -1;
  for (int f = 0; f < c.numFaces() && quad < 0; ++f)
    if (c.faceSize(f) != 3) quad = f;
  ASSERT_GE(quad, 0);
  PatchCache forged = c;
  forged.faceStatus[quad] |= GP_ST_AFFINE;
  writePatchCache(forged, file);
  EXPECT_THROW(readPatchCache(file), InputError);
}

namespace {

/// Face f's patch at domain point X by the formula of gp_patch_eval_affine3, written out here from
/// the triangle's vertices and its records' end tangents (the Hermite edge curves of Eq. 6) with
/// barycentric coordinates from the domain's corners: an independent computation of the map.
Eigen::Vector3d flatTrianglePoint(const PatchCache& c, int f, const Eigen::Vector2d& X) {
  double recs[3 * GP_E_NFIELDS];
  gatherRecords(c, f, recs);
  auto get = [&](int k, int field) { return Eigen::Vector3d(&recs[k * GP_E_NFIELDS + field]); };
  const Eigen::Vector2d a = domainCorner(3, 0), b = domainCorner(3, 1), d = domainCorner(3, 2);
  Eigen::Matrix2d T;
  T << b - a, d - a;
  const Eigen::Vector2d l12 = T.inverse() * (X - a);
  const double lambda[3] = {1 - l12.x() - l12.y(), l12.x(), l12.y()};
  Eigen::Vector3d g = lambda[0] * get(0, GP_E_V0) + lambda[1] * get(1, GP_E_V0) + lambda[2] * get(2, GP_E_V0);
  for (int k = 0; k < 3; ++k) {
    const double s = lambda[k] + lambda[(k + 1) % 3];
    if (!(s > 0)) continue;
    const double t = lambda[(k + 1) % 3] / s;
    const Eigen::Vector3d v0 = get(k, GP_E_V0), v1 = get(k, GP_E_V1);
    const Eigen::Vector3d curve = (2 * t * t * t - 3 * t * t + 1) * v0 + (t * t * t - 2 * t * t + t) * get(k, GP_E_M0) +
                                  (3 * t * t - 2 * t * t * t) * v1 + (t * t * t - t * t) * get(k, GP_E_M1);
    g += s * (curve - ((1 - t) * v0 + t * v1));
  }
  return g;
}

}  // namespace

// Plates with a round hole: every flat triangle is marked, those at the rim with a curved edge (the
// crease curve through the rim's vertices); the design page's construction proves some of them
// folded, the default one certifies every patch and leaves no fault. Each marked patch is the
// formula's map at every point of a domain grid (and its derivatives the map's difference
// quotients), meets its neighbours at every edge, turns its normal nowhere off its plane's (a
// dense check of what the bound proves), lies in its a-priori box (patchBoxes), and every SIMD
// target gives the scalar bits.
TEST(AffineTriangles, FlatTrianglesWithCurvedEdgesKeepTheirCurvesAndNeverFold) {
  hostile::TempDir dir("sf_affine_plate");
  int foldedOff = 0, curvedTotal = 0, points = 0;
  double worst = 0, worstDerivative = 0, worstGap = 0, worstTurn = 0, smallestCos = 1, worstFloat = 0;
  for (const int m : {16, 24, 40}) {
    const std::string path = (dir.path / ("plate" + std::to_string(m) + ".obj")).string();
    std::ofstream(path) << test::holedPlateObj(m, 0.5, 0.4);
    PatchCache off = slabCache(path, FoldRepairMode::Off), on = slabCache(path, FoldRepairMode::On),
               onFloat = slabCache(path, FoldRepairMode::On, Precision::Float);
    ASSERT_EQ(off.numFaces(), on.numFaces()) << m;  // nothing to cut: the same faces
    const int flat = 2 * (m + 4) + 8;               // top and bottom, m + 4 each, and the outer sides
    ASSERT_EQ(on.numFaces(), flat + 2 * m) << m;
    const std::vector<PatchBox> boxes = patchBoxes(on);  // the lazy query's a-priori boxes
    int marked = 0, curved = 0, outsideBox = 0;
    std::vector<int32_t> faces;
    std::vector<double> xs, ys;
    for (int f = 0; f < on.numFaces(); ++f) {
      EXPECT_EQ(off.faceStatus[f] & GP_ST_AFFINE, 0u) << m << " face " << f;
      if (!(on.faceStatus[f] & GP_ST_AFFINE)) continue;
      ++marked;
      EXPECT_TRUE(onFloat.faceStatus[f] & GP_ST_AFFINE) << m << " face " << f;
      double recs[3 * GP_E_NFIELDS];
      gatherRecords(on, f, recs);
      curved += test::hasCurvedEdge(3, recs, 1e-6);
      Eigen::Vector3d V[3];
      for (int k = 0; k < 3; ++k) V[k] = Eigen::Vector3d(recs + k * GP_E_NFIELDS + GP_E_V0);
      const Eigen::Vector3d plane = (V[1] - V[0]).cross(V[2] - V[0]).normalized();
      for (int i = 0; i <= 16; ++i)
        for (int j = 0; i + j <= 16; ++j) {  // barycentric grid, corners and edges included
          const Eigen::Vector2d a = domainCorner(3, 0), b = domainCorner(3, 1), d = domainCorner(3, 2);
          const Eigen::Vector2d X = a + (i / 16.0) * (b - a) + (j / 16.0) * (d - a);
          const PatchPoint p = evaluatePatch(on, f, X.x(), X.y());
          ASSERT_FALSE(p.status & GP_ST_NOT_A_PATCH_POINT) << m << " face " << f;
          worst = std::max(worst, (p.pos - flatTrianglePoint(on, f, X)).norm());
          outsideBox += !(boxes[f].valid && (p.pos.array() >= boxes[f].lo.array()).all() &&
                          (p.pos.array() <= boxes[f].hi.array()).all());
          smallestCos = std::min(smallestCos, p.normal.dot(plane));
          worstFloat = std::max(worstFloat, (evaluatePatch(onFloat, f, X.x(), X.y()).pos - p.pos).norm());
          faces.push_back(f);
          xs.push_back(X.x());
          ys.push_back(X.y());
          ++points;
          // central differences of the map inside the domain (its derivatives jump only at the
          // corner opposite a curved edge)
          if (i + j >= 16 || i == 0 || j == 0 || i + j < 1) continue;
          const double h = 1e-6;
          const Eigen::Vector2d ex(h, 0), ey(0, h);
          const Eigen::Vector3d fx = (flatTrianglePoint(on, f, X + ex) - flatTrianglePoint(on, f, X - ex)) / (2 * h);
          const Eigen::Vector3d fy = (flatTrianglePoint(on, f, X + ey) - flatTrianglePoint(on, f, X - ey)) / (2 * h);
          worstDerivative = std::max({worstDerivative, (p.dxi - fx).norm(), (p.deta - fy).norm()});
        }
      // every edge meets the neighbour's patch; off the creases with the same tangent plane
      for (int k = 0; k < 3; ++k) {
        const int twin = on.slotTwin[on.faceOffsets[f] + k];
        ASSERT_GE(twin, 0);
        const int g = slotFace(on.faceOffsets, twin), i = twin - on.faceOffsets[g], n = on.faceSize(g);
        const bool crease = isCreaseEdge(on, f, k);
        for (int j = 1; j <= 15; ++j) {
          const Eigen::Vector2d xf = test::edgePoint(3, k, j / 16.0, 0), xg = test::edgePoint(n, i, 1 - j / 16.0, 0);
          const PatchPoint pf = evaluatePatch(on, f, xf.x(), xf.y()), pg = evaluatePatch(on, g, xg.x(), xg.y());
          worstGap = std::max(worstGap, (pf.pos - pg.pos).norm());
          if (!crease)
            worstTurn = std::max(worstTurn, std::atan2(pf.normal.cross(pg.normal).norm(), pf.normal.dot(pg.normal)));
        }
      }
    }
    EXPECT_EQ(marked, flat) << m;
    EXPECT_EQ(outsideBox, 0) << m;
    EXPECT_EQ(curved, 2 * m) << m;  // the rim's triangles, top and bottom
    curvedTotal += curved;
    for (SimdTarget t : supportedSimdTargets())
      EXPECT_EQ(sameAsScalar(on, t, faces, xs, ys), faces.size()) << m << " " << toString(t);
    // the marked faces' certificates: the design page's patches (a budget enough to prove folds,
    // not to decide every patch) and the default's (the map's bound: no cells); the wall's Gregory
    // patches are the design page's in both constructions, and the surface check below covers them
    CertificateOptions budget;
    budget.maxCells = budget.triangleMaxCells = 1000;
    budget.cornerNormalDirection = budget.normalConeDirection = budget.regularity = false;
    int certified = 0, folded = 0;
    for (int f = 0; f < on.numFaces(); ++f) {
      if (!(on.faceStatus[f] & GP_ST_AFFINE)) continue;
      double recs[3 * GP_E_NFIELDS];
      gatherRecords(off, f, recs);
      folded += certifyPatch(3, recs, off.options.crossTangent, budget, off.faceStatus[f]).verdict ==
                CertificateVerdict::Folded;
      gatherRecords(on, f, recs);
      const PatchCertificate pc = certifyPatch(3, recs, on.options.crossTangent, {}, on.faceStatus[f]);
      certified += pc.verdict == CertificateVerdict::Certified && pc.margin > 0.999;
    }
    foldedOff += folded;
    EXPECT_EQ(certified, marked) << m;
    const SurfaceFaults faults = measureSurfaceFaults(PatchSurface(on));
    EXPECT_TRUE(faults.closed) << m;
    EXPECT_EQ(faults.faultArea(), 0.0) << m;
    std::printf(
        "plate, hole of %2d segments: %3d faces, %3d flat marked (%2d with a curved edge), %d of them certified; "
        "design page's construction: %2d proven folded; default: fault area %g of %g\n",
        m, on.numFaces(), marked, curved, certified, folded, faults.faultArea(), faults.totalArea);
  }
  std::printf(
      "marked patches: %d points; %.2g m off the formula, derivatives %.2g off its difference quotients, float "
      "%.2g; edges: gap %.2g m, tangent planes %.2g rad apart; normal against the plane's: cos >= %.17g\n",
      points, worst, worstDerivative, worstFloat, worstGap, worstTurn, smallestCos);
  EXPECT_EQ(curvedTotal, 2 * (16 + 24 + 40));
  EXPECT_GT(foldedOff, 0);  // the inputs fold under the design page's construction
  EXPECT_LT(worst, 1e-14);
  EXPECT_LT(worstDerivative, 1e-7);
  EXPECT_LT(worstFloat, 1e-6);
  EXPECT_LT(worstGap, 1e-14);
  EXPECT_LT(worstTurn, 1e-12);
  EXPECT_GT(smallestCos, 1 - 1e-12);
}

}  // namespace sf
