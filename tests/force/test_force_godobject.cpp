// SPDX-License-Identifier: Apache-2.0
// The god-object baselines (direct, shading) on closed meshes: contact is kept on a HIP path
// that moves continuously inside a thin tube, and a first HIP already inside the polygons
// starts contact on the nearest polygon point (PolygonScene::contains).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/generators.h>
#include "patch_test_support.h"

namespace sf {
namespace {

/// The (2,3) torus knot of 120 x 12 quads scaled to `size` (m, the largest box side).
std::shared_ptr<const PatchCache> knotCache(const TorusKnotParams& k) {
  const PolygonMesh pm = torusKnot(k).toPolygonMesh();
  auto c = std::make_shared<PatchCache>(preparePatchCache(pm, cornerNormals(pm, NormalMode::Angle), PatchOptions{}, 0));
  constructPatches(*c, Backend::Serial);
  return c;
}

TEST(PolygonSceneInside, ContainsAndFirstCrossing) {
  auto cache = std::make_shared<const PatchCache>(test::cacheFromShape(ref::refUnitSphereCube()));
  const PolygonScene scene(*cache);
  const double h = 1 / std::sqrt(3.0);
  EXPECT_TRUE(scene.contains(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(scene.contains(Eigen::Vector3d(0.9 * h, 0.9 * h, 0.9 * h), Eigen::Vector3d::Zero()));
  EXPECT_FALSE(scene.contains(Eigen::Vector3d(0, 0, h + 1e-3), Eigen::Vector3d(0, 0, 1)));
  EXPECT_FALSE(scene.contains(Eigen::Vector3d(3, 0.1, 0.2), Eigen::Vector3d(1, 0, 0)));
  const PolygonCrossing out = scene.firstCrossing(Eigen::Vector3d(0, 0.1, 0), Eigen::Vector3d(0, 0.1, 2));
  ASSERT_GE(out.face, 0);
  EXPECT_FALSE(out.entering);  // leaving through the top
  EXPECT_NEAR(out.point.z(), h, 1e-12);
  const PolygonCrossing in = scene.firstCrossing(Eigen::Vector3d(0, 0.1, 2), Eigen::Vector3d(0, 0.1, -2));
  ASSERT_GE(in.face, 0);
  EXPECT_TRUE(in.entering);
  EXPECT_NEAR(in.point.z(), h, 1e-12);
}

// A HIP on a helix around the knot's 5 mm tube (7 turns per lap, 1,690 steps as in
// docs/sweeps.md), `depth` inside the analytic tube: it stays inside the closed polygon mesh
// all along, so the god-object must stay in contact on every step, by its own constraint
// passes (no SF_TRACK_INSIDE recovery, no pass limit). Before the fix: contact on the first
// 42 (2 mm) and 70 (4 mm) steps only. At 2 mm the proxy also stays within 1.5 depths of the
// HIP; at 4 mm (1.1 mm from the tube's axis, behind every facet of the ring) it keeps its
// facet while the HIP turns under it, up to 6 mm away, as a god-object does.
TEST(GodObjectTube, HelixInsideThinTubeKeepsContact) {
  TorusKnotParams k;
  k.scale = 0.1 / 2.95;  // tube radius 5.1 mm
  auto cache = knotCache(k);
  auto scene = std::make_shared<const PolygonScene>(*cache);
  const int steps = 1690;
  for (double depth : {0.002, 0.004}) {
    for (ForceMethod m : {ForceMethod::Direct, ForceMethod::Shading}) {
      auto r = makeForceRenderer(cache, scene, m, ForceOptions{});
      Eigen::Vector3d n0;
      const Eigen::Vector3d p0 = torusKnotSurface(k, 0, 0, &n0);
      EXPECT_FALSE(r->step(p0 + 0.001 * n0).contact);
      int contact = 0, firstLost = -1, recovered = 0, limited = 0, far = 0;
      for (int i = 0; i < steps; ++i) {
        const double phi = 2 * std::numbers::pi * i / (steps - 1);
        Eigen::Vector3d n;
        const Eigen::Vector3d p = torusKnotSurface(k, phi, 7 * phi, &n), hip = p - depth * n;
        const ForceSample s = r->step(hip);
        contact += s.contact;
        recovered += (s.status & SF_TRACK_INSIDE) != 0;
        limited += (s.status & SF_TRACK_PROXY_LIMIT) != 0;
        far += (s.scp - hip).norm() > 1.5 * depth;
        if (!s.contact && firstLost < 0) firstLost = i;
      }
      std::printf(
          "  %s depth %.3f: contact on %d of %d steps (%d put back on the surface, %d at the pass limit, %d "
          "over 1.5 depths from the HIP)\n",
          toString(m), depth, contact, steps, recovered, limited, far);
      EXPECT_EQ(contact, steps) << toString(m) << " depth " << depth << " first lost at step " << firstLost;
      EXPECT_EQ(recovered, 0) << toString(m) << " depth " << depth;
      EXPECT_EQ(limited, 0) << toString(m) << " depth " << depth;
      if (depth < 0.003) {
        EXPECT_EQ(far, 0) << toString(m);
      }
    }
  }
}

// The sweep's probe on the spot cage: per HIP reset(), step(p + 0.001 depth n), step(p - depth n)
// with (p, n) on the patches. Where the patch lies inside the coarse cage, the approach point
// is already inside the polygons; the god-object then starts on the nearest polygon point.
// Of the HIPs that the patch method has contact on, direct and shading must have contact on
// every one that lies inside the polygons; the others (the patch bulges out of the cage by
// more than the depth) are outside the polygons, where no god-object has contact.
// Measured on these HIPs (2% / 4% of the diagonal): patch contact 2254 / 2186, inside the
// polygons 2084 / 2140, god-object contact on all of them; without the start on the nearest
// point 1822 of 2084 and 1923 of 2140 (87% and 90%).
TEST(GodObjectProbe, SpotDefaultApproachContactWherePatchHasContact) {
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  auto scene = std::make_shared<const PolygonScene>(*cache);
  const PolygonFacets& pf = scene->facets();
  auto patch = makeForceRenderer(cache, scene, ForceMethod::Patch, ForceOptions{});
  auto direct = makeForceRenderer(cache, scene, ForceMethod::Direct, ForceOptions{});
  auto shading = makeForceRenderer(cache, scene, ForceMethod::Shading, ForceOptions{});
  for (double frac : {0.02, 0.04}) {
    const double depth = frac * pf.extent();
    int patchContact = 0, inside = 0, contact[2] = {0, 0}, contactInside[2] = {0, 0};
    for (int f = 0; f < cache->numFaces(); ++f) {
      const int n = cache->faceSize(f);
      for (int k = 0; k < n; ++k)
        for (double a : {0.0, 0.3, 0.6, 0.9}) {
          if (a == 0.0 && k > 0) continue;  // the centre once
          const Eigen::Vector2d X = a * 0.5 * (domainCorner(n, k) + domainCorner(n, (k + 1) % n));
          const PatchPoint q = evaluatePatch(*cache, f, X.x(), X.y());
          const Eigen::Vector3d hip = q.pos - depth * q.normal;
          auto probe = [&](ForceRenderer& r) {
            r.reset();
            r.step(q.pos + 1e-3 * depth * q.normal);
            return r.step(hip).contact;
          };
          if (!probe(*patch)) continue;
          ++patchContact;
          const bool in = scene->contains(hip, pf.facetNormal[scene->nearest(hip).facet]);
          inside += in;
          for (int m = 0; m < 2; ++m) {
            const bool c = probe(m == 0 ? *direct : *shading);
            contact[m] += c;
            contactInside[m] += c && in;
          }
        }
    }
    std::printf(
        "  spot depth %.0f%%: patch contact on %d HIPs, %d of them inside the polygons; direct contact on %d "
        "(%d inside), shading %d (%d inside)\n",
        100 * frac, patchContact, inside, contact[0], contactInside[0], contact[1], contactInside[1]);
    ASSERT_GT(inside, 2000);
    EXPECT_GE(contactInside[0], 0.99 * inside) << "direct";
    EXPECT_GE(contactInside[1], 0.99 * inside) << "shading";
  }
}

}  // namespace
}  // namespace sf
