// SPDX-License-Identifier: Apache-2.0
// step() of every force method does not allocate. Counted at the C allocator (glibc's
// __libc_* entry points behind thin interposers that count while armed on this thread), so
// that operator new (whoever replaces it; test_runtime_loop.cpp does), Eigen and Embree's
// aligned allocations are all seen. Off under sanitizers, which bring their own allocator.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>

#include <Eigen/Geometry>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/embree_scene.h>
#include "force_test_support.h"
#include "patch_test_support.h"
#include "query_test_support.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SF_FORCE_COUNT_ALLOCS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define SF_FORCE_COUNT_ALLOCS 0
#endif
#endif
#if !defined(SF_FORCE_COUNT_ALLOCS) && defined(__GLIBC__)
#define SF_FORCE_COUNT_ALLOCS 1
#endif
#ifndef SF_FORCE_COUNT_ALLOCS
#define SF_FORCE_COUNT_ALLOCS 0
#endif

namespace {
thread_local bool gArmed = false;
thread_local long gAllocations = 0;
}  // namespace

#if SF_FORCE_COUNT_ALLOCS
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void* malloc(size_t n) {
  if (gArmed) ++gAllocations;
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t m) {
  if (gArmed) ++gAllocations;
  return __libc_calloc(n, m);
}
void* realloc(void* p, size_t n) {
  if (gArmed) ++gAllocations;
  return __libc_realloc(p, n);
}
void* memalign(size_t a, size_t n) {
  if (gArmed) ++gAllocations;
  return __libc_memalign(a, n);
}
void* aligned_alloc(size_t a, size_t n) {
  if (gArmed) ++gAllocations;
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, size_t a, size_t n) {
  if (a < sizeof(void*) || (a & (a - 1))) return EINVAL;
  if (gArmed) ++gAllocations;
  void* p = __libc_memalign(a, n);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
}
#endif

namespace sf {
namespace {

/// Winding number of the polygon cage around q: the signed solid angles of the faces' fan
/// triangles (Van Oosterom and Strackee), summed, over 4 pi.
int polygonWinding(const PatchCache& c, const Eigen::Vector3d& q) {
  auto P = [&](int slot) -> Eigen::Vector3d {  // a plain vector, not an expression of a temporary
    const int v = c.faceVertices[slot];
    return Eigen::Vector3d(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]) - q;
  };
  double w = 0;
  for (int f = 0; f < c.numFaces(); ++f) {
    const Eigen::Vector3d a = P(c.faceOffsets[f]);
    for (int k = 1; k + 1 < c.faceSize(f); ++k) {
      const Eigen::Vector3d b = P(c.faceOffsets[f] + k), d = P(c.faceOffsets[f] + k + 1);
      const double la = a.norm(), lb = b.norm(), ld = d.norm();
      w += 2 * std::atan2(a.dot(b.cross(d)), la * lb * ld + a.dot(b) * ld + b.dot(d) * la + d.dot(a) * lb);
    }
  }
  return static_cast<int>(std::lround(w / (4 * M_PI)));
}

/// A mesh, its skeleton (patches built lazily inside step()), and a HIP path over it.
struct RealtimeCase {
  std::string name;
  std::shared_ptr<const PatchCache> cache, skeleton;
  std::vector<Eigen::Vector3d> hips;
  std::vector<char> inPatch, inPolygon;  ///< per HIP, computed independently; empty: not checked
  int patchInside = 0, polygonInside = 0;
};

RealtimeCase loadCase(const std::string& rel) {
  RealtimeCase c;
  c.name = rel;
  c.cache = std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh(rel)));
  c.skeleton = std::make_shared<const PatchCache>(test::skeletonFromFile(test::sharedMesh(rel)));
  return c;
}

/// The spot cage, in and out of the cage across many faces (pentagons, triangles, folded
/// patches) and deep through it: allocation only (contact there depends on the path's history:
/// the trackers hold contact through thin parts).
RealtimeCase spotCase() {
  RealtimeCase c = loadCase("keenan_crane/spot_control_mesh.obj");
  for (int i = 0; i < 2000; ++i) {
    const double a = 2 * M_PI * i / 500.0;
    c.hips.emplace_back(0.3 * std::cos(a), 0.1 + 0.6 * std::sin(0.7 * a), 0.35 * std::sin(a) + 0.1 * std::cos(3 * a));
  }
  return c;
}

