// SPDX-License-Identifier: Apache-2.0
// The per-patch certificate (patch_certificate.h) against an independent computation: dense
// samples of the scalar evaluation (kernels/ in double). The enclosures behind it hold every
// sampled point of every box (corners, boundary-crossing boxes, triangles to hexagons, folded
// and non-convex faces); a certified patch has no sampled point whose normal leaves the face's
// side, and its margin bounds every sampled cosine; a patch whose sampled normal turns over is
// never certified; a corner normal tilted against the face is proven folded.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>

#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/detail/patch_enclosure.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_certificate.h>
#include "gregory_reference.h"
#include "reference_patch_support.h"
#include "ref_sampling.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

/// The design page's construction (fold repair off): its folds are what the certificate must find.
/// cage: the mesh read as a Catmull-Clark cage (its limit positions and normals).
PatchCache meshCache(const std::string& rel, bool cage = false) {
  PatchOptions o;
  o.foldRepair = FoldRepairMode::Off;
  if (cage) o.cage = CageMode::CatmullClark;
  return buildPatchCache(loadMesh(test::sharedMesh(rel), o), o, Backend::Tbb);
}

/// The polygon's unit Newell normal, from the mesh's own positions.
Eigen::Vector3d newellNormal(const PatchCache& c, int f) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const int m = c.faceSize(f), first = c.faceOffsets[f];
  for (int k = 0; k < m; ++k) {
    const double* a = &c.positions[3 * size_t(c.faceVertices[first + k])];
    const double* b = &c.positions[3 * size_t(c.faceVertices[first + (k + 1) % m])];
    n += Eigen::Vector3d((a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]), (a[0] - b[0]) * (a[1] + b[1]));
  }
  return n.normalized();
}

struct Sample {
  bool inside = false;
  Eigen::Vector3d pos, dxi, deta;
};

Sample sampleAt(int n, const double* recs, int mode, double x, double y) {
  gpd::gp_domain scratch;
  const gpd::gp_eval_result r = gpd::gp_patch_eval_dom_d(gpd::gp_domain_of(n, &scratch, 1), recs, mode, x, y, 1);
  Sample s;
  s.inside = !(r.status & GP_ST_OUTSIDE);
  s.pos = {r.pos.x, r.pos.y, r.pos.z};
  s.dxi = {r.dxi.x, r.dxi.y, r.dxi.z};
  s.deta = {r.deta.x, r.deta.y, r.deta.z};
  return s;
}

/// Strictly inside the domain of the n-gon (every d_k > 0), so that the sample is the patch's.
bool inDomain(int n, double x, double y) {
  for (int k = 0; k < n; ++k) {
    const double a = (2 * k + 1) * std::numbers::pi / n;
    if (!(std::cos(std::numbers::pi / n) - (x * std::cos(a) + y * std::sin(a)) > 0)) return false;
  }
  return true;
}

/// The smallest sampled cosine between the patch normal and the face normal over a grid of
/// side g on the domain's box (points strictly inside the domain), and the count of samples.
double smallestSampledCosine(int n, const double* recs, int mode, const Eigen::Vector3d& nf, int g, int* count) {
  double worst = 2;
  *count = 0;
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j) {
      const double x = -1 + 2.0 * i / g, y = -1 + 2.0 * j / g;
      if (!inDomain(n, x, y)) continue;
      const Sample s = sampleAt(n, recs, mode, x, y);
      const Eigen::Vector3d N = s.dxi.cross(s.deta);
      worst = std::min(worst, N.norm() > 0 ? N.dot(nf) / N.norm() : -1.0);
      ++*count;
    }
  return worst;
}

/// The direction a certificate speaks of (PatchCertificate::direction).
Eigen::Vector3d directionOf(const PatchCertificate& pc) {
  return {pc.direction[0], pc.direction[1], pc.direction[2]};
}

/// The unit mean of a patch's unit corner normals (the certificate's second direction).
Eigen::Vector3d cornerNormalMean(int n, const double* recs) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const double* c = recs + k * GP_E_NFIELDS + GP_E_N0;
    m += Eigen::Vector3d(c[0], c[1], c[2]).normalized();
  }
  return m.normalized();
}

