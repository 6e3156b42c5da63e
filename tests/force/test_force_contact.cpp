// SPDX-License-Identifier: Apache-2.0
// Contact logic of the three force methods: entering and leaving, no pop-through on a thin
// plate, the god-object on flat faces and across a convex edge, options and names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/force/god_object.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "patch_test_support.h"

namespace sf {
namespace {

/// A closed thin box [0,1]^2 x [-t/2, t/2]: top and bottom m x m quads, one ring of side quads.
PolygonMesh thinBox(int m, double t) {
  PolygonMesh pm;
  auto top = [&](int i, int j) { return j * (m + 1) + i; };
  auto bot = [&](int i, int j) { return (m + 1) * (m + 1) + j * (m + 1) + i; };
  for (double z : {t / 2, -t / 2})
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) pm.positions.emplace_back(double(i) / m, double(j) / m, z);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      pm.addFace({top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)});
      pm.addFace({bot(i, j), bot(i, j + 1), bot(i + 1, j + 1), bot(i + 1, j)});
    }
  std::vector<std::pair<int, int>> ring;  // boundary, counter-clockwise seen from +z
  for (int i = 0; i < m; ++i) ring.emplace_back(i, 0);
  for (int j = 0; j < m; ++j) ring.emplace_back(m, j);
  for (int i = m; i > 0; --i) ring.emplace_back(i, m);
  for (int j = m; j > 0; --j) ring.emplace_back(0, j);
  for (size_t k = 0; k < ring.size(); ++k) {
    const auto [ai, aj] = ring[k];
    const auto [bi, bj] = ring[(k + 1) % ring.size()];
    pm.addFace({bot(ai, aj), bot(bi, bj), top(bi, bj), top(ai, aj)});
  }
  return pm;
}

std::shared_ptr<const PatchCache> thinBoxCache(int m, double t) {
  const PolygonMesh pm = thinBox(m, t);
  auto c = std::make_shared<PatchCache>(preparePatchCache(pm, cornerNormals(pm, NormalMode::Angle), PatchOptions{}, 0));
  constructPatches(*c, Backend::Serial);
  return c;
}

TEST(ForceThinPlate, NoPopThroughForAnyMethod) {
  const double t = 0.02;
  auto cache = thinBoxCache(4, t);
  for (int32_t s : cache->slotTwin) ASSERT_GE(s, 0);  // closed and consistently oriented
  auto scene = std::make_shared<const PolygonScene>(*cache);
  for (ForceMethod method : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading}) {
    auto r = makeForceRenderer(cache, scene, method, ForceOptions{});
    int contactSteps = 0, entered = -1;
    const int steps = 400;
    for (int i = 0; i <= steps; ++i) {  // from 1 cm above the top to 3 cm below the bottom
      const Eigen::Vector3d hip(0.61, 0.63, t / 2 + 0.01 - (t + 0.04) * i / steps);
      const ForceSample s = r->step(hip);
      if (s.contact && entered < 0) entered = i;
      if (entered >= 0) {
        ASSERT_TRUE(s.contact) << toString(method) << " popped through at z = " << hip.z();
        EXPECT_GT(s.force.z(), 0) << toString(method) << " at z = " << hip.z();
        EXPECT_NEAR(s.force.z(), s.force.norm(), 1e-9 * s.force.norm()) << toString(method);
        EXPECT_NEAR(s.force.norm(), 500.0 * (s.scp.z() - hip.z()), 1e-9) << toString(method);
        EXPECT_GT(s.scp.z(), t / 2 - 1e-9) << toString(method);  // the contact stays on the top
        ++contactSteps;
      }
    }
    EXPECT_GE(entered, 0) << toString(method);
    EXPECT_GT(contactSteps, steps * 3 / 4) << toString(method);
  }
}