/// The quad-sphere (448 quads, 64 triangles at the poles; convex, no folded patch): 1,960 HIPs
/// across 25 patches (test::slidePath from face 0 through edge 0), alternately 20 steps 1% of
/// the diagonal below the patch surface and 20 above it (along the patch normal). Inside each
/// surface, computed here independently at every HIP: the patches' by the dense oracle's ray
/// parity (which must agree with the side the path was built on), the polygons' by the winding
/// number.
RealtimeCase sphereCase() {
  RealtimeCase c = loadCase("polygon_laplacian/quad-sphere.off");
  constexpr int kFaces = 25, kPerHalf = 40, kHalfPeriod = 20;
  const double amplitude = 0.01 * boundingDiagonal(*c.cache);
  const test::SlidePath on = test::slidePath(*c.cache, 0, 0, kFaces, kPerHalf, 0.0);
  const test::SlidePath below = test::slidePath(*c.cache, 0, 0, kFaces, kPerHalf, 1.0);  // G - N
  EXPECT_EQ(on.faces, kFaces);
  const test::DenseOracle oracle(*c.cache);
  int bySide = 0;
  for (size_t i = on.slideBegin + 1; i < on.hips.size(); ++i) {  // after the approach: G(X) - N(X)
    const bool pressed = (i / kHalfPeriod) % 2 == 0;
    c.hips.push_back(on.hips[i] + (pressed ? 1 : -1) * amplitude * (below.hips[i] - on.hips[i]));
    c.inPatch.push_back(oracle.winding(c.hips.back()) >= 1);
    c.inPolygon.push_back(polygonWinding(*c.cache, c.hips.back()) >= 1);
    c.patchInside += c.inPatch.back();
    c.polygonInside += c.inPolygon.back();
    bySide += c.inPatch.back() == pressed;
  }
  const int n = static_cast<int>(c.hips.size());
  EXPECT_EQ(n, (2 * kFaces - 1) * kPerHalf);
  EXPECT_EQ(bySide, n);  // the oracle agrees with the path's construction
  EXPECT_GT(c.polygonInside, n / 4);
  return c;
}

// step() of every method does not allocate, over both paths. On the quad-sphere, contact is
// exactly the inside of the surface each method renders, at every step: the patch surface for
// patch, the polygons for direct and shading (the god-object).
TEST(ForceRealtime, StepDoesNotAllocate) {
  if (!SF_FORCE_COUNT_ALLOCS) GTEST_SKIP() << "allocation counting needs glibc and no sanitizer";
  int checkedSteps = 0;
  for (const RealtimeCase& c : {spotCase(), sphereCase()}) {
    auto scene = std::make_shared<const PolygonScene>(*c.cache);
    auto skeletonScene = std::make_shared<const PolygonScene>(*c.skeleton);
    const int n = static_cast<int>(c.hips.size());
    ASSERT_LE(n, 4096);
    if (!c.inPatch.empty())
      std::printf("  %s: %d HIPs, inside the patches %d, the polygons %d\n", c.name.c_str(), n, c.patchInside,
                  c.polygonInside);
    for (ForceMethod m : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading})
      for (RefineMethod rm : {RefineMethod::Newton, RefineMethod::PaperDescent})
        for (bool lazy : {false, true}) {
          ForceOptions o;
          o.refine = rm;
          o.patchCapacity = 16;
          auto r = lazy ? makeForceRenderer(c.skeleton, skeletonScene, m, o) : makeForceRenderer(c.cache, scene, m, o);
          static char contact[4096];  // written while armed: no allocation
          gAllocations = 0;
          gArmed = true;
          for (int i = 0; i < n; ++i) contact[i] = r->step(c.hips[i]).contact;
          r->reset();
          gArmed = false;
          const std::string what = c.name + " " + toString(m) + " " + toString(rm) + (lazy ? " lazy" : "");
          EXPECT_EQ(gAllocations, 0) << what;
          if (lazy && m == ForceMethod::Patch) {
            EXPECT_GT(r->patchesBuilt(), 16) << what << ": the path should evict and rebuild";
          }
          if (c.inPatch.empty()) continue;
          const std::vector<char>& inside = m == ForceMethod::Patch ? c.inPatch : c.inPolygon;
          int contacts = 0, agree = 0;
          std::string where;
          for (int i = 0; i < n; ++i) {
            contacts += contact[i];
            agree += contact[i] == inside[i];
            if (contact[i] != inside[i] && where.size() < 200) {
              where += ' ';  // in two parts: " " + std::to_string(i) trips GCC 12's -Wrestrict (false positive)
              where += std::to_string(i);
            }
          }
          EXPECT_EQ(contacts, m == ForceMethod::Patch ? c.patchInside : c.polygonInside) << what;
          EXPECT_EQ(agree, n) << what << ": contact differs from inside at HIPs" << where;
          checkedSteps += n;
        }
  }
  EXPECT_EQ(checkedSteps, 12 * 1960);
  static void* volatile sink;  // control: counting works
  gAllocations = 0;
  gArmed = true;
  sink = std::malloc(24);
  std::free(sink);
  sink = new std::vector<int>(3);
  gArmed = false;
  delete static_cast<std::vector<int>*>(sink);
  EXPECT_EQ(gAllocations, 3);
}

}  // namespace
}  // namespace sf
