#include <smoothforce/sweep/sweep_run.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include <smoothforce/base/hash.h>
#include <smoothforce/sweep/sweep_opencl.h>

namespace sf {

namespace {
double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

HipSet buildHipSet(SweepInputs& in, std::unique_ptr<ReferenceSurface>* reference) {
  SweepConfig& c = in.config;
  const PatchCache& cache = *in.cache;
  c.diagonal = boundingDiagonal(cache);
  c.faces = cache.numFaces();
  c.meshHash = hexHash(cache.meshHash);
  if (!(c.trajectoryStep > 0)) c.trajectoryStep = c.diagonal / 400;
  std::unique_ptr<TriangleSoup> soup;
  if (!c.reference.empty()) soup = std::make_unique<TriangleSoup>(loadTriangleSoup(c.reference));
  HipSet set;
  if (!in.hipsFile.empty()) {
    c.sampleOn = "file";
    const PatchSurfaceSampler sampler(cache, c.level);
    const PatchProjector projector(cache, c.level);
    set = makeFileHips(readPointsCsv(in.hipsFile), projector, c.diagonal, sampler.area());
    c.samples = set.samples.size();
  } else if (c.sampleOn == "reference") {
    if (!soup) throw InputError("--sample-on reference needs --reference");
    set = makeDepthHips(sampleTriangleSoup(*soup, c.samples, c.seed), in.depths, c.diagonal, soup->area());
  } else if (c.sampleOn == "patch") {
    const PatchSurfaceSampler sampler(cache, c.level);
    set = makeDepthHips(sampler.sample(c.samples, c.seed), in.depths, c.diagonal, sampler.area());
  } else {
    throw InputError("--sample-on: expected patch or reference, got '" + c.sampleOn + "'");
  }
  c.area = set.area;
  c.groupLabels.clear();
  c.groupDepths.clear();
  for (const auto& g : set.groups) {
    c.groupLabels.push_back(g.label);
    c.groupDepths.push_back(g.depth);
  }
  if (!(c.approach > 0) || !std::isfinite(c.approach)) throw InputError("--approach must be positive");
  set.approachFactor = c.approach;
  c.hipHash = hexHash(set.hash());
  if (reference) {
    if (!c.analytic.empty())
      *reference = makeAnalyticSurface(c.analytic);
    else if (soup)
      *reference = std::make_unique<MeshDistance>(std::move(*soup), c.reference);
  }
  return set;
}

static SweepData runSweepImpl(SweepInputs in, const SweepControl& control, SweepTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!in.cache) throw InputError("sweep: no patch cache");
  if (in.config.methods.empty()) throw InputError("--methods: empty list");
  ForceOptions opt;
  opt.stiffness = in.config.stiffness;
  opt.refine = parseRefineMethod(in.config.refine);
  opt.angleTolerance = in.config.angleTolerance;
  opt.maxIterations = in.config.maxIterations;
  opt.initialGuess = parseInitialGuess(in.config.initialGuess);
  opt.tessellationLevel = in.config.guessLevel;
  if (in.config.backend == "opencl" && opt.initialGuess == InitialGuess::Tessellation)
    throw InputError("--initial-guess tessellation: the OpenCL refinement starts from the polygon point; use "
                     "--backend tbb or --initial-guess polygon");
  // A skeleton cache (sweep --mesh with --sample-on reference): every worker's patch renderer
  // builds the patches its HIPs touch, none evicted; nothing else may evaluate patches.
  const bool lazy = !hasPatchData(*in.cache);
  if (lazy && (in.config.sampleOn == "patch" || !in.hipsFile.empty() || !in.config.trajectories.empty() ||
               in.config.backend == "opencl"))
    throw InputError("sweep: patches built lazily only with --sample-on reference, no --hips, no --trajectory and "
                     "the CPU backend");
  opt.patchCapacity = 0;
  if (!in.makeRenderer) {
    auto cache = in.cache;
    in.makeRenderer = [cache, opt](const std::string& m) { return makeForceRenderer(cache, parseForceMethod(m), opt); };
  }
  for (const auto& m : in.config.methods) in.makeRenderer(m);  // bad names and options fail here, once
  std::unique_ptr<ReferenceSurface> ref;
  const HipSet set = buildHipSet(in, &ref);
  SweepData d;
  d.config = in.config;
  d.shardIndex = in.shardIndex;
  d.shardCount = in.shardCount;
  shardRange(set.size(), in.shardIndex, in.shardCount, d.begin, d.end);
  for (uint64_t g = d.begin; g < d.end; ++g) d.hips.push_back(set.hip(g));
  SweepTiming tm;
  tm.setupSeconds = since(t0);
  tm.hipsRun = d.end - d.begin;
  bool stopped = false;
  for (const auto& m : d.config.methods) {
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<HipResult> out(d.end - d.begin);
    const RendererFactory make = [&in, m] { return in.makeRenderer(m); };
    // --backend opencl: the patch method's refinements run on the device (sweep_opencl.h)
    long built = 0;
    const size_t done =
        m == "patch" && in.config.backend == "opencl"
            ? runPatchProbesOpenCL(set, d.begin, d.end, in.cache, opt, ref.get(), out.data(), control, in.opencl)
            : runProbes(set, d.begin, d.end, make, ref.get(), out.data(), control, lazy ? &built : nullptr);
    tm.methodPatchesBuilt.push_back(built);
    stopped = stopped || done < d.end - d.begin;
    tm.methodDone.push_back(done);
    d.results.push_back(std::move(out));
    tm.methodSeconds.push_back(since(t1));
  }
  // Trajectories: the first shard runs them, whole (they are short and sequential).
  const bool wantTraj =
      !lazy && in.shardIndex == 0 && in.hipsFile.empty() && !stopped && !(control.stop && control.stop->load());
  if (wantTraj) {
    const auto t2 = std::chrono::steady_clock::now();
    SweepConfig& c = d.config;
    const PatchProjector projector(*in.cache, c.level);
    std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>> paths;
    for (const auto& f : c.trajectories) paths.emplace_back(std::filesystem::path(f).stem().string(), readPointsCsv(f));
    if (c.trajectories.empty()) {
      auto loop = defaultTrajectory(*in.cache, c.level);
      if (loop.size() >= 2) paths.emplace_back("default", std::move(loop));
    }
    std::vector<std::vector<SurfaceSample>> full, half;
    for (const auto& [name, pts] : paths) {
      full.push_back(trajectorySamples(pts, c.trajectoryStep, projector));
      half.push_back(trajectorySamples(pts, c.trajectoryStep / 2, projector));
    }
    for (size_t t = 0; t < paths.size(); ++t)
      for (const auto& m : c.methods)
        for (size_t g = 0; g < set.groups.size(); ++g)
          for (int h = 0; h < 2; ++h) {
            TrajectorySeries s;
            s.trajectory = paths[t].first;
            s.method = m;
            s.depthLabel = set.groups[g].label;
            s.depth = set.groups[g].depth;
            s.step = h ? c.trajectoryStep / 2 : c.trajectoryStep;
            s.half = h == 1;
            d.trajectories.push_back(std::move(s));
          }
    tbb::parallel_for(size_t(0), d.trajectories.size(), [&](size_t i) {
      TrajectorySeries& s = d.trajectories[i];
      const size_t per = c.methods.size() * set.groups.size() * 2;
      const auto& path = s.half ? half[i / per] : full[i / per];
      auto r = in.makeRenderer(s.method);
      runTrajectory(path, s.depth, c.approach, *r, s);
    });
    tm.trajectorySeconds = since(t2);
  }
  d.interrupted = stopped;
  if (timing) *timing = tm;
  return d;
}

SweepData runSweep(SweepInputs in, const SweepControl& control, SweepTiming* timing) {
  if (control.threads <= 0) return runSweepImpl(std::move(in), control, timing);
  tbb::task_arena arena(control.threads);  // sampling, probes and trajectories alike
  return arena.execute([&] { return runSweepImpl(std::move(in), control, timing); });
}

}  // namespace sf
