// SPDX-License-Identifier: Apache-2.0
// Force across creases: a HIP pressed in at 0.1%, 0.25% and 1% of the diagonal slides across
// every crease edge of every creased mesh (generated solids with ridges and valleys, the prism's
// curved rims, shared CAD-like meshes under a crease angle), from one face's interior over the
// edge's midpoint to the other's. On every step: contact held, no refinement stopped by its
// iteration cap, and the SCP as near as the nearest point of the patch surface by an independent
// dense oracle (at a valley the SCP rests on the crease curve while the HIP turns under it; at a
// ridge the nearer of the two sheets wins). The force changes faster than the HIP moves only at
// the crease.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/mesh/creases.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>
#include <smoothforce/sweep/sweep_run.h>

#include "patch_test_support.h"
#include "polygon_mesh_support.h"
#include "query_test_support.h"
#include "test_hostile_support.h"

namespace sf {
namespace {

/// The closed quad mesh of the boundary of a union of unit voxels (integer cells), outward
/// faces; vertex ids by lattice point. Coplanar neighbours share a smooth edge; every other
/// edge is a ridge or a valley of 90 degrees.
std::string voxelObj(const std::vector<std::array<int, 3>>& cells) {
  std::map<std::array<int, 3>, int> cell, vertex;
  for (const auto& c : cells) cell[c] = 1;
  std::string v, f;
  auto id = [&](std::array<int, 3> p) {
    auto [it, fresh] = vertex.emplace(p, static_cast<int>(vertex.size()) + 1);
    if (fresh) v += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    return it->second;
  };
  for (const auto& c : cells)
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {0, 1}) {
        std::array<int, 3> nb = c;
        nb[axis] += side ? 1 : -1;
        if (cell.count(nb)) continue;
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        std::array<int, 3> p[4];
        for (int j = 0; j < 4; ++j) {
          p[j] = c;
          p[j][axis] += side;
        }
        p[1][u] += 1;
        p[2][u] += 1;
        p[2][w] += 1;
        p[3][w] += 1;
        // (u, w, axis) is right-handed: p0 p1 p2 p3 faces +axis; reversed for the -axis side
        int q[4];
        for (int j = 0; j < 4; ++j) q[j] = id(p[side ? j : 3 - j]);
        f += "f " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
             std::to_string(q[3]) + "\n";
      }
  return v + f;
}

/// A closed cylinder (radius 1, height 2, n sides) as CAD exports write one: triangles only (the
/// caps as fans around a centre vertex, two long thin triangles per side panel) and a normal
/// per corner, split at the rims (f v//vn): read with --normals file, the rims are creases.
std::string triangulatedCylinderObj(int n) {
  std::string s;
  char buf[128];
  for (int z : {0, 2})
    for (int i = 0; i < n; ++i) {
      std::snprintf(buf, sizeof buf, "v %.17g %.17g %d\n", std::cos(2 * std::numbers::pi * i / n),
                    std::sin(2 * std::numbers::pi * i / n), z);
      s += buf;
    }
  s += "v 0 0 0\nv 0 0 2\nvn 0 0 -1\nvn 0 0 1\n";
  for (int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof buf, "vn %.17g %.17g 0\n", std::cos(2 * std::numbers::pi * i / n),
                  std::sin(2 * std::numbers::pi * i / n));
    s += buf;
  }
  auto corner = [](int v, int vn) { return " " + std::to_string(v + 1) + "//" + std::to_string(vn + 1); };
  const int bottomCentre = 2 * n, topCentre = 2 * n + 1;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    s += "f" + corner(bottomCentre, 0) + corner(j, 0) + corner(i, 0) + "\n";
    s += "f" + corner(topCentre, 1) + corner(n + i, 1) + corner(n + j, 1) + "\n";
    s += "f" + corner(i, 2 + i) + corner(j, 2 + j) + corner(n + j, 2 + j) + "\n";
    s += "f" + corner(i, 2 + i) + corner(n + j, 2 + j) + corner(n + i, 2 + i) + "\n";
  }
  return s;
}

struct CreasedMesh {
  std::string name;
  std::shared_ptr<const PatchCache> cache, skeleton;  // prebuilt patches; built on demand
};

