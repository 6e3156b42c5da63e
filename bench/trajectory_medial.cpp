// SPDX-License-Identifier: Apache-2.0
// Where the patch force leaves k x depth along the sweep's default constant-depth loop:
// runs the loop as `sweep` does (the section loop resampled every diagonal / 400, each point
// pressed in along its normal by the depth, one tracker without reset) and, at every point,
// the global nearest patch point of the HIP (nearestOnPatches). A HIP nearer to the surface than
// the depth (by 0.1%) lies past the medial axis: another part of the surface is nearer than the
// point it was pressed in from (the part is thinner, or the surface more curved, than the depth
// allows). Prints every run of points whose |F| is outside [1/1.5, 1.5] x k x depth, with the
// last point past the medial axis before its end, and the counts (runs that start at most 5
// points after a point past the medial axis, or contain one, are counted as such); then the
// sweep's smoothness ratio (largest consecutive force change at half the step / at the step) and
// whether each largest change lies within 3 points of one past the medial axis.
//   build/bench/trajectory_medial [MESH] [--depth 0.01]
#include <cstdio>
#include <cstdlib>
#include <string>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "bench_common.h"

namespace {
int run(int argc, char** argv) {
  using namespace sf;
  std::string mesh = std::string(SF_SHARED_MESHES) + "/keenan_crane/spot_control_mesh.obj";
  double frac = 0.01;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf("usage: trajectory_medial [MESH] [--depth 0.01]\n");
      return 0;
    }
    if (a == "--depth" && i + 1 < argc)
      frac = std::atof(argv[++i]);
    else if (a.rfind('-', 0) == 0) {
      std::fprintf(stderr, "trajectory_medial: unknown option or missing value: %s (--help)\n", a.c_str());
      return 2;
    } else
      mesh = a;
  }
  if (!(frac > 0)) {
    std::fprintf(stderr, "trajectory_medial: --depth must be > 0 (a fraction of the diagonal)\n");
    return 2;
  }
  PatchOptions po;
  auto cache = std::make_shared<const PatchCache>(buildPatchCache(loadMesh(mesh, po), po, Backend::Tbb));
  const double diag = boundingDiagonal(*cache), depth = frac * diag;
  const PatchProjector projector(*cache, 8);
  const ForceOptions opt;
  auto surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(opt));
  PatchRefiner refiner(*cache);
  // the loop as the sweep runs it (fresh tracker, approach step, then every point pressed in),
  // with each HIP's force and contact, and whether it lies past the medial axis
  struct Loop {
    std::vector<Eigen::Vector3d> force;
    std::vector<char> contact, beyond;
  };
  auto runLoop = [&](double step) {
    const std::vector<SurfaceSample> w = trajectorySamples(defaultTrajectory(*cache, 8), step, projector);
    Loop l;
    if (w.empty()) return l;
    auto r = makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, opt, surface);
    r->reset();
    r->step(w[0].point + 0.001 * depth * w[0].normal);
    for (const SurfaceSample& x : w) {
      const Eigen::Vector3d hip = x.point - depth * x.normal;
      const ForceSample s = r->step(hip);
      l.force.push_back(s.force);
      l.contact.push_back(s.contact);
      l.beyond.push_back(nearestOnPatches(*surface, refiner, hip, opt).nearest.distance < 0.999 * depth);
    }
    return l;
  };
  const Loop loop = runLoop(diag / 400);
  if (loop.force.empty()) {
    std::printf("%s: no default trajectory\n", mesh.c_str());
    return 0;
  }
  size_t outside = 0, past = 0, lost = 0, runs = 0, runsAfterCrossing = 0;
  long lastPast = -1, runStart = -1;
  double runMax = 0;
  auto endRun = [&](size_t i) {
    if (runStart < 0) return;
    ++runs;
    const bool crossed = lastPast >= 0 && lastPast >= runStart - 5;  // within the run, or just before it
    runsAfterCrossing += crossed;
    std::printf("  points %ld..%zu: |F| %s to %.2f x k x depth; the last point past the medial axis up to there: %ld\n",
                runStart, i - 1, runMax > 1 ? "up" : "down", runMax, lastPast);
    runStart = -1;
    runMax = 0;
  };
  for (size_t i = 0; i < loop.force.size(); ++i) {
    lost += !loop.contact[i];
    const double r = loop.force[i].norm() / (opt.stiffness * depth);
    const bool off = loop.contact[i] && (r > 1.5 || r < 1 / 1.5);
    if (!off) endRun(i);  // a run ends at i - 1: lastPast is still "at or before its last point"
    if (loop.beyond[i]) {
      ++past;
      lastPast = static_cast<long>(i);
    }
    outside += off;
    if (off && runStart < 0) runStart = static_cast<long>(i);
    if (off) runMax = r > 1 ? std::max(runMax, r) : (runMax == 0 ? r : std::min(runMax, r));
  }
  endRun(loop.force.size());
  // the sweep's smoothness ratio: the largest consecutive force change at half the step over the
  // one at the step; and whether it sits next to the medial axis
  auto largestChange = [](const Loop& l, size_t& at, bool& nearMedial) {
    double best = 0;
    at = 0;
    for (size_t i = 1; i < l.force.size(); ++i)
      if ((l.force[i] - l.force[i - 1]).norm() > best) {
        best = (l.force[i] - l.force[i - 1]).norm();
        at = i;
      }
    nearMedial = false;
    for (size_t j = at > 3 ? at - 3 : 0; j < std::min(l.force.size(), at + 4); ++j) nearMedial |= l.beyond[j] != 0;
    return best;
  };
  size_t at1 = 0, at2 = 0;
  bool near1 = false, near2 = false;
  const double d1 = largestChange(loop, at1, near1), d2 = largestChange(runLoop(diag / 800), at2, near2);
  std::printf(
      "  largest consecutive force change: %.4g N at point %zu%s; at half the step %.4g N at point %zu%s; "
      "ratio %.2f\n",
      d1, at1, near1 ? " (within 3 points of one past the medial axis)" : "", d2, at2,
      near2 ? " (within 3 points of one past the medial axis)" : "", d1 > 0 ? d2 / d1 : 0.0);
  std::printf(
      "%s, depth %.3g of the diagonal: %zu points; %zu past the medial axis; %zu in contact with |F| outside "
      "[1/1.5, 1.5] x k x depth, in %zu runs (%zu of them at a point past the medial axis or at most 5 points after "
      "one); %zu out of "
      "contact\n",
      mesh.c_str(), frac, loop.force.size(), past, outside, runs, runsAfterCrossing, lost);
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return sf::bench::guardedMain("trajectory_medial", [&] { return run(argc, argv); });
}
