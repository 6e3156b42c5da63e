// SPDX-License-Identifier: Apache-2.0
// Vertex normals: modes, angle and area weights, planar meshes, file normals, fallbacks;
// auto honouring the file's normals (per vertex or through face references) and its rule at
// crease vertices.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <set>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include "cli_test_support.h"
#include "file_bytes.h"
#include "polygon_mesh_support.h"
#include "shared_mesh_files.h"

namespace {

using sf::test::cubeMesh;
using sf::test::polygonMesh;
using sf::test::sharedMesh;

std::string errorOf(const sf::PolygonMesh& m, sf::NormalMode mode) {
  try {
    sf::cornerNormals(m, mode);
  } catch (const sf::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

}  // namespace

TEST(Normals, ModeNamesRoundTrip) {
  for (auto m : {sf::NormalMode::Auto, sf::NormalMode::File, sf::NormalMode::Angle, sf::NormalMode::Area})
    EXPECT_EQ(sf::parseNormalMode(sf::toString(m)), m);
  EXPECT_THROW(sf::parseNormalMode("Angle "), sf::InputError);
  EXPECT_THROW(sf::parseNormalMode(""), sf::InputError);
}

TEST(Normals, NewellNormalIsTwiceTheArea) {
  const sf::PolygonMesh m = polygonMesh({{1, 1, 5}, {3, 1, 5}, {3, 4, 5}, {1, 4, 5}}, {{0, 1, 2, 3}, {0, 3, 2, 1}});
  EXPECT_TRUE(sf::newellNormal(m, 0).isApprox(Eigen::Vector3d(0, 0, 12)));
  EXPECT_TRUE(sf::newellNormal(m, 1).isApprox(Eigen::Vector3d(0, 0, -12)));
}

TEST(Normals, CubeCornersPointAlongDiagonals) {
  const sf::PolygonMesh m = cubeMesh();
  for (auto mode : {sf::NormalMode::Angle, sf::NormalMode::Area, sf::NormalMode::Auto}) {
    std::vector<int> fallback{99};
    const auto n = sf::cornerNormals(m, mode, &fallback);
    ASSERT_EQ(n.size(), 24u);
    EXPECT_TRUE(fallback.empty());
    for (int c = 0; c < 24; ++c)
      EXPECT_TRUE(n[c].isApprox(m.positions[m.faceVertices[c]] / std::sqrt(3.0), 1e-14)) << c;
  }
}

TEST(Normals, PlanarMeshesGiveThePlaneNormal) {
  const std::pair<const char*, Eigen::Vector3d> planes[] = {
      {"keenan_crane/semi2.obj", Eigen::Vector3d::UnitZ()},
      {"keenan_crane/semi6.obj", Eigen::Vector3d::UnitZ()},
      {"pmp/L.off", Eigen::Vector3d::UnitZ()},
      {"polygon_laplacian/tetris.obj", Eigen::Vector3d::UnitY()},
      {"polygon_laplacian/L-plane.obj", Eigen::Vector3d::UnitY()}};
  for (const auto& [file, axis] : planes) {
    const sf::PolygonMesh m = sf::readMesh(sharedMesh(file));
    for (auto mode : {sf::NormalMode::Angle, sf::NormalMode::Area}) {
      const auto n = sf::cornerNormals(m, mode);
      const double sign = n[0].dot(axis) > 0 ? 1 : -1;
      for (size_t c = 0; c < n.size(); ++c) ASSERT_NEAR(sign * n[c].dot(axis), 1.0, 1e-9) << file << " corner " << c;
    }
  }
}

TEST(Normals, FileCornerNormalsSurvive) {
  sf::PolygonMesh m = sf::readMesh(sharedMesh("odedstein/bunny.obj"));
  ASSERT_EQ(m.fileCornerNormals.size(), static_cast<size_t>(m.numCorners()));
  auto n = sf::cornerNormals(m, sf::NormalMode::File);
  for (int c = 0; c < m.numCorners(); ++c) ASSERT_TRUE(n[c].isApprox(m.fileCornerNormals[c].normalized(), 1e-15));
  // The bunny is flat-shaded (a normal per face): every vertex is split, so auto uses the
  // angle-weighted normal everywhere.
  const auto a = sf::cornerNormals(m, sf::NormalMode::Auto);
  const auto angle = sf::cornerNormals(m, sf::NormalMode::Angle);
  EXPECT_EQ(a, angle);
  // Flipping the faces carries the corner normals along.
  sf::flipFaces(m);
  n = sf::cornerNormals(m, sf::NormalMode::File);
  for (int c = 0; c < m.numCorners(); ++c) ASSERT_TRUE(n[c].isApprox(m.fileCornerNormals[c].normalized(), 1e-15));
}

TEST(Normals, FileVertexNormalsUsedByAutoAndFile) {
  sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  m.fileNormals = {{0, 0, 2}, {0, 3, 0}, {4, 0, 0}};
  for (auto mode : {sf::NormalMode::Auto, sf::NormalMode::File}) {
    const auto n = sf::cornerNormals(m, mode);
    EXPECT_EQ(n, (std::vector<Eigen::Vector3d>{{0, 0, 1}, {0, 1, 0}, {1, 0, 0}}));
  }
  EXPECT_EQ(sf::cornerNormals(m, sf::NormalMode::Angle)[1], Eigen::Vector3d(0, 0, 1));
}

TEST(Normals, BadFileNormalsThrowNamingTheElement) {
  sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2}});
  m.sourcePath = "quad.obj";
  EXPECT_NE(errorOf(m, sf::NormalMode::File).find("quad.obj: normal mode 'file' but the file has no normals"),
            std::string::npos);
  EXPECT_NO_THROW(sf::cornerNormals(m, sf::NormalMode::Auto));
  m.fileNormals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, std::nan("")}};
  EXPECT_NE(errorOf(m, sf::NormalMode::Auto).find("quad.obj: vertex 3: zero or non-finite"), std::string::npos);
  m.fileNormals.clear();
  m.fileCornerNormals.assign(6, Eigen::Vector3d(0, 0, 1));
  m.fileCornerNormals[5].setZero();
  EXPECT_NE(errorOf(m, sf::NormalMode::File).find("quad.obj: face 1 corner 2: zero or non-finite"), std::string::npos);
  m.fileCornerNormals.pop_back();
  EXPECT_NE(errorOf(m, sf::NormalMode::File).find("5 corner normals for 6 corners"), std::string::npos);
}

