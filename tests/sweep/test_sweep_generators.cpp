// SPDX-License-Identifier: Apache-2.0
// Generators of test objects with exact normals (torus knot, quad-sphere, torus).
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/sweep/generators.h>
#include <smoothforce/sweep/sweep_reference.h>

namespace sf {
namespace {

/// Every directed edge once, and its reverse once: closed, manifold, consistently oriented.
void expectClosedManifold(const GeneratedMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) ++directed[{q[k], q[(k + 1) % 4]}];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << "directed edge " << e.first << "-" << e.second << " used " << n << " times";
    EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is a boundary";
  }
  std::vector<int> used(m.positions.size(), 0);
  for (const auto& q : m.quads)
    for (int v : q) used[v] = 1;
  for (size_t v = 0; v < used.size(); ++v) EXPECT_TRUE(used[v]) << "vertex " << v << " unreferenced";
}

/// Unit normals, and each quad's Newell normal agrees with its corners' normals (outward).
void expectOutwardUnitNormals(const GeneratedMesh& m) {
  for (const auto& n : m.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-14);
  for (size_t f = 0; f < m.quads.size(); ++f) {
    Eigen::Vector3d newell = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) newell += m.positions[m.quads[f][k]].cross(m.positions[m.quads[f][(k + 1) % 4]]);
    for (int k = 0; k < 4; ++k) EXPECT_GT(newell.normalized().dot(m.normals[m.quads[f][k]]), 0.5) << "quad " << f;
  }
}

TEST(GeneratorTorusKnot, FourteenFortyQuadsClosedOutward) {
  TorusKnotParams k;  // p 2, q 3, 120 x 12
  const GeneratedMesh m = torusKnot(k);
  EXPECT_EQ(m.quads.size(), 1440u);
  EXPECT_EQ(m.positions.size(), 1440u);
  expectClosedManifold(m);
  expectOutwardUnitNormals(m);
}

TEST(GeneratorTorusKnot, NormalsAreTheAnalyticTubeNormals) {
  TorusKnotParams k;
  k.scale = 0.1 / 3.1;  // a 10 cm knot
  const GeneratedMesh m = torusKnot(k);
  for (int i = 0; i < k.segments; ++i) {
    Eigen::Vector3d c, d1, d2;
    torusKnotCurve(k, 2 * std::numbers::pi * i / k.segments, c, d1, d2);
    for (int j = 0; j < k.sides; ++j) {
      const int v = i * k.sides + j;
      const Eigen::Vector3d radial = m.positions[v] - c;
      EXPECT_NEAR(radial.norm(), k.scale * k.tube, 1e-15);             // on the tube
      EXPECT_NEAR(radial.normalized().dot(m.normals[v]), 1.0, 1e-14);  // normal = from the centre curve
      EXPECT_NEAR(radial.dot(d1), 0.0, 1e-15);                         // in the normal plane
    }
  }
  char spec[96];
  std::snprintf(spec, sizeof spec, "torus-knot:2,3,1,0.4,0.15,%.17g", k.scale);
  const auto tube = makeAnalyticSurface(spec);
  for (size_t v = 0; v < m.positions.size(); v += 7) EXPECT_LT(tube->distance(m.positions[v]), 1e-15);
  EXPECT_NEAR(tube->distance(m.positions[0] + 0.001 * m.normals[0]), 0.001, 1e-8);
}

TEST(GeneratorTorusKnot, OtherKnotsAndBadInput) {
  TorusKnotParams k;
  k.p = 3;
  k.q = 5;
  k.segments = 200;
  k.sides = 8;
  const GeneratedMesh m = torusKnot(k);
  EXPECT_EQ(m.quads.size(), 1600u);
  expectClosedManifold(m);
  expectOutwardUnitNormals(m);
  k.sides = 2;
  EXPECT_THROW(torusKnot(k), InputError);
  k.sides = 8;
  k.tube = -1;
  EXPECT_THROW(torusKnot(k), InputError);
}

TEST(GeneratorSphere, CountsRadialNormalsOnSphere) {
  for (int n : {1, 2, 5}) {
    const GeneratedMesh m = quadSphere(0.05, n);
    EXPECT_EQ(m.quads.size(), static_cast<size_t>(6 * n * n));
    EXPECT_EQ(m.positions.size(), static_cast<size_t>(6 * n * n + 2));
    expectClosedManifold(m);
    expectOutwardUnitNormals(m);
    for (size_t v = 0; v < m.positions.size(); ++v) {
      EXPECT_NEAR(m.positions[v].norm(), 0.05, 1e-16);
      EXPECT_NEAR(m.positions[v].normalized().dot(m.normals[v]), 1.0, 1e-15);
    }
  }
  EXPECT_THROW(quadSphere(1, 0), InputError);
}