/// A certified patch has no sampled point whose normal turns from the direction it was proven
/// along by more than its margin allows; one with a sampled turn-over against its polygon
/// (cosineToFace <= 0) is certified only along the second direction. Returns whether pc is
/// certified along another direction than the face normal.
bool checkAgainstSamples(const PatchCertificate& pc, int n, const double* recs, const Eigen::Vector3d& face,
                         double cosineToFace, int grid) {
  if (pc.verdict != CertificateVerdict::Certified) return false;
  EXPECT_GT(pc.margin, 0);
  const Eigen::Vector3d d = directionOf(pc);
  const bool other = (d - face.normalized()).norm() > 1e-12;
  int count = 0;
  const double cosine = other ? smallestSampledCosine(n, recs, 0, d, grid, &count) : cosineToFace;
  EXPECT_GE(cosine, pc.margin * (1 - 1e-12));
  if (cosineToFace <= 0) {
    EXPECT_TRUE(other) << "certified along the face normal with a sampled turn-over";
  }
  return other;
}

TEST(PatchCertificate, EnclosuresHoldEverySampledPointOfEveryBox) {
  // faces of every size from 3 to 6, convex and not, folded and not
  const std::vector<std::pair<std::string, int>> meshes = {
      {"keenan_crane/spot_control_mesh.obj", 9}, {"geomview/dodecahedron.off", 1},
      {"polygon_laplacian/hexaSphere.off", 7},   {"keenan_crane/bob_tri.obj", 97},
      {"polygon_laplacian/tetris.obj", 1},       {"pmp/L.off", 1}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  long boxes = 0, points = 0, violations = 0;
  for (const auto& [rel, stride] : meshes) {
    SCOPED_TRACE(rel);
    const PatchCache c = meshCache(rel);
    for (int f = 0; f < c.numFaces(); f += stride) {
      const int n = c.faceSize(f);
      std::array<double, GP_MAX_N * GP_E_NFIELDS> recs;
      gatherRecords(c, f, recs.data());
      const Eigen::Vector3d nf = newellNormal(c, f);
      gpd::gp_domain scratch;
      const gpd::gp_domain* dom = gpd::gp_domain_of(n, &scratch, 1);
      // box centres: two domain corners, an edge midpoint, the centre, two random points
      std::vector<Eigen::Vector2d> centres = {{dom->cx[0], dom->cy[0]},
                                              {dom->cx[1], dom->cy[1]},
                                              {0.5 * (dom->cx[1] + dom->cx[2]), 0.5 * (dom->cy[1] + dom->cy[2])},
                                              {0, 0}};
      for (int r = 0; r < 2; ++r) {
        Eigen::Vector2d p(U(rng), U(rng));
        while (!inDomain(n, p.x(), p.y())) p = {U(rng), U(rng)};
        centres.push_back(p);
      }
      for (const Eigen::Vector2d& ctr : centres)
        for (double h : {0.25, 1.0 / 16, 1.0 / 64, 1.0 / 256}) {
          const double x0 = ctr.x() - h, x1 = ctr.x() + h, y0 = ctr.y() - h, y1 = ctr.y() + h;
          const detail::PatchEnclosure e =
              detail::enclosePatch(n, recs.data(), CrossTangentMode::Corrected, nf.data(), x0, x1, y0, y1);
          ++boxes;
          for (int i = 0; i <= 6; ++i)
            for (int j = 0; j <= 6; ++j) {
              const double x = x0 + (x1 - x0) * i / 6, y = y0 + (y1 - y0) * j / 6;
              if (!inDomain(n, x, y)) continue;
              const Sample s = sampleAt(n, recs.data(), 0, x, y);
              ++points;
              for (int a = 0; a < 3; ++a)
                violations +=
                    !e.pos[a].contains(s.pos[a]) + !e.dxi[a].contains(s.dxi[a]) + !e.deta[a].contains(s.deta[a]);
              violations += !e.J.contains(s.dxi.cross(s.deta).dot(nf));
            }
        }
    }
  }
  EXPECT_EQ(violations, 0);
  EXPECT_EQ(boxes, 6864);
  EXPECT_GT(points, 50000);
}

/// The value of model t's polynomial part at (ex, ey) of its box.
double polynomialAt(const interval::Taylor& t, double ex, double ey) {
  return t.c + t.gx * ex + t.gy * ey + t.hxx * ex * ex + t.hxy * ex * ey + t.hyy * ey * ey;
}

TEST(PatchCertificate, TaylorModelsHoldEverySampledValueOfTheirOperations) {
  // random exact quadratics a, b over the box (no error term), each operation's model against
  // the same function evaluated in double at 7 x 7 points of the box: |f - P| <= err, up to the
  // double evaluation's own rounding; reciprocals and square roots also near their pole, where
  // the model falls back to the interval
  using interval::Taylor;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  auto quadratic = [&](double centre, double spread) {
    return Taylor(centre, spread * U(rng), spread * U(rng), 0.3 * spread * U(rng), 0.3 * spread * U(rng),
                  0.3 * spread * U(rng), 0.0);
  };
  long checked = 0, violations = 0, fallbacks = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double spread = std::pow(10.0, -3 + 3 * (U(rng) + 1) / 2);  // 1e-3 .. 1
    const Taylor a = quadratic(2 * U(rng), spread), b = quadratic(2 * U(rng), spread);
    const Taylor p = quadratic(1.5 + U(rng), spread);  // positive for most spreads, near 0 for some
    struct Op {
      Taylor model;
      std::function<double(double, double)> f;
    };
    std::vector<Op> ops = {{a + b, [&](double x, double y) { return polynomialAt(a, x, y) + polynomialAt(b, x, y); }},
                           {a - b, [&](double x, double y) { return polynomialAt(a, x, y) - polynomialAt(b, x, y); }},
                           {a * b, [&](double x, double y) { return polynomialAt(a, x, y) * polynomialAt(b, x, y); }},
                           {a * b * a, [&](double x, double y) {
                              return polynomialAt(a, x, y) * polynomialAt(b, x, y) * polynomialAt(a, x, y);
                            }}};
    if (!(p.range().lo <= 0)) {
      ops.push_back({recip(p), [&](double x, double y) { return 1 / polynomialAt(p, x, y); }});
      ops.push_back({gp_sqrt(p), [&](double x, double y) { return std::sqrt(polynomialAt(p, x, y)); }});
      ops.push_back({a / p, [&](double x, double y) { return polynomialAt(a, x, y) / polynomialAt(p, x, y); }});
      fallbacks += recip(p).gx == 0 && p.gx != 0;
    }
    for (const Op& op : ops)
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
          const double x = -1 + i / 3.0, y = -1 + j / 3.0, v = op.f(x, y);
          ++checked;
          const double slack = 1e-14 * (std::fabs(v) + op.model.mag());
          violations += !(std::fabs(v - polynomialAt(op.model, x, y)) <= op.model.err + slack) ||
                        !op.model.range().contains(v);
        }
  }
  std::printf("Taylor models: %ld sampled values, %ld outside their model; %ld reciprocals fell back to the interval\n",
              checked, violations, fallbacks);
  EXPECT_EQ(violations, 0);
  EXPECT_GT(checked, 500000);
  EXPECT_GT(fallbacks, 0);
}

