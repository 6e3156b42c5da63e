// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_run.h>

#include <smoothforce/sweep/sweep_option_text.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/csv_reader.h>
#include <smoothforce/base/error.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/base/status.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/probe_inside.h>
#include <smoothforce/sweep/sweep_opencl.h>
#include <smoothforce/sweep/sweep_outputs.h>

namespace sf {

namespace {
/// The sampler of the cache's patch surface; its InputError (patches of zero area) names the mesh.
PatchSurfaceSampler samplerOf(const PatchCache& cache, const SweepConfig& c) {
  try {
    return PatchSurfaceSampler(cache, c.level);
  } catch (const InputError& e) {
    throw InputError(c.source + ": " + e.what());
  }
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

HipSet buildHipSet(SweepInputs& in, std::unique_ptr<ReferenceSurface>* reference) {
  SweepConfig& c = in.config;
  if (!in.hipsFile.empty()) c.sampleOn = "file";
  checkSweepOptions(c);  // the shared reader's checks and messages (sweep_option_text.h)
  const PatchCache& cache = *in.cache;
  c.diagonal = boundingDiagonal(cache);
  c.faces = cache.numFaces();
  c.meshHash = hexHash(cache.meshHash);
  if (!(c.trajectoryStep > 0)) c.trajectoryStep = c.diagonal / 400;
  std::unique_ptr<TriangleSoup> soup;
  c.referenceHash.clear();
  if (!c.reference.empty()) {
    soup = std::make_unique<TriangleSoup>(loadTriangleSoup(c.reference));
    uint64_t h = hashBytes(soup->positions.data(), soup->positions.size() * sizeof(Eigen::Vector3d));
    h = hashBytes(soup->triangles.data(), soup->triangles.size() * sizeof(soup->triangles[0]), h);
    h = hashBytes(soup->cornerNormals.data(), soup->cornerNormals.size() * sizeof(soup->cornerNormals[0]), h);
    c.referenceHash = hexHash(h);
  }
  HipSet set;
  if (!in.hipsFile.empty()) {
    c.sampleOn = "file";
    const PatchSurfaceSampler sampler = samplerOf(cache, c);
    const PatchProjector projector(cache, c.level);
    set = makeFileHips(readPointsCsv(in.hipsFile), projector, c.diagonal, sampler.area());
    c.samples = set.samples.size();
  } else if (c.sampleOn == "reference") {
    if (!soup) throw OptionError("--sample-on reference needs --reference");
    set = makeDepthHips(sampleTriangleSoup(*soup, c.samples, c.seed), in.depths, c.diagonal, soup->area());
  } else if (c.sampleOn == "patch") {
    const PatchSurfaceSampler sampler = samplerOf(cache, c);
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
  if (!(c.approach > 0) || !std::isfinite(c.approach)) throw OptionError("--approach must be positive");
  set.approachFactor = c.approach;
  // every HIP and approach point a position the queries take (a depth or approach factor so
  // large that they leave the coordinate range would only give SF_TRACK_BAD_HIP records)
  for (size_t g = 0; g < set.size(); ++g)
    if (!inCoordinateRange(set.hip(g)) || !inCoordinateRange(set.approach(g))) {
      const std::string& depth = set.groups[g / set.perGroup()].label;
      char msg[200];
      if (!inCoordinateRange(set.hip(g)))
        std::snprintf(msg, sizeof msg, "--depth %s: HIP %zu lies beyond the coordinate range +-1e15 m", depth.c_str(), g);
      else
        std::snprintf(msg, sizeof msg, "--approach %g: the approach point of HIP %zu (depth %s) lies beyond the "
                      "coordinate range +-1e15 m", c.approach, g, depth.c_str());
      throw OptionError(msg);
    }
  c.hipHash = hexHash(set.hash());
  if (reference) {
    if (!c.analytic.empty())
      *reference = makeAnalyticSurface(c.analytic);
    else if (soup)
      *reference = std::make_unique<MeshDistance>(std::move(*soup), c.reference);
  }
  return set;
}

namespace {

using Path = std::pair<std::string, std::vector<Eigen::Vector3d>>;

/// What `cache build` reports of the patches where the patch method's force may turn sharply:
/// a line for the folded and one for the bulging patches, each only where there are some.
std::vector<std::string> patchStatusNotes(const PatchCache& cache) {
  const PatchStatusSummary s = summarizePatchStatus(cache);
  std::vector<std::string> notes;
  if (s.fold > 0)
    notes.push_back(
        "sweep: " + std::to_string(s.fold) +
        " folded patches (normal opposite to the edge normal near an edge), faces:" + faceIdsText(s.foldFaces));
  if (s.bulge > 0) {
    char max[32];
    std::snprintf(max, sizeof max, "%.3f", s.maxBulge);
    notes.push_back("sweep: " + std::to_string(s.bulge) +
                    " bulging patches (> 0.5 face diameters outside the face's box; max " + max +
                    "), faces:" + faceIdsText(s.bulgeFaces));
  }
  return notes;
}

/// The trajectories of a sweep: the files (named by stem), else the default section loop, or
/// none, with a note in *note, where no section of the surface exists (defaultTrajectory).
std::vector<Path> trajectoryPaths(const SweepConfig& c, const PatchCache& cache, std::string* note) {
  std::vector<Path> paths;
  // every series is taken at the step and at half of it (the step's refinement check): the
  // resampling's bound holds for the half step, checked here, before any probe runs
  const double finest = c.trajectoryStep / 2;
  // a file's trajectory too long for the step is the file's (exit 1); the default loop's, the step's
  auto check = [&](const std::vector<Eigen::Vector3d>& pts, const std::string& what, bool fromFile) {
    char step[64], length[64];
    std::snprintf(step, sizeof step, "%.6g", c.trajectoryStep);
    const std::string e = resampleLimitError(pts, finest, what);
    if (!e.empty()) {
      const std::string m = e + " (--trajectory-step " + step + " m: the series are taken at half of it too)";
      if (fromFile) throw InputError(m);
      throw OptionError(m);
    }
    // a series of one point has no force difference: its traj|dF| would read as perfectly smooth
    const double len = polylineLength(pts);
    std::snprintf(length, sizeof length, "%.6g", len);
    if (!(len > 0))
      throw InputError(what + ": the trajectory has no length (" + std::to_string(pts.size()) +
                       (pts.size() == 1 ? " point" : " points, all at one place") +
                       "): a trajectory needs two distinct points");
    if (len < c.trajectoryStep)
      throw OptionError("--trajectory-step " + std::string(step) + " m is longer than " + what + " (" + length +
                        " m): its series would have one point, and no force difference to measure");
  };
  for (const auto& f : c.trajectories) {
    paths.emplace_back(std::filesystem::path(f).stem().string(), readPointsCsv(f));
    check(paths.back().second, f, true);
  }
  if (c.trajectories.empty()) {
    auto loop = defaultTrajectory(cache, c.level);
    if (loop.empty()) {  // not asked for: the sweep runs without it, and says so
      *note =
          "sweep: note: no default trajectory: no plane through the centre of the surface's box normal to "
          "one of its axes meets the surface; the sweep has no trajectory series (give one with --trajectory)";
      return paths;
    }
    check(loop, "the default trajectory (a section loop)", false);
    paths.emplace_back("default", std::move(loop));
  }
  return paths;
}

/// A note when at least 9 in 10 of pts lie farther from the mesh's box than its diagonal (no
/// contact there: a file in millimetres for a mesh in metres, say); "" otherwise.
std::string farPointsNote(const std::vector<Eigen::Vector3d>& pts, const PatchCache& cache, const std::string& what,
                          const std::string& consequence) {
  Eigen::Vector3d lo, hi;
  if (pts.empty() || !referencedBox(cache, lo, hi)) return "";
  size_t far = 0;
  for (const auto& p : pts) far += farBeyondBox(p, lo, hi);
  if (far * 10 < pts.size() * 9) return "";
  char msg[400];
  std::snprintf(msg, sizeof msg,
                "sweep: note: %zu of %zu %s lie farther from the mesh's bounding box than its diagonal (%.4g m): %s; "
                "are they in another unit of length than the mesh (mm for m)?",
                far, pts.size(), what.c_str(), (hi - lo).norm(), consequence.c_str());
  return msg;
}

/// Takes over a checkpoint of the same sweep and shard (records and finished series).
void adoptCheckpoint(SweepData& prev, SweepData& d) {
  const std::string where = prev.directory.empty() ? "--resume" : prev.directory;
  const std::string diff = sweepConfigDifference(prev.config, d.config);
  if (!diff.empty())
    throw InputError(where + ": holds another sweep (" + diff + "): give the options it was run with, or another -o");
  if (prev.shardIndex != d.shardIndex || prev.shardCount != d.shardCount || prev.begin != d.begin ||
      prev.end != d.end || prev.results.size() != d.results.size())
    throw InputError(where + ": holds shard " + std::to_string(prev.shardIndex) + "/" +
                     std::to_string(prev.shardCount) + ", not " + std::to_string(d.shardIndex) + "/" +
                     std::to_string(d.shardCount));
  if (prev.trajectoryTotal != d.trajectoryTotal || prev.trajectoryBegin != d.trajectoryBegin ||
      prev.trajectoryEnd != d.trajectoryEnd)
    throw InputError(where + ": holds another list of trajectory series");
  d.results = std::move(prev.results);
  d.trajectories = std::move(prev.trajectories);
}

/// Probe blocks sized so that checkpoints come about every checkpointSeconds: a block takes
/// about a quarter of that (0.02 .. 2 s), measured from the previous block. Without
/// checkpoints a block is everything.
struct BlockSizer {
  explicit BlockSizer(const SweepControl& c)
      : target(c.checkpoint ? std::clamp(c.checkpointSeconds / 4, 0.02, 2.0) : 0),
        next(c.checkpoint ? 1024 : std::numeric_limits<size_t>::max()) {}
  void update(size_t hips, double seconds) {
    if (target > 0 && seconds > 0)
      next = static_cast<size_t>(std::clamp(static_cast<double>(hips) * target / seconds, 256.0, 4194304.0));
  }
  double target;
  size_t next;
};

/// The sweep's inside test of every HIP of d, per method (SF_PROBE_* bits, probe_inside.h): one
/// test of the patch surface (kept in *patchTest, for the surface faults of missed contacts),
/// one of the polygons shared by direct and shading. A method the test cannot serve (patches
/// built lazily, a name of a custom renderer) gets UNDECIDED.
std::vector<std::vector<uint32_t>> insideBits(const SweepData& d, const PatchCache& cache, bool lazy,
                                              std::unique_ptr<ProbeInsideTest>* patchTest) {
  std::vector<uint32_t> patch, polygon;
  std::vector<std::vector<uint32_t>> bits;
  for (const std::string& name : d.config.methods) {
    ForceMethod method;
    try {
      method = parseForceMethod(name);
    } catch (const InputError&) {
      bits.emplace_back(d.hips.size(), SF_PROBE_UNDECIDED);
      continue;
    }
    if (method == ForceMethod::Patch && lazy) {
      bits.emplace_back(d.hips.size(), SF_PROBE_UNDECIDED);
      continue;
    }
    std::vector<uint32_t>& v = method == ForceMethod::Patch ? patch : polygon;
    if (v.empty() && !d.hips.empty()) {
      auto test = std::make_unique<ProbeInsideTest>(cache, method);
      v = test->classify(d.hips);
      if (method == ForceMethod::Patch) *patchTest = std::move(test);
    }
    bits.push_back(v);
  }
  return bits;
}

}  // namespace

std::string methodListProblem(const std::vector<std::string>& methods) {
  if (methods.empty()) return "--methods: empty list";
  for (size_t m = 0; m < methods.size(); ++m)  // one result set per method: a repeat is a mistake
    for (size_t k = 0; k < m; ++k)
      if (methods[k] == methods[m])
        return "--methods: '" + methods[m] + "' is listed twice (items " + std::to_string(k + 1) + " and " +
               std::to_string(m + 1) + ")";
  return {};
}

static SweepData runSweepImpl(SweepInputs in, const SweepControl& control, SweepTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!in.cache) throw InputError("sweep: no patch cache");
  if (const std::string why = methodListProblem(in.config.methods); !why.empty()) throw InputError(why);
  if (control.checkpoint && !(control.checkpointSeconds > 0))
    throw InputError("--checkpoint-every: expected a time > 0 s");
  ForceOptions opt = in.config.force;
  validateForceOptions(opt);
  // A skeleton cache (sweep --mesh with --sample-on reference): every worker's patch renderer
  // builds the patches its HIPs touch, none evicted; nothing else may evaluate patches.
  const bool lazy = !hasPatchData(*in.cache);
  if (lazy && (in.config.sampleOn == "patch" || !in.hipsFile.empty() || !in.config.trajectories.empty() ||
               in.config.backend == "opencl"))
    throw InputError(
        "sweep: patches built lazily only with --sample-on reference, no --hips, no --trajectory and "
        "the CPU backend");
  if (in.config.backend == "opencl" && opt.surfaceIndex == SurfaceIndex::Bounds)
    throw InputError("sweep: --surface-index bounds only with the CPU backend (the OpenCL prober's global query runs "
                     "on the tessellation)");
  opt.patchCapacity = 0;
  // the patch method's scene and surface, where this sweep makes them: the OpenCL prober shares them
  std::shared_ptr<const PolygonScene> sharedPatchScene;
  std::shared_ptr<const PatchSurface> sharedSurface;
  if (!in.makeRenderer) {
    // one polygon scene per kind and, with the tessellation index, one patch surface, shared by every
    // worker's renderer (the bounds index keeps per-renderer cell caches: each renderer makes its own)
    auto cache = in.cache;
    auto patchScene = std::make_shared<const PolygonScene>(*cache, kPlanarTolerance);
    auto godScene = std::make_shared<const PolygonScene>(*cache, kWatertightPlanarTolerance);
    std::shared_ptr<const PatchSurface> surface;
    const bool wantSurface =
        std::find(in.config.methods.begin(), in.config.methods.end(), "patch") != in.config.methods.end();
    if (wantSurface && !lazy && opt.initialGuess == InitialGuess::Surface &&
        opt.surfaceIndex != SurfaceIndex::Bounds)  // auto: the tessellation, for a batch
      surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(opt));
    sharedPatchScene = patchScene;
    sharedSurface = surface;
    in.makeRenderer = [cache, opt, patchScene, godScene, surface](const std::string& m) {
      const ForceMethod method = parseForceMethod(m);
      return makeForceRenderer(cache, method == ForceMethod::Patch ? patchScene : godScene, method, opt, surface);
    };
  }
  if (!in.hipsFile.empty() && !in.config.trajectories.empty())
    throw OptionError(
        "sweep: --hips with --trajectory: trajectories are probed at the --depth values, and a HIP file has "
        "none; run the trajectories in a sweep with --depth");
  for (const auto& m : in.config.methods) in.makeRenderer(m);  // bad names and options fail here, once
  std::unique_ptr<ReferenceSurface> ref;
  const HipSet set = buildHipSet(in, &ref);
  // Trajectory series (trajectory, method, depth, step), spread over the shards like the HIPs;
  // the files' points are part of the configuration (a file changed under its path is another sweep).
  std::string noTrajectory;
  const std::vector<Path> paths =
      !lazy && in.hipsFile.empty() ? trajectoryPaths(in.config, *in.cache, &noTrajectory) : std::vector<Path>{};
  in.config.trajectoryHashes.clear();
  for (size_t t = 0; t < in.config.trajectories.size(); ++t)
    in.config.trajectoryHashes.push_back(
        hexHash(hashBytes(paths[t].second.data(), paths[t].second.size() * sizeof(Eigen::Vector3d))));
  if (control.note) {
    std::vector<std::string> notes{noTrajectory};
    if (!in.hipsFile.empty())
      notes.push_back(
          farPointsNote(set.groups[0].hips, *in.cache, "HIPs of " + csvDisplayName(in.hipsFile), "no contact there"));
    for (size_t t = 0; t < in.config.trajectories.size(); ++t)
      notes.push_back(farPointsNote(paths[t].second, *in.cache, "points of --trajectory " + in.config.trajectories[t],
                                    "they are projected onto the surface from there"));
    const auto& methods = in.config.methods;
    if (!lazy && std::find(methods.begin(), methods.end(), "patch") != methods.end())
      for (std::string& n : patchStatusNotes(*in.cache)) notes.push_back(std::move(n));
    for (const auto& n : notes)
      if (!n.empty()) control.note(n);
  }
  SweepData d;
  d.config = in.config;
  d.shardIndex = in.shardIndex;
  d.shardCount = in.shardCount;
  shardRange(set.size(), in.shardIndex, in.shardCount, d.begin, d.end);
  for (uint64_t g = d.begin; g < d.end; ++g) {
    d.hips.push_back(set.hip(g));
    d.normals.push_back(set.samples[g % set.perGroup()].normal);
  }
  const size_t n = d.end - d.begin, M = d.config.methods.size(), G = set.groups.size();
  std::unique_ptr<ProbeInsideTest> patchTest;
  const std::vector<std::vector<uint32_t>> probeBits = insideBits(d, *in.cache, lazy, &patchTest);
  d.results.assign(M, std::vector<HipResult>(n));
  d.trajectoryTotal = paths.size() * M * G * 2;
  shardRange(d.trajectoryTotal, in.shardIndex, in.shardCount, d.trajectoryBegin, d.trajectoryEnd);
  if (in.resume) adoptCheckpoint(*in.resume, d);

  SweepTiming tm;
  tm.setupSeconds = since(t0);
  tm.hipsRun = n;
  const std::vector<uint64_t> doneBefore = d.doneCounts();
  uint64_t pending = 0;
  for (uint64_t k : doneBefore) pending += n - k;
  if (control.started) control.started(pending, n * M);
  auto stopRequested = [&] { return control.stop && control.stop->load(); };
  auto lastCheckpoint = std::chrono::steady_clock::now();
  auto maybeCheckpoint = [&] {
    if (!control.checkpoint || since(lastCheckpoint) < control.checkpointSeconds) return;
    control.checkpoint(d);
    lastCheckpoint = std::chrono::steady_clock::now();
  };
  BlockSizer blocks(control);
  for (size_t m = 0; m < M; ++m) {
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<HipResult>& out = d.results[m];
    const std::string& method = d.config.methods[m];
    // --backend opencl: the patch method's refinements run on the device (sweep_opencl.h)
    const bool opencl = method == "patch" && in.config.backend == "opencl";
    RendererPool pool([&in, method] { return in.makeRenderer(method); });
    // set up once per sweep, before the first block that has work: the device program, the cache
    // upload and the patch surface
    std::unique_ptr<OpenCLPatchProber> prober;
    size_t computed = 0;
    for (size_t i = 0; i < n && !stopRequested();) {
      if (out[i].done) {
        ++i;
        continue;
      }
      size_t j = i;
      while (j < n && !out[j].done && j - i < blocks.next) ++j;
      const auto tb = std::chrono::steady_clock::now();
      if (opencl && !prober)
        prober = std::make_unique<OpenCLPatchProber>(in.cache, sharedPatchScene, sharedSurface, opt, in.opencl);
      const size_t got = opencl ? prober->run(set, d.begin + i, d.begin + j, ref.get(), out.data() + i, control)
                                : runProbes(set, d.begin + i, d.begin + j, pool, ref.get(), out.data() + i, control);
      computed += got;
      for (size_t k = i; k < j; ++k) {
        if (!out[k].done) continue;
        out[k].status |= probeBits[m][k];
        // a missed contact of the patch method within reach of a surface fault: a sheet that folds
        // or overlaps lies no farther from the HIP than the surface point it was pressed in from
        if (method == "patch" && patchTest && hipMissed(out[k])) {
          const double reach = (d.hips[k] - set.samples[(d.begin + k) % set.samples.size()].point).norm();
          if (patchTest->surfaceFaultDistance(d.hips[k]) <= reach) out[k].status |= SF_PROBE_ON_FAULT;
        }
      }
      blocks.update(j - i, since(tb));
      i = j;
      maybeCheckpoint();
    }
    tm.methodPatchesBuilt.push_back(lazy ? pool.patchesBuilt() : 0);
    tm.methodDone.push_back(computed);
    tm.methodSeconds.push_back(since(t1));
  }
  std::vector<uint64_t> pendingSeries;
  for (uint64_t k = d.trajectoryBegin, t = 0; k < d.trajectoryEnd; ++k) {
    while (t < d.trajectories.size() && d.trajectories[t].index < k) ++t;
    if (t == d.trajectories.size() || d.trajectories[t].index != k) pendingSeries.push_back(k);
  }
  if (!pendingSeries.empty() && !stopRequested()) {
    const auto t2 = std::chrono::steady_clock::now();
    const SweepConfig& c = d.config;
    const size_t per = M * G * 2;
    const PatchProjector projector(*in.cache, c.level);
    std::vector<std::vector<SurfaceSample>> walk(2 * paths.size());  // [2 t + half]: only those needed
    std::vector<std::vector<uint8_t>> crossings(walk.size());        // their crease crossings
    for (uint64_t k : pendingSeries) {
      const size_t t = k / per, h = k % 2;
      if (walk[2 * t + h].empty()) {
        walk[2 * t + h] = trajectorySamples(paths[t].second, h ? c.trajectoryStep / 2 : c.trajectoryStep, projector);
        crossings[2 * t + h] = creaseCrossings(walk[2 * t + h], *in.cache);
      }
    }
    std::vector<TrajectorySeries> fresh(pendingSeries.size());
    std::vector<uint8_t> ran(pendingSeries.size(), 0);
    tbb::parallel_for(size_t(0), pendingSeries.size(), [&](size_t i) {
      if (stopRequested()) return;
      const uint64_t k = pendingSeries[i];
      const size_t t = k / per, m = k % per / (G * 2), g = k % (G * 2) / 2, h = k % 2;
      TrajectorySeries& s = fresh[i];
      s.index = k;
      s.trajectory = paths[t].first;
      s.method = c.methods[m];
      s.depthLabel = set.groups[g].label;
      s.depth = set.groups[g].depth;
      s.step = h ? c.trajectoryStep / 2 : c.trajectoryStep;
      s.half = h == 1;
      auto r = in.makeRenderer(s.method);
      runTrajectory(walk[2 * t + h], s.depth, c.approach, *r, s);
      markPastMedialAxis(walk[2 * t + h], s.depth, projector, s);
      s.crease = crossings[2 * t + h];
      ran[i] = 1;
    });
    for (size_t i = 0; i < fresh.size(); ++i)
      if (ran[i]) d.trajectories.push_back(std::move(fresh[i]));
    std::sort(d.trajectories.begin(), d.trajectories.end(),
              [](const TrajectorySeries& a, const TrajectorySeries& b) { return a.index < b.index; });
    tm.trajectorySeconds = since(t2);
  }
  d.interrupted = !d.complete() && stopRequested();
  if (timing) *timing = tm;
  return d;
}

SweepData runSweep(SweepInputs in, const SweepControl& control, SweepTiming* timing) {
  if (control.threads <= 0) return runSweepImpl(std::move(in), control, timing);
  tbb::task_arena arena(control.threads);  // sampling, probes and trajectories alike
  return arena.execute([&] { return runSweepImpl(std::move(in), control, timing); });
}

}  // namespace sf
