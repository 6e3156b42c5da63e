// SPDX-License-Identifier: Apache-2.0
// The batch surface query's rate against the dense mesh's: signed distances of the same points
// from SurfaceQuery on a coarse prebuilt cache (the patch surface: global nearest point and inside
// test) and from the dense mesh's polygons (Embree's nearest point, PolygonScene::nearest, and its
// ray-parity inside test, PolygonScene::contains), in one run, alternating per round; points
// uniform in the coarse mesh's box grown by 10% and pressed 0.5% of its diagonal in and out of its
// patch surface, half each. Prints points/s per round, their medians and the ratio.
//   build/bench/surface_query_rate [--points 20000] [--rounds 5] [--threads 1] [COARSE DENSE]
//   (default: the spot cage and odedstein/spot.obj of ../shared/meshes)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/query/surface_query.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "../tests/shared_mesh_files.h"
#include "bench_common.h"

using namespace sf;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int run(int argc, char** argv) {
  int points = 20000, rounds = 5, threads = 1;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--points" || a == "--rounds" || a == "--threads") && i + 1 < argc) {
      (a == "--points" ? points : a == "--rounds" ? rounds : threads) = std::atoi(argv[++i]);
    } else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "usage: surface_query_rate [--points N] [--rounds R] [--threads T] [COARSE DENSE]\n");
      return 2;
    } else {
      meshes.push_back(a);
    }
  }
  if (meshes.empty())
    meshes = {test::sharedMesh("keenan_crane/spot_control_mesh.obj"), test::sharedMesh("odedstein/spot.obj")};
  if (meshes.size() != 2 || points < 2 || rounds < 1 || threads < 1) {
    std::fprintf(stderr, "surface_query_rate: two meshes, --points >= 2, --rounds and --threads >= 1\n");
    return 2;
  }
  PatchOptions po;
  auto coarse = std::make_shared<const PatchCache>(buildPatchCache(loadMesh(meshes[0], po), po, Backend::Tbb));
  const PatchCache dense = preparePatchSkeleton(loadMesh(meshes[1], po), po);
  const SurfaceQuery query(coarse);
  const PolygonScene scene(dense);
  // the points
  Eigen::Vector3d lo, hi;
  referencedBox(*coarse, lo, hi);
  const double diag = (hi - lo).norm();
  std::vector<double> pts;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-0.05, 1.05);
  for (int i = 0; i < points / 2; ++i)
    for (int a = 0; a < 3; ++a) pts.push_back(lo[a] + U(rng) * (hi[a] - lo[a]));
  const PatchSurfaceSampler sampler(*coarse, 6);
  const std::vector<SurfaceSample> samples = sampler.sample(size_t(points - points / 2), 6);
  for (size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d p = samples[i].point + (i % 2 ? 0.005 : -0.005) * diag * samples[i].normal;
    pts.insert(pts.end(), {p.x(), p.y(), p.z()});
  }
  const size_t n = pts.size() / 3;
  std::vector<SurfaceQueryResult> patchOut(n);
  std::vector<double> denseOut(n);
  tbb::task_arena arena(threads);
  auto denseRun = [&] {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 64), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const Eigen::Vector3d p(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
          const NearestPolygonPoint q = scene.nearest(p);
          const double d = (p - q.point).norm();
          denseOut[i] = scene.contains(p, q.point - p) ? -d : d;
        }
      });
    });
  };
  auto patchRun = [&] { query.query(pts.data(), n, patchOut.data(), threads); };
  patchRun();  // warm-up: the refiners and caches
  denseRun();
  std::vector<double> patchRate, denseRate;
  for (int r = 0; r < rounds; ++r) {
    for (int k = 0; k < 2; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      (k == 0) == (r % 2 == 0) ? patchRun() : denseRun();
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ((k == 0) == (r % 2 == 0) ? patchRate : denseRate).push_back(double(n) / s);
    }
    std::printf("round %d: patch surface %.4g points/s, dense polygons %.4g points/s\n", r, patchRate.back(),
                denseRate.back());
  }
  int signs = 0;
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    signs += (patchOut[i].signedDistance < 0) == (denseOut[i] < 0);
    worst = std::max(worst, std::abs(patchOut[i].signedDistance - denseOut[i]));
  }
  std::printf("%s (%d faces, patch surface) against %s (%d faces, polygons), %zu points, %d threads:\n",
              std::filesystem::path(meshes[0]).filename().string().c_str(), coarse->numFaces(),
              std::filesystem::path(meshes[1]).filename().string().c_str(), dense.numFaces(), n, threads);
  std::printf("  medians: patch %.4g points/s, dense %.4g points/s, ratio %.3f\n", median(patchRate),
              median(denseRate), median(patchRate) / median(denseRate));
  // the two are different surfaces (a cage's patches interpolate the cage, not the dense mesh)
  std::printf("  the surfaces differ: same sign on %d of %zu points, largest signed-distance difference %.3g of the "
              "diagonal\n",
              signs, n, worst / diag);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guardedMain("surface_query_rate", [&] { return run(argc, argv); });
}
