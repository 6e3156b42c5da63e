// SPDX-License-Identifier: Apache-2.0
// Where a sweep probe of the patch method spends its time: the parts of the
// two out-of-contact steps a probe runs (runProbes: reset, a step 0.1% of the depth outside the
// surface, then the step at the HIP), each timed alone on one thread with steady_clock:
//   seed        the seed's evaluation (PatchRefiner::refine with no iteration), as the tracker
//               seeds its global query: the approach step at the HIP's surface sample
//               (ForceRenderer::resetNear), the step at the HIP at the approach step's nearest point
//   candidates  PatchSurface::candidates (Embree point query over the adaptive triangles),
//               bounded as the tracker bounds it: by the band's triangle and the seed
//   refine      refineCandidates (Newton from each candidate in another basin; the seed stands
//               in for one where it may)
//   band        PatchSurface::inErrorBand (the uniform triangle under the seed's point first, as
//               the tracker's hint; else an Embree point query over the uniform triangles)
//   winding     PatchSurface::winding, where the HIP is outside every band (2-3 Embree rays)
// and the evaluations per step (the patch records read in place, double). The HIPs are patch
// samples pressed in along the normal by --depth (fraction of the diagonal), visited in face
// order as the sweep's Morton order would.
//   build/bench/probe_breakdown [MESH] [--depth 0.005] [--samples 20000]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "bench_common.h"

