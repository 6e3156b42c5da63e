// SPDX-License-Identifier: Apache-2.0
// attributeFaults (surface_faults.h): the spot cage (whose ears already hold 4 intersecting
// pairs) pierced by a small cube (a part modelled into another, the kind of input no surface
// through its vertices can render without faults).
// The faults split into the input's, on faces within reach of the intersecting polygons, and the
// construction's, which are exactly the cage's own faults (measured without the cube) on the
// faces out of that reach, face by face.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <set>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_intersect.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>
#include "shared_mesh_files.h"

namespace sf {
namespace {

/// A cube of edge 2h about c, axes u, v, n (right-handed), faces outward, appended to m.
void appendCube(PolygonMesh& m, const Eigen::Vector3d& c, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                const Eigen::Vector3d& n, double h) {
  const int o = m.numVertices();
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(c + h * ((i & 1 ? 1 : -1) * u + (i & 2 ? 1 : -1) * v + (i & 4 ? 1 : -1) * n));
  for (const auto& f : std::vector<std::vector<int32_t>>{
           {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}})
    m.addFace({f[0] + o, f[1] + o, f[2] + o, f[3] + o});
}

SurfaceFaults faultsOf(const PatchCache& cache) {
  PatchSurfaceOptions o;
  o.candidates = false;
  o.level = 6;  // coarser than the query's 12: the same verdict rules, a tenth of the time
  return measureSurfaceFaults(PatchSurface(cache, o));
}

TEST(FaultSplit, APartPiercingTheCageIsTheInputsTheRestTheConstructions) {
  const PolygonMesh spot = readMesh(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const int nf = spot.numFaces();
  // the largest quad; the cube, a quarter of its size, straddles it at its centroid
  const MeshTriangles tri = polygonTriangles(spot);
  int f0 = -1;
  for (int f = 0; f < nf; ++f)
    if (spot.faceSize(f) == 4 && (f0 < 0 || tri.faceArea[f] > tri.faceArea[f0])) f0 = f;
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) c += spot.positions[spot.faceVertex(f0, k)] / 4;
  for (int k = 0; k < 4; ++k)
    n += (spot.positions[spot.faceVertex(f0, k)] - c).cross(spot.positions[spot.faceVertex(f0, k + 1)] - c);
  n.normalize();
  const Eigen::Vector3d u = (spot.positions[spot.faceVertex(f0, 0)] - c).cross(n).normalized(), v = n.cross(u);
  PolygonMesh piercedMesh = spot;
  appendCube(piercedMesh, c, u, v, n, 0.125 * std::sqrt(tri.faceArea[f0]));

  PatchOptions opt;
  const LoadedMesh lm = loadMesh(piercedMesh, 1, opt);
  ASSERT_FALSE(lm.flipped);
  const MeshReport& r = lm.report;
  // the cage's own 4 pairs (beside its bow-ties) and the cube's against the cage
  const std::vector<IntersectingPair> own = findIntersectingFaces(spot);
  ASSERT_EQ(own.size(), 4u);
  int withCube = 0;
  for (const IntersectingPair& p : r.intersectingPairs) {
    EXPECT_LT(p.a, nf);
    if (p.b >= nf) ++withCube;
  }
  EXPECT_GT(withCube, 0);
  EXPECT_EQ(r.intersectingPairs.size(), own.size() + withCube);
  const std::vector<int> crossing = r.intersectingFaces();
  EXPECT_TRUE(std::binary_search(crossing.begin(), crossing.end(), f0));
  const std::vector<char> near = facesNearIntersections(lm.mesh, r.intersectingPairs);
  for (int f = nf; f < nf + 6; ++f) EXPECT_TRUE(near[f]) << f;

  const SurfaceFaults pierced = faultsOf(buildPatchCache(lm, opt, Backend::Tbb));
  ASSERT_TRUE(pierced.closed);
  const FaultAttribution split = attributeFaults(pierced, near);
  EXPECT_GT(split.inputArea, 0);  // the cube's sheets inside the cow and the cow's inside the cube
  EXPECT_GT(split.constructionArea, 0);
  EXPECT_NEAR(split.inputArea + split.constructionArea, pierced.faultArea(), 1e-12 * pierced.totalArea);
  for (int f : split.inputFaces) EXPECT_TRUE(near[f]) << f;
  for (int f : split.constructionFaces) EXPECT_FALSE(near[f]) << f;
  EXPECT_EQ(split.inputFaces.size() + split.constructionFaces.size(), pierced.faultFaces().size());

  // out of reach of the cube, the faults are the cage's own, face by face
  const LoadedMesh alone = loadMesh(spot, 1, opt);
  const SurfaceFaults cage = faultsOf(buildPatchCache(alone, opt, Backend::Tbb));
  std::set<int> ownOutOfReach, construction(split.constructionFaces.begin(), split.constructionFaces.end());
  for (int f : cage.faultFaces())
    if (!near[f]) ownOutOfReach.insert(f);
  EXPECT_EQ(construction, ownOutOfReach);
  for (int f : ownOutOfReach) EXPECT_NEAR(pierced.faceFault[f], cage.faceFault[f], 1e-9 * cage.totalArea) << f;
  EXPECT_GE(ownOutOfReach.size(), 20u);  // most of the cage's ~50 fault faces are away from the cube

  // no intersection: everything is the construction's
  const FaultAttribution none = attributeFaults(cage, {});
  EXPECT_EQ(none.inputArea, 0);
  EXPECT_EQ(none.constructionFaces, cage.faultFaces());
  EXPECT_THROW(attributeFaults(cage, std::vector<char>(3, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace sf
