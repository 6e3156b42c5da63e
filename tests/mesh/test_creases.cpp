// SPDX-License-Identifier: Apache-2.0
// Creases: every way a crease is marked (OpenSubdiv tags, smoothing groups, split file normals,
// PLY edge creases, a dihedral threshold) gives the same surface, and on every creased mesh each
// interior edge is one curve that both faces build bit for bit (the welded export is closed),
// each side keeps its own tangent plane along a crease, and every other edge stays G1.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <smoothforce/mesh/creases.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>

#include "patch_test_support.h"
#include "test_hostile_support.h"

namespace sf {
namespace {

using Edge = std::array<int32_t, 2>;
Edge key(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

/// A closed prism over a regular n-gon (radius 1, height 1) with `rings` rows of side quads:
/// vertex r * n + i is corner i of ring r. The caps' rims are the creases (rimCreases); the dart
/// is the side edge from vertex 0 up to vertex n (vertex 0 then has three creases: a corner).
struct Prism {
  PolygonMesh mesh;
  std::vector<Edge> rimCreases, dart;
  std::vector<int> capFaces[2], sideFaces;
};
Prism prism(int n, int rings) {
  Prism p;
  for (int r = 0; r <= rings; ++r)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      p.mesh.positions.emplace_back(std::cos(a), std::sin(a), double(r) / rings);
    }
  std::vector<int32_t> bottom, top;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  for (int i = 0; i < n; ++i) top.push_back(rings * n + i);
  p.capFaces[0].push_back(p.mesh.numFaces());
  p.mesh.addFace(bottom);
  p.capFaces[1].push_back(p.mesh.numFaces());
  p.mesh.addFace(top);
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < n; ++i) {
      const int j = (i + 1) % n;
      p.sideFaces.push_back(p.mesh.numFaces());
      p.mesh.addFace({r * n + i, r * n + j, (r + 1) * n + j, (r + 1) * n + i});
    }
  for (int i = 0; i < n; ++i) {
    p.rimCreases.push_back(key(i, (i + 1) % n));
    p.rimCreases.push_back(key(rings * n + i, rings * n + (i + 1) % n));
  }
  p.dart.push_back(key(0, n));
  return p;
}

std::string faceLine(const PolygonMesh& m, int f, bool withNormals) {
  std::string s = "f";
  for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) {
    s += ' ';  // appended piecewise: GCC 12 warns (-Wrestrict) about " " + std::to_string(...)
    s += std::to_string(m.faceVertices[c] + 1);
    if (withNormals) {
      s += "//";
      s += std::to_string(c + 1);
    }
  }
  return s + "\n";
}

std::string vertexLines(const PolygonMesh& m) {
  std::string s;
  char buf[128];
  for (const auto& p : m.positions) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    s += buf;
  }
  return s;
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

/// OBJ with `t crease` tags (0-based ids, infinitely sharp).
std::string objWithTags(const PolygonMesh& m, const std::vector<Edge>& creases) {
  std::string s = vertexLines(m);
  for (const Edge& e : creases) s += "t crease 2/1/0 " + std::to_string(e[1]) + " " + std::to_string(e[0]) + " 10\n";
  for (int f = 0; f < m.numFaces(); ++f) s += faceLine(m, f, false);
  return s;
}

/// OBJ with smoothing groups: group[f] per face.
std::string objWithGroups(const PolygonMesh& m, const std::vector<int>& group) {
  std::string s = vertexLines(m);
  for (int f = 0; f < m.numFaces(); ++f) s += "s " + std::to_string(group[f]) + "\n" + faceLine(m, f, false);
  return s;
}

/// OBJ with one `vn` per corner (f v//vn), exactly the given normals.
std::string objWithCornerNormals(const PolygonMesh& m, const std::vector<Eigen::Vector3d>& normals) {
  std::string s = vertexLines(m);
  char buf[128];
  for (const auto& n : normals) {
    std::snprintf(buf, sizeof buf, "vn %.17g %.17g %.17g\n", n.x(), n.y(), n.z());
    s += buf;
  }
  for (int f = 0; f < m.numFaces(); ++f) s += faceLine(m, f, true);
  return s;
}