TEST(PatchCertificate, CertifiedPatchesTurnNowhereAgainstTheirDirection) {
  struct Case {
    std::string rel;
    int stride, certified, folded;  // expected counts over the faces visited
    int cells = 20000;              // the budget per patch (triangles: triangleMaxCells)
    bool cage = false;              // read as a Catmull-Clark cage
    std::vector<int> only = {};     // visit these faces alone
  };
  // the spot cage's faces 0, 30, ..., 150 and its 16 sampled folds; small closed polyhedra; planar
  // non-convex polygons (most fold); triangles of a sphere (their domain's corners are where the
  // edge parameters' denominators vanish); two patches of the spot cage's limit surface that turn
  // past 90 degrees from their polygon's plane, proven along their corner normals' mean; a
  // triangle of that surface proven only with cells down to 2^-14 of its box near a corner; four
  // patches of the spot cage that neither the face normal nor that mean proves, proven along the
  // centre of their sampled normal cone
  const std::vector<Case> cases = {{"lagrange/cube.obj", 1, 6, 0},
                                   {"geomview/dodecahedron.off", 1, 12, 0},
                                   {"polygon_laplacian/tetris.obj", 1, -1, -1},
                                   {"pmp/L.off", 1, 0, 1},
                                   {"keenan_crane/spot_control_mesh.obj", 30, -1, -1},
                                   {"odedstein/sphere.obj", 320, 4, 0},
                                   {"keenan_crane/spot_control_mesh.obj", 1, 2, 0, 400000, true, {39, 129}},
                                   {"keenan_crane/spot_control_mesh.obj", 1, 1, 0, 500000, true, {81}},
                                   {"keenan_crane/spot_control_mesh.obj", 1, 4, 0, 400000, false, {22, 74, 112, 164}}};
  long sampled = 0;
  int certifiedTotal = 0, turnedTotal = 0, alongCorners = 0, alongCone = 0;
  for (const Case& cs : cases) {
    SCOPED_TRACE(cs.rel);
    const PatchCache c = meshCache(cs.rel, cs.cage);
    CertificateOptions o;
    o.maxCells = cs.cells;
    o.triangleMaxCells = std::max(cs.cells, 200000);
    o.regularity = false;  // the fixed directions (the cell-by-cell proof: RegularPatches... below)
    int certified = 0, folded = 0, visited = 0;
    for (int f = 0; f < c.numFaces(); ++f) {
      if (!cs.only.empty() ? std::find(cs.only.begin(), cs.only.end(), f) == cs.only.end()
                           : f % cs.stride != 0 && !(c.faceStatus[f] & GP_ST_FOLD))
        continue;
      ++visited;
      const int n = c.faceSize(f);
      std::array<double, GP_MAX_N * GP_E_NFIELDS> recs;
      gatherRecords(c, f, recs.data());
      const PatchCertificate pc = certifyPatch(n, recs.data(), CrossTangentMode::Corrected, o);
      int count = 0;
      const double cosine = smallestSampledCosine(n, recs.data(), 0, newellNormal(c, f), 60, &count);
      sampled += count;
      ASSERT_GT(count, 1000);
      SCOPED_TRACE(f);
      certified += pc.verdict == CertificateVerdict::Certified;
      if (checkAgainstSamples(pc, n, recs.data(), newellNormal(c, f), cosine, 60))
        ((directionOf(pc) - cornerNormalMean(n, recs.data())).norm() < 1e-12 ? alongCorners : alongCone) += 1;
      if (pc.verdict == CertificateVerdict::Folded) {
        ++folded;
        EXPECT_LT(pc.margin, 0);
      }
      turnedTotal += cosine <= 0;
    }
    std::printf("%s: %d faces visited, %d certified, %d proven folded\n", cs.rel.c_str(), visited, certified, folded);
    if (cs.certified >= 0) {
      EXPECT_EQ(certified, cs.certified);
    }
    if (cs.folded >= 0) {
      EXPECT_EQ(folded, cs.folded);
    }
    certifiedTotal += certified;
  }
  std::printf("%d certified along the corner normals' mean, %d along the normal cone's centre\n", alongCorners,
              alongCone);
  EXPECT_EQ(alongCorners, 2);  // the limit surface's two
  EXPECT_EQ(alongCone, 4);
  EXPECT_GT(certifiedTotal, 18);
  EXPECT_GT(turnedTotal, 0);
  EXPECT_GT(sampled, 50000);
}

