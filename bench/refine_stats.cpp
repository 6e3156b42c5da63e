// SPDX-License-Identifier: Apache-2.0
// How the Newton refinement ends on real meshes: for each mesh, HIPs uniform in its box (grown by
// 5% of the diagonal) and patch points pressed in along their normal (0.5-10% of the diagonal),
// the HIPs of HeldContact's test. Per mesh: the global queries' nearest points at the iteration
// cap, and every candidate of those queries (the first batch) refined from its own start: how
// many refinements, iterations, and how each ended (converged, at the cap, stalled; at a
// singular point, GP_ST_SINGULAR), with the wall time of the queries.
//   refine_stats [--query-only] [MESH...]   (default: every shared mesh up to 3 MB; --query-only:
//   only the timed queries, for profiling)
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <smoothforce/base/status.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/patch_surface.h>
#include "../tests/pressed_hips_support.h"  // HeldContact's HIPs
#include "../tests/shared_mesh_files.h"
#include "bench_common.h"

using namespace sf;

namespace {
int run(std::vector<std::string> meshes) {
  const bool queryOnly = !meshes.empty() && meshes[0] == "--query-only";  // profiling the queries
  if (queryOnly) meshes.erase(meshes.begin());
  if (meshes.empty()) meshes = test::sharedMeshFiles();
  const ForceOptions options;
  std::printf("%-40s %5s %6s %8s %9s %6s %7s %7s %7s %9s\n", "mesh", "HIPs", "capNP", "refines", "iters", "cap",
              "capSing", "stalled", "convSg", "query_s");
  for (const std::string& path : meshes) {
    const PatchCache cache = bench::meshCache(path, Precision::Double);
    const PatchSurface surface(cache);
    PatchRefiner refiner(cache);
    const std::vector<Eigen::Vector3d> hips = test::heldContactHips(cache);
    long capNearest = 0, refines = 0, iters = 0, cap = 0, capSingular = 0, stalled = 0, convSingular = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Eigen::Vector3d& h : hips)
      capNearest += (nearestOnPatches(surface, refiner, h, options).nearest.status & SF_TRACK_MAX_ITER) != 0;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<SurfaceCandidate> c(PatchSurface::kMaxCandidates);
    for (const Eigen::Vector3d& h : queryOnly ? std::vector<Eigen::Vector3d>{} : hips) {
      const size_t n = surface.candidates(h, c.data(), c.size());
      for (size_t i = 0; i < n; ++i) {
        const RefineResult r = refiner.refine(h, c[i].face, c[i].X.x(), c[i].X.y(), options);
        ++refines;
        iters += r.iterations;
        const bool singular = (r.status & SF_ST_SINGULAR) != 0;
        if (r.status & SF_TRACK_MAX_ITER) {
          ++cap;
          capSingular += singular;
        }
        stalled += (r.status & SF_TRACK_STALLED) != 0;
        convSingular += singular && (r.status & SF_TRACK_CONVERGED);
      }
    }
    const std::string name = std::filesystem::path(path).filename().string();
    std::printf("%-40s %5zu %6ld %8ld %9ld %6ld %7ld %7ld %7ld %9.3f\n", name.c_str(), hips.size(), capNearest, refines,
                iters, cap, capSingular, stalled, convSingular, seconds);
    std::fflush(stdout);
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "-h" || args[0] == "--help")) {
    std::printf("usage: refine_stats [--query-only] [MESH...]   (default: every shared mesh up to 3 MB)\n");
    return 0;
  }
  return bench::guardedMain("refine_stats", [&] { return run(args); });
}
