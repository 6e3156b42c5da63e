// `smoothforce sweep (--cache C | --mesh M) --depth D[,D...] ... -o OUTDIR` and
// `smoothforce sweep-merge DIR... -o OUTDIR`.
#include "cmd_sweep.h"

#include <tbb/info.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/sweep/sweep_run.h>
#include "cli_common.h"
#include "sweep_progress.h"
#include "sweep_report.h"

namespace sf::cli {

namespace {

std::atomic<bool> gStop{false};
extern "C" void onSigint(int) { gStop.store(true); }  // SA_RESETHAND: a second Ctrl-C kills

struct SigintGuard {
  struct sigaction old {};
  SigintGuard() {
    gStop.store(false);
    struct sigaction sa {};
    sa.sa_handler = onSigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old);
  }
  ~SigintGuard() { sigaction(SIGINT, &old, nullptr); }
};

struct SweepArgs {
  std::string cache, mesh, depth, methods = "patch,direct,shading", reference, analytic;
  std::string sampleOn = "patch", hips, shard = "0/1", output, trajectoryStep;
  std::vector<std::string> trajectories;
  uint64_t samples = 10000, seed = 1;
  double stiffness = 500, thresholdDeg = 10, approach = 1e-3;
  int knn = 8, level = 8;
  bool noPlots = false;
  PatchArgs patch;
  RefineArgs refine;
};

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) v.push_back(item);
  return v;
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void runSweepCommand(const SweepArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.cache.empty() == a.mesh.empty()) throw InputError("sweep: give exactly one of --cache and --mesh");
  if (a.depth.empty() == a.hips.empty()) throw InputError("sweep: give exactly one of --depth and --hips");
  SweepInputs in;
  SweepConfig& c = in.config;
  c.source = a.cache.empty() ? a.mesh : a.cache;
  c.methods = splitList(a.methods);
  for (const auto& m : c.methods) parseForceMethod(m);
  c.samples = a.samples;
  c.seed = a.seed;
  c.level = a.level;
  c.stiffness = a.stiffness;
  c.approach = a.approach;
  ForceOptions fo;
  a.refine.apply(fo);
  validateForceOptions(fo);
  c.refine = toString(fo.refine);
  c.angleTolerance = fo.angleTolerance;
  c.maxIterations = fo.maxIterations;
  c.initialGuess = toString(fo.initialGuess);
  c.guessLevel = fo.tessellationLevel;
  c.preset = a.refine.preset;
  c.backend = a.patch.backend;
  c.reference = a.reference;
  c.analytic = a.analytic;
  c.knn = a.knn;
  c.thresholdDeg = a.thresholdDeg;
  c.trajectories = a.trajectories;
  c.sampleOn = a.sampleOn;
  parseShard(a.shard, in.shardIndex, in.shardCount);
  if (!a.depth.empty()) in.depths = parseDepthList(a.depth);
  in.hipsFile = a.hips;

  if (!a.mesh.empty() && isPatchCacheFile(a.mesh)) throw InputError(a.mesh + ": this is a patch cache: use --cache");
  if (!a.cache.empty() && !isPatchCacheFile(a.cache)) throw InputError(a.cache + ": not a patch cache: use --mesh");
  PatchArgs patch = a.patch;
  patch.precision = toString(a.refine.precision(parsePrecision(a.patch.precision)));
  // Only the patches the probes touch are built when nothing else needs the patch surface:
  // HIPs sampled on the reference mesh, no HIP file or trajectory to project onto the patches.
  const bool lazy = !a.mesh.empty() && c.sampleOn == "reference" && a.hips.empty() && a.trajectories.empty() &&
                    a.patch.backendKind() != Backend::OpenCL;
  Source src = openSource(c.source, patch, lazy);
  if (lazy)
    std::printf(
        "sweep: patches of %s built lazily where the probes go (HIPs on the reference mesh; the default "
        "trajectory needs every patch and is skipped: give --cache or --trajectory for it)\n",
        a.mesh.c_str());
  else if (src.loaded)
    std::printf(
        "sweep: built all %d patches of %s in %.2f s (%s backend; the HIPs are placed on or projected onto "
        "the patch surface, which needs every patch)\n",
        src.cache.numFaces(), a.mesh.c_str(), src.buildSeconds, a.patch.backend.c_str());
  if (a.patch.backendKind() == Backend::OpenCL)
    std::printf(
        "sweep: --backend opencl: patch construction (with --mesh) and the patch method's refinements on the "
        "OpenCL device; global queries, contact decisions, god-objects and trajectories on the CPU (oneTBB)\n");
  in.opencl.device = a.patch.device;
  in.cache = std::make_shared<const PatchCache>(std::move(src.cache));
  if (!a.trajectoryStep.empty()) {
    const auto s = parseDepthList(a.trajectoryStep);
    if (s.size() != 1) throw InputError("--trajectory-step: one value");
    c.trajectoryStep = s[0].metres(boundingDiagonal(*in.cache));
  }
  const int threads = a.patch.backendKind() == Backend::Serial ? 1 : a.patch.threads;

  // The HIP count is known only after sampling; the bar is created on the first report.
  SigintGuard sigint;
  std::unique_ptr<ProgressBar> bar;
  std::once_flag barOnce;
  uint64_t total = 0;
  {
    uint64_t b = 0, e = 0;
    const uint64_t perGroup = a.hips.empty() ? a.samples : readPointsCsv(a.hips).size();
    shardRange(perGroup * (a.hips.empty() ? in.depths.size() : 1), in.shardIndex, in.shardCount, b, e);
    total = (e - b) * c.methods.size();
  }
  SweepControl ctl;
  ctl.threads = threads;
  ctl.stop = &gStop;
  ctl.progress = [&](size_t n) {
    std::call_once(barOnce, [&] { bar = std::make_unique<ProgressBar>(total, "HIP"); });
    if (total) bar->add(n);
  };
  SweepTiming tm;
  const int meshFaces = in.cache->numFaces();
  SweepData d = runSweep(std::move(in), ctl, &tm);
  if (bar) bar->finish();
  if (d.interrupted) std::fprintf(stderr, "sweep: interrupted; writing the HIPs done so far (marked partial)\n");

  writeSweepData(d, a.output);
  nlohmann::ordered_json tj{{"wall_s", seconds(t0)},
                            {"setup_s", tm.setupSeconds},
                            {"trajectory_s", tm.trajectorySeconds},
                            {"threads", threads > 0 ? threads : tbb::info::default_concurrency()},
                            {"shard", a.shard},
                            {"hips_per_method", tm.hipsRun},
                            {"methods", nlohmann::ordered_json::object()}};
  for (size_t m = 0; m < d.config.methods.size(); ++m) {
    const double s = tm.methodSeconds[m], n = static_cast<double>(tm.methodDone[m]);
    tj["methods"][d.config.methods[m]] = {
        {"seconds", s}, {"hips", tm.methodDone[m]}, {"hips_per_s", s > 0 ? n / s : 0.0}};
    std::printf("sweep: %-8s %llu HIPs in %.2f s (%.4g HIPs/s)\n", d.config.methods[m].c_str(),
                static_cast<unsigned long long>(tm.methodDone[m]), s, s > 0 ? n / s : 0.0);
    if (lazy && d.config.methods[m] == "patch")
      std::printf("sweep: patch    %ld patch constructions (each worker builds the patches its HIPs touch), %d "
                  "faces in the mesh\n",
                  tm.methodPatchesBuilt[m], meshFaces);
  }
  if (d.shardCount > 1) {
    std::ofstream(a.output + "/timing.json") << tj.dump(2) << "\n";
    std::printf("sweep: shard %d/%d (HIPs %llu..%llu of %llu) -> %s; join the shards with smoothforce sweep-merge\n",
                d.shardIndex, d.shardCount, static_cast<unsigned long long>(d.begin),
                static_cast<unsigned long long>(d.end), static_cast<unsigned long long>(d.total()), a.output.c_str());
    return;
  }
  const auto t1 = std::chrono::steady_clock::now();
  finishSweepOutputs(d, a.output, !a.noPlots);
  tj["summary_s"] = seconds(t1);
  tj["wall_s"] = seconds(t0);
  std::ofstream(a.output + "/timing.json") << tj.dump(2) << "\n";
  std::printf("sweep: wall time %.2f s\n", seconds(t0));
}

}  // namespace