/// One square (sides 4) or equilateral triangle (sides 3) in the plane z = 0 with normal +z at
/// every corner but corner 0, whose normal is tilted by `deg` degrees away from the face
/// (outwards from the polygon's centre, past the face's plane beyond 90 degrees).
PatchCache tiltedPolygon(int sides, double deg) {
  PolygonMesh m;
  if (sides == 4)
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  else
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(0.75), 0}};
  for (int k = 0; k < sides; ++k) m.faceVertices.push_back(k);
  m.faceOffsets = {0, sides};
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : m.positions) centre += p / sides;
  const double a = deg * std::numbers::pi / 180;
  const Eigen::Vector3d away = (m.positions[0] - centre).normalized();
  std::vector<Eigen::Vector3d> normals(sides, Eigen::Vector3d::UnitZ());
  normals[0] = std::cos(a) * Eigen::Vector3d::UnitZ() + std::sin(a) * away;
  PatchCache c = preparePatchCache(m, normals, PatchOptions{}, 0);
  constructPatches(c, Backend::Serial);
  return c;
}

TEST(PatchCertificate, ACornerNormalTiltedPastTheFaceIsProvenFolded) {
  int certified = 0, folded = 0, turned = 0, alongCorners = 0;
  for (int deg = 0; deg <= 170; deg += 10) {
    SCOPED_TRACE(deg);
    const PatchCache c = tiltedPolygon(4, deg);
    std::array<double, 4 * GP_E_NFIELDS> recs;
    gatherRecords(c, 0, recs.data());
    CertificateOptions o;
    o.regularity = false;  // the fixed directions
    const PatchCertificate pc = certifyPatch(4, recs.data(), CrossTangentMode::Corrected, o);
    int count = 0;
    const double cosine = smallestSampledCosine(4, recs.data(), 0, Eigen::Vector3d::UnitZ(), 80, &count);
    certified += pc.verdict == CertificateVerdict::Certified;
    const bool other = checkAgainstSamples(pc, 4, recs.data(), Eigen::Vector3d::UnitZ(), cosine, 80);
    alongCorners += other;
    folded += pc.verdict == CertificateVerdict::Folded;
    turned += cosine <= 0;
    if (deg > 90) {  // the corner's own normal turns over: never certified along the face normal
      EXPECT_TRUE(pc.verdict == CertificateVerdict::Folded || other);
    }
  }
  std::printf("tilted square: %d certified (%d along the corner normals' mean), %d proven folded, %d with sampled "
              "turn-over of 18\n",
              certified, alongCorners, folded, turned);
  EXPECT_GE(certified, 5);
  EXPECT_GE(folded + alongCorners, 8);
}

