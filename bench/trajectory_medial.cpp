// Where the patch force leaves k x depth along the sweep's default constant-depth loop (issue 10):
// runs the loop as `sweep` does (the section loop resampled every diagonal / 400, each point
// pressed in along its normal by the depth, one tracker without reset) and, at every point,
// the global nearest patch point of the HIP (nearestOnPatches). A HIP nearer to the surface than
// the depth (by 0.1%) lies past the medial axis: another part of the surface is nearer than the
// point it was pressed in from (the part is thinner, or the surface more curved, than the depth
// allows). Prints every run of points whose |F| is outside [1/1.5, 1.5] x k x depth, with the
// last point past the medial axis before its end, and the counts (runs that start at most 5
// points after a point past the medial axis, or contain one, are counted as such).
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

int main(int argc, char** argv) {
  using namespace sf;
  std::string mesh = std::string(SF_SHARED_MESHES) + "/keenan_crane/spot_control_mesh.obj";
  double frac = 0.01;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--depth" && i + 1 < argc)
      frac = std::atof(argv[++i]);
    else
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
  const std::vector<SurfaceSample> walk = trajectorySamples(defaultTrajectory(*cache, 8), diag / 400, projector);
  const ForceOptions opt;
  auto surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(opt));
  auto tracker =
      makeForceRenderer(cache, std::make_shared<const PolygonScene>(*cache), ForceMethod::Patch, opt, surface);
  PatchRefiner refiner(*cache);
  if (walk.empty()) {
    std::printf("%s: no default trajectory\n", mesh.c_str());
    return 0;
  }
  tracker->reset();
  tracker->step(walk[0].point + 0.001 * depth * walk[0].normal);
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
  for (size_t i = 0; i < walk.size(); ++i) {
    const Eigen::Vector3d hip = walk[i].point - depth * walk[i].normal;
    const ForceSample s = tracker->step(hip);
    const PatchNearest q = nearestOnPatches(*surface, refiner, hip, opt);
    lost += !s.contact;
    const double r = s.force.norm() / (opt.stiffness * depth);
    const bool off = s.contact && (r > 1.5 || r < 1 / 1.5);
    if (!off) endRun(i);  // a run ends at i - 1: lastPast is still "at or before its last point"
    if (q.nearest.distance < 0.999 * depth) {
      ++past;
      lastPast = static_cast<long>(i);
    }
    outside += off;
    if (off && runStart < 0) runStart = static_cast<long>(i);
    if (off) runMax = r > 1 ? std::max(runMax, r) : (runMax == 0 ? r : std::min(runMax, r));
  }
  endRun(walk.size());
  std::printf(
      "%s, depth %.3g of the diagonal: %zu points; %zu past the medial axis; %zu in contact with |F| outside "
      "[1/1.5, 1.5] x k x depth, in %zu runs (%zu of them at a point past the medial axis or at most 5 points after one); %zu out of "
      "contact\n",
      mesh.c_str(), frac, walk.size(), past, outside, runs, runsAfterCrossing, lost);
  return 0;
}