TEST(Normals, AngleAndAreaWeightsDiffer) {
  // Vertex 0 is shared by a right triangle in z = 0 (angle pi/2, Newell (0,0,1)) and a
  // steep one (Newell (0,-2,0)); the two weightings give different, known normals.
  const sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0, -2}}, {{0, 1, 2}, {1, 0, 3}});
  const double theta = std::acos(0.5 / std::sqrt(4.25));
  const Eigen::Vector3d angle =
      (std::numbers::pi / 2 * Eigen::Vector3d(0, 0, 1) + theta * Eigen::Vector3d(0, -1, 0)).normalized();
  const Eigen::Vector3d area = Eigen::Vector3d(0, -2, 1).normalized();
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Angle)[0].isApprox(angle, 1e-14));
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Area)[0].isApprox(area, 1e-14));
}

namespace {

/// Twice the area vector of face f by the component formula (sum over edges of
/// (y_i - y_j)(z_i + z_j), ...), not the library's fan of cross products.
Eigen::Vector3d componentNewell(const sf::PolygonMesh& m, int f) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const int k = m.faceSize(f);
  for (int i = 0; i < k; ++i) {
    const Eigen::Vector3d& a = m.positions[m.faceVertex(f, i)];
    const Eigen::Vector3d& b = m.positions[m.faceVertex(f, (i + 1) % k)];
    n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                         (a.x() - b.x()) * (a.y() + b.y()));
  }
  return n;
}

/// Angle between u and v by Kahan's half-angle formula, 2 atan(|u' - v'| / |u' + v'|).
double kahanAngle(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const Eigen::Vector3d a = u.normalized(), b = v.normalized();
  return 2 * std::atan2((a - b).norm(), (a + b).norm());
}

}  // namespace