TEST(PatchCertificate, ATriangleIsCertifiedUntilItsTiltedCornerTurnsOver) {
  // The edge parameters' denominators vanish at a triangle's domain corners: the certificate
  // must bound J there (before, no triangle was ever certified). Flat up to a tilt of 40 degrees;
  // proven folded from 100.
  int certified = 0, folded = 0;
  for (int deg : {0, 20, 40, 100, 140}) {
    SCOPED_TRACE(deg);
    const PatchCache c = tiltedPolygon(3, deg);
    std::array<double, 3 * GP_E_NFIELDS> recs;
    gatherRecords(c, 0, recs.data());
    const PatchCertificate pc = certifyPatch(3, recs.data(), CrossTangentMode::Corrected);
    int count = 0;
    const double cosine = smallestSampledCosine(3, recs.data(), 0, Eigen::Vector3d::UnitZ(), 80, &count);
    ASSERT_GT(count, 1000);
    certified += pc.verdict == CertificateVerdict::Certified;
    EXPECT_FALSE(checkAgainstSamples(pc, 3, recs.data(), Eigen::Vector3d::UnitZ(), cosine, 80));
    folded += pc.verdict == CertificateVerdict::Folded;
    EXPECT_EQ(pc.verdict, deg <= 40 ? CertificateVerdict::Certified : CertificateVerdict::Folded)
        << "smallest sampled cosine " << cosine;
  }
  EXPECT_EQ(certified, 3);
  EXPECT_EQ(folded, 2);
}

