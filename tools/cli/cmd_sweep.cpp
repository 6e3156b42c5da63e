// SPDX-License-Identifier: Apache-2.0
// `smoothforce sweep (--cache C | --mesh M) --depth D[,D...] ... -o OUTDIR` and
// `smoothforce sweep-merge DIR... -o OUTDIR`.
#include "cmd_sweep.h"

#include <tbb/info.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/sweep/sweep_option_text.h>
#include <smoothforce/sweep/sweep_run.h>
#include "cli_common.h"
#include "cli_exit.h"
#include "sweep_progress.h"
#include "sweep_report.h"

namespace sf::cli {

namespace {

struct SweepArgs {
  std::string cache, mesh, depth, methods = "patch,direct,shading", reference, analytic;
  std::string sampleOn = "patch", hips, shard = "0/1", output, trajectoryStep, seed = "1";
  std::vector<std::string> trajectories;
  uint64_t samples = 10000;
  double stiffness = 500, thresholdDeg = 10, approach = 1e-3;
  int knn = 8, level = 8;
  double checkpointEvery = 60, progressEvery = 10;
  bool noPlots = false, resume = false;
  PatchArgs patch;
  RefineArgs refine;
};

/// The comma-separated items of option `option`'s value s; throws UsageError for an empty item
/// (an empty value, a leading, trailing or doubled comma).
std::vector<std::string> splitList(const std::string& s, const char* option) {
  std::vector<std::string> v;
  for (size_t at = 0;;) {
    const size_t comma = s.find(',', at);
    v.push_back(s.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
    if (v.back().empty()) throw UsageError(std::string(option) + ": an empty item in '" + s + "'");
    if (comma == std::string::npos) return v;
    at = comma + 1;
  }
}

/// optionCheck of a sweep option (sweep_option_text.h), by key.
CLI::Validator sweepOptionCheck(const char* key) {
  return optionCheck(key, [key](const std::string& value) {
    SweepConfig scratch;
    setSweepOption(scratch, key, value, OptionSpelling::Flag);
  });
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Fills the inputs from the options; every mistake here is a usage error (exit 2).
void sweepInputs(const SweepArgs& a, SweepInputs& in) {
  if (a.cache.empty() == a.mesh.empty()) throw UsageError("sweep: give exactly one of --cache and --mesh");
  if (a.depth.empty() == a.hips.empty()) throw UsageError("sweep: give exactly one of --depth and --hips");
  SweepConfig& c = in.config;
  c.source = a.cache.empty() ? a.mesh : a.cache;
  c.methods = splitList(a.methods, "--methods");
  if (const std::string why = methodListProblem(c.methods); !why.empty()) throw UsageError(why);
  for (const auto& m : c.methods) parseForceMethod(m);
  // the sweep's options through the shared reader (sweep_option_text.h), by flag
  setSweepOption(c, "samples", static_cast<double>(a.samples), OptionSpelling::Flag);
  setSweepOption(c, "seed", a.seed, OptionSpelling::Flag);
  setSweepOption(c, "level", a.level, OptionSpelling::Flag);
  setSweepOption(c, "approach", a.approach, OptionSpelling::Flag);
  ForceOptions fo;
  a.refine.apply(fo);
  fo.stiffness = a.stiffness;
  validateForceOptions(fo);
  c.force = fo;
  c.preset = a.refine.preset;
  c.backend = a.patch.backend;
  c.reference = a.reference;
  c.analytic = a.analytic;
  if (!c.analytic.empty()) makeAnalyticSurface(c.analytic);  // the spec's errors now
  setSweepOption(c, "knn", a.knn, OptionSpelling::Flag);
  setSweepOption(c, "threshold_deg", a.thresholdDeg, OptionSpelling::Flag);
  c.trajectories = a.trajectories;
  setSweepOption(c, "sample_on", a.sampleOn, OptionSpelling::Flag);
  parseShard(a.shard, in.shardIndex, in.shardCount);
  if (!a.hips.empty() && (!a.trajectories.empty() || !a.trajectoryStep.empty()))
    throw UsageError(std::string("sweep: --hips with ") +
                     (a.trajectories.empty() ? "--trajectory-step" : "--trajectory") +
                     ": trajectories are probed at the --depth values, and a HIP file has none; run the trajectories "
                     "in a sweep with --depth");
  if (!a.depth.empty()) in.depths = parseDepthList(a.depth);
  if (!a.trajectoryStep.empty() && parseDepthList(a.trajectoryStep, "--trajectory-step").size() != 1)
    throw UsageError("--trajectory-step: one value");
  if (!(a.checkpointEvery > 0)) throw UsageError("--checkpoint-every: expected a time > 0 s");
  if (!(a.progressEvery >= 0) || !std::isfinite(a.progressEvery))
    throw UsageError("--progress-every: expected a time >= 0 s (0: none)");
  in.hipsFile = a.hips;
}

std::string doneText(const SweepData& d) {
  std::string s;
  const std::vector<uint64_t> done = d.doneCounts();
  for (size_t m = 0; m < done.size(); ++m)
    s += (s.empty() ? "" : ", ") + d.config.methods[m] + " " + std::to_string(done[m]) + " of " +
         std::to_string(d.end - d.begin) + " HIPs";
  return s + ", trajectory series " + std::to_string(d.trajectories.size()) + " of " +
         std::to_string(d.trajectoryEnd - d.trajectoryBegin);
}

void runSweepCommand(const SweepArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  SweepInputs in;
  checkOptions([&] { sweepInputs(a, in); });
  SweepConfig& c = in.config;
  if (!a.mesh.empty() && isPatchCacheFile(a.mesh)) throw InputError(a.mesh + ": this is a patch cache: use --cache");
  if (!a.cache.empty() && !isPatchCacheFile(a.cache)) throw InputError(a.cache + ": not a patch cache: use --mesh");
  namespace fs = std::filesystem;
  const std::string checkpoint = a.output + "/sweep.json";
  if (a.resume && fs::exists(checkpoint)) {
    in.resume = readSweepData(a.output);
    std::fprintf(stderr, "sweep: resuming %s: %s done%s\n", in.resume->label().c_str(), doneText(*in.resume).c_str(),
                 in.resume->complete() ? " (complete)" : "");
  } else if (a.resume) {
    std::fprintf(stderr, "sweep: --resume: no checkpoint in %s yet: starting\n", a.output.c_str());
  }
  PatchArgs patch = a.patch;
  patch.precision = toString(a.refine.precision(parsePrecision(a.patch.precision)));
  // Only the patches the probes touch are built when nothing else needs the patch surface:
  // HIPs sampled on the reference mesh, no HIP file or trajectory to project onto the patches.
  const bool lazy = !a.mesh.empty() && c.sampleOn == "reference" && a.hips.empty() && a.trajectories.empty() &&
                    a.patch.backendKind() != Backend::OpenCL;
  Source src = openSource(c.source, patch, lazy);
  if (lazy)
    std::fprintf(stderr,
                 "sweep: patches of %s built lazily where the probes go (HIPs on the reference mesh; the default "
                 "trajectory needs every patch and is skipped: give --cache or --trajectory for it)\n",
                 a.mesh.c_str());
  else if (src.loaded)
    std::fprintf(stderr,
                 "sweep: built all %d patches of %s in %.2f s (%s backend; the HIPs are placed on or projected onto "
                 "the patch surface, which needs every patch)\n",
                 src.cache.numFaces(), a.mesh.c_str(), src.buildSeconds, a.patch.backend.c_str());
  if (a.patch.backendKind() == Backend::OpenCL)
    std::fprintf(stderr,
                 "sweep: --backend opencl: patch construction (with --mesh) and the patch method's refinements on the "
                 "OpenCL device; global queries, contact decisions, god-objects and trajectories on the CPU "
                 "(oneTBB)\n");
  in.opencl.device = a.patch.clDevice;
  in.cache = std::make_shared<const PatchCache>(std::move(src.cache));
  if (!a.trajectoryStep.empty())
    c.trajectoryStep = parseDepthList(a.trajectoryStep, "--trajectory-step")[0].metres(boundingDiagonal(*in.cache));
  const int threads = a.patch.backendKind() == Backend::Serial ? 1 : a.patch.threads;

  SweepWriter writer(a.output);
  std::unique_ptr<ProgressBar> bar;
  SweepControl ctl;
  ctl.threads = threads;
  ctl.stop = &stopFlag();
  ctl.started = [&](uint64_t pending, uint64_t) {
    bar = std::make_unique<ProgressBar>(pending, "probe", a.progressEvery);
  };
  ctl.progress = [&](size_t n) {
    if (bar) bar->add(n);
  };
  ctl.checkpoint = [&](const SweepData& d) { writer.write(d); };
  ctl.checkpointSeconds = a.checkpointEvery;
  ctl.note = [](const std::string& n) { std::fprintf(stderr, "%s\n", n.c_str()); };
  SweepTiming tm;
  const int meshFaces = in.cache->numFaces();
  SweepData d = runSweep(std::move(in), ctl, &tm);  // an OptionError: exit 2 (main)
  if (bar) bar->finish();
  writer.write(d);  // the final checkpoint, complete or not
  if (d.interrupted)
    throwIfInterrupted("sweep", doneText(d) + " done, saved in " + a.output + " (continue with sweep --resume)");

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
      std::printf(
          "sweep: patch    %ld patch constructions (each worker builds the patches its HIPs touch), %d "
          "faces in the mesh\n",
          tm.methodPatchesBuilt[m], meshFaces);
  }
  if (d.shardCount > 1) {
    std::ofstream(a.output + "/timing.json") << tj.dump(2) << "\n";
    std::printf(
        "sweep: shard %d/%d (HIPs %llu..%llu of %llu, trajectory series %llu..%llu of %llu) -> %s; join the "
        "shards with smoothforce sweep-merge\n",
        d.shardIndex, d.shardCount, static_cast<unsigned long long>(d.begin), static_cast<unsigned long long>(d.end),
        static_cast<unsigned long long>(d.total()), static_cast<unsigned long long>(d.trajectoryBegin),
        static_cast<unsigned long long>(d.trajectoryEnd), static_cast<unsigned long long>(d.trajectoryTotal),
        a.output.c_str());
    return;
  }
  throwIfInterrupted("sweep", "the per-HIP data in " + a.output +
                                  " is complete; the summary was not written (sweep --resume writes it)");
  const auto t1 = std::chrono::steady_clock::now();
  finishSweepOutputs(d, a.output, !a.noPlots);
  tj["summary_s"] = seconds(t1);
  tj["wall_s"] = seconds(t0);
  std::ofstream(a.output + "/timing.json") << tj.dump(2) << "\n";
  std::printf("sweep: wall time %.2f s\n", seconds(t0));
}

/// Refuses, before any work, an input listed twice and an output directory that is one of the
/// inputs (its files would be overwritten while read): usage errors.
void checkMergeDirectories(const std::vector<std::string>& dirs, const std::string& out) {
  namespace fs = std::filesystem;
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    return a == b || fs::equivalent(a, b, ec);
  };
  for (size_t i = 0; i < dirs.size(); ++i) {
    if (same(out, dirs[i]))
      throw UsageError("sweep-merge: the output directory " + out + " is the input shard " + dirs[i] + " (item " +
                       std::to_string(i + 1) + "): its files would be overwritten; give another -o");
    for (size_t k = 0; k < i; ++k)
      if (same(dirs[k], dirs[i]))
        throw UsageError("sweep-merge: the shard " + dirs[i] + " is listed twice (items " + std::to_string(k + 1) +
                         " and " + std::to_string(i + 1) + ")");
  }
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
  s->add_option("--hips", a->hips,
                "CSV with header x,y,z (or # x,y,z): explicit HIPs instead of --depth; - reads stdin");
  s->add_option("--samples", a->samples, "surface samples per depth")
      ->check(sweepOptionCheck("samples"))
      ->capture_default_str();
  s->add_option("--methods", a->methods, "comma-separated: patch, direct, shading")->capture_default_str();
  s->add_option("--seed", a->seed, "sampling seed (std::mt19937_64), an integer in [0, 2^64 - 1]")
      ->check(sweepOptionCheck("seed"))
      ->capture_default_str();
  s->add_option("--stiffness", a->stiffness, "N/m, in (0, 1e12]")
      ->check(forceOptionCheck("stiffness"))
      ->capture_default_str();
  s->add_option("--approach", a->approach, "probes first step at p + APPROACH * depth * n (outside), then at the HIP")
      ->check(sweepOptionCheck("approach"))
      ->capture_default_str();
  s->add_option("--level", a->level, "tessellation level for sampling and projection")
      ->check(sweepOptionCheck("level"))
      ->capture_default_str();
  s->add_option(
      "--trajectory", a->trajectories,
      "x,y,z CSV polylines on the surface (default: the surface's section by a plane through its box's centre)");
  s->add_option("--trajectory-step", a->trajectoryStep, "resampling step: metres or percent (default 0.25%)");
  s->add_option("--reference", a->reference, "dense reference mesh: SCP accuracy (and --sample-on reference)");
  s->add_option("--sample-on", a->sampleOn, "patch|reference: where surface samples are drawn")
      ->check(sweepOptionCheck("sample_on"))
      ->capture_default_str();
  s->add_option("--analytic", a->analytic, "exact surface: sphere:R, torus:R,r or torus-knot:p,q,R,r,tube[,scale]");
  s->add_option("--knn", a->knn, "neighbours per HIP for the discontinuity metric")
      ->check(sweepOptionCheck("knn"))
      ->capture_default_str();
  s->add_option("--threshold-deg", a->thresholdDeg, "flag neighbour pairs above this angle, in (0, 180]")
      ->check(sweepOptionCheck("threshold_deg"))
      ->capture_default_str();
  s->add_option("--shard", a->shard,
                "I/N: compute slice I (0-based) of N of the HIP list and of the trajectory series (join with "
                "sweep-merge)")
      ->capture_default_str();
  s->add_flag("--resume", a->resume,
              "continue from the checkpoint in the output directory (the same options; without a checkpoint: "
              "start)");
  s->add_option("--checkpoint-every", a->checkpointEvery,
                "seconds between checkpoints of the per-HIP files (atomic; a killed run loses at most this much)")
      ->capture_default_str();
  s->add_option("--progress-every", a->progressEvery,
                "seconds between progress lines on stderr when it is not a terminal (0: none)")
      ->capture_default_str();
  s->add_flag("--no-plots", a->noPlots, "do not run tools/sweep_plots.py");
  s->add_option("-o,--output", a->output, "output directory")->required();
  addPatchArgs(*s, a->patch);
  addRefineArgs(*s, a->refine);
  s->footer(
      "--backend tbb|serial|opencl: opencl builds the patches and runs the patch method's refinements and (with "
      "cl_khr_fp64) its global queries' candidate searches on the OpenCL device, half a chunk of HIPs per kernel run, "
      "while the CPU runs the rest of the other half's steps with oneTBB; god-objects and trajectories run on the "
      "CPU.\nSIGINT (Ctrl-C) and SIGTERM (Slurm's time limit, scancel) stop at the "
      "next chunk: the HIPs done are saved as a checkpoint and the exit status is 130 or 143; --resume continues. "
      "See docs/sweeps.md; tools/slurm/ has job-array scripts.");
  s->callback([a] { runSweepCommand(*a); });

  auto* m = app.add_subcommand("sweep-merge", "Join sweep shards (--shard I/N outputs) into the whole run");
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto noPlots = std::make_shared<bool>(false);
  m->add_option("DIRS", *dirs, "shard output directories")->required();
  m->add_option("-o,--output", *out, "output directory")->required();
  m->add_flag("--no-plots", *noPlots, "do not run tools/sweep_plots.py");
  m->callback([=] {
    checkMergeDirectories(*dirs, *out);
    std::vector<SweepData> shards;
    throwIfInterrupted("sweep-merge");
    for (const auto& d : *dirs) shards.push_back(readSweepData(d));
    const SweepConfig& c = shards[0].config;  // shards that differ in this are refused by the merge
    if ((!c.trajectories.empty() && c.trajectoryHashes.empty()) || (!c.reference.empty() && c.referenceHash.empty()))
      std::fprintf(stderr,
                   "sweep-merge: note: the shards were written before sweeps recorded the contents of their "
                   "--trajectory and --reference files: that those did not change between the shards is not "
                   "checked\n");
    const SweepData merged = mergeSweepData(std::move(shards));
    throwIfInterrupted("sweep-merge");
    writeSweepData(merged, *out);
    std::printf("sweep-merge: %zu shards, %llu HIPs -> %s\n", dirs->size(),
                static_cast<unsigned long long>(merged.total()), out->c_str());
    finishSweepOutputs(merged, *out, !*noPlots);
  });
}

}  // namespace sf::cli
