// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/morton_order.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <utility>

namespace sf {

namespace {
/// Spreads the low 21 bits of x to every third bit (bit i to bit 3 i).
uint64_t spreadBits3(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}
}  // namespace

std::vector<uint32_t> mortonOrder(const std::vector<Eigen::Vector3d>& points) {
  const size_t m = points.size();
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& q : points)
    if (q.allFinite()) box.extend(q);
  const Eigen::Vector3d lo = box.isEmpty() ? Eigen::Vector3d::Zero() : box.min();
  const double extent = box.isEmpty() ? 0.0 : box.sizes().maxCoeff();
  const double scale = extent > 0 ? double((1 << 21) - 1) / extent : 0.0;
  std::vector<std::pair<uint64_t, uint32_t>> key(m);
  tbb::parallel_for(size_t(0), m, [&](size_t i) {
    const Eigen::Vector3d& q = points[i];
    uint64_t code = ~uint64_t(0);  // non-finite points last
    if (q.allFinite()) {
      code = 0;
      for (int a = 0; a < 3; ++a)
        code |= spreadBits3(uint64_t(std::clamp((q[a] - lo[a]) * scale, 0.0, double((1 << 21) - 1)))) << a;
    }
    key[i] = {code, static_cast<uint32_t>(i)};
  });
  tbb::parallel_sort(key.begin(), key.end());  // (code, index) pairs are distinct: one order
  std::vector<uint32_t> order(m);
  for (size_t i = 0; i < m; ++i) order[i] = key[i].second;
  return order;
}

}  // namespace sf