/// ASCII PLY with an edge element carrying a crease value.
std::string plyWithEdgeCreases(const PolygonMesh& m, const std::vector<Edge>& creases) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.numVertices()) +
                  "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                  std::to_string(m.numFaces()) + "\nproperty list uchar int vertex_indices\nelement edge " +
                  std::to_string(creases.size()) +
                  "\nproperty int vertex1\nproperty int vertex2\nproperty float crease\nend_header\n";
  char buf[128];
  for (const auto& p : m.positions) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    s += buf;
  }
  for (int f = 0; f < m.numFaces(); ++f) {
    s += std::to_string(m.faceSize(f));
    for (int k = 0; k < m.faceSize(f); ++k) {
      s += ' ';
      s += std::to_string(m.faceVertex(f, k));
    }
    s += "\n";
  }
  for (const Edge& e : creases) s += std::to_string(e[0]) + " " + std::to_string(e[1]) + " 10\n";
  return s;
}

PatchCache build(const LoadedMesh& loaded, const PatchOptions& o) { return buildPatchCache(loaded, o, Backend::Tbb); }

/// The crease edges of a built cache (summarizeCreases), as vertex pairs.
std::vector<Edge> creaseEdges(const PatchCache& c) {
  return summarizeCreases(cacheBaseMesh(c), c.slotTwin, c.cornerNormals.data()).edges;
}

/// Field i of slot s.
double field(const PatchCache& c, int s, int i) { return c.edgeDataD[static_cast<size_t>(i) * c.numSlots() + s]; }

/// Interior edges whose two records do not describe one curve bit for bit (V0 = V1', V1 = V0',
/// M0 = -M1', M1 = -M0'); *edges receives the number of interior edges checked.
int curvesNotShared(const PatchCache& c, int* edges) {
  int bad = 0;
  *edges = 0;
  for (int s = 0; s < c.numSlots(); ++s) {
    const int t = c.slotTwin[s];
    if (t < s) continue;
    ++*edges;
    bool same = true;
    for (int a = 0; a < 3; ++a) {
      same = same && field(c, s, GP_E_V0 + a) == field(c, t, GP_E_V1 + a) &&
             field(c, s, GP_E_V1 + a) == field(c, t, GP_E_V0 + a) &&
             field(c, s, GP_E_M0 + a) == -field(c, t, GP_E_M1 + a) &&
             field(c, s, GP_E_M1 + a) == -field(c, t, GP_E_M0 + a);
    }
    bad += !same;
  }
  return bad;
}

BatchEvaluator cpuEvaluator(const PatchCache& c) {
  return [&c](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    evaluatePatches(c, f, x, y, n, out, Backend::Serial, 0);
  };
}

struct CreaseStats {
  int creaseEdges = 0, smoothEdges = 0;
  double maxEndError = 0;        // |angle between the sides' patch normals at a crease end - corner normals' angle|
  double minAlongRatio = 1e300;  // smallest (angle along the crease) / (smaller end angle)
  double maxSmoothAngle = 0;     // largest tangent-plane angle across a smooth edge, 1e-5 inside
};