TEST(ForceTracker, EntersAndLeavesContact) {
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("polygon_laplacian/quad-sphere.off")));
  auto r = makeForceRenderer(cache, ForceMethod::Patch, ForceOptions{});
  EXPECT_EQ(r->patchesBuilt(), cache->numFaces());
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
  ForceSample s = r->step(1.5 * dir);
  EXPECT_FALSE(s.contact);
  EXPECT_EQ(s.face, -1);
  EXPECT_EQ(s.force.norm(), 0.0);
  EXPECT_TRUE(s.status & SF_TRACK_GLOBAL);
  s = r->step(0.97 * dir);
  ASSERT_TRUE(s.contact);
  EXPECT_TRUE(s.status & SF_TRACK_ENTER);
  EXPECT_TRUE(s.status & SF_TRACK_CONVERGED);
  EXPECT_GT(s.force.dot(dir), 0);
  EXPECT_NEAR(s.force.norm(), 500.0 * (s.scp - 0.97 * dir).norm(), 1e-9);
  EXPECT_NEAR(s.normal.dot(dir), 1.0, 1e-3);
  EXPECT_TRUE(insideDomain(cache->faceSize(s.face), s.xi, s.eta, 1e-12));
  s = r->step(0.96 * dir);  // tracking: no global query
  EXPECT_TRUE(s.contact);
  EXPECT_FALSE(s.status & SF_TRACK_GLOBAL);
  s = r->step(1.2 * dir);
  EXPECT_FALSE(s.contact);
  EXPECT_TRUE(s.status & SF_TRACK_LEAVE);
  EXPECT_EQ(s.force.norm(), 0.0);
  r->step(0.97 * dir);
  r->reset();
  s = r->step(0.97 * dir);
  EXPECT_TRUE(s.status & SF_TRACK_GLOBAL);
  s = r->step(Eigen::Vector3d(NAN, 0, 0));
  EXPECT_FALSE(s.contact);
  EXPECT_TRUE(s.status & SF_TRACK_BAD_HIP);
}

// Out of contact, a HIP outside the closed patch surface beyond every error band needs no patch
// work (insideByWinding 0: no candidates, no refinement), and the step's verdict and SCP are
// those of the full global query (nearestOnPatches + insidePatchSurface) for every HIP: on
// the spot cage and the quad-sphere, 4 points per face pressed in and pulled out along the
// patch normal by 0.2%, 1%, 3% and 6% of the diagonal.
TEST(ForceTracker, FarOutsideStepsDoNoPatchWork) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    auto cache = std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh(rel)));
    const ForceOptions opt;
    auto surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(opt));
    auto r = makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, opt, surface);
    PatchRefiner refiner(*cache);
    const double diag = boundingDiagonal(*cache);
    size_t hips = 0, far = 0, contacts = 0, agree = 0;
    for (int f = 0; f < cache->numFaces(); ++f) {
      const int n = cache->faceSize(f);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d X = 0.4 * domainCorner(n, k) + 0.05 * domainCorner(n, k + 1);
        const PatchPoint p = evaluatePatch(*cache, f, X.x(), X.y());
        for (double d : {-0.06, -0.03, -0.01, -0.002, 0.002, 0.01, 0.03, 0.06}) {
          const Eigen::Vector3d hip = p.pos + d * diag * p.normal;
          r->reset();
          const ForceSample s = r->step(hip);
          const PatchNearest q = nearestOnPatches(*surface, refiner, hip, opt);
          RefineResult scp;
          const bool inside = insidePatchSurface(*surface, hip, q, &scp);
          ++hips;
          contacts += s.contact;
          if (insideByWinding(*surface, hip) == 0) {
            ++far;
            EXPECT_FALSE(s.contact);
            EXPECT_EQ(s.iterations, 0) << rel << " face " << f;
            EXPECT_FALSE(s.status & SF_TRACK_MASK & ~SF_TRACK_GLOBAL) << rel << " face " << f;
          }
          agree += s.contact == inside && (!inside || (s.scp == scp.scp && s.face == scp.face));
        }
      }
    }
    EXPECT_EQ(hips, size_t(32) * cache->numFaces());
    EXPECT_EQ(agree, hips) << rel;
    EXPECT_GT(far, hips / 4) << rel;
    EXPECT_GT(contacts, hips / 3) << rel;
  }
}