/// What dense samples of the independent reference (tests/reference) say of a patch's
/// regularity: the smallest sine of the angle between dG/dxi and dG/deta over the fan samples
/// of its domain, the smallest cosine between the unit normals of two neighbouring samples of a
/// fan triangle, and the smallest cosine between the patch normal and the edge normal n_c(t) at
/// points of every edge (1e-7 inside the domain, t from the domain point as Eq. 4 gives it).
struct SampledRegularity {
  double minSine = 2, minNeighbourCosine = 2, minEdgeCosine = 2;
  int samples = 0;
};
SampledRegularity sampleRegularity(const PatchCache& c, int f, int grid) {
  const int n = c.faceSize(f);
  const ref::RefPatch rp = test::referencePatchOf(c, f);
  const ref::RefPatchEvaluator ev(rp);
  SampledRegularity r;
  // the fan triangle (O, C_k, C_k+1) sampled as (i C_k + j C_k+1) / grid: neighbours differ in i or j
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d a = ref::refDomainCorner(n, k), b = ref::refDomainCorner(n, (k + 1) % n);
    std::vector<Eigen::Vector3d> normal((grid + 1) * (grid + 1));
    for (int i = 0; i <= grid; ++i)
      for (int j = 0; i + j <= grid; ++j) {
        const Eigen::Vector2d x = (i * a + j * b) / grid * (1 - 1e-9);
        const ref::RefEval e = ev.evaluate(x.x(), x.y());
        const Eigen::Vector3d N = e.dxi.cross(e.deta);
        r.minSine = std::min(r.minSine, N.norm() / (e.dxi.norm() * e.deta.norm()));
        normal[i * (grid + 1) + j] = N.normalized();
        ++r.samples;
        if (i > 0)
          r.minNeighbourCosine = std::min(r.minNeighbourCosine, N.normalized().dot(normal[(i - 1) * (grid + 1) + j]));
        if (j > 0)
          r.minNeighbourCosine = std::min(r.minNeighbourCosine, N.normalized().dot(normal[i * (grid + 1) + j - 1]));
      }
    for (int i = 1; i < grid; ++i) {  // edge k, away from its corners
      const Eigen::Vector2d x = ref::refDomainEdgePoint(n, k, double(i) / grid, 1e-7);
      auto d = [&](int j) { return std::cos(std::numbers::pi / n) - x.dot(ref::refDomainEdgeNormal(n, (j + n) % n)); };
      const double t = d(k - 1) / (d(k - 1) + d(k + 1));
      const ref::RefEval e = ev.evaluate(x.x(), x.y());
      r.minEdgeCosine = std::min(r.minEdgeCosine, e.normal.dot(ref::refEdgeNormal(rp, k, t)));
    }
  }
  return r;
}

TEST(PatchCertificate, RegularPatchesHaveNoSampledFoldAndMeetEveryEdgeAlongItsNormal) {
  // Only the face normal and the cell-by-cell proof: the square with a tilted corner normal
  // (0 to 170 degrees), a patch of the spot cage's limit surface that turns past 90 degrees from
  // its polygon's plane and from its corner normals' mean alike (only the cell-by-cell proof
  // certifies it), and one of the spot cage's own. A regular patch's samples never
  // turn back; a patch whose samples do (the tilted square past 100 degrees, whose edge or
  // interior turns over) is never regular.
  CertificateOptions o;
  o.cornerNormalDirection = o.normalConeDirection = false;
  struct Item {
    PatchCache cache;
    int face;
    std::string name;
  };
  std::vector<Item> items;
  for (int deg = 0; deg <= 170; deg += 10) items.push_back({tiltedPolygon(4, deg), 0, "tilt " + std::to_string(deg)});
  const PatchCache limit = meshCache("keenan_crane/spot_control_mesh.obj", true);
  const PatchCache cage = meshCache("keenan_crane/spot_control_mesh.obj");
  items.push_back({limit, 178, "limit face 178"});  // (faces 88 and 125 are their mirror images)
  items.push_back({cage, 35, "cage face 35"});
  int regular = 0, turned = 0, limitRegular = 0, samples = 0;
  for (const Item& it : items) {
    SCOPED_TRACE(it.name);
    const int n = it.cache.faceSize(it.face);
    std::array<double, GP_MAX_N * GP_E_NFIELDS> recs;
    gatherRecords(it.cache, it.face, recs.data());
    const PatchCertificate pc = certifyPatch(n, recs.data(), CrossTangentMode::Corrected, o);
    const SampledRegularity r = sampleRegularity(it.cache, it.face, 48);
    samples += r.samples;
    const bool sampledTurn = !(r.minSine > 0) || !(r.minNeighbourCosine > 0) || !(r.minEdgeCosine > 0);
    turned += sampledTurn;
    if (pc.verdict == CertificateVerdict::Regular) {
      ++regular;
      limitRegular += it.name.rfind("limit", 0) == 0;
      EXPECT_FALSE(sampledTurn) << "sine " << r.minSine << ", neighbours " << r.minNeighbourCosine << ", edges "
                                << r.minEdgeCosine;
      EXPECT_GT(pc.margin, 0);
      EXPECT_EQ(directionOf(pc).norm(), 0);
      // the face normal did not prove it: the patch turns past 90 degrees from it somewhere
      int count = 0;
      EXPECT_LE(smallestSampledCosine(n, recs.data(), 0, newellNormal(it.cache, it.face), 60, &count), 0.05);
    }
    if (sampledTurn) {
      EXPECT_NE(pc.verdict, CertificateVerdict::Regular);
    }
    std::printf("%s: verdict %d, %d cells; sampled sine %.3g, neighbour cosine %.3g, edge cosine %.3g\n",
                it.name.c_str(), static_cast<int>(pc.verdict), pc.cells, r.minSine, r.minNeighbourCosine,
                r.minEdgeCosine);
  }
  EXPECT_EQ(limitRegular, 1);
  EXPECT_EQ(regular, 4);  // the tilts of 90 and 100 degrees, and the two faces
  EXPECT_EQ(turned, 7);  // the tilts from 110 degrees on
  EXPECT_EQ(samples, 20 * 4 * 49 * 50 / 2);
}