// Every vertex of real meshes (triangles, quads, pentagons and hexagons): the angle- and the
// area-weighted normal equal the normalised weighted sums of the incident faces' normals computed
// here independently (component-formula Newell vectors, Kahan's corner angles, 2 pi minus that
// where the corner turns against the face normal: the spot cage's 14 corners of non-planar quads);
// every corner carries its vertex's normal. No face has zero area (asserted), so no fallback applies.
TEST(Normals, WeightedNormalsMatchAnIndependentSumAtEveryVertex) {
  struct Case {
    const char* file;
    int vertices, corners, reflex;  // counted from the files independently (awk)
  };
  const Case cases[] = {{"odedstein/bunny.obj", 3301, 19794, 0},
                        {"keenan_crane/spot_control_mesh.obj", 188, 732, 14},
                        {"polygon_laplacian/hexaSphere.off", 1760, 5280, 0}};
  for (const Case& cs : cases) {
    SCOPED_TRACE(cs.file);
    const sf::PolygonMesh m = sf::readMesh(sharedMesh(cs.file));
    const int nv = m.numVertices();
    std::vector<Eigen::Vector3d> angleSum(nv, Eigen::Vector3d::Zero()), areaSum(nv, Eigen::Vector3d::Zero());
    std::vector<int> valence(nv, 0);
    int reflex = 0, zeroArea = 0;
    for (int f = 0; f < m.numFaces(); ++f) {
      const Eigen::Vector3d N = componentNewell(m, f);
      const int k = m.faceSize(f);
      double perimeter = 0;
      for (int i = 0; i < k; ++i)
        perimeter += (m.positions[m.faceVertex(f, (i + 1) % k)] - m.positions[m.faceVertex(f, i)]).norm();
      zeroArea += !(N.norm() > 1e-9 * perimeter * perimeter);
      for (int i = 0; i < k; ++i) {
        const int v = m.faceVertex(f, i);
        const Eigen::Vector3d& p = m.positions[v];
        const Eigen::Vector3d next = m.positions[m.faceVertex(f, (i + 1) % k)] - p;
        const Eigen::Vector3d prev = m.positions[m.faceVertex(f, (i + k - 1) % k)] - p;
        const bool turnsBack = next.cross(prev).dot(N) < 0;
        reflex += turnsBack;
        const double theta = kahanAngle(next, prev);
        angleSum[v] += (turnsBack ? 2 * std::numbers::pi - theta : theta) * N.normalized();
        areaSum[v] += N;
        ++valence[v];
      }
    }
    EXPECT_EQ(reflex, cs.reflex);
    EXPECT_EQ(zeroArea, 0);
    std::vector<int> fallback[2];
    const auto angle = sf::cornerNormals(m, sf::NormalMode::Angle, &fallback[0]);
    const auto area = sf::cornerNormals(m, sf::NormalMode::Area, &fallback[1]);
    ASSERT_EQ(angle.size(), m.faceVertices.size());
    ASSERT_EQ(area.size(), m.faceVertices.size());
    EXPECT_TRUE(fallback[0].empty());
    EXPECT_TRUE(fallback[1].empty());
    int corners = 0, angleOk = 0, areaOk = 0, differ = 0, libDiffer = 0;
    for (int c = 0; c < static_cast<int>(m.faceVertices.size()); ++c) {
      const int v = m.faceVertices[c];
      const Eigen::Vector3d a = angleSum[v].normalized(), b = areaSum[v].normalized();
      ++corners;
      angleOk += (angle[c] - a).norm() <= 1e-12;
      areaOk += (area[c] - b).norm() <= 1e-12;
      differ += kahanAngle(a, b) > std::numbers::pi / 180;
      libDiffer += kahanAngle(angle[c], area[c]) > std::numbers::pi / 180;
    }
    int used = 0;
    for (int v = 0; v < nv; ++v) used += valence[v] > 0;
    std::printf("  %s: %d vertices, %d corners; angle vs area > 1 degree apart at %d corners\n", cs.file, used, corners,
                differ);
    EXPECT_EQ(angleOk, corners);
    EXPECT_EQ(areaOk, corners);
    EXPECT_EQ(libDiffer, differ);
    EXPECT_EQ(used, cs.vertices);
    EXPECT_EQ(corners, cs.corners);
  }
}

TEST(Normals, ReflexCornersWeighTheirFullInteriorAngle) {
  // Vertex 3 is the reflex corner (3pi/2) of an L-shaped hexagon in z = 0, and also a
  // corner of a triangle standing in the plane y = 0.
  const sf::PolygonMesh m = polygonMesh({{-1, -1, 0}, {1, -1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, -1}},
                                 {{0, 1, 2, 3, 4, 5}, {3, 2, 6}});
  const Eigen::Vector3d nTri = sf::newellNormal(m, 1).normalized();
  const double theta = std::acos(Eigen::Vector3d(1, 0, 0).dot(Eigen::Vector3d(-1, 0, -1).normalized()));
  const Eigen::Vector3d expected = (1.5 * std::numbers::pi * Eigen::Vector3d::UnitZ() + theta * nTri).normalized();
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Angle)[3].isApprox(expected, 1e-14));
}