// A known bound on the distance to the surface (reach: the distance to a patch point, or the
// error band's; with or without that point's face) only shortens the candidate search:
// PatchSurface::candidates returns the same candidates, bit for bit, as without it. And a
// tracker whose global query is seeded and bounded by the point its last step ended at (an
// approach step just outside, then the HIP) renders the step a fresh one renders: the same
// contact verdict for every HIP; the same SCP up to the refinement's stopping rule (4 tau, tau =
// min(sin(angleTolerance) |HIP - SCP|, positionTolerance x diagonal): both ends are within the
// tolerance of the stationary point) for all but 1 in 1,000 steps, and for those a stationary
// point as near (1e-6 of the diagonal: near a centre of curvature the stopping rule bounds the
// residual, not the position). Every face of the spot cage and the quad-sphere, every 10th of the
// triangulated spot (586 faces), 4 points each, pressed in and pulled out by 0.1%-6% of the
// diagonal; reaches: the exact distance to the nearest point found, the distance to the unpressed
// point (with and without its face), and the band's (with and without its face).

/// The meshes of the seeded-query tests, and a cache, patch surface and two patch renderers on it.
const char* const kSeedMeshes[] = {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off",
                                   "keenan_crane/spot_triangulated.obj"};
struct TwoTrackers {
  explicit TwoTrackers(const char* rel)
      : cache(std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh(rel)))),
        surface(std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(opt))),
        scene(std::make_shared<const PolygonScene>(*cache)),
        a(makeForceRenderer(cache, scene, ForceMethod::Patch, opt, surface)),
        b(makeForceRenderer(cache, scene, ForceMethod::Patch, opt, surface)) {}
  const ForceOptions opt;
  std::shared_ptr<const PatchCache> cache;
  std::shared_ptr<const PatchSurface> surface;
  std::shared_ptr<const PolygonScene> scene;
  std::unique_ptr<ForceRenderer> a, b;
};