TEST(PatchCertificate, APatchWithACornerInsideOutIsProvenFolded) {
  // At a corner whose two edge curves leave the vertex in the wrong order about its normal (the
  // independent reference's end derivatives: (C_k'(0) x -C_k-1'(1)) . N_k < 0), the patch meets
  // its neighbours upside down. Over every face of the spot cage: each such patch is proven
  // folded, whatever the budget inside (a tiny one here), and the construction's report names
  // them (its Catmull-Clark limit has none).
  const PatchCache c = meshCache("keenan_crane/spot_control_mesh.obj");
  CertificateOptions o;
  o.maxCells = o.triangleMaxCells = 200;  // what is proven at the boundary needs no cell inside
  o.cornerNormalDirection = o.normalConeDirection = o.regularity = false;
  int insideOut = 0, folded = 0;
  std::vector<int> insideOutFaces;  // by the reference
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    const ref::RefPatch rp = test::referencePatchOf(c, f);
    double least = 1;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d out = ref::refEdgeCurveDerivative(rp, k, 0).normalized();
      const Eigen::Vector3d in = -ref::refEdgeCurveDerivative(rp, (k + n - 1) % n, 1).normalized();
      least = std::min(least, out.cross(in).dot(rp.N[k].normalized()));
    }
    std::array<double, GP_MAX_N * GP_E_NFIELDS> recs;
    gatherRecords(c, f, recs.data());
    const PatchCertificate pc = certifyPatch(n, recs.data(), CrossTangentMode::Corrected, o);
    SCOPED_TRACE(f);
    if (least < 0) insideOutFaces.push_back(f);
    if (least < -1e-6) {
      ++insideOut;
      EXPECT_EQ(pc.verdict, CertificateVerdict::Folded) << "corner sine " << least;
      EXPECT_LT(pc.margin, 0);
    }
    folded += pc.verdict == CertificateVerdict::Folded;
  }
  std::printf("spot cage: %d patches with a corner inside out, %d proven folded (200 cells)\n", insideOut, folded);
  EXPECT_EQ(insideOut, 20);  // 10 mirror pairs
  EXPECT_GE(folded, insideOut);
  EXPECT_EQ(summarizePatchStatus(c).insideOutFaces, insideOutFaces);  // the report, from the records
  const PatchCache limit = meshCache("keenan_crane/spot_control_mesh.obj", true);
  EXPECT_TRUE(summarizePatchStatus(limit).insideOutFaces.empty());
}

TEST(PatchCertificate, TheCacheFileKeepsThemInFormat2) {
  PatchCache c = meshCache("lagrange/cube.obj");
  const std::string plain = ::testing::TempDir() + "/cert_plain.sfcache", cert = ::testing::TempDir() + "/cert.sfcache";
  writePatchCache(c, plain);
  EXPECT_TRUE(readPatchCache(plain).faceCertificate.empty());
  certifyPatches(c);
  ASSERT_EQ(c.faceCertificate.size(), 6u);
  writePatchCache(c, cert);
  const PatchCache back = readPatchCache(cert);
  EXPECT_EQ(back.faceCertificate, c.faceCertificate);
  const CertificateSummary s = summarizeCertificates(back);
  EXPECT_TRUE(s.present);
  EXPECT_EQ(s.certified, 6);
  auto version = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char h[12];
    in.read(h, 12);
    uint32_t v;
    std::memcpy(&v, h + 8, 4);
    return v;
  };
  EXPECT_EQ(version(plain), 1u);
  EXPECT_EQ(version(cert), 2u);
}

}  // namespace
}  // namespace sf
