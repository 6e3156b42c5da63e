// SPDX-License-Identifier: Apache-2.0
// --cage catmull-clark: every vertex on OpenSubdiv's limit surface (checked against Bfr's own
// evaluation, a different code path from the Far limit masks the option uses), every patch corner
// on it, G1 across every edge, and the patch surface within a measured distance of the limit
// surface, on the spot cage and on in-code cages (closed quads, an open grid with boundary and
// corners, triangles and pentagons, a generated torus). Expected-failure: unsupported cages.
#include <gtest/gtest.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <smoothforce/base/hash.h>
#include <smoothforce/mesh/cage_limit.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/limit_distance.h>
#include <smoothforce/sweep/generators.h>
#include "patch_test_support.h"

namespace sf {
namespace {

namespace Far = OpenSubdiv::Far;
namespace Bfr = OpenSubdiv::Bfr;
namespace Sdc = OpenSubdiv::Sdc;

/// A named cage and the distance bound asserted for it (fraction of the diagonal).
struct Cage {
  std::string name;
  PolygonMesh mesh;
  double maxDistance;
};

PolygonMesh cube() {
  PolygonMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  for (auto f : std::vector<std::vector<int32_t>>{
           {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
    m.addFace(f);
  return m;
}

/// 6 x 4 quads over [0, 6] x [0, 4] with a smooth bump: an open sheet, boundary valence-2 corners.
PolygonMesh grid() {
  PolygonMesh m;
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 6; ++x) m.positions.emplace_back(x, y, 0.8 * std::sin(0.9 * x) * std::cos(0.7 * y));
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) m.addFace({y * 7 + x, y * 7 + x + 1, (y + 1) * 7 + x + 1, (y + 1) * 7 + x});
  return m;
}

/// A pentagonal prism with its top capped by a fan of 5 triangles: one pentagon, 5 quads, 5
/// triangles; closed, with valence-3, -4 and -5 vertices.
PolygonMesh pentaHouse() {
  PolygonMesh m;
  for (int k = 0; k < 5; ++k) m.positions.emplace_back(std::cos(2 * M_PI * k / 5), std::sin(2 * M_PI * k / 5), 0);
  for (int k = 0; k < 5; ++k) m.positions.emplace_back(std::cos(2 * M_PI * k / 5), std::sin(2 * M_PI * k / 5), 1.2);
  m.positions.emplace_back(0, 0, 1.9);
  m.addFace({4, 3, 2, 1, 0});  // bottom, seen from below
  for (int k = 0; k < 5; ++k) m.addFace({k, (k + 1) % 5, 5 + (k + 1) % 5, 5 + k});
  for (int k = 0; k < 5; ++k) m.addFace({5 + k, 5 + (k + 1) % 5, 10});
  return m;
}

std::vector<Cage> cages() {
  std::vector<Cage> out;
  // bounds: the larger of the two maxima LimitDistanceWithinStatedBound prints (level 16, Bfr
  // approximation level 8), with about 25% headroom; docs/cage.md lists them
  PolygonMesh spot = readMesh(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  out.push_back({"spot cage", spot, 0.012});                            // measured 0.981%
  out.push_back({"cube", cube(), 0.045});                               // 3.69%: 8 points span the whole limit
  out.push_back({"open grid", grid(), 0.003});                          // 0.220% (limit to patch, at the boundary)
  out.push_back({"pentagon, quads, triangles", pentaHouse(), 0.0175});  // 1.40%
  PolygonMesh torus = torusMesh(1.0, 0.35, 8, 5).toPolygonMesh();
  torus.fileNormals.clear();  // a cage: the generator's exact normals are of the torus, not of its limit
  out.push_back({"torus 8 x 5", torus, 0.007});  // 0.572%
  return out;
}

struct Built {
  LoadedMesh loaded;
  PatchCache cache;
};

Built buildCage(const PolygonMesh& mesh) {
  PatchOptions o;
  o.cage = CageMode::CatmullClark;
  Built b{loadMesh(mesh, 0, o), {}};
  b.cache = buildPatchCache(b.loaded, o, Backend::Tbb);
  return b;
}

/// Limit position and unit normal at every face corner (#C), by Bfr::Surface evaluated at the
/// parameterization's vertex coordinates, from the cage as oriented by loadMesh; regular: the
/// face's surface is one B-spline patch (exact derivatives). Positions are exact everywhere (Bfr
/// places an irregular patch's corner at the vertex's limit); derivatives at irregular corners
/// come from Gregory end caps after 8 levels of isolation (measured: within 2.3e-4 rad of the
/// exact limit normal on the spot cage, 1.7e-3 at 4 levels, 1.2e-2 at 2: they converge to it).
void bfrCorners(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>& cage, std::vector<Eigen::Vector3d>& pos,
                std::vector<Eigen::Vector3d>& nrm, std::vector<bool>& regular) {
  std::vector<int> sizes;
  for (int f = 0; f < mesh.numFaces(); ++f) sizes.push_back(mesh.faceSize(f));
  Far::TopologyDescriptor d;
  d.numVertices = mesh.numVertices();
  d.numFaces = mesh.numFaces();
  d.numVertsPerFace = sizes.data();
  d.vertIndicesPerFace = mesh.faceVertices.data();
  Sdc::Options so;
  so.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(d, Factory::Options(Sdc::SCHEME_CATMARK, so)));
  ASSERT_TRUE(refiner);
  Bfr::RefinerSurfaceFactory<>::Options fo;
  fo.SetApproxLevelSmooth(8);
  const Bfr::RefinerSurfaceFactory<> factory(*refiner, fo);
  std::vector<double> pts;
  for (const auto& p : cage) pts.insert(pts.end(), {p.x(), p.y(), p.z()});
  Bfr::Surface<double> s;
  std::vector<double> patch;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    ASSERT_TRUE(factory.InitVertexSurface(f, &s)) << "face " << f;
    patch.resize(size_t(s.GetNumPatchPoints()) * 3);
    s.PreparePatchPoints(pts.data(), 3, patch.data(), 3);
    for (int k = 0; k < mesh.faceSize(f); ++k) {
      double uv[2], P[3], Du[3], Dv[3];
      s.GetParameterization().GetVertexCoord(k, uv);
      s.Evaluate(uv, patch.data(), 3, P, Du, Dv);
      pos.emplace_back(P[0], P[1], P[2]);
      nrm.push_back(Eigen::Vector3d(Du[0], Du[1], Du[2]).cross(Eigen::Vector3d(Dv[0], Dv[1], Dv[2])).normalized());
      regular.push_back(s.IsRegular());
    }
  }
}

TEST(CageLimit, EveryVertexOnBfrLimitAndEveryPatchCornerInterpolatesIt) {
  for (const Cage& cg : cages()) {
    const Built b = buildCage(cg.mesh);
    const PatchCache& c = b.cache;
    const double diag = boundingDiagonal(c);
    std::vector<Eigen::Vector3d> pos, nrm;
    std::vector<bool> regular;
    bfrCorners(b.loaded.mesh, b.loaded.cagePositions, pos, nrm, regular);
    ASSERT_EQ(static_cast<int>(pos.size()), c.numSlots()) << cg.name;
    int corners = 0, moved = 0;
    double worstPos = 0, worstNormal = 0, worstRegularNormal = 0, worstPatch = 0, worstPatchNormal = 0;
    int regularCorners = 0;
    auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return std::atan2(a.cross(b).norm(), a.dot(b));
    };
    for (int f = 0; f < c.numFaces(); ++f) {
      const int n = c.faceSize(f);
      for (int k = 0; k < n; ++k) {
        const int s = c.faceOffsets[f] + k, v = c.faceVertices[s];
        const Eigen::Vector3d p(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]);
        const Eigen::Vector3d cn(c.cornerNormals[3 * s], c.cornerNormals[3 * s + 1], c.cornerNormals[3 * s + 2]);
        worstPos = std::max(worstPos, (p - pos[s]).norm() / diag);
        worstNormal = std::max(worstNormal, angle(cn, nrm[s]));
        if (regular[s]) {
          worstRegularNormal = std::max(worstRegularNormal, angle(cn, nrm[s]));
          ++regularCorners;
        }
        moved += (p - b.loaded.cagePositions[v]).norm() > 1e-9 * diag;
        const Eigen::Vector2d X = domainCorner(n, k);
        const PatchPoint q = evaluatePatch(c, f, X.x(), X.y());
        worstPatch = std::max(worstPatch, (q.pos - p).norm() / diag);
        worstPatchNormal = std::max(worstPatchNormal, angle(q.normal, cn));
        ++corners;
      }
    }
    std::printf(
        "%-28s corners %4d (moved %4d, regular %4d): |P - Bfr| %.2e diag, normal vs Bfr %.2e rad (regular "
        "%.2e); patch corner %.2e diag, %.2e rad\n",
        cg.name.c_str(), corners, moved, regularCorners, worstPos, worstNormal, worstRegularNormal, worstPatch,
        worstPatchNormal);
    EXPECT_EQ(corners, c.numSlots()) << cg.name;
    EXPECT_GT(moved, corners / 2) << cg.name << ": a cage's vertices move to the limit";
    EXPECT_LT(worstPos, 1e-12) << cg.name;
    EXPECT_LT(worstRegularNormal, 1e-12) << cg.name;
    EXPECT_LT(worstNormal, 5e-4) << cg.name;
    EXPECT_LT(worstPatch, 1e-12) << cg.name;
    EXPECT_LT(worstPatchNormal, 1e-12) << cg.name;
  }
}