TEST(ForceTracker, GlobalQueryReachKeepsTheCandidates) {
  for (const char* rel : kSeedMeshes) {
    TwoTrackers T(rel);
    const auto& cache = T.cache;
    const auto& surface = T.surface;
    const ForceOptions& opt = T.opt;
    ForceRenderer* tracked = T.a.get();
    ForceRenderer* fresh = T.b.get();
    PatchRefiner refiner(*cache);
    const double diag = boundingDiagonal(*cache);
    auto same = [](const SurfaceCandidate* a, size_t na, const SurfaceCandidate* b, size_t nb) {
      if (na != nb) return false;
      for (size_t i = 0; i < na; ++i)
        if (a[i].face != b[i].face || a[i].triangle != b[i].triangle || a[i].lower != b[i].lower || a[i].X != b[i].X)
          return false;
      return true;
    };
    size_t hips = 0, lists = 0, equalLists = 0, band = 0, steps = 0, sameScp = 0, agree = 0;
    SurfaceCandidate c0[PatchSurface::kMaxCandidates], c1[PatchSurface::kMaxCandidates];
    const int stride = (cache->numFaces() + 599) / 600;  // at most 600 faces: every face of the coarse meshes
    int faces = 0;
    for (int f = 0; f < cache->numFaces(); f += stride, ++faces) {
      const int n = cache->faceSize(f);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d X = 0.4 * domainCorner(n, k) + 0.05 * domainCorner(n, k + 1);
        const PatchPoint p = evaluatePatch(*cache, f, X.x(), X.y());
        for (double d : {-0.06, -0.01, -0.005, -0.001, 0.001, 0.01, 0.06}) {
          const Eigen::Vector3d hip = p.pos + d * diag * p.normal;
          ++hips;
          const size_t n0 = surface->candidates(hip, c0, PatchSurface::kMaxCandidates);
          const double nearest = nearestOnPatches(*surface, refiner, hip, opt).nearest.distance;
          double bandReach = std::numeric_limits<double>::infinity();
          int bandFace = -1;
          band += surface->inErrorBand(hip, &bandReach, &bandFace);
          const std::pair<double, int> reaches[] = {{nearest, -1},
                                                    {(hip - p.pos).norm(), -1},
                                                    {(hip - p.pos).norm(), f},
                                                    {bandReach, -1},
                                                    {bandReach, bandFace}};
          for (const auto& [reach, face] : reaches) {
            if (!std::isfinite(reach)) continue;
            ++lists;
            equalLists += same(c0, n0, c1, surface->candidates(hip, c1, PatchSurface::kMaxCandidates, reach, face));
          }
          // approach from just outside, then the HIP: the step from a reset
          tracked->reset();
          const ForceSample a = tracked->step(p.pos + 0.001 * std::abs(d) * diag * p.normal);
          if (a.contact) continue;  // then the HIP step tracks instead of querying
          const ForceSample s1 = tracked->step(hip);
          fresh->reset();
          const ForceSample s0 = fresh->step(hip);
          ++steps;
          const double d0 = (hip - s0.scp).norm(), d1 = (hip - s1.scp).norm();
          const double tau = std::min(std::sin(opt.angleTolerance) * d0, opt.positionTolerance * diag);
          const bool same = s0.contact == s1.contact && (!s0.contact || (s0.scp - s1.scp).norm() <= 4 * tau);
          const bool ok = same || (s0.contact == s1.contact && std::abs(d0 - d1) <= 1e-6 * diag);
          sameScp += same;
          agree += ok;
          if (!ok && std::getenv("SF_VERBOSE"))
            std::printf("    face %d, %g x diag: fresh contact %d face %d status %x, seeded contact %d face %d status %x, "
                        "distances %.9g / %.9g x diag\n",
                        f, d, s0.contact, s0.face, s0.status, s1.contact, s1.face, s1.status, d0 / diag, d1 / diag);
        }
      }
    }
    EXPECT_EQ(hips, size_t(28) * faces) << rel;
    EXPECT_GE(faces, std::min(cache->numFaces(), 580)) << rel;
    EXPECT_EQ(equalLists, lists) << rel;
    EXPECT_GE(lists, 3 * hips) << rel;  // the nearest and the unpressed point's reaches for every HIP
    EXPECT_GT(band, 0u) << rel;         // the band's reach was exercised
    EXPECT_EQ(agree, steps) << rel;
    EXPECT_GE(sameScp, steps - steps / 1000) << rel;
    EXPECT_GT(steps, hips * 9 / 10) << rel;
    std::printf(
        "  %s: %zu HIPs, %zu candidate lists with a reach (%zu from a band) equal; %zu seeded steps: the same "
        "verdict and SCP %zu, a point as near %zu\n",
        rel, hips, lists, band, steps, sameScp, agree - sameScp);
  }
}