CreasedMesh load(const std::string& name, const std::string& path, double creaseAngle,
                 NormalMode normals = NormalMode::Auto) {
  PatchOptions o;
  o.creases.angleDeg = creaseAngle;
  o.normals = normals;
  const LoadedMesh l = loadMesh(path, o);
  return {name, std::make_shared<const PatchCache>(buildPatchCache(l, o, Backend::Tbb)),
          std::make_shared<const PatchCache>(preparePatchSkeleton(l, o))};
}

/// One slide across the crease edge k of face f at depth d, through the point M of the edge at
/// parameter t (0.5: its midpoint; 0: its first vertex, where other sheets may meet): over f's
/// patch from 0.7 of the way to its centre to M, then around M (the HIP at M - d n, n turning from f's
/// normal there to the neighbour's), then over the neighbour's patch to 0.7 of the way to its
/// centre; HIP = G(X) - d N(X) on the patches. Preceded by an approach along f's normal from d
/// outside. `nearCrease[i]`: HIP i is within 2 d of M.
struct CreaseSlide {
  std::vector<Eigen::Vector3d> hips;
  std::vector<char> nearCrease;
  size_t slideBegin = 0;
  bool valley = false;  ///< the neighbour's sheet turns up towards the HIP's side
  bool throughVertex = false;  ///< t = 0: through the edge's vertex, where other creases may meet
};
CreaseSlide creaseSlide(const PatchCache& c, int f, int k, double d, double step, double t) {
  CreaseSlide s;
  s.throughVertex = t == 0;
  const int twin = c.slotTwin[c.faceOffsets[f] + k];
  const int g = slotFace(c.faceOffsets, twin), i = twin - c.faceOffsets[g];
  const Eigen::Vector2d ef = test::edgePoint(c.faceSize(f), k, t, 0), eg = test::edgePoint(c.faceSize(g), i, 1 - t, 0);
  const PatchPoint mf = evaluatePatch(c, f, ef.x(), ef.y()), mg = evaluatePatch(c, g, eg.x(), eg.y());
  const Eigen::Vector3d M = mf.pos, nL = mf.normal, nR = mg.normal;
  // the neighbour's side seen from f: a point just inside g lies above f's tangent plane at M
  const PatchPoint inG = evaluatePatch(c, g, 0.9 * eg.x(), 0.9 * eg.y());
  s.valley = (inG.pos - M).dot(nL) > 0;
  auto add = [&](const Eigen::Vector3d& h) {
    s.hips.push_back(h);
    s.nearCrease.push_back((h - M).norm() <= 2 * d);
  };
  auto sheet = [&](int face, const Eigen::Vector2d& e, bool toEdge) {
    const PatchPoint a = evaluatePatch(c, face, 0.3 * e.x(), 0.3 * e.y());
    const int n = std::max(8, static_cast<int>(std::ceil((a.pos - M).norm() / step)));
    for (int j = 0; j <= n; ++j) {
      const double u = toEdge ? double(j) / n : 1 - double(j) / n;  // 0 at 0.3 e, 1 at the edge
      const Eigen::Vector2d X = (0.3 + 0.7 * u) * e;
      const PatchPoint p = evaluatePatch(c, face, X.x(), X.y());
      add(p.pos - d * p.normal);
    }
  };
  const PatchPoint a = evaluatePatch(c, f, 0.3 * ef.x(), 0.3 * ef.y());
  for (int j = 0; j < 8; ++j) add(a.pos + d * (1 - j / 4.0) * a.normal);
  s.slideBegin = s.hips.size();
  sheet(f, ef, true);
  const double turn = std::atan2(nL.cross(nR).norm(), nL.dot(nR));
  const int n = std::max(8, static_cast<int>(std::ceil(d * turn / step)));
  for (int j = 1; j < n; ++j) {  // slerp from nL to nR
    const double u = double(j) / n;
    const Eigen::Vector3d nn =
        (std::sin((1 - u) * turn) * nL + std::sin(u * turn) * nR) / std::sin(turn);
    add(M - d * nn.normalized());
  }
  sheet(g, eg, false);
  return s;
}


/// What one tracker met over every slide of a mesh.
struct Counts {
  int steps = 0, onSurface = 0;
  int noContact = 0, falseContact = 0, capStops = 0, notNearest = 0;
  int jumpsAtRidges = 0, jumpsAtValleys = 0, jumpsAway = 0;
  double worstExcess = 0;        // largest (SCP distance - oracle distance) / depth, through edge midpoints
  double worstVertexExcess = 0;  // the same through crease vertices
};

