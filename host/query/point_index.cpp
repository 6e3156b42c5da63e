// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/point_index.h>

#include <nanoflann.hpp>

namespace sf {

namespace {
struct Cloud {
  const std::vector<Eigen::Vector3d>* pts;
  size_t kdtree_get_point_count() const { return pts->size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return (*pts)[i][static_cast<int>(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using Tree3 = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, uint32_t>;
}  // namespace

struct PointIndex::Tree {
  Cloud cloud;
  Tree3 tree;
  explicit Tree(const std::vector<Eigen::Vector3d>* p)
      : cloud{p}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

PointIndex::PointIndex(std::vector<Eigen::Vector3d> points) : points_(std::move(points)) {
  tree_ = std::make_unique<Tree>(&points_);
}

PointIndex::~PointIndex() = default;

size_t PointIndex::knn(const Eigen::Vector3d& q, size_t k, uint32_t* indices, double* dist2) const {
  if (points_.empty() || k == 0) return 0;
  const double qp[3] = {q.x(), q.y(), q.z()};
  return tree_->tree.knnSearch(qp, k, indices, dist2);
}

int64_t PointIndex::nearest(const Eigen::Vector3d& q) const {
  uint32_t i = 0;
  double d2 = 0;
  return knn(q, 1, &i, &d2) ? static_cast<int64_t>(i) : -1;
}

}  // namespace sf