// A sweep's probe (ForceRenderer::resetNear at the HIP's surface sample, the approach step, the
// step at the HIP) renders what a plain reset() renders: the same verdict for every HIP, the SCP
// within the refinement's tolerance (4 tau as above); and the seed serves (its steps report 0
// iterations) on every mesh (where the first candidate refined is a neighbour of the triangle
// under the seed, it does not: on the triangulated spot most probes). resetNear with a face out
// of range or a non-finite domain point is reset(): the same bits. 1,000 samples of each of three
// meshes at 0.1%, 0.5%, 1% and 3% of the diagonal.
TEST(ForceTracker, ResetNearASampleRendersThePlainProbe) {
  for (const char* rel : kSeedMeshes) {
    TwoTrackers T(rel);
    const auto& cache = T.cache;
    const ForceOptions& opt = T.opt;
    ForceRenderer* seeded = T.a.get();
    ForceRenderer* plain = T.b.get();
    const double diag = boundingDiagonal(*cache);
    const std::vector<SurfaceSample> samples = PatchSurfaceSampler(*cache, 4).sample(1000, 11);
    size_t probes = 0, same = 0, zeroIterations = 0, badHints = 0;
    for (double depth : {0.001, 0.005, 0.01, 0.03})
      for (const SurfaceSample& p : samples) {
        const Eigen::Vector3d approach = p.point + 1e-3 * depth * diag * p.normal;
        const Eigen::Vector3d hip = p.point - depth * diag * p.normal;
        seeded->resetNear(p.face, p.xi, p.eta);
        seeded->step(approach);
        const ForceSample s1 = seeded->step(hip);
        plain->reset();
        plain->step(approach);
        const ForceSample s0 = plain->step(hip);
        ++probes;
        const double tau =
            std::min(std::sin(opt.angleTolerance) * (hip - s0.scp).norm(), opt.positionTolerance * diag);
        same += s0.contact == s1.contact && (!s0.contact || (s0.scp - s1.scp).norm() <= 4 * tau);
        zeroIterations += s1.contact && s1.iterations == 0;
        // a bad hint is no hint: the same bits as reset()
        const int badFace = p.face % 2 ? -1 : cache->numFaces();
        seeded->resetNear(badFace, p.xi, p.eta);
        seeded->step(approach);
        const ForceSample b1 = seeded->step(hip);
        seeded->resetNear(p.face, std::numeric_limits<double>::quiet_NaN(), p.eta);
        seeded->step(approach);
        const ForceSample b2 = seeded->step(hip);
        for (const ForceSample* b : {&b1, &b2})
          badHints += b->contact == s0.contact && b->scp == s0.scp && b->face == s0.face &&
                      b->iterations == s0.iterations && b->status == s0.status;
      }
    EXPECT_EQ(probes, 4u * samples.size()) << rel;
    EXPECT_EQ(same, probes) << rel;
    EXPECT_EQ(badHints, 2 * probes) << rel;
    EXPECT_GT(zeroIterations, 0u) << rel;
    std::printf("  %s: %zu probes, the same as from reset() %zu, seed used %zu, bad hints ignored %zu\n", rel, probes,
                same, zeroIterations, badHints);
  }
}

TEST(ForceTracker, FloatCacheAgreesWithDouble) {
  const std::string mesh = test::sharedMesh("polygon_laplacian/quad-sphere.off");
  auto d =
      std::make_shared<const PatchCache>(test::cacheFromFile(mesh, CrossTangentMode::Corrected, Precision::Double));
  auto f = std::make_shared<const PatchCache>(test::cacheFromFile(mesh, CrossTangentMode::Corrected, Precision::Float));
  for (RefineMethod m : {RefineMethod::Newton, RefineMethod::PaperDescent}) {
    ForceOptions o;
    o.refine = m;
    auto rd = makeForceRenderer(d, ForceMethod::Patch, o), rf = makeForceRenderer(f, ForceMethod::Patch, o);
    double worst = 0;
    for (int i = 0; i <= 200; ++i) {  // press in, then slide along a great circle
      const double a = 0.004 * i;
      const Eigen::Vector3d h = (i < 10 ? 1.02 - 0.006 * i : 0.96) * Eigen::Vector3d(std::sin(a), 0.1, std::cos(a));
      const ForceSample sd = rd->step(h), sf = rf->step(h);
      ASSERT_EQ(sd.contact, sf.contact) << i;
      worst = std::max(worst, (sd.force - sf.force).norm());
    }
    // N, at forces of ~20 N. Newton: 1e-3 (measured 1.3e-4). The paper's descent differences
    // float positions (step 1e-3 in the domain), whose noise bounds it: 0.1 (measured 0.023).
    EXPECT_LT(worst, m == RefineMethod::Newton ? 1e-3 : 0.1) << toString(m);
  }
}