/// Limit normals (#V, unit, oriented by tangent1 x tangent2 as OpenSubdiv gives them) computed
/// after `levels` uniform refinements: the tangent plane of a vertex's limit does not depend on
/// the level it is computed from, so three levels (other neighbourhoods, other weights) must
/// agree with the one level the option uses, at irregular vertices too.
std::vector<Eigen::Vector3d> farNormals(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>& cage, int levels) {
  struct P3 {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const P3& s, double w) {
      for (int d = 0; d < 3; ++d) p[d] += w * s.p[d];
    }
  };
  std::vector<int> sizes;
  for (int f = 0; f < mesh.numFaces(); ++f) sizes.push_back(mesh.faceSize(f));
  Far::TopologyDescriptor d;
  d.numVertices = mesh.numVertices();
  d.numFaces = mesh.numFaces();
  d.numVertsPerFace = sizes.data();
  d.vertIndicesPerFace = mesh.faceVertices.data();
  Sdc::Options so;
  so.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> r(Factory::Create(d, Factory::Options(Sdc::SCHEME_CATMARK, so)));
  Far::TopologyRefiner::UniformOptions u(levels);
  u.fullTopologyInLastLevel = true;
  r->RefineUniform(u);
  std::vector<P3> src(cage.size());
  for (size_t i = 0; i < cage.size(); ++i) src[i] = {{cage[i].x(), cage[i].y(), cage[i].z()}};
  for (int l = 1; l <= levels; ++l) {
    std::vector<P3> dst(r->GetLevel(l).GetNumVertices());
    Far::PrimvarRefinerReal<double>(*r).Interpolate(l, src, dst);
    src.swap(dst);
  }
  std::vector<P3> pos(src.size()), t1(src.size()), t2(src.size());
  Far::PrimvarRefinerReal<double>(*r).Limit(src, pos, t1, t2);
  std::vector<Eigen::Vector3d> out;
  for (size_t v = 0; v < cage.size(); ++v)  // vertex children come first at every level
    out.push_back(Eigen::Vector3d(t1[v].p[0], t1[v].p[1], t1[v].p[2])
                      .cross(Eigen::Vector3d(t2[v].p[0], t2[v].p[1], t2[v].p[2]))
                      .normalized());
  return out;
}

