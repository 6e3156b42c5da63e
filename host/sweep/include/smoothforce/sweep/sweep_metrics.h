// SPDX-License-Identifier: Apache-2.0
// Sweep metrics: force-direction discontinuity over nearest HIP neighbours, consecutive force
// differences along trajectories, percentiles.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace sf {

/// Nearest-rank percentiles of the finite values (count = how many); NaN when none.
struct Percentiles {
  size_t count = 0;
  double p50, p99, p999, max;
};
Percentiles percentiles(std::vector<double> values);

/// Force-direction discontinuity (paper Fig. 12). For every HIP i with a defined direction
/// (valid[i]), over its k nearest valid neighbours j (distance d_ij > 0):
///   local[i] = max_j angle(dir_i, dir_j) / d_ij   (rad/m; NaN where undefined).
/// flaggedPairs counts unordered neighbour pairs {i, j} with angle > thresholdRad and
/// d_ij < spacing. positions #P by 3 (m), directions #P by 3 (need not be unit).
/// With sampleNormals (#P by 3, each HIP's surface sample normal), neighbours whose sample normals
/// point apart (n_i . n_j < 0: opposite sides of a part thinner than the neighbourhood, where the
/// force rightly turns over) are left out of both, and counted once per unordered pair in
/// leftOutPairs: the metric measures the method, not the thinness of the mesh.
struct Discontinuity {
  std::vector<double> local;
  Percentiles stats;
  size_t flaggedPairs = 0;
  size_t leftOutPairs = 0;  ///< neighbour pairs on opposite sides (sampleNormals given)
  double maxAngle = 0;      ///< rad, the largest neighbour angle seen
};
Discontinuity forceDiscontinuity(const std::vector<Eigen::Vector3d>& positions,
                                 const std::vector<Eigen::Vector3d>& directions, const std::vector<char>& valid, int k,
                                 double thresholdRad, double spacing, int threads = 0,
                                 const std::vector<Eigen::Vector3d>* sampleNormals = nullptr);

/// |F_{i+1} - F_i| for consecutive points (forces 3 * #points, N); pairs where either point
/// is out of contact count as differences too (contact lost is a jump).
std::vector<double> consecutiveDifferences(const std::vector<float>& forces);

}  // namespace sf