TEST(Normals, FallbackWhenSumsCancelOrFacesAreDegenerate) {
  // A two-sided triangle (its normals cancel) and a collinear "triangle" (zero Newell).
  const sf::PolygonMesh m =
      polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {7, 0, 0}}, {{0, 1, 2}, {0, 2, 1}, {3, 4, 5}});
  for (auto mode : {sf::NormalMode::Angle, sf::NormalMode::Area}) {
    std::vector<int> fallback;
    const auto n = sf::cornerNormals(m, mode, &fallback);
    EXPECT_EQ(fallback, (std::vector<int>{0, 1, 2, 3, 4, 5}));
    for (int c = 0; c < 6; ++c) EXPECT_EQ(n[c], Eigen::Vector3d(0, 0, 1));  // first face's normal
    for (int c = 6; c < 9; ++c) EXPECT_NEAR(n[c].norm(), 1.0, 1e-15);
  }
  // The Stanford res4 bunny has such two-sided triangles too; all normals stay unit.
  const sf::PolygonMesh bunny = sf::readMesh(sharedMesh("stanford/bun_zipper_res4.ply"));
  std::vector<int> fallback;
  for (const auto& n : sf::cornerNormals(bunny, sf::NormalMode::Angle, &fallback)) ASSERT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_EQ(fallback.size(), 6u);
}

// ---- Auto honours the file's normals (OBJ `f v//vn` and `f v/vt/vn`) ----

namespace {

namespace fs = std::filesystem;

/// A temporary folder for this process, removed at exit.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("sf_test_normals_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string tempPath(const std::string& name) {
  static const TempDir dir;
  return (dir.path / name).string();
}

/// The closed and open polygon meshes the file-normal tests loop over, oriented outward.
std::vector<sf::PolygonMesh> fileNormalMeshes() {
  std::vector<sf::PolygonMesh> out;
  for (const std::string& path :
       {std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", sharedMesh("polygon_laplacian/quad-sphere.off"),
        sharedMesh("polygon_laplacian/hexaSphere.off"), sharedMesh("pmp/hole_capsule.off")}) {
    sf::PolygonMesh m = sf::readMesh(path);
    sf::applyOrientation(m, sf::checkMesh(m), sf::OrientPolicy::Outward);
    m.sourcePath = fs::path(path).filename().string();
    out.push_back(std::move(m));
  }
  return out;
}

/// Per-vertex normals for a generated file: the angle-weighted normal tilted by 0.1 to 0.3
/// rad in a pseudo-random direction, so that they differ from anything computed from the
/// polygons (a file's own normals), and scaled to lengths 0.5 to 2 (the reader normalises).
std::vector<Eigen::Vector3d> tiltedVertexNormals(const sf::PolygonMesh& m, unsigned seed) {
  std::vector<int> firstCorner(m.numVertices(), -1);
  for (int c = m.numCorners() - 1; c >= 0; --c) firstCorner[m.faceVertices[c]] = c;
  const auto angle = sf::cornerNormals(m, sf::NormalMode::Angle);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Vector3d> n(m.numVertices(), Eigen::Vector3d::UnitZ());
  for (int v = 0; v < m.numVertices(); ++v) {
    if (firstCorner[v] < 0) continue;
    const Eigen::Vector3d a = angle[firstCorner[v]];
    const Eigen::Vector3d axis = Eigen::AngleAxisd(2 * std::numbers::pi * u(rng), a) * a.unitOrthogonal();
    n[v] = (0.5 + 1.5 * u(rng)) * (Eigen::AngleAxisd(0.1 + 0.2 * u(rng), axis) * a);
  }
  return n;
}

/// How the generated OBJ references its normals.
enum class VnStyle {
  PerVertex,    ///< one `vn` per vertex, in a shuffled order; faces `f v//vn`
  PerCornerVt,  ///< one `vn` line per corner (duplicates), in reverse corner order; `f v/vt/vn`
};

