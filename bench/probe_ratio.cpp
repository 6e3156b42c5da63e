// SPDX-License-Identifier: Apache-2.0
// Issue 11's yardstick in one run: sweep probes (runProbes: reset, a step just outside, the step
// at the HIP) of the patch method on the spot cage against direct rendering (the god-object) of
// the dense spot meshes, HIPs pressed in by --depth (fraction of the diagonal) at points of each
// mesh's own patch surface, as `smoothforce sweep` places them. The methods alternate within
// every round, so a VM whose speed drifts slows them alike; each round times each method once
// (renderers made and warmed up before, as the sweep's shared surface and scenes are); prints the
// rates per round, their medians and the ratios of the medians.
//   build/bench/probe_ratio [--samples 100000] [--depth 0.005] [--rounds 5] [--threads 2]
//                           [--only patch|direct]   (one kind of case, e.g. under perf record)
//                           [--final-step evaluated|model|both]   (the patch method's; both: two cases)
//                           [--search on]   (also the spot cage under --fold-repair search: normal_search.h)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/normal_search.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep.h>
#include <smoothforce/sweep/sweep_sampling.h>

namespace {

using namespace sf;

struct Case {
  std::string label, path;
  ForceMethod method = ForceMethod::Patch;
  ForceOptions opt;  ///< the patch method's finalStep differs between the patch cases
  bool search = false;  ///< the cache under FoldRepairMode::Search
  std::shared_ptr<const PatchCache> cache;
  HipSet hips;
  std::unique_ptr<RendererPool> pool;
  std::vector<double> rates;  ///< HIPs/s per round
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace

int main(int argc, char** argv) {
  int samples = 100000, rounds = 5, threads = 2;
  double depth = 0.005;
  std::string only, finalStep = "evaluated";
  bool search = false;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf(
          "usage: probe_ratio [--samples 100000] [--depth 0.005] [--rounds 5] [--threads 2] [--only patch|direct] "
          "[--final-step evaluated|model|both] [--search on|off]\n");
      return 0;
    }
    if (i + 1 == argc) {
      std::fprintf(stderr, "probe_ratio: %s needs a value (--help)\n", a.c_str());
      return 2;
    }
    if (a == "--samples")
      samples = std::atoi(argv[i + 1]);
    else if (a == "--depth")
      depth = std::atof(argv[i + 1]);
    else if (a == "--rounds")
      rounds = std::atoi(argv[i + 1]);
    else if (a == "--threads")
      threads = std::atoi(argv[i + 1]);
    else if (a == "--only")
      only = argv[i + 1];
    else if (a == "--final-step")
      finalStep = argv[i + 1];
    else if (a == "--search")
      search = std::string(argv[i + 1]) == "on";
    else {
      std::fprintf(stderr, "probe_ratio: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (samples < 1 || rounds < 1 || threads < 1 || !(depth > 0 && depth < 0.5) ||
      !(only.empty() || only == "patch" || only == "direct") ||
      !(finalStep == "evaluated" || finalStep == "model" || finalStep == "both")) {
    std::fprintf(stderr,
                 "probe_ratio: --samples, --rounds, --threads must be >= 1, --depth in (0, 0.5), --only patch or "
                 "direct, --final-step evaluated, model or both\n");
    return 2;
  }
  const std::string shared = SF_SHARED_MESHES;
  const std::string cage = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";
  std::vector<Case> cases;
  auto add = [&](const char* label, const std::string& path, ForceMethod method, FinalStep step = FinalStep::Evaluated) {
    if (!only.empty() && (only == "patch") != (method == ForceMethod::Patch)) return;
    cases.emplace_back();
    cases.back().label = label;
    cases.back().path = path;
    cases.back().method = method;
    cases.back().opt.finalStep = step;
  };
  if (finalStep != "model") add("patch, spot cage", cage, ForceMethod::Patch);
  if (search && finalStep != "model") {
    add("patch, spot cage, fold repair search", cage, ForceMethod::Patch);
    if (!cases.empty() && cases.back().label.find("search") != std::string::npos) cases.back().search = true;
  }
  if (finalStep != "evaluated") add("patch (model), spot cage", cage, ForceMethod::Patch, FinalStep::Model);
  add("direct, spot.obj", shared + "/odedstein/spot.obj", ForceMethod::Direct);
  add("direct, spot_triangulated", shared + "/keenan_crane/spot_triangulated.obj", ForceMethod::Direct);
  add("direct, spot cage", cage, ForceMethod::Direct);
  SweepControl control;
  control.threads = threads;
  for (auto it = cases.begin(); it != cases.end();) {
    if (!std::filesystem::exists(it->path)) {
      std::printf("%s: %s not found, left out\n", it->label.c_str(), it->path.c_str());
      it = cases.erase(it);
      continue;
    }
    PatchOptions po;
    if (it->search) po.foldRepair = FoldRepairMode::Search;
    PatchCache built = buildPatchCache(loadMesh(it->path, po), po, Backend::Tbb);
    finishFoldRepair(built);
    it->cache = std::make_shared<const PatchCache>(std::move(built));
    const PatchSurfaceSampler sampler(*it->cache);
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.6g%%", 100 * depth);
    it->hips = makeDepthHips(sampler.sample(static_cast<size_t>(samples), 1), parseDepthList(pct),
                             boundingDiagonal(*it->cache), sampler.area());
    // one polygon scene and (patch) one patch surface shared by every worker's renderer
    auto scene = std::make_shared<const PolygonScene>(*it->cache);
    std::shared_ptr<const PatchSurface> surface;
    const ForceOptions opt = it->opt;
    if (it->method == ForceMethod::Patch)
      surface = std::make_shared<const PatchSurface>(*it->cache, patchSurfaceOptions(opt));
    const auto cache = it->cache;
    const ForceMethod method = it->method;
    it->pool = std::make_unique<RendererPool>(
        [cache, scene, surface, method, opt] { return makeForceRenderer(cache, scene, method, opt, surface); });
    std::vector<HipResult> out(it->hips.size());
    runProbes(it->hips, 0, std::min<size_t>(it->hips.size(), 4000), *it->pool, nullptr, out.data(), control);
    ++it;
  }
  std::printf("%d HIPs per mesh at %.3g of the diagonal, %d threads, %d rounds (the methods alternate)\n", samples,
              depth, threads, rounds);
  for (int r = 0; r < rounds; ++r)
    for (Case& c : cases) {
      std::vector<HipResult> out(c.hips.size());
      const auto t0 = std::chrono::steady_clock::now();
      runProbes(c.hips, 0, c.hips.size(), *c.pool, nullptr, out.data(), control);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      c.rates.push_back(double(c.hips.size()) / s);
    }
  for (const Case& c : cases) {
    std::printf("%-26s %6d faces  HIPs/s:", c.label.c_str(), c.cache->numFaces());
    for (double x : c.rates) std::printf(" %.3g", x);
    std::printf("  median %.3g\n", median(c.rates));
  }
  for (const Case& p : cases)
    if (p.method == ForceMethod::Patch)
      for (const Case& d : cases)
        if (d.method != ForceMethod::Patch)
          std::printf("%s / %s: %.3g (medians)\n", p.label.c_str(), d.label.c_str(), median(p.rates) / median(d.rates));
  return 0;
}