/// Evaluates both sides of every interior edge: at a crease, the sides' patch normals at the
/// two ends and at 9 points along it; at a smooth edge, the tangent-plane angle 1e-5 inside.
CreaseStats measureCreases(const PatchCache& c) {
  CreaseStats st;
  const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); };
  const auto normalAt = [&](int corner) { return Eigen::Vector3d(&c.cornerNormals[3 * static_cast<size_t>(corner)]); };
  for (int s = 0; s < c.numSlots(); ++s) {
    const int t = c.slotTwin[s];
    if (t < s) continue;
    const int f = slotFace(c.faceOffsets, s), g = slotFace(c.faceOffsets, t);
    const int k = s - c.faceOffsets[f], i = t - c.faceOffsets[g];
    if (!isCreaseEdge(c, f, k)) {
      ++st.smoothEdges;
      for (int j = 1; j <= 9; ++j) {
        const Eigen::Vector2d xf = test::edgePoint(c.faceSize(f), k, j / 10.0, 1e-5);
        const Eigen::Vector2d xg = test::edgePoint(c.faceSize(g), i, 1 - j / 10.0, 1e-5);
        const PatchPoint pf = evaluatePatch(c, f, xf.x(), xf.y()), pg = evaluatePatch(c, g, xg.x(), xg.y());
        st.maxSmoothAngle = std::max(st.maxSmoothAngle, angle(pf.normal, pg.normal));
      }
      continue;
    }
    ++st.creaseEdges;
    int32_t a0, a1;
    acrossCorners(c, f, k, a0, a1);
    const int s1 = c.faceOffsets[f] + (k + 1) % c.faceSize(f);
    const double end0 = angle(normalAt(s), normalAt(a0)), end1 = angle(normalAt(s1), normalAt(a1));
    for (int j = 0; j <= 10; ++j) {
      const Eigen::Vector2d xf = test::edgePoint(c.faceSize(f), k, j / 10.0, 0);
      const Eigen::Vector2d xg = test::edgePoint(c.faceSize(g), i, 1 - j / 10.0, 0);
      const PatchPoint pf = evaluatePatch(c, f, xf.x(), xf.y()), pg = evaluatePatch(c, g, xg.x(), xg.y());
      const double a = angle(pf.normal, pg.normal);
      if (j == 0) st.maxEndError = std::max(st.maxEndError, std::abs(a - end0));
      if (j == 10) st.maxEndError = std::max(st.maxEndError, std::abs(a - end1));
      // along a crease between two crease ends (a dart or a corner tag's edge fades out by design)
      if (j > 0 && j < 10 && std::min(end0, end1) > 0)
        st.minAlongRatio = std::min(st.minAlongRatio, a / std::min(end0, end1));
    }
  }
  return st;
}

/// The corner normals loadMesh computes for the file's faces as read (the fold repair off: by
/// default it fans the prism's caps, whose corners become the fans').
std::vector<Eigen::Vector3d> normalsAsRead(const std::string& path, PatchOptions options) {
  options.foldRepair = FoldRepairMode::Off;
  return loadMesh(path, options).cornerNormals;
}

/// The properties every creased cache has; `expected`: its crease edges.
void expectCreasedSurface(const PatchCache& c, const std::vector<Edge>& expected, const std::string& what) {
  SCOPED_TRACE(what);
  std::vector<Edge> want = expected;
  std::sort(want.begin(), want.end());
  EXPECT_EQ(creaseEdges(c), want);
  int edges = 0;
  EXPECT_EQ(curvesNotShared(c, &edges), 0) << "of " << edges << " interior edges";
  // the welded export is closed: every shared edge welds at the strict default tolerance
  TriangleMesh tm = tessellatePatches(c, 4, cpuEvaluator(c));
  const WeldReport weld = weldPatchSeams(c, 4, tm);
  EXPECT_EQ(weld.openEdges, 0u);
  EXPECT_EQ(static_cast<int>(weld.edgesWelded), edges);
  const CreaseStats st = measureCreases(c);
  EXPECT_EQ(st.creaseEdges, static_cast<int>(want.size()));
  EXPECT_EQ(st.creaseEdges + st.smoothEdges, edges);
  std::printf("creases %-40s edges %4d crease %4d | end angle error %.2g rad, along/end >= %.3g | smooth G1 %.2g rad\n",
              what.c_str(), edges, st.creaseEdges, st.maxEndError, st.minAlongRatio, st.maxSmoothAngle);
  EXPECT_LT(st.maxEndError, 1e-9);       // each side's patch normal is its own corner normal
  EXPECT_GT(st.minAlongRatio, 0.5);      // the crease stays sharp along the edge
  EXPECT_LT(st.maxSmoothAngle, 1e-3);    // G1 elsewhere (about 1e-5 rad per 1e-5 inside)
  const PatchStatusSummary ps = summarizePatchStatus(c);
  EXPECT_EQ(ps.notBuilt, 0);
}

