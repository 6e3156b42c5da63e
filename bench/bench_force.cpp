// SPDX-License-Identifier: Apache-2.0
// Per-step compute time of the force methods (patch with Newton or the paper's descent, patch
// with Newton on a skeleton whose patches are built lazily, direct god-object, force shading) on
// the spot cage and the quad-sphere:
//   ContactStart  reset, then one step at a HIP 3 cm inside: the patch method's global Embree
//                 query + MVC + refinement; for direct/shading the HIP is reached from a
//                 point outside (their contact starts at a segment crossing), so this is a
//                 free step plus the contact-start step - subtract FreeStep.
//   FreeStep      a step out of contact (patch: global query + refinement; god-object: a
//                 segment query) at HIPs 5 cm outside random patch points, one after another;
//                 on the spot cage some of them lie inside another part of the cow (contact
//                 starts: counter contact_fraction) or within an error band of the folded
//                 patches (the whole global query runs).
//   OutsideStep   the same over the HIPs a patch step from out of contact decides without any
//                 patch work (outside every error band, winding number 0; counter clear_hips):
//                 what an out-of-contact step costs where the surface is well-behaved.
//   TrackingStep  a step in contact along a slide across edges at constant depth.
// Run: build/bench/bench_force [--benchmark_format=json]. Warm-up and construction excluded
// (the lazy renderer builds each patch the first time it needs it, in the first repetitions;
// its capacity holds every face of both meshes, so the steady state has no construction).
#include <benchmark/benchmark.h>

#include <memory>
#include <random>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/query/embree_scene.h>
#include "bench_common.h"