TEST(CageLimit, LimitNormalsAgreeWithThreeLevelsOfRefinement) {
  for (const Cage& cg : cages()) {
    const Built b = buildCage(cg.mesh);
    const std::vector<Eigen::Vector3d> deep = farNormals(b.loaded.mesh, b.loaded.cagePositions, 3);
    int same = 0;
    double worst = 0;
    for (int s = 0; s < b.cache.numSlots(); ++s) {
      const Eigen::Vector3d cn(b.cache.cornerNormals[3 * s], b.cache.cornerNormals[3 * s + 1],
                               b.cache.cornerNormals[3 * s + 2]);
      const Eigen::Vector3d& n = deep[b.cache.faceVertices[s]];
      const double a = std::atan2(cn.cross(n).norm(), cn.dot(n));
      worst = std::max(worst, a);
      same += a < 1e-12;
    }
    std::printf("%-28s corner normals vs 3 levels: %d of %d within 1e-12 rad (worst %.2e)\n", cg.name.c_str(), same,
                b.cache.numSlots(), worst);
    EXPECT_EQ(same, b.cache.numSlots()) << cg.name;
  }
}

TEST(CageLimit, PatchSurfaceIsG1OnEveryEdge) {
  for (const Cage& cg : cages()) {
    const PatchCache c = buildCage(cg.mesh).cache;
    const test::G1Stats a = test::measureG1(c, 1e-3), b = test::measureG1(c, 1e-4), d = test::measureG1(c, 1e-5);
    std::printf("G1 %-28s edges %4d max angle (deg) %.3g, %.3g, %.3g at 1e-3, 1e-4, 1e-5\n", cg.name.c_str(), a.edges,
                a.maxAngle * 180 / M_PI, b.maxAngle * 180 / M_PI, d.maxAngle * 180 / M_PI);
    ASSERT_GT(a.edges, 0) << cg.name;
    if (a.maxAngle > 1e-9) {
      EXPECT_LT(b.maxAngle, 0.2 * a.maxAngle) << cg.name << " (face " << b.worstFace << ")";
    }
    if (b.maxAngle > 1e-9) {
      EXPECT_LT(d.maxAngle, 0.2 * b.maxAngle) << cg.name << " (face " << d.worstFace << ")";
    }
    EXPECT_LT(d.maxGap, 1e-4 * boundingDiagonal(c)) << cg.name;  // G0: points 1e-5 inside both domains
  }
}

