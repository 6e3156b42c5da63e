// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_opencl.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <future>
#include <utility>
#include <limits>
#include <memory>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/opencl/opencl_candidates.h>
#include <smoothforce/opencl/opencl_refine.h>
#include <smoothforce/query/embree_scene.h>

namespace sf {

struct OpenCLPatchProber::Impl {
  Impl(std::shared_ptr<const PatchCache> c, std::shared_ptr<const PolygonScene> sc,
       std::shared_ptr<const PatchSurface> su, const ForceOptions& o, const OpenCLOptions& cl)
      : cache(std::move(c)),
        options(o),
        scene(std::move(sc)),
        surface(std::move(su)),
        cpu([this] { return std::make_unique<PatchRefiner>(*cache); }) {
    for (int f = 0; f < cache->numFaces(); ++f) maxN = std::max(maxN, cache->faceSize(f));
    // The device's context, program load and cache upload wait on the driver; the scene's and the
    // surface's BVHs keep the cores busy meanwhile.
    if (o.initialGuess != InitialGuess::Surface) surface.reset();
    const bool wantSurface = o.initialGuess == InitialGuess::Surface && !surface;
    tbb::task_group g;
    g.run([&] { refiner = std::make_unique<OpenCLRefiner>(*cache, cl); });
    try {
      if (!scene) scene = std::make_shared<const PolygonScene>(*cache, kPlanarTolerance);
      if (wantSurface) surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(o));
      // the seeded steps' candidate searches on the device too, where it can (usable())
      if (surface) {
        search = std::make_unique<OpenCLCandidateSearch>(*surface, cl);
        if (!search->usable()) search.reset();
      }
    } catch (...) {
      try {
        g.wait();
      } catch (...) {  // the first failure is the one reported
      }
      throw;
    }
    g.wait();
  }

  std::shared_ptr<const PatchCache> cache;
  ForceOptions options;
  std::shared_ptr<const PolygonScene> scene;
  std::shared_ptr<const PatchSurface> surface;
  std::unique_ptr<OpenCLRefiner> refiner;
  /// the candidate search of the seeded steps' global queries (null: on the host)
  std::unique_ptr<OpenCLCandidateSearch> search;
  /// the CPU refines the global query's further candidates (those whose lower bound is below the
  /// nearest distance found so far)
  tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> cpu;
  int maxN = 3;
  // per HIP of a chunk: contact state, the step's sample and start, the refinement, and the
  // patch point the last step ended at (the next step's hint: seed and reach)
  std::vector<PatchContactState> state;
  std::vector<ForceSample> sample;
  std::vector<PatchStepStart> start;
  std::vector<uint8_t> refine;
  std::vector<RefineQuery> query;
  std::vector<RefineResult> result;
  std::vector<PatchStepHint> hint;
  /// per HIP of a chunk: an unseeded step's candidates, searched in beginPatchStep (kCandidates of
  /// storage; a step with more searches again when it finishes)
  static constexpr int kCandidates = 16;
  std::unique_ptr<CandidateBuffer<kCandidates>[]> candidateStore;  ///< left uninitialised: the search writes it
  size_t storeSize = 0;
  std::vector<CandidateList> candidates;
  // the steps whose candidates the device searches, per half of a chunk: their HIPs and results
  static constexpr int kDeviceCandidates = OpenCLCandidateSearch::kMaxCap;
  struct SearchBatch {
    std::vector<Eigen::Vector3d> hip;
    std::vector<int32_t> ids, count;
    std::vector<uint32_t> offset;
  };
  SearchBatch batch[2];
  std::vector<int32_t> searchSlot;  ///< per HIP of the chunk: its place in its half's batch, or -1
  OpenCLProbeTiming timing;
};

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

OpenCLPatchProber::OpenCLPatchProber(std::shared_ptr<const PatchCache> cache, const ForceOptions& options,
                                     const OpenCLOptions& opencl)
    : OpenCLPatchProber(std::move(cache), nullptr, nullptr, options, opencl) {}