/// Every step of a slide at depth d for one tracker's sample r (prev: its previous step's),
/// against the oracle's nearest point o and inside verdict.
void countStep(const CreaseSlide& p, size_t i, double d, const ForceSample& r, const ForceSample& prev,
               const test::DenseOracle::Nearest& o, bool inside, double stiffness, Counts& n) {
  ++n.steps;
  // a HIP on the surface itself (within 1e-3 depths) may go either way: pressed in at a
  // 90-degree ridge, M - d n lies on the other side's sheet
  const bool onSurface = o.distance <= 1e-3 * d;
  n.onSurface += onSurface;
  if (!onSurface && inside != r.contact) {
    if (n.noContact + n.falseContact < 8)
      std::printf("  step %zu/%zu near %d valley %d: contact %d inside %d, nearest %.3g depths face %d; status %x face %d\n", i,
                  p.hips.size(), p.nearCrease[i], p.valley, r.contact, inside, o.distance / d, o.face, r.status, r.face);
    (inside ? n.noContact : n.falseContact) += 1;
  }
  n.capStops += (r.status & SF_TRACK_MAX_ITER) != 0;
  if (r.contact && !onSurface) {
    // the SCP is the nearest surface point: within 1e-6 depths through an edge's midpoint;
    // through a vertex where three or more sheets meet, within 1% of the depth
    const double excess = ((r.scp - p.hips[i]).norm() - o.distance) / d;
    double& worst = p.throughVertex ? n.worstVertexExcess : n.worstExcess;
    worst = std::max(worst, excess);
    n.notNearest += excess > (p.throughVertex ? 1e-2 : 1e-6);
  }
  if (i > p.slideBegin && r.contact && prev.contact) {
    // the force changing faster than the HIP moves, by a margin: a jump
    const double dF = (r.force - prev.force).norm(), dH = (p.hips[i] - p.hips[i - 1]).norm();
    if (dF > 4 * stiffness * dH) {
      if (!p.nearCrease[i] && !p.nearCrease[i - 1])
        ++n.jumpsAway;
      else  // a vertex of a valley can be a ridge's too
        (p.valley && !p.throughVertex ? n.jumpsAtValleys : n.jumpsAtRidges) += 1;
    }
  }
}

