// SPDX-License-Identifier: Apache-2.0
// Shared by the global-query and held-contact tests (and bench/refine_stats.cpp): HIPs pressed
// into a patch surface along the normals of sampled patch points, whose distance to the surface
// is known not to exceed the depth, and HIPs uniform in a mesh's box.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <random>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

#include <smoothforce/sweep/sweep_sampling.h>

namespace sf::test {

/// A HIP pressed `depth` (m) into the patch surface along the normal of samples[sample]: that
/// patch point lies at exactly `depth` from it, with the HIP below it, so the nearest patch point
/// is no farther.
struct PressedHip {
  Eigen::Vector3d hip;
  double depth = 0;
  size_t sample = 0;
};

/// For each depth (x diag, m) in turn, every sample pressed in by it: depths.size() x
/// samples.size() HIPs.
inline std::vector<PressedHip> pressedHips(const std::vector<SurfaceSample>& samples,
                                           std::initializer_list<double> depths, double diag) {
  std::vector<PressedHip> out;
  out.reserve(depths.size() * samples.size());
  for (double depth : depths)
    for (size_t i = 0; i < samples.size(); ++i)
      out.push_back({samples[i].point - depth * diag * samples[i].normal, depth * diag, i});
  return out;
}

/// `count` HIPs uniform in the box of the cache's vertices grown by `grow` x its diagonal on every
/// side (std::mt19937_64 seeded with `seed`; coordinates drawn x, y, z per HIP); *boxDiagonal
/// (when given): that box's diagonal before growing, m.
inline std::vector<Eigen::Vector3d> uniformHipsInBox(const PatchCache& cache, int count, uint64_t seed,
                                                     double grow = 0.05, double* boxDiagonal = nullptr) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (size_t v = 0; v < cache.positions.size() / 3; ++v) {
    const Eigen::Vector3d p(cache.positions[3 * v], cache.positions[3 * v + 1], cache.positions[3 * v + 2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double g = grow * (hi - lo).norm();
  if (boxDiagonal) *boxDiagonal = (hi - lo).norm();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Vector3d> hips;
  for (int i = 0; i < count; ++i) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = lo[a] - g + u(rng) * (hi[a] - lo[a] + 2 * g);
    hips.push_back(p);
  }
  return hips;
}

/// The HIPs HeldContact holds still on a mesh (and refine_stats refines to): 300 uniform in the
/// box grown by 5% of its diagonal (seed 11), then 300 patch samples (seed 5) pressed in along
/// their normals by 0.5%, 2%, 5% and 10% of the box diagonal in turn; 600 in all. *boxDiagonal
/// (when given): that diagonal, m.
inline std::vector<Eigen::Vector3d> heldContactHips(const PatchCache& cache, double* boxDiagonal = nullptr) {
  constexpr int kUniform = 300, kPressed = 300;
  constexpr double kDepth[] = {0.005, 0.02, 0.05, 0.1};
  double diag = 0;
  std::vector<Eigen::Vector3d> hips = uniformHipsInBox(cache, kUniform, 11, 0.05, &diag);
  const std::vector<SurfaceSample> samples = PatchSurfaceSampler(cache).sample(kPressed, 5);
  for (size_t i = 0; i < samples.size(); ++i)
    hips.push_back(samples[i].point - kDepth[i % std::size(kDepth)] * diag * samples[i].normal);
  if (boxDiagonal) *boxDiagonal = diag;
  return hips;
}

}  // namespace sf::test