TEST(CageLimit, LimitDistanceWithinStatedBound) {
  for (const Cage& cg : cages()) {
    const Built b = buildCage(cg.mesh);
    const LimitDistance d = measureLimitDistance(b.cache, b.loaded, 16);
    std::printf(
        "%-28s faces %4d: patch->limit max %.4f%% mean %.5f%%, limit->patch max %.4f%% mean %.5f%% of the "
        "diagonal (worst face %d; %zu + %zu points)\n",
        cg.name.c_str(), d.facesMeasured, 100 * d.maxPatchToLimit, 100 * d.meanPatchToLimit, 100 * d.maxLimitToPatch,
        100 * d.meanLimitToPatch, d.worstFace, d.patchPoints, d.limitPoints);
    EXPECT_EQ(d.facesMeasured, b.cache.numFaces()) << cg.name;
    EXPECT_LT(d.maxPatchToLimit, cg.maxDistance) << cg.name;
    EXPECT_LT(d.maxLimitToPatch, cg.maxDistance) << cg.name;
  }
}

TEST(CageLimit, NoCageKeepsTheCacheBytesAndTheOptionsHash) {
  // the cage enters the options hash only when it is not none (and the fold repair only when it
  // is not off): caches built before they existed keep their hash
  PatchOptions o;
  o.foldRepair = FoldRepairMode::Off;
  const uint64_t none = hashPatchOptions(o);
  o.cage = CageMode::CatmullClark;
  EXPECT_NE(hashPatchOptions(o), none);
  // the hash of the default options as every earlier build computed it (the text it hashes)
  const std::string text =
      "precision=double;cross-tangent=corrected;normals=auto;orient=outward;fields=" + std::to_string(GP_E_NFIELDS);
  EXPECT_EQ(none, hashBytes(text.data(), text.size()));
}

TEST(CageLimit, CacheFileKeepsTheCageAndTheMovedMesh) {
  const Built b = buildCage(pentaHouse());
  const std::string path = ::testing::TempDir() + "cage_limit.sfcache";
  writePatchCache(b.cache, path);
  const PatchCache r = readPatchCache(path);
  EXPECT_EQ(r.options.cage, CageMode::CatmullClark);
  EXPECT_EQ(r.positions, b.cache.positions);
  EXPECT_EQ(r.edgeDataD, b.cache.edgeDataD);
  PatchOptions plain;
  EXPECT_THROW(readPatchCache(path, {std::nullopt, plain}), InputError);
  std::remove(path.c_str());
}

TEST(CageLimit, UnsupportedCagesAreRefusedNamingTheProblem) {
  PatchOptions o;
  o.cage = CageMode::CatmullClark;
  auto message = [&](const PolygonMesh& m, const PatchOptions& opt) -> std::string {
    try {
      loadMesh(m, 0, opt);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  PolygonMesh fin = cube();  // a fin on edge 0-2: three faces there
  fin.positions.emplace_back(-1, 0.5, 0.5);
  fin.addFace({0, 8, 2});
  EXPECT_NE(message(fin, o).find("non-manifold edge 0-2"), std::string::npos) << message(fin, o);
  PolygonMesh bowtie = grid();  // two sheets joined at one vertex
  const int base = bowtie.numVertices();
  for (int i = 0; i < 3; ++i) bowtie.positions.emplace_back(6 + i, 4 + i % 2, 1);
  bowtie.addFace({34, base, base + 1, base + 2});
  EXPECT_NE(message(bowtie, o).find("non-manifold vertex 34"), std::string::npos) << message(bowtie, o);
  PolygonMesh twisted = cube();
  std::reverse(twisted.faceVertices.begin(), twisted.faceVertices.begin() + 4);  // face 0 turned over
  PatchOptions keep = o;  // --orient outward turns face 0 back first (orientCoherently); keep refuses it
  keep.keepOrientation = true;
  EXPECT_NE(message(twisted, keep).find("inconsistent face orientation"), std::string::npos) << message(twisted, keep);
  EXPECT_EQ(message(twisted, o), "");
  EXPECT_EQ(loadMesh(twisted, 0, o).orientation.turnedFaces, std::vector<int>{0});
  PolygonMesh repeat = cube();
  repeat.addFace({0, 1, 0, 3});
  EXPECT_NE(message(repeat, o).find("face 6 repeats vertex 0"), std::string::npos) << message(repeat, o);
  PatchOptions area = o;
  area.normals = NormalMode::Area;
  EXPECT_NE(message(cube(), area).find("--normals area cannot be combined"), std::string::npos)
      << message(cube(), area);
  EXPECT_THROW(parseCageMode("loop"), InputError);
}

}  // namespace
}  // namespace sf