/// Slides across both directions of every crease edge at 0.1%, 0.25% and 1% of the diagonal,
/// with the prebuilt and the lazy tracker; returns {valley slides, ridge slides}. certify: also
/// prove that no patch folds (false for a mesh whose every patch another test certifies, built
/// with the same options).
std::array<int, 2> slideAcrossEveryCrease(const CreasedMesh& m, bool certify = true) {
  const PatchCache& c = *m.cache;
  const double diag = boundingDiagonal(c);
  ForceOptions fo;
  std::unique_ptr<ForceRenderer> renderer[2] = {
      makePatchForceRenderer(m.cache, std::make_shared<const PolygonScene>(c), fo),
      makePatchForceRenderer(m.skeleton, std::make_shared<const PolygonScene>(*m.skeleton), fo)};
  // the creased surface as a whole: no fault (folded or overlapping sheets) on the closed
  // surface, and no patch proven to turn over against its polygon
  const SurfaceFaults faults = measureSurfaceFaults(PatchSurface(c));
  EXPECT_TRUE(faults.closed) << m.name;
  EXPECT_EQ(faults.faultArea(), 0.0) << m.name;
  std::printf("crease slides %-26s surface faults %.3g m^2 of %.3g\n", m.name.c_str(), faults.faultArea(),
              faults.totalArea);
  if (certify) {
    PatchCache certified = c;
    CertificateOptions budget;
    budget.maxCells = budget.triangleMaxCells = 12000;  // an undecided patch costs at most this many cells
    budget.regularity = false;  // the test asks for no patch proven folded: the fixed directions decide that
    certifyPatches(certified, 0, budget);
    const CertificateSummary cs = summarizeCertificates(certified);
    std::printf("crease slides %-26s certificate: %d of %d certified, %d undecided, %d proven to fold\n",
                m.name.c_str(), cs.certified, c.numFaces(), cs.undecided, cs.folded);
    EXPECT_EQ(cs.folded, 0) << m.name;
  }
  test::DenseOracle oracle(c);
  PatchRefiner refiner(c);
  Counts n[2];
  std::array<int, 2> kinds{0, 0};
  // through every crease edge's midpoint at three depths, and through its first vertex (where a
  // sheet that meets the face only there may be the nearer one) at one
  for (const auto& [frac, t] : {std::pair{0.001, 0.5}, {0.0025, 0.5}, {0.01, 0.5}, {0.0025, 0.0}}) {
    const double d = frac * diag, step = d / 4;
    for (int s = 0; s < c.numSlots(); ++s) {
      const int f = slotFace(c.faceOffsets, s), k = s - c.faceOffsets[f];
      if (!isCreaseEdge(c, f, k)) continue;
      const CreaseSlide p = creaseSlide(c, f, k, d, step, t);
      kinds[p.valley ? 0 : 1] += 1;
      ForceSample prev[2];
      for (auto& r : renderer) r->reset();
      for (size_t i = 0; i < p.hips.size(); ++i) {
        ForceSample r[2];
        for (int j = 0; j < 2; ++j) r[j] = renderer[j]->step(p.hips[i]);
        if (i >= p.slideBegin) {
          const test::DenseOracle::Nearest o = oracle.nearest(p.hips[i], refiner);
          const bool inside = oracle.winding(p.hips[i]) >= 1;
          for (int j = 0; j < 2; ++j) countStep(p, i, d, r[j], prev[j], o, inside, fo.stiffness, n[j]);
        }
        prev[0] = r[0];
        prev[1] = r[1];
      }
    }
  }
  for (int j = 0; j < 2; ++j) {
    SCOPED_TRACE(m.name + (j ? " (lazy)" : " (prebuilt)"));
    std::printf("crease slides %-26s %-9s %3d valley, %3d ridge slides, %6d steps: no contact %d, false contact %d "
                "(%d HIPs on the surface), cap stops %d, not nearest %d (worst %.1g depths, %.1g through vertices); force jumps at ridges "
                "%d, at valleys %d, elsewhere %d\n",
                m.name.c_str(), j ? "lazy" : "prebuilt", kinds[0], kinds[1], n[j].steps, n[j].noContact,
                n[j].falseContact, n[j].onSurface, n[j].capStops, n[j].notNearest, n[j].worstExcess, n[j].worstVertexExcess,
                n[j].jumpsAtRidges, n[j].jumpsAtValleys, n[j].jumpsAway);
    EXPECT_GT(n[j].steps, 0);
    EXPECT_EQ(n[j].noContact, 0);
    EXPECT_EQ(n[j].falseContact, 0);
    EXPECT_EQ(n[j].capStops, 0);
    EXPECT_EQ(n[j].notNearest, 0);
    EXPECT_EQ(n[j].jumpsAway, 0);
    EXPECT_EQ(n[j].jumpsAtValleys, 0);  // under a valley the force turns with the HIP
  }
  return kinds;
}