/// Writes `m` as OBJ with corner normal `cornerN[c]` for every corner c (%.17g: exact).
/// PerVertex needs all corners of a vertex to carry the same normal.
std::string writeObjWithNormals(const sf::PolygonMesh& m, const std::vector<Eigen::Vector3d>& cornerN, VnStyle style,
                                const std::string& name) {
  std::string s = "# generated by test_normals\n";
  char buf[128];
  for (const auto& p : m.positions) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    s += buf;
  }
  const int nc = m.numCorners();
  std::vector<int> vnOf(nc);  // 1-based vn index per corner
  std::vector<Eigen::Vector3d> vn;
  if (style == VnStyle::PerVertex) {
    std::vector<int> order(m.numVertices()), slot(m.numVertices());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937(7));
    std::vector<Eigen::Vector3d> perVertex(m.numVertices(), Eigen::Vector3d::UnitZ());
    for (int c = 0; c < nc; ++c) perVertex[m.faceVertices[c]] = cornerN[c];
    for (int i = 0; i < m.numVertices(); ++i) {
      slot[order[i]] = i + 1;
      vn.push_back(perVertex[order[i]]);
    }
    for (int c = 0; c < nc; ++c) vnOf[c] = slot[m.faceVertices[c]];
  } else {
    for (int c = nc - 1; c >= 0; --c) {
      vn.push_back(cornerN[c]);
      vnOf[c] = nc - c;
    }
    s += "vt 0 0\nvt 1 0\n";
  }
  for (const auto& n : vn) {
    std::snprintf(buf, sizeof buf, "vn %.17g %.17g %.17g\n", n.x(), n.y(), n.z());
    s += buf;
  }
  for (int f = 0; f < m.numFaces(); ++f) {
    s += "f";
    for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) {
      const char* fmt = style == VnStyle::PerVertex ? " %d//%d" : " %d/%d/%d";
      if (style == VnStyle::PerVertex)
        std::snprintf(buf, sizeof buf, fmt, m.faceVertices[c] + 1, vnOf[c]);
      else
        std::snprintf(buf, sizeof buf, fmt, m.faceVertices[c] + 1, 1 + c % 2, vnOf[c]);
      s += buf;
    }
    s += "\n";
  }
  const std::string path = tempPath(name);
  std::ofstream(path, std::ios::binary) << s;
  return path;
}


/// Bitwise equality of two arrays of trivially copyable values.
template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// The unit vector the reader-plus-normaliser must produce for a written normal.
Eigen::Vector3d unit(const Eigen::Vector3d& n) { return n / n.norm(); }

}  // namespace

// On OBJ files whose faces reference one normal per vertex,
// `--normals auto` builds the same cache as `--normals file`: every array of the two caches
// (positions, faces, corner normals, adjacency, status, bulge, edge records) is bitwise
// equal, and the written .sfcache files are equal after the 128-byte header (the header
// records the normal mode, hence the options hash and the header checksum differ).
TEST(NormalsAuto, FaceReferencedVertexNormalsBuildTheFileCache) {
  int meshes = 0;
  for (const sf::PolygonMesh& base : fileNormalMeshes()) {
    const std::vector<Eigen::Vector3d> vn = tiltedVertexNormals(base, 11);
    std::vector<Eigen::Vector3d> cornerN;
    for (int v : base.faceVertices) cornerN.push_back(vn[v]);
    for (VnStyle style : {VnStyle::PerVertex, VnStyle::PerCornerVt}) {
      SCOPED_TRACE(base.sourcePath + (style == VnStyle::PerVertex ? " f v//vn" : " f v/vt/vn"));
      const std::string obj = writeObjWithNormals(
          base, cornerN, style, "refs_" + std::to_string(meshes) + "_" + std::to_string(int(style)) + ".obj");
      sf::PatchOptions autoOpt, fileOpt, angleOpt;
      fileOpt.normals = sf::NormalMode::File;
      angleOpt.normals = sf::NormalMode::Angle;
      const sf::LoadedMesh a = sf::loadMesh(obj, autoOpt), f = sf::loadMesh(obj, fileOpt),
                           g = sf::loadMesh(obj, angleOpt);
      ASSERT_FALSE(a.flipped);
      ASSERT_EQ(a.mesh.fileCornerNormals.size(), static_cast<size_t>(base.numCorners()));
      EXPECT_EQ(a.normalReport.source, sf::NormalSource::FileFaceRefs);
      EXPECT_TRUE(a.normalReport.splitVertices.empty());
      EXPECT_EQ(a.creaseCorners, 0);
      EXPECT_TRUE(a.normalFallbacks.empty());
      // Every corner of every face carries its vertex's written normal, normalised.
      int exact = 0, tilted = 0;
      for (int c = 0; c < base.numCorners(); ++c) {
        exact += a.cornerNormals[c] == unit(vn[base.faceVertices[c]]);
        tilted += std::acos(std::min(1.0, a.cornerNormals[c].dot(g.cornerNormals[c]))) > 0.09;
      }
      EXPECT_EQ(exact, base.numCorners());
      EXPECT_EQ(tilted, base.numCorners());  // auto is not the angle-weighted surface
      EXPECT_TRUE(sameBits(a.cornerNormals, f.cornerNormals));

      const sf::PatchCache ca = sf::buildPatchCache(a, autoOpt, sf::Backend::Tbb);
      const sf::PatchCache cf = sf::buildPatchCache(f, fileOpt, sf::Backend::Tbb);
      EXPECT_EQ(ca.meshHash, cf.meshHash);
      EXPECT_TRUE(sameBits(ca.positions, cf.positions));
      EXPECT_TRUE(sameBits(ca.faceOffsets, cf.faceOffsets));
      EXPECT_TRUE(sameBits(ca.faceVertices, cf.faceVertices));
      EXPECT_TRUE(sameBits(ca.cornerNormals, cf.cornerNormals));
      EXPECT_TRUE(sameBits(ca.slotTwin, cf.slotTwin));
      EXPECT_TRUE(sameBits(ca.faceStatus, cf.faceStatus));
      EXPECT_TRUE(sameBits(ca.faceBulge, cf.faceBulge));
      ASSERT_FALSE(ca.edgeDataD.empty());
      EXPECT_TRUE(sameBits(ca.edgeDataD, cf.edgeDataD));
      const std::string pa = obj + ".auto.sfcache", pf = obj + ".file.sfcache";
      sf::writePatchCache(ca, pa);
      sf::writePatchCache(cf, pf);
      const std::string ba = sf::test::fileBytes(pa), bf = sf::test::fileBytes(pf);
      ASSERT_EQ(ba.size(), bf.size());
      ASSERT_GT(ba.size(), 128u);
      EXPECT_TRUE(ba.compare(128, std::string::npos, bf, 128, std::string::npos) == 0);
      EXPECT_EQ(sf::readPatchCache(pa).options.normals, sf::NormalMode::Auto);
    }
    ++meshes;
  }
  EXPECT_EQ(meshes, 4);
}