TEST(Creases, EveryMarkingConventionGivesTheSameSurface) {
  hostile::TempDir dir("sf_creases");
  const Prism p = prism(12, 3);
  const PolygonMesh& m = p.mesh;
  // rims only: tags, smoothing groups, PLY edges, the crease angle, split normals (file, auto)
  std::vector<int> groups(m.numFaces(), 3);
  groups[p.capFaces[0][0]] = 1;
  groups[p.capFaces[1][0]] = 2;
  writeFile(dir.path / "tags.obj", objWithTags(m, p.rimCreases));
  writeFile(dir.path / "groups.obj", objWithGroups(m, groups));
  writeFile(dir.path / "edges.ply", plyWithEdgeCreases(m, p.rimCreases));
  writeFile(dir.path / "plain.obj", objWithTags(m, {}));
  PatchOptions o, angle, none;
  angle.creases.angleDeg = 45;  // rims 90 degrees, sides 30
  none.creases.tags = none.creases.groups = false;
  const LoadedMesh tags = loadMesh((dir.path / "tags.obj").string(), o);
  writeFile(dir.path / "split.obj", objWithCornerNormals(m, normalsAsRead((dir.path / "tags.obj").string(), o)));
  PatchOptions file, autoNormals;
  file.normals = NormalMode::File;
  autoNormals.creases.normals = true;
  const PatchCache ref = build(tags, o);
  expectCreasedSurface(ref, p.rimCreases, "prism rims: t crease tags");
  EXPECT_EQ(tags.normalReport.creases.fromTags, static_cast<int>(p.rimCreases.size()));
  struct Case {
    std::string what, file;
    PatchOptions options;
  };
  const std::vector<Case> cases = {{"smoothing groups", "groups.obj", o},
                                   {"PLY edge creases", "edges.ply", o},
                                   {"--crease-angle 45", "plain.obj", angle},
                                   {"split normals, --normals file", "split.obj", file},
                                   {"split normals, --creases normals", "split.obj", autoNormals}};
  for (const Case& k : cases) {
    SCOPED_TRACE(k.what);
    const LoadedMesh l = loadMesh((dir.path / k.file).string(), k.options);
    const PatchCache c = build(l, k.options);
    if (k.file == "split.obj") {
      // the file's normals are normalised as read: the same up to rounding
      double d = 0;
      for (size_t i = 0; i < c.edgeDataD.size(); ++i) d = std::max(d, std::abs(c.edgeDataD[i] - ref.edgeDataD[i]));
      EXPECT_LT(d, 1e-12);
      expectCreasedSurface(c, p.rimCreases, "prism rims: " + k.what);
    } else {
      EXPECT_EQ(l.cornerNormals, tags.cornerNormals);
      EXPECT_EQ(c.edgeDataD, ref.edgeDataD);  // bit for bit the tags' surface
    }
    EXPECT_EQ(creaseEdges(c), creaseEdges(ref));
  }
  // unmarked, or with the marks switched off: no crease, one normal per vertex
  for (const auto& [f, opt] : {std::pair{"plain.obj", o}, {"tags.obj", none}, {"groups.obj", none}}) {
    const PatchCache c = build(loadMesh((dir.path / f).string(), opt), opt);
    EXPECT_TRUE(creaseEdges(c).empty()) << f;
  }
  // split normals under plain auto are averaged (flat-shaded exports split every vertex)
  const PatchCache averaged = build(loadMesh((dir.path / "split.obj").string(), o), o);
  EXPECT_TRUE(creaseEdges(averaged).empty());
}

