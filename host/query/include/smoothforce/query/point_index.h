// SPDX-License-Identifier: Apache-2.0
// k-nearest-neighbour queries on 3-D point sets (nanoflann k-d tree), for force sweeps.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

namespace sf {

/// A static k-d tree over #P points (copied). Queries are const and thread-safe.
class PointIndex {
 public:
  explicit PointIndex(std::vector<Eigen::Vector3d> points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  /// The k points nearest q, nearest first: indices into the point list and squared
  /// distances (both k long). Returns how many were found (< k only when #P < k).
  size_t knn(const Eigen::Vector3d& q, size_t k, uint32_t* indices, double* dist2) const;
  /// Index of the point nearest q (-1 for an empty set).
  int64_t nearest(const Eigen::Vector3d& q) const;
  size_t size() const { return points_.size(); }
  const Eigen::Vector3d& point(size_t i) const { return points_[i]; }

 private:
  struct Tree;
  std::vector<Eigen::Vector3d> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace sf