// Per-corner normals: a third of the vertices get a crease (corner j of the vertex tilted by
// 0.05 j rad from its first corner), a third get near-duplicates (odd corners 3e-4 rad off,
// lengths varying: one normal within kSameNormalAngle), the rest exact duplicates. Auto
// reports exactly the crease vertices, gives them the angle-weighted normal and every other
// vertex its first corner's file normal; File keeps every corner as written.
TEST(NormalsAuto, CreaseVerticesAreCountedAndGetTheAngleWeightedNormal) {
  int meshes = 0;
  for (const sf::PolygonMesh& base : fileNormalMeshes()) {
    SCOPED_TRACE(base.sourcePath);
    const std::vector<Eigen::Vector3d> vn = tiltedVertexNormals(base, 23);
    std::vector<int> corners(base.numVertices(), 0), firstCorner(base.numVertices(), -1);
    std::vector<Eigen::Vector3d> cornerN(base.numCorners());
    std::vector<int> creases;  // written crease vertices: v % 3 == 0 with two or more corners
    for (int c = 0; c < base.numCorners(); ++c) {
      const int v = base.faceVertices[c], j = corners[v]++;
      if (firstCorner[v] < 0) firstCorner[v] = c;
      const Eigen::Vector3d axis = vn[v].normalized().unitOrthogonal();
      if (v % 3 == 0) {
        cornerN[c] = Eigen::AngleAxisd(0.05 * j, axis) * vn[v];
        if (j == 1) creases.push_back(v);
      } else if (v % 3 == 1) {
        cornerN[c] = (1.0 + 0.25 * j) * (Eigen::AngleAxisd(j % 2 ? 3e-4 : 0.0, axis) * vn[v]);
      } else {
        cornerN[c] = vn[v];
      }
    }
    std::sort(creases.begin(), creases.end());
    ASSERT_GT(creases.size(), 10u);
    const std::string obj =
        writeObjWithNormals(base, cornerN, VnStyle::PerCornerVt, "crease_" + std::to_string(meshes) + ".obj");
    sf::PatchOptions autoOpt, fileOpt, angleOpt;
    fileOpt.normals = sf::NormalMode::File;
    angleOpt.normals = sf::NormalMode::Angle;
    // the corners as read (the fold repair may fan flat faces between crease edges)
    autoOpt.foldRepair = fileOpt.foldRepair = angleOpt.foldRepair = sf::FoldRepairMode::Off;
    const sf::LoadedMesh a = sf::loadMesh(obj, autoOpt), f = sf::loadMesh(obj, fileOpt),
                         g = sf::loadMesh(obj, angleOpt);
    EXPECT_EQ(a.normalReport.source, sf::NormalSource::FileAndAngle);
    EXPECT_EQ(a.normalReport.splitVertices, creases);
    EXPECT_EQ(f.normalReport.splitVertices, creases);
    EXPECT_EQ(a.creaseCorners, 0);  // one normal per vertex: the surface stays closed
    const std::set<int> creaseSet(creases.begin(), creases.end());
    int angleCorners = 0, fileCorners = 0, asWritten = 0, creaseCorners = 0, expectAngle = 0;
    for (int c = 0; c < base.numCorners(); ++c) {
      const int v = base.faceVertices[c];
      if (creaseSet.count(v)) {
        ++expectAngle;
        angleCorners += a.cornerNormals[c] == g.cornerNormals[c];
      } else {
        fileCorners += a.cornerNormals[c] == unit(cornerN[firstCorner[v]]);
      }
      asWritten += f.cornerNormals[c] == unit(cornerN[c]);
      creaseCorners += (unit(cornerN[c]) - unit(cornerN[firstCorner[v]])).norm() > 1e-12;
    }
    EXPECT_EQ(angleCorners, expectAngle);
    EXPECT_EQ(fileCorners, base.numCorners() - expectAngle);
    EXPECT_EQ(asWritten, base.numCorners());
    EXPECT_EQ(f.creaseCorners, creaseCorners);
    EXPECT_EQ(a.normalReport.fileVertices + static_cast<int>(creases.size()),
              static_cast<int>(std::set<int>(base.faceVertices.begin(), base.faceVertices.end()).size()));

    // The report names the count; `cache build` prints it.
    const std::vector<std::string> lines = a.normalReport.describe();
    const std::string count = "split vertices: " + std::to_string(creases.size()) +
                              " (first: " + std::to_string(creases[0]) + " " + std::to_string(creases[1]);
    EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [&](const std::string& l) {
      return l.starts_with(count) && l.find("auto used the angle-weighted normal") != std::string::npos;
    }));
    ++meshes;
  }
  EXPECT_EQ(meshes, 4);
}