namespace {

using namespace sf;

struct Scene {
  std::shared_ptr<const PatchCache> cache, skeleton;  ///< skeleton: the same mesh, no patch built
  std::shared_ptr<const PolygonScene> scene, skeletonScene;
  std::vector<Eigen::Vector3d> inside, outside, slide;
  std::vector<Eigen::Vector3d> clear;  ///< the outside HIPs a patch step decides without patch work
  Eigen::Vector3d slideEntry;  ///< outside the start of the slide, for the god-object's first crossing
};

/// Slide under the patches at `depth`: from face f0's centre through edge k0, then through the
/// opposite edges, `faces` faces, there and back (a closed path).
std::vector<Eigen::Vector3d> slidePath(const PatchCache& c, int f0, int k0, int faces, int perHalf, double depth) {
  std::vector<Eigen::Vector3d> p;
  auto mid = [&](int f, int k) {
    const int n = c.faceSize(f);
    return Eigen::Vector2d(0.5 * (domainCorner(n, k) + domainCorner(n, (k + 1) % n)));
  };
  auto at = [&](int f, const Eigen::Vector2d& X) {
    const PatchPoint q = evaluatePatch(c, f, X.x(), X.y());
    return Eigen::Vector3d(q.pos - depth * q.normal);
  };
  int f = f0, in = -1, out = k0;
  for (int i = 0; i < faces; ++i) {
    if (in >= 0)
      for (int j = 0; j < perHalf; ++j) p.push_back(at(f, mid(f, in) * (1 - double(j) / perHalf)));
    for (int j = 0; j < perHalf; ++j) p.push_back(at(f, mid(f, out) * (double(j) / perHalf)));
    const int twin = c.slotTwin[c.faceOffsets[f] + out];
    if (twin < 0) break;
    f = slotFace(c.faceOffsets, twin);
    in = twin - c.faceOffsets[f];
    out = (in + c.faceSize(f) / 2) % c.faceSize(f);
  }
  for (int j = static_cast<int>(p.size()) - 2; j > 0; --j) p.push_back(p[j]);
  return p;
}

const Scene& scene(int which) {
  static std::unique_ptr<Scene> s[2];
  if (!s[which]) {
    s[which] = std::make_unique<Scene>();
    Scene& sc = *s[which];
    const std::string rel = which == 0 ? "keenan_crane/spot_control_mesh.obj" : "polygon_laplacian/quad-sphere.off";
    sc.cache = std::make_shared<const PatchCache>(
        bench::meshCache(std::string(SF_SHARED_MESHES) + "/" + rel, Precision::Double));
    sc.scene = std::make_shared<const PolygonScene>(*sc.cache);
    PatchCache skeleton = *sc.cache;
    skeleton.edgeDataD.clear();
    skeleton.edgeDataF.clear();
    sc.skeleton = std::make_shared<const PatchCache>(std::move(skeleton));
    sc.skeletonScene = std::make_shared<const PolygonScene>(*sc.skeleton);
    const bench::Queries q = bench::randomQueries(*sc.cache, 512);
    for (size_t i = 0; i < q.face.size(); ++i) {
      const PatchPoint p = evaluatePatch(*sc.cache, q.face[i], q.xi[i], q.eta[i]);
      sc.inside.push_back(p.pos - 0.03 * p.normal);
      sc.outside.push_back(p.pos + 0.05 * p.normal);
    }
    {  // the outside HIPs a step from out of contact leaves out of contact without refining
      auto r = makeForceRenderer(sc.cache, sc.scene, ForceMethod::Patch, ForceOptions{});
      for (const Eigen::Vector3d& h : sc.outside) {
        r->reset();
        const ForceSample s = r->step(h);
        if (!s.contact && s.iterations == 0) sc.clear.push_back(h);
      }
    }
    const int f0 = which == 0 ? 11 : 0;
    sc.slide = slidePath(*sc.cache, f0, 0, 6, 40, which == 0 ? 0.03 : 0.05);
    const PatchPoint p0 = evaluatePatch(*sc.cache, f0, 0, 0);
    sc.slideEntry = p0.pos + 0.05 * p0.normal;
  }
  return *s[which];
}

std::unique_ptr<ForceRenderer> renderer(const Scene& sc, int method) {
  ForceOptions o;
  if (method == 3) o.refine = RefineMethod::PaperDescent;
  if (method == 5) o.finalStep = FinalStep::Model;
  if (method == 6) o.surfaceIndex = SurfaceIndex::Bounds;
  if (method == 7) applyForcePreset(findForcePreset("fast"), o);
  if (method == 4) {
    o.patchCapacity = 1024;
    return makeForceRenderer(sc.skeleton, sc.skeletonScene, ForceMethod::Patch, o);
  }
  return makeForceRenderer(sc.cache, sc.scene, method >= 3 ? ForceMethod::Patch : ForceMethod(method), o);
}

std::string label(int mesh, int method) {
  static const char* names[] = {"patch/newton",
                                "direct",
                                "shading",
                                "patch/paper",
                                "patch/newton, lazy",
                                "patch/newton, model final step",
                                "patch/newton, bounds index",
                                "patch/newton, preset fast"};
  return std::string(mesh == 0 ? "spot cage, " : "quad-sphere, ") + names[method];
}

// args: mesh (0 spot, 1 quad-sphere), method (0 patch/newton, 1 direct, 2 shading, 3 patch/paper,
// 4 patch/newton on the skeleton, patches built lazily, 5 patch/newton with FinalStep::Model,
// 6 patch/newton with SurfaceIndex::Bounds, the servo loop's, 7 patch/newton with --preset fast;
// the others on a prebuilt cache use the tessellation, auto's choice for a batch)
void BM_ContactStart(benchmark::State& state) {
  const Scene& sc = scene(static_cast<int>(state.range(0)));
  const int method = static_cast<int>(state.range(1));
  auto r = renderer(sc, method);
  size_t i = 0, contacts = 0;
  for (auto _ : state) {
    r->reset();
    if (method == 1 || method == 2) r->step(sc.outside[i]);
    const ForceSample s = r->step(sc.inside[i]);
    contacts += s.contact;
    benchmark::DoNotOptimize(s.force.data());
    i = (i + 1) % sc.inside.size();
  }
  state.SetLabel(label(static_cast<int>(state.range(0)), method) +
                 (method == 1 || method == 2 ? " (free step + contact start)" : ""));
  state.counters["contact_fraction"] = double(contacts) / double(state.iterations());
}

void freeSteps(benchmark::State& state, const std::vector<Eigen::Vector3d>& hips) {
  const Scene& sc = scene(static_cast<int>(state.range(0)));
  const int method = static_cast<int>(state.range(1));
  auto r = renderer(sc, method);
  size_t i = 0, contacts = 0;
  for (auto _ : state) {
    const ForceSample s = r->step(hips[i]);
    contacts += s.contact;
    benchmark::DoNotOptimize(s.force.data());
    i = (i + 1) % hips.size();
  }
  state.SetLabel(label(static_cast<int>(state.range(0)), method));
  state.counters["contact_fraction"] = double(contacts) / double(state.iterations());
}

void BM_FreeStep(benchmark::State& state) { freeSteps(state, scene(static_cast<int>(state.range(0))).outside); }

void BM_OutsideStep(benchmark::State& state) {
  const Scene& sc = scene(static_cast<int>(state.range(0)));
  state.counters["clear_hips"] = double(sc.clear.size());
  freeSteps(state, sc.clear);
}

void BM_TrackingStep(benchmark::State& state) {
  const Scene& sc = scene(static_cast<int>(state.range(0)));
  const int method = static_cast<int>(state.range(1));
  auto r = renderer(sc, method);
  r->step(sc.slideEntry);  // warm-up: enter from outside, one pass along the slide
  for (const Eigen::Vector3d& h : sc.slide) r->step(h);
  size_t i = 0, contacts = 0, iterations = 0;
  for (auto _ : state) {
    const ForceSample s = r->step(sc.slide[i]);
    contacts += s.contact;
    iterations += s.iterations;
    benchmark::DoNotOptimize(s.force.data());
    i = (i + 1) % sc.slide.size();
  }
  state.SetLabel(label(static_cast<int>(state.range(0)), method));
  state.counters["contact_fraction"] = double(contacts) / double(state.iterations());
  state.counters["iterations"] = double(iterations) / double(state.iterations());
}

#define SF_FORCE_ARGS ArgsProduct({{0, 1}, {0, 7, 6, 5, 4, 3, 1, 2}})->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_ContactStart)->SF_FORCE_ARGS;
BENCHMARK(BM_FreeStep)->SF_FORCE_ARGS;
BENCHMARK(BM_OutsideStep)->SF_FORCE_ARGS;
BENCHMARK(BM_TrackingStep)->SF_FORCE_ARGS;

}  // namespace

BENCHMARK_MAIN();
