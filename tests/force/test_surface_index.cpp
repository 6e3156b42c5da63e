// SPDX-License-Identifier: Apache-2.0
// The two indexes of the patch method's global query on a prebuilt cache (SurfaceIndex,
// force_method.h): the servo loop's scenes hold the bounds index, batches the tessellation, and
// the two track the same contacts away from surface faults (where the tessellation's winding
// number and the nearest sheet's side may disagree, surface_faults.h). Checked on every closed
// mesh of ../shared/meshes with sequences that
// a device produces: an approach from outside, a press to 0.1%, 0.5% and 2% of the diagonal (a
// contact start), a slide along the surface, a jump out to three diagonals (no contact may
// survive it) and a jump back in.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <algorithm>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/force/shared_geometry.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "patch_test_support.h"
#include "shared_mesh_files.h"

namespace sf {
namespace {

std::vector<std::string> partNames(const SharedGeometry& g) {
  std::vector<std::string> names;
  for (const SharedGeometry::Part& p : g.memory()) names.push_back(p.name);
  return names;
}

TEST(SurfaceIndex, AutoIsTheBoundsIndexInTheServoLoopAndTheTessellationElsewhere) {
  EXPECT_EQ(ForceOptions{}.surfaceIndex, SurfaceIndex::Auto);
  EXPECT_EQ(rt::servoForceOptions(ForceOptions{}).surfaceIndex, SurfaceIndex::Bounds);
  ForceOptions tess;
  tess.surfaceIndex = SurfaceIndex::Tessellation;
  EXPECT_EQ(rt::servoForceOptions(tess).surfaceIndex, SurfaceIndex::Tessellation);  // an explicit choice stays
  auto cache = std::make_shared<const PatchCache>(test::cacheFromFile(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj"));
  // the servo loop's scene: its object holds the bounds index, and its shared geometry no tessellation
  auto geometry = std::make_shared<SharedGeometry>(cache);
  const rt::Scene scene = rt::singleObjectScene(
      cache, "spot", ForceMethod::Patch, ForceOptions{},
      [&](std::shared_ptr<const PatchCache>, ForceMethod m, const ForceOptions& o) { return geometry->makeRenderer(m, o); });
  ASSERT_EQ(scene.objects().size(), 1u);
  EXPECT_EQ(scene.objects()[0].force.surfaceIndex, SurfaceIndex::Bounds);
  EXPECT_EQ(partNames(*geometry), (std::vector<std::string>{"cache", "polygon_scene", "lazy_surface"}));
  // a batch renderer (makeForceRenderer's auto) and an explicit tessellation: the tessellation
  SharedGeometry batch(cache);
  batch.makeRenderer(ForceMethod::Patch, ForceOptions{});
  batch.makeRenderer(ForceMethod::Patch, tess);
  EXPECT_EQ(partNames(batch), (std::vector<std::string>{"cache", "polygon_scene", "patch_surface"}));
}

/// Steps of one device sequence from surface sample s at depth d (m): approach, press, slide
/// along the surface (8 steps of 0.25% of the diagonal: 1 m/s at 1 kHz on a 40 cm object), jump
/// out to 3 diagonals, jump back to the press.
std::vector<Eigen::Vector3d> deviceSequence(const SurfaceSample& s, double d, double diag) {
  const Eigen::Vector3d t = s.normal.unitOrthogonal();
  std::vector<Eigen::Vector3d> h;
  h.push_back(s.point + 1e-3 * d * s.normal);
  h.push_back(s.point - d * s.normal);
  for (int i = 1; i <= 8; ++i) h.push_back(s.point - d * s.normal + i * 0.0025 * diag * t);
  h.push_back(s.point + 3 * diag * s.normal);
  h.push_back(s.point - d * s.normal);
  return h;
}

TEST(SurfaceIndex, BothIndexesTrackTheSameContactsOnEveryClosedSharedMesh) {
  constexpr size_t kSamples = 60;  // per mesh and depth
  int meshes = 0, faulty = 0;
  long steps = 0, contacts = 0, differ = 0, differAtFaults = 0, heldAfterJump = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    auto cache = std::make_shared<const PatchCache>(test::cacheFromFile(path));
    if (!std::all_of(cache->slotTwin.begin(), cache->slotTwin.end(), [](int t) { return t >= 0; }))
      continue;  // open: no inside to agree on
    const double diag = boundingDiagonal(*cache);
    auto surface = std::make_shared<const PatchSurface>(*cache);
    const SurfaceFaults faults = measureSurfaceFaults(*surface);
    ASSERT_TRUE(faults.closed);
    faulty += faults.faultArea() > 0;
    // a face within reach of the surface's faults: one with fault area, or sharing a vertex with one
    std::vector<char> nearFault(cache->numFaces(), 0);
    {
      std::vector<char> faultVertex(cache->numVertices(), 0);
      for (int f : faults.faultFaces())
        for (int k = 0; k < cache->faceSize(f); ++k) faultVertex[cache->faceVertices[cache->faceOffsets[f] + k]] = 1;
      for (int f = 0; f < cache->numFaces(); ++f)
        for (int k = 0; k < cache->faceSize(f); ++k)
          nearFault[f] |= faultVertex[cache->faceVertices[cache->faceOffsets[f] + k]];
    }
    ForceOptions bounds, tess;
    bounds.surfaceIndex = SurfaceIndex::Bounds;
    tess.surfaceIndex = SurfaceIndex::Tessellation;
    auto scene = std::make_shared<const PolygonScene>(*cache);
    auto a = makeForceRenderer(cache, scene, ForceMethod::Patch, bounds);
    auto b = makeForceRenderer(cache, scene, ForceMethod::Patch, tess, surface);
    const std::vector<SurfaceSample> samples = PatchSurfaceSampler(*cache).sample(kSamples, 11);
    ASSERT_EQ(samples.size(), kSamples);
    long meshDiffer = 0, meshAtFaults = 0;
    for (double depth : {0.001, 0.005, 0.02})
      for (const SurfaceSample& s : samples) {
        a->reset();
        b->reset();
        const std::vector<Eigen::Vector3d> seq = deviceSequence(s, depth * diag, diag);
        for (size_t i = 0; i < seq.size(); ++i) {
          const ForceSample x = a->step(seq[i]), y = b->step(seq[i]);
          ++steps;
          contacts += x.contact;
          if (i + 2 == seq.size()) heldAfterJump += x.contact + y.contact;  // 3 diagonals out
          const bool same = x.contact == y.contact && (!x.contact || (x.scp - y.scp).norm() <= 1e-6 * diag);
          if (same) continue;
          const bool atFault = nearFault[s.face] || (x.face >= 0 && nearFault[x.face]) || (y.face >= 0 && nearFault[y.face]);
          if (atFault) {
            ++meshAtFaults;
          } else if (meshDiffer++ < 3) {
            ADD_FAILURE() << "step " << i << " at depth " << depth << " from face " << s.face << ": bounds "
                          << x.contact << " (face " << x.face << "), tessellation " << y.contact << " (face " << y.face
                          << "), SCPs " << (x.scp - y.scp).norm() / diag << " diagonals apart, residuals "
                          << (seq[i] - x.scp).cross(x.normal).norm() / diag << " and "
                          << (seq[i] - y.scp).cross(y.normal).norm() / diag << ", status 0x" << std::hex << x.status
                          << " and 0x" << y.status << std::dec << ", distances " << (seq[i] - x.scp).norm() / diag
                          << " and " << (seq[i] - y.scp).norm() / diag;
          }
        }
      }
    std::printf("  %s: fault area %.3g%%, steps differing %ld away from faults, %ld at faults\n", path.c_str(),
                100 * faults.faultArea() / faults.totalArea, meshDiffer, meshAtFaults);
    differ += meshDiffer;
    differAtFaults += meshAtFaults;
    ++meshes;
  }
  std::printf(
      "%d closed meshes (%d with surface faults), %ld steps, %ld in contact: %ld differ away from faults, %ld at "
      "faults; contacts held 3 diagonals out %ld\n",
      meshes, faulty, steps, contacts, differ, differAtFaults, heldAfterJump);
  EXPECT_EQ(meshes, 18);
  EXPECT_EQ(steps, meshes * 3L * kSamples * 12);
  EXPECT_EQ(differ, 0);
  EXPECT_LE(differAtFaults, steps / 1000);  // measured: 24, all on the spot cage (1.58% fault area)
  EXPECT_EQ(heldAfterJump, 0);
  EXPECT_GT(contacts, steps / 2);
}

}  // namespace
}  // namespace sf