namespace {

using namespace sf;
using Clock = std::chrono::steady_clock;

double us(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::micro>(b - a).count(); }

int run(int argc, char** argv) {
  std::string mesh = std::string(SF_SHARED_MESHES) + "/keenan_crane/spot_control_mesh.obj";
  double depth = 0.005;
  int samples = 20000;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf("usage: probe_breakdown [MESH] [--depth 0.005] [--samples 20000]\n");
      return 0;
    }
    if (a == "--depth" && i + 1 < argc)
      depth = std::atof(argv[++i]);
    else if (a == "--samples" && i + 1 < argc)
      samples = std::atoi(argv[++i]);
    else if (a.rfind('-', 0) == 0) {
      std::fprintf(stderr, "probe_breakdown: unknown option or missing value: %s (--help)\n", a.c_str());
      return 2;
    } else
      mesh = a;
  }
  if (!(depth > 0) || samples < 1) {
    std::fprintf(stderr, "probe_breakdown: --depth must be > 0 and --samples >= 1\n");
    return 2;
  }
  PatchOptions po;
  const PatchCache cache = buildPatchCache(loadMesh(mesh, po), po, Backend::Tbb);
  const double diag = boundingDiagonal(cache);
  const PatchSurface surface(cache);
  std::vector<SurfaceSample> s = PatchSurfaceSampler(cache, 8).sample(samples, 1);
  std::sort(s.begin(), s.end(), [](const SurfaceSample& a, const SurfaceSample& b) {
    return a.face < b.face || (a.face == b.face && a.xi < b.xi);
  });
  std::printf("%s: %d faces, patch surface level %d (%zu uniform triangles), %d HIPs at %.3g of the diagonal\n",
              mesh.c_str(), cache.numFaces(), surface.level(), surface.numTriangles(), samples, depth);
  PatchRefiner refiner(cache);
  const ForceOptions opt;
  // the approach step's nearest point (face, X): the tracker seeds the HIP step with it
  std::vector<RefineResult> approachNearest(s.size());
  ForceOptions seedOpt = opt;
  seedOpt.maxIterations = 0;  // a seed is evaluated, not refined
  for (int pass = 0; pass < 2; ++pass) {
    double tc = 0, tr = 0, tb = 0, tw = 0, ts = 0;
    long candidates = 0, refined = 0, iterations = 0, inBand = 0, rays = 0, seedsUsed = 0;
    for (size_t i = 0; i < s.size(); ++i) {
      const SurfaceSample& x = s[i];
      const Eigen::Vector3d hip = pass == 0 ? Eigen::Vector3d(x.point + 0.001 * depth * diag * x.normal)
                                            : Eigen::Vector3d(x.point - depth * diag * x.normal);
      CandidateBuffer<> c;
      // as the tracker's step: the band (and the winding number outside every band) first, then
      // the candidates within the bound on the distance known so far, then their refinement
      double reach = std::numeric_limits<double>::infinity();
      // the seed's patch point (below) is the band test's hint, as the tracker's (the approach
      // step's point unknown, as after resetNear)
      const int hintFace = pass == 0 ? x.face : approachNearest[i].face;
      const Eigen::Vector2d hintX =
          pass == 0 ? Eigen::Vector2d(x.xi, x.eta) : Eigen::Vector2d(approachNearest[i].xi, approachNearest[i].eta);
      const Eigen::Vector3d hintPoint =
          pass == 0 ? Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()) : approachNearest[i].scp;
      const auto t0 = Clock::now();
      int reachFace = -1;
      const bool band = surface.inErrorBand(hip, &reach, &reachFace, hintFace, hintX, hintPoint);
      const auto t1 = Clock::now();
      if (!band) (void)surface.winding(hip);
      const auto t2 = Clock::now();
      SurfaceCandidate from;
      from.face = pass == 0 ? x.face : approachNearest[i].face;
      from.X =
          pass == 0 ? Eigen::Vector2d(x.xi, x.eta) : Eigen::Vector2d(approachNearest[i].xi, approachNearest[i].eta);
      const RefineResult seed =
          from.face >= 0 ? refiner.refine(hip, from.face, from.X.x(), from.X.y(), seedOpt) : RefineResult{};
      const auto t3 = Clock::now();
      const bool seeded = from.face >= 0 && seed.scp.allFinite() && !(seed.status & SF_TRACK_DEGENERATE);
      // the tighter bound by the search radius it gives (reach + 2 x the face's error bound)
      if (seeded && surface.searchRadius(seed.distance, seed.face) < surface.searchRadius(reach, reachFace)) {
        reach = seed.distance;
        reachFace = seed.face;
      }
      const int n = static_cast<int>(surface.candidates(hip, c.data(), c.size(), reach, reachFace));
      const auto t4 = Clock::now();
      const PatchNearest q = refineCandidates(c.data(), n, surface.spacing(), refiner, hip, opt,
                                              seeded ? &seed : nullptr, seeded ? &from : nullptr, &surface);
      const auto t5 = Clock::now();
      if (pass == 0 && q.nearest.scp.allFinite() && !(q.nearest.status & SF_TRACK_DEGENERATE))
        approachNearest[i] = q.nearest;
      seedsUsed += seeded && q.nearest.face == seed.face && q.nearest.xi == seed.xi && q.nearest.eta == seed.eta &&
                   q.nearest.iterations == 0;
      tb += us(t0, t1);
      tw += us(t1, t2);
      ts += us(t2, t3);
      tc += us(t3, t4);
      tr += us(t4, t5);
      candidates += n;
      refined += q.refined;
      iterations += q.nearest.iterations;
      inBand += band;
      rays += !band;
    }
    const double N = static_cast<double>(s.size());
    std::printf(
        "%-9s step: seed %.2f us (the nearest point in %.0f%%), candidates %.2f us (%.1f of them), refine %.2f us "
        "(%.2f refinements, %.2f iterations to the nearest), band %.2f us (%.0f%% in a band), winding %.2f us "
        "(%.0f%% of the steps)\n",
        pass == 0 ? "approach" : "HIP", ts / N, 100.0 * seedsUsed / N, tc / N, candidates / N, tr / N, refined / N,
        iterations / N, tb / N, 100.0 * inBand / N, tw / N, 100.0 * rays / N);
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return sf::bench::guardedMain("probe_breakdown", [&] { return run(argc, argv); });
}
