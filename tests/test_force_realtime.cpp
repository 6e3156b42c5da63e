// step() of every force method does not allocate. Counted at the C allocator (glibc's
// __libc_* entry points behind thin interposers that count while armed on this thread), so
// that operator new (whoever replaces it; test_runtime_loop.cpp does), Eigen and Embree's
// aligned allocations are all seen. Off under sanitizers, which bring their own allocator.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/embree_scene.h>
#include "patch_test_support.h"

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

TEST(ForceRealtime, StepDoesNotAllocate) {
  if (!SF_FORCE_COUNT_ALLOCS) GTEST_SKIP() << "allocation counting needs glibc and no sanitizer";
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  auto scene = std::make_shared<const PolygonScene>(*cache);
  // and over a skeleton: patches built lazily inside step(), 16 held, so that faces are evicted
  // and rebuilt during the path
  auto skeleton = std::make_shared<const PatchCache>(
      test::skeletonFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  auto skeletonScene = std::make_shared<const PolygonScene>(*skeleton);
  std::vector<Eigen::Vector3d> hips;  // in and out of the cage, across many faces
  for (int i = 0; i < 2000; ++i) {
    const double a = 2 * M_PI * i / 500.0;
    hips.emplace_back(0.3 * std::cos(a), 0.1 + 0.6 * std::sin(0.7 * a), 0.35 * std::sin(a) + 0.1 * std::cos(3 * a));
  }
  for (ForceMethod m : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading})
    for (RefineMethod rm : {RefineMethod::Newton, RefineMethod::PaperDescent})
      for (bool lazy : {false, true}) {
      ForceOptions o;
      o.refine = rm;
      o.patchCapacity = 16;
      auto r = lazy ? makeForceRenderer(skeleton, skeletonScene, m, o) : makeForceRenderer(cache, scene, m, o);
      int contacts = 0;
      gAllocations = 0;
      gArmed = true;
      for (const Eigen::Vector3d& h : hips) contacts += r->step(h).contact;
      r->reset();
      gArmed = false;
      EXPECT_EQ(gAllocations, 0) << toString(m) << " " << toString(rm) << (lazy ? " lazy" : "");
      if (lazy && m == ForceMethod::Patch) {
        EXPECT_GT(r->patchesBuilt(), 16) << "the path should evict and rebuild";
      }
      EXPECT_GT(contacts, 50) << toString(m);
      EXPECT_LT(contacts, 1990) << toString(m);
    }
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