// Real files: bob_tri.obj (`f v/vt/vn`, normal indices differ from vertex indices, one normal
// per vertex), L-plane and tetris (one `vn` shared by every corner) give auto == file; the
// flat-shaded odedstein meshes (a `vn` per face) split every vertex, so auto is angle-weighted.
TEST(NormalsAuto, RealObjFiles) {
  for (const char* file :
       {"keenan_crane/bob_tri.obj", "polygon_laplacian/L-plane.obj", "polygon_laplacian/tetris.obj"}) {
    SCOPED_TRACE(file);
    const sf::PolygonMesh m = sf::readMesh(sharedMesh(file));
    ASSERT_EQ(m.fileCornerNormals.size(), static_cast<size_t>(m.numCorners()));
    sf::NormalReport r;
    const auto a = sf::cornerNormals(m, sf::NormalMode::Auto, r);
    EXPECT_EQ(r.source, sf::NormalSource::FileFaceRefs);
    EXPECT_TRUE(r.splitVertices.empty());
    EXPECT_TRUE(sameBits(a, sf::cornerNormals(m, sf::NormalMode::File)));
    int asWritten = 0;
    for (int c = 0; c < m.numCorners(); ++c) asWritten += a[c] == unit(m.fileCornerNormals[c]);
    EXPECT_EQ(asWritten, m.numCorners());
  }
  {
    // bob's exported normals are not the polygons' angle-weighted ones (old auto's result).
    const sf::PolygonMesh m = sf::readMesh(sharedMesh("keenan_crane/bob_tri.obj"));
    const auto a = sf::cornerNormals(m, sf::NormalMode::Auto), g = sf::cornerNormals(m, sf::NormalMode::Angle);
    int differ = 0;
    for (int c = 0; c < m.numCorners(); ++c) differ += (a[c] - g[c]).norm() > 1e-3;
    EXPECT_GT(differ, m.numCorners() / 2);
  }
  for (const char* file : {"odedstein/bunny.obj", "odedstein/spot_low_resolution.obj"}) {
    SCOPED_TRACE(file);
    const sf::PolygonMesh m = sf::readMesh(sharedMesh(file));
    // Independently: a vertex is split when some corner's normal is further than 1e-3 rad
    // (by the dot product) from its first corner's.
    std::vector<int> first(m.numVertices(), -1);
    std::set<int> split;
    for (int c = 0; c < m.numCorners(); ++c) {
      const int v = m.faceVertices[c];
      if (first[v] < 0) first[v] = c;
      const double d = m.fileCornerNormals[c].normalized().dot(m.fileCornerNormals[first[v]].normalized());
      if (d < std::cos(sf::kSameNormalAngle)) split.insert(v);
    }
    sf::NormalReport r;
    const auto a = sf::cornerNormals(m, sf::NormalMode::Auto, r);
    EXPECT_EQ(r.splitVertices, std::vector<int>(split.begin(), split.end()));
    EXPECT_EQ(static_cast<int>(split.size()), m.numVertices());  // flat shading: every vertex
    EXPECT_TRUE(sameBits(a, sf::cornerNormals(m, sf::NormalMode::Angle)));
  }
}

