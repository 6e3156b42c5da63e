// SPDX-License-Identifier: Apache-2.0
// `smoothforce trace (--cache C | --mesh M) --method M --hips IN.csv -o OUT.csv`
#include "cmd_trace.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <smoothforce/base/csv_reader.h>
#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/query/embree_scene.h>
#include "cli_common.h"
#include "cli_exit.h"
#include "cli_output.h"

namespace sf::cli {
namespace {

struct TraceArgs {
  std::string cache, mesh, method = "patch", hips, output;
  double stiffness = ForceOptions{}.stiffness;
  int patchCapacity = 256;
  PatchArgs patch;
  RefineArgs refine;
  bool json = false;
};

/// Reads the `x,y,z` rows of `path` ("-": stdin) with the one CSV reader (csv_reader.h).
std::vector<Eigen::Vector3d> readHips(const std::string& path) {
  const NumericCsv t = readNumericCsv(path, {"x", "y", "z"});
  requirePositions(t, path);
  std::vector<Eigen::Vector3d> hips(t.rows());
  for (size_t r = 0; r < t.rows(); ++r) hips[r] = Eigen::Vector3d(t.at(r, 0), t.at(r, 1), t.at(r, 2));
  return hips;
}

void run(const TraceArgs& a) {
  ForceOptions opt;
  ForceMethod method{};
  checkOptions([&] {
    if (a.cache.empty() == a.mesh.empty()) throw UsageError("trace: give exactly one of --cache and --mesh");
    opt.stiffness = a.stiffness;
    a.refine.apply(opt);
    opt.patchCapacity = a.patchCapacity;
    method = parseForceMethod(a.method);
    validateForceOptions(opt);
  });
  const std::string& input = a.cache.empty() ? a.mesh : a.cache;
  if (!a.cache.empty() && !isPatchCacheFile(a.cache)) throw InputError(a.cache + ": not a patch cache file");
  if (!a.mesh.empty() && isPatchCacheFile(a.mesh)) throw InputError(a.mesh + ": is a patch cache; use --cache");
  const std::vector<Eigen::Vector3d> hips = readHips(a.hips);
  PatchArgs patch = a.patch;
  patch.precision = toString(a.refine.precision(parsePrecision(a.patch.precision)));
  Source src = openSource(input, patch, /*lazy=*/true);  // a mesh: patches built where the HIPs go
  auto cache = std::make_shared<const PatchCache>(std::move(src.cache));
  auto scene = std::make_shared<const PolygonScene>(*cache);
  auto renderer = makeForceRenderer(cache, scene, method, opt);
  TextOutput file(a.output);  // opened first: an unwritable path fails before the work

  std::vector<ForceSample> out(hips.size());
  std::vector<double> stepSeconds(hips.size());
  const std::atomic<bool>& stop = stopFlag();
  for (size_t i = 0; i < hips.size(); ++i) {
    if (stop.load(std::memory_order_relaxed))
      throwIfInterrupted("trace", "stopped after " + std::to_string(i) + " of " + std::to_string(hips.size()) +
                                      " steps, nothing written");
    const auto t0 = std::chrono::steady_clock::now();
    out[i] = renderer->step(hips[i]);
    stepSeconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  std::FILE* f = file.file();
  std::fprintf(f, "x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status\n");
  size_t inContact = 0, starts = 0, maxAt = 0;
  double maxDiff = 0, total = 0, worst = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const ForceSample& s = out[i];
    const Eigen::Vector3d& h = hips[i];
    std::fprintf(f, "%.17g,%.17g,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%u\n", h.x(), h.y(),
                 h.z(), s.contact ? 1 : 0, s.contact ? s.face : -1, s.xi, s.eta, s.scp.x(), s.scp.y(), s.scp.z(),
                 s.force.x(), s.force.y(), s.force.z(), s.iterations, s.status);
    inContact += s.contact;
    starts += (s.status & SF_TRACK_ENTER) != 0 && s.contact;
    if (i > 0) {
      const double d = (s.force - out[i - 1].force).norm();
      if (d > maxDiff) {
        maxDiff = d;
        maxAt = i;
      }
    }
    total += stepSeconds[i];
    worst = std::max(worst, stepSeconds[i]);
  }
  file.commit();
  const double meanUs = hips.empty() ? 0.0 : 1e6 * total / static_cast<double>(hips.size());
  std::FILE* report = reportStream(file.toStdout());
  if (a.json) {
    nlohmann::ordered_json j{{"steps", hips.size()},
                             {"method", toString(method)},
                             {"refine", toString(opt.refine)},
                             {"preset", a.refine.preset},
                             {"final_step", toString(opt.finalStep)},
                             {"in_contact", inContact},
                             {"contacts", starts},
                             {"max_force_difference_n", maxDiff},
                             {"max_force_difference_step", maxAt},
                             {"compute_us_mean", meanUs},
                             {"compute_us_max", 1e6 * worst},
                             {"output", file.name()},
                             {"faces", cache->numFaces()},
                             {"patches_built", renderer->patchesBuilt()}};
    printJson(report, j);
    return;
  }
  std::fprintf(report,
               "trace: %zu steps (%s%s%s%s%s), %zu in contact, %zu contacts, max consecutive force difference "
               "%.6g N (step %zu), compute %.3g us/step mean, %.3g us max -> %s\n",
               hips.size(), toString(method), method == ForceMethod::Patch ? ", refine " : "",
               method == ForceMethod::Patch ? toString(opt.refine) : "", a.refine.preset.empty() ? "" : ", preset ",
               a.refine.preset.c_str(), inContact, starts, maxDiff, maxAt, meanUs, 1e6 * worst, file.name().c_str());
  if (!a.mesh.empty())
    std::fprintf(report,
                 "trace: %d lazy patch constructions for %d faces (at most %s held; a face evicted and needed again "
                 "is built again)\n",
                 renderer->patchesBuilt(), cache->numFaces(),
                 a.patchCapacity > 0 ? std::to_string(a.patchCapacity).c_str() : "all");
}

}  // namespace

void addTraceCommand(CLI::App& app) {
  auto* t = app.add_subcommand("trace", "Render forces along a HIP sequence with contact tracking (one row per step)");
  auto a = std::make_shared<TraceArgs>();
  auto* cache = t->add_option("--cache", a->cache, "patch cache file");
  auto* mesh = t->add_option("--mesh", a->mesh, "mesh file (patches built lazily where the HIPs go)");
  t->add_option("--patch-capacity", a->patchCapacity,
                "with --mesh: patches held at once, least recently used evicted (<= 0: no bound)")
      ->check(forceOptionCheck("patch_capacity"))
      ->capture_default_str();
  cache->excludes(mesh);
  mesh->excludes(cache);
  t->add_option("--method", a->method, "patch|direct|shading")
      ->check(forceOptionCheck("method"))
      ->capture_default_str();
  t->add_option("--hips", a->hips, "CSV with header x,y,z (or # x,y,z): one HIP (m) per servo step; - reads stdin")
      ->required();
  t->add_option("-o,--output", a->output,
                "CSV to write: x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status; - writes stdout")
      ->required();
  t->add_flag("--json", a->json,
              "summary as one JSON object (steps, method, refine, preset, in_contact, contacts, "
              "max_force_difference_n, max_force_difference_step, compute_us_mean, compute_us_max, output, faces, "
              "patches_built); on stderr with -o -");
  t->add_option("--stiffness", a->stiffness, "k in N/m (F = k (SCP - HIP)), in (0, 1e12]")
      ->check(forceOptionCheck("stiffness"))
      ->capture_default_str();
  addPatchArgs(*t, a->patch);
  addRefineArgs(*t, a->refine);
  t->callback([a] { run(*a); });
}

}  // namespace sf::cli