TEST(Creases, DartsAndCornersFromTagsPlyAndSplitNormals) {
  hostile::TempDir dir("sf_creases_dart");
  const Prism p = prism(12, 3);
  std::vector<Edge> marked = p.rimCreases;
  marked.insert(marked.end(), p.dart.begin(), p.dart.end());
  writeFile(dir.path / "tags.obj", objWithTags(p.mesh, marked));
  writeFile(dir.path / "edges.ply", plyWithEdgeCreases(p.mesh, marked));
  PatchOptions o, file;
  file.normals = NormalMode::File;
  const LoadedMesh tags = loadMesh((dir.path / "tags.obj").string(), o);
  writeFile(dir.path / "split.obj", objWithCornerNormals(p.mesh, normalsAsRead((dir.path / "tags.obj").string(), o)));
  const PatchCache ref = build(tags, o);
  expectCreasedSurface(ref, marked, "prism rims + dart: tags");
  const CreaseSummary sum = summarizeCreases(cacheBaseMesh(ref), ref.slotTwin, ref.cornerNormals.data());
  EXPECT_EQ(sum.darts, std::vector<int32_t>{12});     // the dart's upper end, inside the side
  EXPECT_EQ(sum.corners, std::vector<int32_t>{0});    // the dart's lower end: three creases
  EXPECT_EQ(sum.creaseVertices.size(), 23u);          // every other rim vertex
  for (const char* f : {"edges.ply", "split.obj"}) {
    SCOPED_TRACE(f);
    const PatchOptions& opt = std::string(f) == "split.obj" ? file : o;
    const PatchCache c = build(loadMesh((dir.path / f).string(), opt), opt);
    if (opt.normals == NormalMode::File)
      expectCreasedSurface(c, marked, "prism rims + dart: split normals");
    else
      EXPECT_EQ(c.edgeDataD, ref.edgeDataD);
  }
  // a corner tag: every face at the vertex keeps its own normal there, so the edges between
  // faces of different columns are creases at it (the faces above and below one another on the
  // side share a normal)
  writeFile(dir.path / "corner.obj", objWithTags(p.mesh, p.rimCreases) + "t corner 1/1/0 20 10\n");
  const PatchCache corner = build(loadMesh((dir.path / "corner.obj").string(), o), o);
  std::vector<Edge> withCorner = p.rimCreases;
  for (int v : {8, 32}) withCorner.push_back(key(20, v));  // vertex 20: ring 1, corner 8
  expectCreasedSurface(corner, withCorner, "prism rims + corner tag");
}