TEST(CreaseSlides, EveryCreaseHoldsContactAndTheNearestSheet) {
  hostile::TempDir dir("sf_crease_slides");
  const std::vector<std::array<int, 3>> ell{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::array<int, 3>> stairs{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 0, 1}, {2, 0, 1}, {2, 0, 2},
                                               {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {1, 1, 1}, {2, 1, 1}, {2, 1, 2}};
  std::ofstream(dir.path / "ell.obj") << voxelObj(ell);
  std::ofstream(dir.path / "stairs.obj") << voxelObj(stairs);
  std::ofstream(dir.path / "prism.obj") << test::turnedObj(12, {{1, 0}, {1, 0.5}, {1, 1}}, {0, 2});
  std::ofstream(dir.path / "cylinder.obj") << triangulatedCylinderObj(16);
  // a cylinder on a wider one: the annulus between them meets the upper side at a curved valley
  std::ofstream(dir.path / "stepped.obj")
      << test::turnedObj(10, {{1, 0}, {1, 0.6}, {0.5, 0.6}, {0.5, 1.2}}, {0, 1, 2, 3});
  std::array<int, 2> total{0, 0};
  auto add = [&](const std::array<int, 2>& k) { total[0] += k[0], total[1] += k[1]; };
  add(slideAcrossEveryCrease(load("L block (voxels)", (dir.path / "ell.obj").string(), 30)));
  add(slideAcrossEveryCrease(load("stairs (voxels)", (dir.path / "stairs.obj").string(), 30)));
  // StraightCornerSplit.CreasedFlatCapsAreFannedKeepTheirSurfaceAndCertify certifies every patch of
  // these two, built from the same files with the same (default) options: not proven again here
  add(slideAcrossEveryCrease(load("prism (tagged rims)", (dir.path / "prism.obj").string(), 0), false));
  add(slideAcrossEveryCrease(load("stepped cylinder (tagged)", (dir.path / "stepped.obj").string(), 0), false));
  add(slideAcrossEveryCrease(
      load("triangulated cylinder (split)", (dir.path / "cylinder.obj").string(), 0, NormalMode::File)));
  add(slideAcrossEveryCrease(load("cube", test::sharedMesh("lagrange/cube.obj"), 30)));
  add(slideAcrossEveryCrease(load("chamfer-cube", test::sharedMesh("pmp/chamfer-cube.off"), 30)));
  std::printf("crease slides: %d across valleys, %d across ridges\n", total[0], total[1]);
  EXPECT_GT(total[0], 0);
  EXPECT_GT(total[1], 0);
}

/// HIPs level with one sheet of a valley: inside a cylinder standing on a wider one, at the height
/// of the annulus between them (its vertices' z, and 1e-12 of the diagonal above and below), near
/// the upper cylinder's wall. The foot on the wall lies on the valley's crease curve, in the
/// annulus's tangent plane, so that plane alone cannot tell the HIP's side. Every such HIP is
/// inside (the dense oracle's winding number), and a contact start there makes contact, prebuilt
/// and lazy, at the nearest patch point.
TEST(CreaseSlides, HipsLevelWithOneSheetOfAValleyAreInside) {
  hostile::TempDir dir("sf_crease_level");
  std::ofstream(dir.path / "stepped.obj")
      << test::turnedObj(10, {{1, 0}, {1, 0.6}, {0.5, 0.6}, {0.5, 1.2}}, {0, 1, 2, 3});
  const CreasedMesh m = load("stepped cylinder (tagged)", (dir.path / "stepped.obj").string(), 0);
  const PatchCache& c = *m.cache;
  const double diag = boundingDiagonal(c);
  double level = NAN;  // the annulus's z as read
  for (int v = 0; v < c.numVertices(); ++v)
    if (std::abs(c.positions[3 * v + 2] - 0.6) < 1e-9) level = c.positions[3 * v + 2];
  ASSERT_TRUE(std::isfinite(level));
  ForceOptions fo;
  std::unique_ptr<ForceRenderer> renderer[2] = {
      makePatchForceRenderer(m.cache, std::make_shared<const PolygonScene>(c), fo),
      makePatchForceRenderer(m.skeleton, std::make_shared<const PolygonScene>(*m.skeleton), fo)};
  test::DenseOracle oracle(c);
  PatchRefiner refiner(c);
  const double apothem = 0.5 * std::cos(std::numbers::pi / 10);  // the upper wall's nearest radius
  int hips = 0, contacts[2] = {0, 0}, notNearest[2] = {0, 0};
  for (int j = 0; j < 40; ++j)
    for (const double f : {0.002, 0.01, 0.05})
      for (const double dz : {0.0, 1e-12, -1e-12}) {
        const double a = 2 * std::numbers::pi * (j + 0.3) / 40, r = apothem * (1 - f);
        const Eigen::Vector3d hip(r * std::cos(a), r * std::sin(a), level + dz * diag);
        ASSERT_GE(oracle.winding(hip), 1) << hip.transpose();
        const test::DenseOracle::Nearest o = oracle.nearest(hip, refiner);
        ++hips;
        for (int i = 0; i < 2; ++i) {
          renderer[i]->reset();
          const ForceSample s = renderer[i]->step(hip);
          contacts[i] += s.contact;
          EXPECT_TRUE(s.contact) << (i ? "lazy" : "prebuilt") << " at " << hip.transpose() << " status " << std::hex
                                 << s.status;
          notNearest[i] += s.contact && (s.scp - hip).norm() > o.distance + 1e-9 * diag;
        }
      }
  std::printf("level with a valley's sheet: %d HIPs inside; contact prebuilt %d, lazy %d; not nearest %d, %d\n", hips,
              contacts[0], contacts[1], notNearest[0], notNearest[1]);
  EXPECT_EQ(hips, 360);
  EXPECT_EQ(contacts[0], hips);
  EXPECT_EQ(contacts[1], hips);
  EXPECT_EQ(notNearest[0], 0);
  EXPECT_EQ(notNearest[1], 0);
}

/// Sweeps over creased solids, on the oneTBB and the OpenCL backends: no HIP inside the surface
/// (the sweep's own inside test) is left without contact, the backends agree on every contact,
/// and along the default trajectory (the section at half height, across the blocks' ridges and
/// the L's valley; the section through the axis of a triangulated cylinder with split normals,
/// across its rims and through its caps' centres) the patch force's consecutive differences away
/// from the crease crossings stay below those at them.
TEST(CreaseSlides, SweepsFindEveryContactAndJumpOnlyAtCreases) {
  hostile::TempDir dir("sf_crease_sweeps");
  std::ofstream(dir.path / "ell.obj") << voxelObj({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  std::ofstream(dir.path / "cylinder.obj") << triangulatedCylinderObj(24);
  std::string why;
  const bool opencl = openclAvailable(&why);
  if (!opencl) std::printf("crease sweeps: OpenCL backend skipped (%s)\n", why.c_str());
  for (const auto& [name, path, angle, normals] :
       {std::tuple<std::string, std::string, double, NormalMode>{"L block", (dir.path / "ell.obj").string(), 30.0,
                                                                 NormalMode::Auto},
        {"chamfer-cube", test::sharedMesh("pmp/chamfer-cube.off"), 30.0, NormalMode::Auto},
        {"tri. cylinder", (dir.path / "cylinder.obj").string(), 0.0, NormalMode::File}}) {
    SCOPED_TRACE(name);
    const CreasedMesh m = load(name, path, angle, normals);
    SweepData d[2];
    for (int b = 0; b < (opencl ? 2 : 1); ++b) {
      SweepInputs in;
      in.cache = m.cache;
      in.config.source = name;
      in.config.methods = {"patch"};
      in.config.samples = 2000;
      in.config.seed = 3;
      in.config.backend = b ? "opencl" : "tbb";
      in.depths = parseDepthList("0.1%,1%");
      d[b] = runSweep(in, {});
      size_t missed = 0, inside = 0;
      for (const HipResult& r : d[b].results[0]) {
        ASSERT_TRUE(r.done);
        inside += (r.status & SF_PROBE_INSIDE) != 0;
        missed += (r.status & SF_PROBE_INSIDE) && !r.contact;
      }
      size_t series = 0;
      for (const TrajectorySeries& t : d[b].trajectories) {
        if (t.half) continue;
        ++series;
        size_t crossings = 0;
        for (auto x : t.crease) crossings += x;
        EXPECT_GT(crossings, 0u) << t.depthLabel;
        const auto mx = maxDifferenceByCreases(t, static_cast<size_t>(std::ceil(2 * t.depth / t.step)) + 1);
        std::printf("crease sweeps %-16s %-6s %s: %zu crease crossings, max |dF| %.3g N near them, %.3g N elsewhere\n",
                    name.c_str(), in.config.backend.c_str(), t.depthLabel.c_str(), crossings, mx[1], mx[0]);
        EXPECT_LT(mx[0], mx[1]) << t.depthLabel;
      }
      std::printf("crease sweeps %-16s %-6s %zu HIPs, %zu inside, missed %zu\n", name.c_str(),
                  in.config.backend.c_str(), d[b].results[0].size(), inside, missed);
      EXPECT_GT(inside, d[b].results[0].size() / 2);
      EXPECT_EQ(missed, 0u);
      EXPECT_EQ(series, 2u);
    }
    if (!opencl) continue;
    size_t contactDiff = 0;
    for (size_t i = 0; i < d[0].results[0].size(); ++i) contactDiff += d[0].results[0][i].contact != d[1].results[0][i].contact;
    EXPECT_EQ(contactDiff, 0u);
  }
}

}  // namespace
}  // namespace sf