OpenCLPatchProber::OpenCLPatchProber(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                                     std::shared_ptr<const PatchSurface> surface, const ForceOptions& options,
                                     const OpenCLOptions& opencl) {
  validateForceOptions(options);
  if (!cache) throw InputError("OpenCLPatchProber: no cache");
  if ((scene && &scene->cache() != cache.get()) || (surface && &surface->cache() != cache.get()))
    throw InputError("OpenCLPatchProber: the polygon scene and the patch surface must be built from the same cache");
  const auto t = Clock::now();
  impl_ = std::make_unique<Impl>(std::move(cache), std::move(scene), std::move(surface), options, opencl);
  impl_->timing.setup = since(t);
}

OpenCLPatchProber::~OpenCLPatchProber() = default;

size_t OpenCLPatchProber::run(const HipSet& set, size_t begin, size_t end, const ReferenceSurface* ref,
                              HipResult* out, const SweepControl& control, size_t chunk) {
  if (begin >= end) return 0;
  const auto t0 = Clock::now();
  Impl& I = *impl_;
  chunk = std::max<size_t>(1, std::min(chunk, end - begin));
  I.state.resize(chunk);
  I.sample.resize(chunk);
  I.start.resize(chunk);
  I.refine.resize(chunk);
  I.query.resize(chunk);
  I.result.resize(chunk);
  I.hint.resize(chunk);
  if (I.storeSize < chunk) {
    I.candidateStore.reset(new CandidateBuffer<Impl::kCandidates>[chunk]);
    I.storeSize = chunk;
  }
  I.candidates.resize(chunk);
  for (size_t i = 0; i < chunk; ++i) I.candidates[i] = CandidateList{I.candidateStore[i].data(), Impl::kCandidates, 0};
  const std::vector<uint32_t> order = probeOrder(set, begin, end);  // as runProbes: neighbours in turn
  I.searchSlot.assign(chunk, -1);
  // Per chunk, two halves in turn, and per half and step: begin (CPU, parallel) -> device (the
  // half's refinements, then its seeded steps' candidate searches) -> finish (CPU, parallel).
  // The device stages run on a thread of their own while the CPU works on the other half.
  size_t c0 = 0;  // the chunk's first HIP (an index into order)
  using Range = std::pair<size_t, size_t>;  // [first, last) of the chunk
  auto beginStep = [&](int step, Range r) {
    const auto t = Clock::now();
    tbb::parallel_for(r.first, r.second, [&](size_t i) {
      thread_local std::vector<double> lambda;
      lambda.resize(I.maxN);
      const size_t g = begin + order[c0 + i];
      if (step == 0) {  // reset(), then resetNear: the HIP's surface sample seeds the approach step
        const SurfaceSample& from = set.sample(g);
        I.state[i] = PatchContactState{};
        I.hint[i] = PatchStepHint{from.face, Eigen::Vector2d(from.xi, from.eta), from.point};
      }
      const Eigen::Vector3d hip = step == 0 ? set.approach(g) : set.hip(g);
      I.candidates[i].count = 0;
      I.refine[i] = beginPatchStep(*I.scene, I.surface.get(), *I.cache, hip, I.state[i], lambda.data(), I.start[i],
                                   I.sample[i], true, I.hint[i], &I.candidates[i]);
      // a seeded start (the tracker's PatchStepHint) is evaluated and tested, not refined
      I.query[i] = RefineQuery{hip, I.refine[i] ? I.start[i].face : -1, I.start[i].X.x(), I.start[i].X.y(),
                               I.start[i].edge, I.start[i].seeded ? 0 : -1};
    });
    I.timing.cpu += since(t);
  };
  // The device's part of a half (on the device thread): the first refinement of every step, then
  // the candidates of the seeded global steps (beginPatchStep leaves them to the finish, bounded
  // by the refinement), as triangle indices whose records the finish computes.
  auto deviceStep = [&I](Range r, Impl::SearchBatch& b) {
    const size_t m = r.second - r.first;
    auto t = Clock::now();
    I.refiner->refine(I.query.data() + r.first, m, I.options, I.result.data() + r.first);
    I.timing.refine += since(t);
    I.timing.kernel += I.refiner->lastKernelSeconds();
    I.timing.transfer += I.refiner->lastTransferSeconds();
    ++I.timing.refinements;
    if (!I.search) return;
    t = Clock::now();
    b.hip.clear();
    for (size_t i = r.first; i < r.second; ++i) {
      I.searchSlot[i] = -1;
      if (I.refine[i] && I.start[i].global && I.start[i].seeded && I.candidates[i].count == 0) {
        I.searchSlot[i] = static_cast<int32_t>(b.hip.size());
        b.hip.push_back(I.query[i].hip);
      }
    }
    b.count.resize(b.hip.size());
    b.offset.resize(b.hip.size());
    I.search->search(b.hip.data(), b.hip.size(), Impl::kDeviceCandidates, b.count.data(), b.offset.data(), b.ids);
    I.timing.search += since(t);
    I.timing.kernel += I.search->lastKernelSeconds();
    I.timing.transfer += I.search->lastTransferSeconds();
  };
  auto finishStep = [&](int step, Range r, const Impl::SearchBatch& b) {
    const auto t = Clock::now();
    tbb::parallel_for(r.first, r.second, [&](size_t i) {
      CandidateBuffer<Impl::kDeviceCandidates> device;
      CandidateList deviceList{device.data(), Impl::kDeviceCandidates, 0};
      CandidateList* list = &I.candidates[i];
      if (I.search && I.searchSlot[i] >= 0) {  // the device's triangles, the host's records
        const size_t k = static_cast<size_t>(I.searchSlot[i]);
        deviceList.count = std::max(0, b.count[k]);
        for (int j = 0; j < deviceList.count; ++j)
          device[j] = I.surface->candidateOf(I.query[i].hip, b.ids[b.offset[k] + j]);
        list = &deviceList;
      }
      if (I.refine[i])
        finishPatchStep(*I.scene, I.surface.get(), *I.cpu.local(), I.query[i].hip, I.start[i], I.result[i], I.options,
                        I.state[i], I.sample[i], &I.hint[i], list);
      if (step == 1) fillHipResult(out[order[c0 + i]], I.sample[i], ref);
    });
    I.timing.cpu += since(t);
  };
  std::future<void> device;  // the device stage in flight
  auto launch = [&](Range r, int half) {
    device = std::async(std::launch::async, deviceStep, r, std::ref(I.batch[half]));
  };
  auto wait = [&] {
    const auto t = Clock::now();
    device.get();  // rethrows the device's errors here
    I.timing.wait += since(t);
  };
  size_t done = 0;
  for (; c0 < end - begin; c0 += chunk) {
    if (control.stop && control.stop->load(std::memory_order_relaxed)) break;
    const size_t m = std::min(chunk, end - begin - c0);
    const Range half[2] = {{0, m / 2}, {m / 2, m}};  // the first is empty for a chunk of 1
    // step 0 of A, then B; step 1 of A, then B: the device works on one half while the CPU
    // begins or finishes the other
    beginStep(0, half[0]);
    launch(half[0], 0);
    beginStep(0, half[1]);
    wait();
    launch(half[1], 1);
    finishStep(0, half[0], I.batch[0]);
    beginStep(1, half[0]);
    wait();
    launch(half[0], 0);
    finishStep(0, half[1], I.batch[1]);
    beginStep(1, half[1]);
    wait();
    launch(half[1], 1);
    finishStep(1, half[0], I.batch[0]);
    wait();
    finishStep(1, half[1], I.batch[1]);
    done += m;
    if (control.progress) control.progress(m);
  }
  I.timing.run += since(t0);
  return done;
}

const OpenCLProbeTiming& OpenCLPatchProber::timing() const { return impl_->timing; }

size_t runPatchProbesOpenCL(const HipSet& set, size_t begin, size_t end, std::shared_ptr<const PatchCache> cache,
                            const ForceOptions& options, const ReferenceSurface* ref, HipResult* out,
                            const SweepControl& control, const OpenCLOptions& opencl, size_t chunk) {
  validateForceOptions(options);
  if (begin >= end) return 0;
  OpenCLPatchProber prober(std::move(cache), options, opencl);
  return prober.run(set, begin, end, ref, out, control, chunk);
}

}  // namespace sf
