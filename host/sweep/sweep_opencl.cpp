#include <smoothforce/sweep/sweep_opencl.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/opencl/opencl_refine.h>
#include <smoothforce/query/embree_scene.h>

namespace sf {

size_t runPatchProbesOpenCL(const HipSet& set, size_t begin, size_t end, std::shared_ptr<const PatchCache> cache,
                            const ForceOptions& options, const ReferenceSurface* ref, HipResult* out,
                            const SweepControl& control, const OpenCLOptions& opencl, size_t chunk) {
  validateForceOptions(options);
  if (options.refine != RefineMethod::Newton)
    throw InputError("--backend opencl refines with --refine newton only (the paper's descent runs on the CPU)");
  if (begin >= end) return 0;
  const PolygonScene scene(*cache);
  std::unique_ptr<const PatchSurface> surface;
  if (options.initialGuess == InitialGuess::Surface)
    surface = std::make_unique<const PatchSurface>(*cache, patchSurfaceOptions(options));
  OpenCLRefiner refiner(*cache, opencl);
  // the CPU refines the global query's further candidates, where they could be nearer (rare)
  tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> cpu([&] { return std::make_unique<PatchRefiner>(*cache); });
  int maxN = 3;
  for (int f = 0; f < cache->numFaces(); ++f) maxN = std::max(maxN, cache->faceSize(f));
  chunk = std::max<size_t>(1, std::min(chunk, end - begin));
  // per HIP of a chunk: contact state, the step's sample and start, and the refinement
  std::vector<PatchContactState> state(chunk);
  std::vector<ForceSample> sample(chunk);
  std::vector<PatchStepStart> start(chunk);
  std::vector<uint8_t> refine(chunk);
  std::vector<RefineQuery> query(chunk);
  std::vector<RefineResult> result(chunk);
  auto body = [&](size_t c0, size_t m, auto&& hipOf, auto&& finish) {
    // begin (CPU, parallel) -> refine (device, whole chunk) -> finish (CPU, parallel)
    tbb::parallel_for(size_t(0), m, [&](size_t i) {
      thread_local std::vector<double> lambda;
      lambda.resize(maxN);
      const Eigen::Vector3d hip = hipOf(c0 + i);
      refine[i] = beginPatchStep(scene, surface.get(), *cache, hip, state[i], lambda.data(), start[i], sample[i]);
      query[i] = RefineQuery{hip, refine[i] ? start[i].face : -1, start[i].X.x(), start[i].X.y(), start[i].edge};
    });
    refiner.refine(query.data(), m, options, result.data());
    tbb::parallel_for(size_t(0), m, [&](size_t i) {
      if (refine[i])
        finishPatchStep(scene, surface.get(), *cpu.local(), query[i].hip, start[i], result[i], options, state[i],
                        sample[i]);
      finish(c0 + i, i);
    });
  };
  size_t done = 0;
  for (size_t c0 = begin; c0 < end; c0 += chunk) {
    if (control.stop && control.stop->load(std::memory_order_relaxed)) break;
    const size_t m = std::min(chunk, end - c0);
    std::fill(state.begin(), state.begin() + m, PatchContactState{});  // reset()
    body(
        c0, m, [&](size_t g) { return set.approach(g); }, [](size_t, size_t) {});
    body(
        c0, m, [&](size_t g) { return set.hip(g); },
        [&](size_t g, size_t i) { fillHipResult(out[g - begin], sample[i], ref); });
    done += m;
    if (control.progress) control.progress(m);
  }
  return done;
}

}  // namespace sf