/// Every shared mesh that has sharp edges, and a cage, with the dihedral threshold.
TEST(Creases, SharedMeshesWithACreaseAngle) {
  hostile::TempDir dir("sf_creases_shared");
  struct M {
    const char* file;
    double degrees;
    int creases;  // edges whose faces' normals are more than `degrees` apart, counted here
  };
  for (const M& m : {M{"lagrange/cube.obj", 30, 12}, M{"pmp/chamfer-cube.off", 30, -1},
                     M{"pmp/hole_capsule.off", 10, -1}, M{"polygon_laplacian/hexaSphere.off", 5, -1}, M{"geomview/dodecahedron.off", 30, 30}}) {
    PatchOptions o;
    o.creases.angleDeg = m.degrees;
    const LoadedMesh l = loadMesh(test::sharedMesh(m.file), o);
    // independently: the dihedral angle of every interior edge from the faces' Newell normals
    std::set<Edge> sharp;
    const std::vector<int32_t> twins = computeSlotTwins(l.mesh);
    for (int f = 0; f < l.mesh.numFaces(); ++f)
      for (int k = 0; k < l.mesh.faceSize(f); ++k) {
        const int t = twins[l.mesh.faceOffsets[f] + k];
        if (t < 0) continue;
        const int g = slotFace(l.mesh.faceOffsets, t);
        const Eigen::Vector3d a = newellNormal(l.mesh, f).normalized(), b = newellNormal(l.mesh, g).normalized();
        if (std::acos(std::clamp(a.dot(b), -1.0, 1.0)) > m.degrees * std::numbers::pi / 180)
          sharp.insert(key(l.mesh.faceVertex(f, k), l.mesh.faceVertex(f, k + 1)));
      }
    if (m.creases >= 0) {
      EXPECT_EQ(static_cast<int>(sharp.size()), m.creases) << m.file;
    }
    ASSERT_FALSE(sharp.empty()) << m.file;
    const PatchCache c = build(l, o);
    expectCreasedSurface(c, std::vector<Edge>(sharp.begin(), sharp.end()),
                         std::string(m.file) + " --crease-angle " + std::to_string(int(m.degrees)));
    // re-exported as an exporter writes a creased part (a normal per corner, split at the
    // creases) and read with --normals file: the same creased surface, with the same corner
    // normals up to the reader's renormalisation
    PatchOptions file;
    file.normals = NormalMode::File;
    writeFile(dir.path / "split.obj", objWithCornerNormals(l.mesh, l.cornerNormals));
    const PatchCache split = build(loadMesh((dir.path / "split.obj").string(), file), file);
    ASSERT_EQ(split.cornerNormals.size(), c.cornerNormals.size());
    double worst = 0;
    for (size_t i = 0; i < c.cornerNormals.size(); ++i)
      worst = std::max(worst, std::abs(split.cornerNormals[i] - c.cornerNormals[i]));
    EXPECT_LE(worst, 1e-15) << m.file;
    expectCreasedSurface(split, std::vector<Edge>(sharp.begin(), sharp.end()),
                         std::string(m.file) + " re-exported with split normals");
    // the closed ones as a whole: no fold or overlap of the patch surface
    const SurfaceFaults faults = measureSurfaceFaults(PatchSurface(c));
    if (faults.closed) {
      EXPECT_EQ(faults.faultArea(), 0.0) << m.file;
    }
  }
}

/// Without a crease, the creased construction is the plain one bit for bit; with creases, every
/// path that builds patches (SIMD targets, serial, lazy, float) agrees with the scalar one.
TEST(Creases, EveryBuildPathGivesTheSameRecords) {
  const Prism p = prism(9, 2);
  PolygonMesh m = p.mesh;
  for (const Edge& e : p.rimCreases) m.creaseTags.push_back({e[0], e[1], 10, 0});
  for (Precision prec : {Precision::Double, Precision::Float}) {
    PatchOptions o;
    o.precision = prec;
    const LoadedMesh l = loadMesh(m, 1, o);
    PatchCache a = preparePatchCache(l.mesh, l.cornerNormals, o, 1), b = a;
    BuildOptions scalar, simd;
    scalar.backend = Backend::Serial;
    scalar.simd = SimdTarget::Scalar;
    constructPatches(a, scalar);
    constructPatches(b, simd);
    EXPECT_EQ(a.edgeDataD, b.edgeDataD);
    EXPECT_EQ(a.edgeDataF, b.edgeDataF);
    EXPECT_EQ(a.faceStatus, b.faceStatus);
    const PatchCache skel = test::skeletonOf(a);
    int lazySame = 0;
    for (int f = 0; f < a.numFaces(); ++f) {
      double rd[GP_MAX_N * GP_E_NFIELDS], gd[GP_MAX_N * GP_E_NFIELDS];
      float rf[GP_MAX_N * GP_E_NFIELDS], gf[GP_MAX_N * GP_E_NFIELDS];
      const int n = a.faceSize(f);
      bool same;
      if (prec == Precision::Double) {
        buildPatchRecords(skel, f, rd);
        gatherRecords(a, f, gd);
        same = std::equal(rd, rd + n * GP_E_NFIELDS, gd);
      } else {
        buildPatchRecords(skel, f, rf);
        gatherRecords(a, f, gf);
        same = std::equal(rf, rf + n * GP_E_NFIELDS, gf);
      }
      lazySame += same;
    }
    EXPECT_EQ(lazySame, a.numFaces());
  }
  // the creased build with the face's own normals as the other side's: gp_build_patch exactly
  int faces = 0, same = 0;
  for (const char* file : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/tetris.obj", "pmp/L.off",
                           "odedstein/bunny.obj"}) {
    const PatchCache c = test::cacheFromFile(test::sharedMesh(file));
    for (int f = 0; f < c.numFaces(); ++f) {
      const int n = c.faceSize(f), first = c.faceOffsets[f];
      if (n > GP_MAX_N) continue;
      gpd::gp_vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N];
      int vid[GP_MAX_N];
      for (int k = 0; k < n; ++k) {
        const int v = c.faceVertices[first + k];
        vid[k] = v;
        V[k] = gpd::gp_v3(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]);
        const double* nn = &c.cornerNormals[3 * (first + k)];
        N[k] = gpd::gp_v3(nn[0], nn[1], nn[2]);
      }
      for (int k = 0; k < n; ++k) PS[k] = N[k], PE[k] = N[(k + 1) % n];
      std::vector<double> r1(n * GP_E_NFIELDS), r2(n * GP_E_NFIELDS);
      const gp_uint s1 = gpd::gp_build_patch(n, V, N, vid, GP_CT_CORRECTED, r1.data());
      const gp_uint s2 = gpd::gp_build_patch_creased(n, V, N, PS, PE, vid, GP_CT_CORRECTED, r2.data());
      ++faces;
      same += s1 == s2 && r1 == r2;
    }
  }
  EXPECT_EQ(same, faces);
}