// Bad per-corner file normals are rejected under auto as under file, naming the corner.
TEST(NormalsAuto, BadCornerNormalsThrowNamingTheCorner) {
  sf::PolygonMesh m = polygonMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2}});
  m.sourcePath = "quad.obj";
  m.fileCornerNormals.assign(6, Eigen::Vector3d(0, 0, 1));
  m.fileCornerNormals[4] = Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 1);
  for (auto mode : {sf::NormalMode::Auto, sf::NormalMode::File})
    EXPECT_NE(errorOf(m, mode).find("quad.obj: face 1 corner 1: zero or non-finite"), std::string::npos);
  m.fileCornerNormals.pop_back();
  EXPECT_NE(errorOf(m, sf::NormalMode::Auto).find("5 corner normals for 6 corners"), std::string::npos);
  // A file normal referenced by a face but zero: the error names the file, face and corner.
  const std::string obj = tempPath("zero_vn.obj");
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 0\nf 1//1 2//1 3//2\n";
  try {
    sf::loadMesh(obj, sf::PatchOptions{});
    ADD_FAILURE() << "no InputError";
  } catch (const sf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(obj + ": face 0 corner 2: zero or non-finite file normal"), std::string::npos)
        << e.what();
  }
}

// End to end: `cache build --normals auto` on a `f v//vn` file writes the file-mode cache
// (bytes after the header) and reports the split vertices of a crease file.
TEST(NormalsAuto, CacheBuildCommand) {
  const sf::PolygonMesh base = sf::readMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj");
  const std::vector<Eigen::Vector3d> vn = tiltedVertexNormals(base, 5);
  std::vector<Eigen::Vector3d> cornerN;
  for (int v : base.faceVertices) cornerN.push_back(vn[v]);
  const std::string obj = writeObjWithNormals(base, cornerN, VnStyle::PerVertex, "cli_refs.obj");
  const auto ra = sf::test::smoothforce("cache build " + obj + " --normals auto -o " + obj + ".a.sfcache");
  const auto rf = sf::test::smoothforce("cache build " + obj + " --normals file -o " + obj + ".f.sfcache");
  ASSERT_EQ(ra.status, 0) << ra.out;
  ASSERT_EQ(rf.status, 0) << rf.out;
  EXPECT_NE(ra.out.find("normals: auto\n  the file's normals, one per vertex (through face references)\n"),
            std::string::npos)
      << ra.out;
  const std::string ba = sf::test::fileBytes(obj + ".a.sfcache"), bf = sf::test::fileBytes(obj + ".f.sfcache");
  ASSERT_GT(ba.size(), 128u);
  EXPECT_EQ(ba.substr(128), bf.substr(128));

  // Crease at vertices 0, 5, 10, ...: every corner after a vertex's first tilted by 0.2 rad.
  std::vector<int> seen(base.numVertices(), 0);
  int creases = 0;
  for (int c = 0; c < base.numCorners(); ++c) {
    const int v = base.faceVertices[c];
    if (v % 5 == 0 && seen[v]++ > 0) cornerN[c] = Eigen::AngleAxisd(0.2, vn[v].normalized().unitOrthogonal()) * vn[v];
    creases += v % 5 == 0 && seen[v] == 2;
  }
  const std::string creaseObj = writeObjWithNormals(base, cornerN, VnStyle::PerCornerVt, "cli_crease.obj");
  const auto rc = sf::test::smoothforce("cache build " + creaseObj + " -o " + creaseObj + ".sfcache");
  ASSERT_EQ(rc.status, 0) << rc.out;
  EXPECT_NE(rc.out.find("split vertices: " + std::to_string(creases) + " (first: 0 5 10 "), std::string::npos)
      << rc.out;
  EXPECT_EQ(creases, 38);  // vertices 0, 5, ..., 185 of the 188
}