void addSweepCommands(CLI::App& app) {
  auto* s = app.add_subcommand("sweep",
                               "Offset-surface force sweep: probe every method at HIPs pressed into the "
                               "surface, measure force-direction discontinuity and accuracy");
  auto a = std::make_shared<SweepArgs>();
  s->add_option("--cache", a->cache, "patch cache file");
  s->add_option("--mesh", a->mesh, "mesh file (all patches are built first)");
  s->add_option("--depth", a->depth,
                "depths below the surface: metres or percent of the bounding-box diagonal, "
                "comma-separated (0.002,0.004 or 2%,4%)");
  s->add_option("--hips", a->hips, "CSV with header x,y,z: explicit HIPs instead of --depth");
  s->add_option("--samples", a->samples, "surface samples per depth")
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 32))
      ->capture_default_str();
  s->add_option("--methods", a->methods, "comma-separated: patch, direct, shading")->capture_default_str();
  s->add_option("--seed", a->seed, "sampling seed (std::mt19937_64)")->capture_default_str();
  s->add_option("--stiffness", a->stiffness, "N/m")->capture_default_str();
  s->add_option("--approach", a->approach, "probes first step at p + APPROACH * depth * n (outside), then at the HIP")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  s->add_option("--level", a->level, "tessellation level for sampling and projection")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  s->add_option("--trajectory", a->trajectories, "x,y,z CSV polylines on the surface (default: a section loop)");
  s->add_option("--trajectory-step", a->trajectoryStep, "resampling step: metres or percent (default 0.25%)");
  s->add_option("--reference", a->reference, "dense reference mesh: SCP accuracy (and --sample-on reference)");
  s->add_option("--sample-on", a->sampleOn, "patch|reference: where surface samples are drawn")
      ->check(CLI::IsMember({"patch", "reference"}))
      ->capture_default_str();
  s->add_option("--analytic", a->analytic, "exact surface: sphere:R, torus:R,r or torus-knot:p,q,R,r,tube[,scale]");
  s->add_option("--knn", a->knn, "neighbours per HIP for the discontinuity metric")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  s->add_option("--threshold-deg", a->thresholdDeg, "flag neighbour pairs above this angle")->capture_default_str();
  s->add_option("--shard", a->shard, "I/N: compute slice I of N of the HIP list (join with sweep-merge)")
      ->capture_default_str();
  s->add_flag("--no-plots", a->noPlots, "do not run tools/sweep_plots.py");
  s->add_option("-o,--output", a->output, "output directory")->required();
  addPatchArgs(*s, a->patch);
  addRefineArgs(*s, a->refine);
  s->footer(
      "--backend tbb|serial|opencl: opencl builds the patches and runs the patch method's refinements (--refine "
      "newton) on the OpenCL device, a chunk of HIPs per kernel run; the global queries, god-objects and "
      "trajectories run on the CPU with oneTBB.\nCtrl-C stops cleanly: the HIPs done are written and "
      "summary.json says \"complete\": false. See docs/sweeps.md.");
  s->callback([a] { runSweepCommand(*a); });

  auto* m = app.add_subcommand("sweep-merge", "Join sweep shards (--shard I/N outputs) into the whole run");
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto noPlots = std::make_shared<bool>(false);
  m->add_option("DIRS", *dirs, "shard output directories")->required();
  m->add_option("-o,--output", *out, "output directory")->required();
  m->add_flag("--no-plots", *noPlots, "do not run tools/sweep_plots.py");
  m->callback([=] {
    std::vector<SweepData> shards;
    for (const auto& d : *dirs) shards.push_back(readSweepData(d));
    const SweepData merged = mergeSweepData(std::move(shards));
    writeSweepData(merged, *out);
    std::printf("sweep-merge: %zu shards, %llu HIPs -> %s\n", dirs->size(),
                static_cast<unsigned long long>(merged.total()), out->c_str());
    finishSweepOutputs(merged, *out, !*noPlots);
  });
}

}  // namespace sf::cli