TEST(GeneratorTorus, ClosedOutwardOnTorus) {
  const GeneratedMesh m = torusMesh(1.0, 0.3, 16, 8);
  EXPECT_EQ(m.quads.size(), 128u);
  expectClosedManifold(m);
  expectOutwardUnitNormals(m);
  const auto t = makeAnalyticSurface("torus:1,0.3");
  for (const auto& p : m.positions) EXPECT_LT(t->distance(p), 1e-15);
  EXPECT_THROW(torusMesh(1, 2, 16, 8), InputError);
}

// Sizes whose vertices leave the coordinate range (every mesh reader and cache build refuses
// them) and integer parameters no mesh can follow are refused, saying the bound; the largest
// accepted ones are made.
TEST(GeneratorBounds, SizesBeyondTheCoordinateRangeAndAbsurdCountsAreRefused) {
  auto message = [](auto&& make) {
    try {
      make();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  TorusKnotParams huge;
  huge.scale = 1e300;
  TorusKnotParams wound;
  wound.p = 2000000000;
  TorusKnotParams many;
  many.segments = 1000000;
  many.sides = 1000;
  const std::pair<std::string, std::string> refused[] = {
      {message([] { quadSphere(1e300, 1); }), "sphere: --radius 1e+300 puts vertices up to 1e+300 m"},
      {message([] { quadSphere(1.0000001e15, 1); }), "beyond the coordinate range +-1e15 m"},
      {message([] { torusMesh(1e300, 1, 3, 3); }), "torus: --R 1e+300 --r 1 puts vertices"},
      {message([] { torusMesh(1e15, 1, 3, 3); }), "up to 1000000000000001 m"},
      {message([] { torusMesh(1, 0.5, 1000000, 1000); }), "torus: --segments x --sides makes 1e+09 quads"},
      {message([&] { torusKnot(huge); }), "torus-knot: --scale x (--R + --r + --tube) puts vertices"},
      {message([&] { torusKnot(wound); }), "--p 2000000000 --q 3 wind 2000000003 times"},
      {message([&] { torusKnot(many); }), "more than 1e8"},
  };
  for (const auto& [got, want] : refused) EXPECT_NE(got.find(want), std::string::npos) << got;
  EXPECT_EQ(std::size(refused), 8u);
  EXPECT_EQ(quadSphere(1e15, 1).positions.size(), 8u);
  EXPECT_EQ(torusMesh(1e15 - 1, 1, 3, 3).quads.size(), 9u);
  TorusKnotParams tight;  // 4 (|p| + |q|) = 20 segments: the fewest that follow a (2,3) knot
  tight.segments = 20;
  EXPECT_EQ(torusKnot(tight).quads.size(), 240u);
  tight.segments = 19;
  EXPECT_THROW(torusKnot(tight), InputError);
}

TEST(GeneratorObj, RoundTripKeepsExactNormals) {
  const auto path = std::filesystem::temp_directory_path() / ("sf_gen_" + std::to_string(::getpid()) + ".obj");
  const GeneratedMesh m = torusKnot({});
  writeGeneratedObj(m, path.string(), "test");
  PatchOptions opt;
  opt.normals = NormalMode::File;
  const LoadedMesh lm = loadMesh(path.string(), opt);
  std::filesystem::remove(path);
  EXPECT_FALSE(lm.flipped);  // already outward
  EXPECT_EQ(lm.creaseCorners, 0);
  ASSERT_EQ(lm.mesh.numFaces(), 1440);
  for (int f = 0; f < lm.mesh.numFaces(); ++f)
    for (int k = 0; k < 4; ++k) {
      const int c = lm.mesh.faceOffsets[f] + k;
      EXPECT_LT((lm.cornerNormals[c] - m.normals[lm.mesh.faceVertices[c]]).norm(), 1e-15);
      EXPECT_EQ(lm.mesh.positions[lm.mesh.faceVertices[c]], m.positions[lm.mesh.faceVertices[c]]);
    }
}

}  // namespace
}  // namespace sf
