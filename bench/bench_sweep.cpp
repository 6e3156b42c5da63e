// SPDX-License-Identifier: Apache-2.0
// Sweep throughput: HIP queries per second per force method and backend (reset, approach,
// pressed-in step) on the spot cage, 1e5 and 1e6 HIPs, all threads. Backends: tbb (all
// methods), opencl (patch: refinements on the OpenCL device, OpenCLPatchProber; skipped with a
// message when no device exists). As in `smoothforce sweep`, the renderers of every thread and
// the OpenCL prober share one polygon scene per method kind and one patch surface, built once
// outside the timed region; a timed run includes the renderers' construction (on first use per
// thread) and the OpenCL prober's (context, program load, cache upload). HIP sampling is outside
// the timed region; one warm-up run precedes the timing.
// Run: build/bench/bench_sweep [--benchmark_format=json] [--benchmark_filter=/100000/]
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep.h>
#include <smoothforce/sweep/sweep_opencl.h>

namespace {

using namespace sf;

struct Spot {
  std::shared_ptr<const PatchCache> cache;
  std::shared_ptr<const PolygonScene> patchScene, godScene;  // as the sweep shares them
  std::shared_ptr<const PatchSurface> surface;
  std::map<int64_t, HipSet> sets;
  static Spot& get() {
    static Spot s;
    if (!s.cache) {
      PatchOptions o;
      s.cache = std::make_shared<const PatchCache>(
          buildPatchCache(loadMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", o), o, Backend::Tbb));
      s.patchScene = std::make_shared<const PolygonScene>(*s.cache, kPlanarTolerance);
      s.godScene = std::make_shared<const PolygonScene>(*s.cache, kWatertightPlanarTolerance);
      s.surface = std::make_shared<const PatchSurface>(*s.cache, patchSurfaceOptions(ForceOptions{}));
    }
    return s;
  }
  std::unique_ptr<ForceRenderer> renderer(ForceMethod method) const {
    return makeForceRenderer(cache, method == ForceMethod::Patch ? patchScene : godScene, method, ForceOptions{},
                             surface);
  }
  const HipSet& hips(int64_t n) {
    auto it = sets.find(n);
    if (it != sets.end()) return it->second;
    const PatchSurfaceSampler sampler(*cache);
    const double diag = boundingDiagonal(*cache);
    return sets
        .emplace(n,
                 makeDepthHips(sampler.sample(static_cast<size_t>(n), 1), parseDepthList("2%"), diag, sampler.area()))
        .first->second;
  }
};

// args: method (0 patch, 1 direct, 2 shading), HIPs
void BM_Sweep(benchmark::State& state) {
  const ForceMethod method = static_cast<ForceMethod>(state.range(0));
  Spot& spot = Spot::get();
  const HipSet& set = spot.hips(state.range(1));
  const RendererFactory make = [&] { return spot.renderer(method); };
  std::vector<HipResult> out(set.size());
  runProbes(set, 0, std::min<size_t>(set.size(), 2000), make, nullptr, out.data(), {});  // warm-up
  for (auto _ : state) {
    runProbes(set, 0, set.size(), make, nullptr, out.data(), {});
    benchmark::DoNotOptimize(out.data());
  }
  size_t contact = 0;
  for (const auto& r : out) contact += r.contact;
  state.counters["HIPs/s"] = benchmark::Counter(double(set.size()) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["contact"] = double(contact) / double(set.size());
  state.SetLabel(std::string(toString(method)) + "/tbb");
}
BENCHMARK(BM_Sweep)
    ->ArgsProduct({{0, 1, 2}, {100000}})
    ->Iterations(1)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Sweep)  // one timed run each: 1e6 HIPs take minutes on one core
    ->ArgsProduct({{0, 1, 2}, {1000000}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// args: HIPs. The patch method with its refinements on the OpenCL device.
void BM_SweepOpenCL(benchmark::State& state) {
  std::string why;
  if (!openclAvailable(&why)) {
    state.SkipWithError(("no OpenCL device: " + why).c_str());
    return;
  }
  Spot& spot = Spot::get();
  const HipSet& set = spot.hips(state.range(0));
  std::vector<HipResult> out(set.size());
  // warm-up: builds (or loads) the program; each timed run includes its context and cache upload
  OpenCLPatchProber(spot.cache, spot.patchScene, spot.surface, ForceOptions{})
      .run(set, 0, std::min<size_t>(set.size(), 2000), nullptr, out.data(), {});
  OpenCLProbeTiming t;
  for (auto _ : state) {
    OpenCLPatchProber prober(spot.cache, spot.patchScene, spot.surface, ForceOptions{});
    prober.run(set, 0, set.size(), nullptr, out.data(), {});
    benchmark::DoNotOptimize(out.data());
    const OpenCLProbeTiming& p = prober.timing();
    t.setup += p.setup, t.run += p.run, t.cpu += p.cpu, t.wait += p.wait, t.refine += p.refine, t.search += p.search;
    t.kernel += p.kernel;
    t.transfer += p.transfer;
    t.refinements += p.refinements;
  }
  size_t contact = 0;
  for (const auto& r : out) contact += r.contact;
  state.counters["HIPs/s"] = benchmark::Counter(double(set.size()) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["contact"] = double(contact) / double(set.size());
  // where the time went, s per run: the prober's set-up; its run, of which the CPU stages, the
  // CPU waiting for the device, and serial work; beside them on the device thread, the refinement
  // and candidate-search calls with their kernel and transfer time
  const double runs = double(state.iterations());
  state.counters["setup_s"] = t.setup / runs;
  state.counters["serial_s"] = (t.run - t.cpu - t.wait) / runs;
  state.counters["wait_s"] = t.wait / runs;
  state.counters["cpu_s"] = t.cpu / runs;
  state.counters["refine_s"] = t.refine / runs;
  state.counters["search_s"] = t.search / runs;
  state.counters["kernel_s"] = t.kernel / runs;
  state.counters["transfer_s"] = t.transfer / runs;
  state.counters["refinements"] = double(t.refinements) / runs;
  state.SetLabel("patch/opencl");
}
BENCHMARK(BM_SweepOpenCL)
    ->Arg(100000)
    ->Iterations(1)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_SweepOpenCL)->Arg(1000000)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
