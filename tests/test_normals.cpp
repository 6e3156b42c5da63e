// Vertex normals: modes, angle and area weights, planar meshes, file normals, fallbacks.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>

namespace {

std::string meshPath(const std::string& rel) { return std::string(SF_SHARED_MESHES) + "/" + rel; }

sf::PolygonMesh make(std::vector<Eigen::Vector3d> p, const std::vector<std::vector<int32_t>>& faces) {
  sf::PolygonMesh m;
  m.positions = std::move(p);
  for (const auto& f : faces) m.addFace(f);
  return m;
}

sf::PolygonMesh unitCube() {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  return make(p, {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}});
}

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
  const sf::PolygonMesh m = make({{1, 1, 5}, {3, 1, 5}, {3, 4, 5}, {1, 4, 5}}, {{0, 1, 2, 3}, {0, 3, 2, 1}});
  EXPECT_TRUE(sf::newellNormal(m, 0).isApprox(Eigen::Vector3d(0, 0, 12)));
  EXPECT_TRUE(sf::newellNormal(m, 1).isApprox(Eigen::Vector3d(0, 0, -12)));
}

TEST(Normals, CubeCornersPointAlongDiagonals) {
  const sf::PolygonMesh m = unitCube();
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
    const sf::PolygonMesh m = sf::readMesh(meshPath(file));
    for (auto mode : {sf::NormalMode::Angle, sf::NormalMode::Area}) {
      const auto n = sf::cornerNormals(m, mode);
      const double sign = n[0].dot(axis) > 0 ? 1 : -1;
      for (size_t c = 0; c < n.size(); ++c) ASSERT_NEAR(sign * n[c].dot(axis), 1.0, 1e-9) << file << " corner " << c;
    }
  }
}

TEST(Normals, FileCornerNormalsSurvive) {
  sf::PolygonMesh m = sf::readMesh(meshPath("odedstein/bunny.obj"));
  ASSERT_EQ(m.fileCornerNormals.size(), static_cast<size_t>(m.numCorners()));
  auto n = sf::cornerNormals(m, sf::NormalMode::File);
  for (int c = 0; c < m.numCorners(); ++c) ASSERT_TRUE(n[c].isApprox(m.fileCornerNormals[c].normalized(), 1e-15));
  // Auto does not use per-corner normals: it computes one normal per vertex.
  const auto a = sf::cornerNormals(m, sf::NormalMode::Auto);
  const auto angle = sf::cornerNormals(m, sf::NormalMode::Angle);
  EXPECT_EQ(a, angle);
  // Flipping the faces carries the corner normals along.
  sf::flipFaces(m);
  n = sf::cornerNormals(m, sf::NormalMode::File);
  for (int c = 0; c < m.numCorners(); ++c) ASSERT_TRUE(n[c].isApprox(m.fileCornerNormals[c].normalized(), 1e-15));
}

TEST(Normals, FileVertexNormalsUsedByAutoAndFile) {
  sf::PolygonMesh m = make({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  m.fileNormals = {{0, 0, 2}, {0, 3, 0}, {4, 0, 0}};
  for (auto mode : {sf::NormalMode::Auto, sf::NormalMode::File}) {
    const auto n = sf::cornerNormals(m, mode);
    EXPECT_EQ(n, (std::vector<Eigen::Vector3d>{{0, 0, 1}, {0, 1, 0}, {1, 0, 0}}));
  }
  EXPECT_EQ(sf::cornerNormals(m, sf::NormalMode::Angle)[1], Eigen::Vector3d(0, 0, 1));
}

TEST(Normals, BadFileNormalsThrowNamingTheElement) {
  sf::PolygonMesh m = make({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2}});
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
  const sf::PolygonMesh m = make({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0, -2}}, {{0, 1, 2}, {1, 0, 3}});
  const double theta = std::acos(0.5 / std::sqrt(4.25));
  const Eigen::Vector3d angle =
      (std::numbers::pi / 2 * Eigen::Vector3d(0, 0, 1) + theta * Eigen::Vector3d(0, -1, 0)).normalized();
  const Eigen::Vector3d area = Eigen::Vector3d(0, -2, 1).normalized();
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Angle)[0].isApprox(angle, 1e-14));
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Area)[0].isApprox(area, 1e-14));

  const sf::PolygonMesh bunny = sf::readMesh(meshPath("odedstein/bunny.obj"));
  const auto a = sf::cornerNormals(bunny, sf::NormalMode::Angle), b = sf::cornerNormals(bunny, sf::NormalMode::Area);
  double maxDeg = 0;
  for (size_t c = 0; c < a.size(); ++c)
    maxDeg = std::max(maxDeg, std::acos(std::min(1.0, a[c].dot(b[c]))) * 180 / std::numbers::pi);
  EXPECT_GT(maxDeg, 1.0);
  EXPECT_LT(maxDeg, 60.0);
}

TEST(Normals, ReflexCornersWeighTheirFullInteriorAngle) {
  // Vertex 3 is the reflex corner (3pi/2) of an L-shaped hexagon in z = 0, and also a
  // corner of a triangle standing in the plane y = 0.
  const sf::PolygonMesh m = make({{-1, -1, 0}, {1, -1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, -1}},
                                 {{0, 1, 2, 3, 4, 5}, {3, 2, 6}});
  const Eigen::Vector3d nTri = sf::newellNormal(m, 1).normalized();
  const double theta = std::acos(Eigen::Vector3d(1, 0, 0).dot(Eigen::Vector3d(-1, 0, -1).normalized()));
  const Eigen::Vector3d expected = (1.5 * std::numbers::pi * Eigen::Vector3d::UnitZ() + theta * nTri).normalized();
  EXPECT_TRUE(sf::cornerNormals(m, sf::NormalMode::Angle)[3].isApprox(expected, 1e-14));
}

TEST(Normals, FallbackWhenSumsCancelOrFacesAreDegenerate) {
  // A two-sided triangle (its normals cancel) and a collinear "triangle" (zero Newell).
  const sf::PolygonMesh m =
      make({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {7, 0, 0}}, {{0, 1, 2}, {0, 2, 1}, {3, 4, 5}});
  for (auto mode : {sf::NormalMode::Angle, sf::NormalMode::Area}) {
    std::vector<int> fallback;
    const auto n = sf::cornerNormals(m, mode, &fallback);
    EXPECT_EQ(fallback, (std::vector<int>{0, 1, 2, 3, 4, 5}));
    for (int c = 0; c < 6; ++c) EXPECT_EQ(n[c], Eigen::Vector3d(0, 0, 1));  // first face's normal
    for (int c = 6; c < 9; ++c) EXPECT_NEAR(n[c].norm(), 1.0, 1e-15);
  }
  // The Stanford res4 bunny has such two-sided triangles too; all normals stay unit.
  const sf::PolygonMesh bunny = sf::readMesh(meshPath("stanford/bun_zipper_res4.ply"));
  std::vector<int> fallback;
  for (const auto& n : sf::cornerNormals(bunny, sf::NormalMode::Angle, &fallback)) ASSERT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_EQ(fallback.size(), 6u);
}