TEST(Creases, OpenCLBuildsTheSameSharedCurves) {
  std::string reason;
  if (!openclAvailable(&reason)) GTEST_SKIP() << "no OpenCL device: " << reason;
  const Prism p = prism(12, 3);
  PolygonMesh m = p.mesh;
  std::vector<Edge> marked = p.rimCreases;
  marked.insert(marked.end(), p.dart.begin(), p.dart.end());
  for (const Edge& e : marked) m.creaseTags.push_back({e[0], e[1], 10, 0});
  PatchOptions o;
  const LoadedMesh l = loadMesh(m, 1, o);
  PatchCache cl = preparePatchCache(l.mesh, l.cornerNormals, o, 1), cpu = cl;
  constructPatchesOpenCL(cl, OpenCLOptions{});
  constructPatches(cpu, Backend::Tbb);
  expectCreasedSurface(cl, marked, "prism rims + dart: OpenCL");
  double maxDiff = 0;
  for (size_t i = 0; i < cpu.edgeDataD.size(); ++i) maxDiff = std::max(maxDiff, std::abs(cpu.edgeDataD[i] - cl.edgeDataD[i]));
  EXPECT_LT(maxDiff, 1e-12);
}

TEST(Creases, BadMarksAreErrorsNamingFileAndLine) {
  hostile::TempDir dir("sf_creases_bad");
  const Prism p = prism(6, 1);
  writeFile(dir.path / "noedge.obj", objWithTags(p.mesh, {}) + "t crease 2/1/0 0 3 10\n");
  try {
    loadMesh((dir.path / "noedge.obj").string(), PatchOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what(), line = ":" + std::to_string(p.mesh.numVertices() + p.mesh.numFaces() + 1) + ":";
    EXPECT_NE(msg.find("noedge.obj" + line), std::string::npos) << msg;
    EXPECT_NE(msg.find("no face has this edge"), std::string::npos) << msg;
  }
  for (double bad : {-1.0, 180.0, std::nan("")}) {
    PatchOptions o;
    o.creases.angleDeg = bad;
    EXPECT_THROW(loadMesh(p.mesh, 1, o), InputError) << bad;
  }
  CreaseOptions c;
  EXPECT_THROW(parseCreaseMarks("tags,tags", c), InputError);
  EXPECT_THROW(parseCreaseMarks("sharp", c), InputError);
  parseCreaseMarks("groups,tags", c);
  EXPECT_EQ(creaseMarksText(c), "tags,groups");
  parseCreaseMarks("none", c);
  EXPECT_EQ(creaseMarksText(c), "none");
}

}  // namespace
}  // namespace sf
