// SPDX-License-Identifier: Apache-2.0
// Starting points for nearest-point refinement from a coarse tessellation of the patches
// (sweep projection, tests).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

class PointIndex;

/// A tessellation vertex: the patch point G(xi, eta) of face `face`; face -1 when there is none.
struct PatchSeed {
  int face = -1;
  Eigen::Vector2d X{0, 0};         ///< domain coordinates to start from: the vertex's, 0.1% towards the centre
  Eigen::Vector3d point{0, 0, 0};  ///< m, the vertex G(vertex's xi, eta)
};

/// The vertices of a level-L tessellation of every evaluable patch (domainRingPoints: 1 +
/// n L (L+1) / 2 per n-gon, evaluated on the CPU) in a k-d tree. nearest() is const,
/// thread-safe, and does not allocate, lock or throw. The cache must outlive the seeds.
class PatchSeeds {
 public:
  /// Throws InputError when level is outside [1, 64]. A cache with no evaluable patch gives
  /// an empty set (nearest() then returns face -1).
  PatchSeeds(const PatchCache& cache, int level);
  ~PatchSeeds();
  PatchSeeds(const PatchSeeds&) = delete;
  PatchSeeds& operator=(const PatchSeeds&) = delete;

  /// The tessellation vertex nearest q (m).
  PatchSeed nearest(const Eigen::Vector3d& q) const noexcept;
  /// The k (<= 64) vertices nearest q, nearest first, into out[0..k); returns how many.
  size_t knn(const Eigen::Vector3d& q, size_t k, PatchSeed* out) const noexcept;
  size_t size() const noexcept { return face_.size(); }

 private:
  std::vector<int32_t> face_;         ///< per vertex
  std::vector<Eigen::Vector2d> dom_;  ///< per vertex
  std::unique_ptr<PointIndex> index_;
};

}  // namespace sf