TEST(GodObject, FlatFaceAndConvexEdge) {
  // the unit-sphere cube: planar faces at distance h, radial corner normals
  auto cache = std::make_shared<const PatchCache>(test::cacheFromShape(ref::refUnitSphereCube()));
  auto scene = std::make_shared<const PolygonScene>(*cache);
  const double h = 1 / std::sqrt(3.0), d = 0.05;
  for (ForceMethod m : {ForceMethod::Direct, ForceMethod::Shading}) {
    GodObjectRenderer r(cache, scene, m, ForceOptions{});
    // a first HIP already inside: the proxy starts on the nearest polygon point
    const ForceSample in = r.step(Eigen::Vector3d(0, 0, h - d));
    ASSERT_TRUE(in.contact);
    EXPECT_TRUE(in.status & SF_TRACK_INSIDE);
    EXPECT_TRUE(in.status & SF_TRACK_ENTER);
    EXPECT_NEAR((in.scp - Eigen::Vector3d(0, 0, h)).norm(), 0, 1e-15);
    r.reset();
    EXPECT_FALSE(r.step(Eigen::Vector3d(0, 0, h + 0.01)).contact);  // outside: no contact
    EXPECT_FALSE(r.step(Eigen::Vector3d(0.01, 0, h + 0.02)).contact);
    r.reset();
    EXPECT_FALSE(r.step(Eigen::Vector3d(0, 0, h + 0.1)).contact);
    ForceSample s = r.step(Eigen::Vector3d(0, 0, h - d));
    ASSERT_TRUE(s.contact);
    EXPECT_NEAR((s.scp - Eigen::Vector3d(0, 0, h)).norm(), 0, 1e-15);
    EXPECT_NEAR((s.force - Eigen::Vector3d(0, 0, 500 * d)).norm(), 0, 1e-12);  // shading: MVC of 4 radial normals
    EXPECT_NEAR(s.xi, 0, 1e-12);
    EXPECT_NEAR(s.eta, 0, 1e-12);
    // slide along +x at constant depth under the top: the proxy is the projection on the top
    // (the god-object keeps its face while the HIP is behind it, even next to the side face)
    for (int i = 1; i <= 100; ++i) {
      const double x = (h - 0.2 * d) * i / 100.0;
      s = r.step(Eigen::Vector3d(x, 0.01, h - d));
      ASSERT_TRUE(s.contact) << toString(m) << " x " << x;
      EXPECT_NEAR((s.scp - Eigen::Vector3d(x, 0.01, h)).norm(), 0, 1e-14);
      if (m == ForceMethod::Direct) {
        EXPECT_NEAR((s.force - Eigen::Vector3d(0, 0, 500 * d)).norm(), 0, 1e-10);
      } else {
        EXPECT_GT(s.force.x(), 0);  // the interpolated normal leans towards the edge
      }
    }
    // out through the side face: the proxy slides off the top, nothing is entered, contact ends
    s = r.step(Eigen::Vector3d(h + 0.01, 0.01, h - d));
    EXPECT_FALSE(s.contact);
    EXPECT_TRUE(s.status & SF_TRACK_LEAVE);
    EXPECT_EQ(s.force.norm(), 0.0);
  }
}

TEST(ForceOptionsAndNames, ParseValidate) {
  EXPECT_EQ(parseForceMethod("patch"), ForceMethod::Patch);
  EXPECT_EQ(parseForceMethod("direct"), ForceMethod::Direct);
  EXPECT_EQ(parseForceMethod("shading"), ForceMethod::Shading);
  EXPECT_EQ(parseRefineMethod("newton"), RefineMethod::Newton);
  EXPECT_EQ(parseRefineMethod("paper"), RefineMethod::PaperDescent);
  EXPECT_STREQ(toString(ForceMethod::Shading), "shading");
  EXPECT_STREQ(toString(RefineMethod::PaperDescent), "paper");
  EXPECT_THROW(parseForceMethod("god"), InputError);
  EXPECT_THROW(parseRefineMethod("lbfgs"), InputError);
  auto cache = std::make_shared<const PatchCache>(test::cacheFromShape(ref::refUnitSphereCube()));
  ForceOptions o;
  o.stiffness = -1;
  EXPECT_THROW(makeForceRenderer(cache, ForceMethod::Patch, o), InputError);
  o = ForceOptions{};
  o.maxIterations = 0;
  EXPECT_THROW(makeForceRenderer(cache, ForceMethod::Direct, o), InputError);
  o = ForceOptions{};
  o.angleTolerance = NAN;
  EXPECT_THROW(makeForceRenderer(cache, ForceMethod::Shading, o), InputError);
}

}  // namespace
}  // namespace sf
