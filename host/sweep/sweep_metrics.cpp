// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_metrics.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include <smoothforce/base/thread_limit.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/sweep/morton_order.h>

namespace sf {

Percentiles percentiles(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  Percentiles p;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  p.p50 = p.p99 = p.p999 = p.max = nan;
  p.count = v.size();
  if (v.empty()) return p;
  tbb::parallel_sort(v.begin(), v.end());  // equal values are interchangeable: one result
  auto rank = [&](double q) {
    const size_t r = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::clamp<size_t>(r, 1, v.size()) - 1];
  };
  p.p50 = rank(0.5);
  p.p99 = rank(0.99);
  p.p999 = rank(0.999);
  p.max = v.back();
  return p;
}

Discontinuity forceDiscontinuity(const std::vector<Eigen::Vector3d>& positions,
                                 const std::vector<Eigen::Vector3d>& directions, const std::vector<char>& valid, int k,
                                 double thresholdRad, double spacing, int threads,
                                 const std::vector<Eigen::Vector3d>* sampleNormals) {
  Discontinuity out;
  const size_t n = positions.size();
  out.local.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<uint32_t> map;  // index in the tree -> HIP index
  std::vector<Eigen::Vector3d> pts;
  for (size_t i = 0; i < n; ++i)
    if (valid[i]) {
      map.push_back(static_cast<uint32_t>(i));
      pts.push_back(positions[i]);
    }
  if (pts.size() >= 2 && k > 0) {
    const PointIndex index(pts);
    const size_t kk = std::min<size_t>(static_cast<size_t>(k) + 1, pts.size());
    std::vector<double> maxAngle(pts.size(), 0);
    // Flagged neighbours per point, counted once per unordered pair below.
    std::vector<std::vector<uint32_t>> flagged(pts.size());
    // Left-out neighbours (opposite sample normals) with a larger tree index: each unordered
    // pair is seen from its smaller end, or from the larger one when the smaller does not list it.
    std::vector<std::vector<uint32_t>> leftOut(pts.size());
    const bool useNormals = sampleNormals && sampleNormals->size() == n;
    // the queries along a Morton curve: consecutive ones walk the same k-d tree nodes (in the
    // points' order, a sweep's random samples, 1M of them took 2.2 s); each query is on its own
    const std::vector<uint32_t> order = mortonOrder(pts);
    auto body = [&](const tbb::blocked_range<size_t>& r) {
      std::vector<uint32_t> idx(kk);
      std::vector<double> d2(kk);
      for (size_t u = r.begin(); u < r.end(); ++u) {
        const size_t t = order[u];
        const size_t found = index.knn(pts[t], kk, idx.data(), d2.data());
        const Eigen::Vector3d& a = directions[map[t]];
        double best = -1, bestAngle = 0;
        for (size_t j = 0; j < found; ++j) {
          if (idx[j] == t || !(d2[j] > 0)) continue;
          if (useNormals && (*sampleNormals)[map[t]].dot((*sampleNormals)[map[idx[j]]]) < 0) {
            leftOut[t].push_back(idx[j]);
            continue;
          }
          const double d = std::sqrt(d2[j]);
          const double ang = angleBetween(a, directions[map[idx[j]]]);
          best = std::max(best, ang / d);
          bestAngle = std::max(bestAngle, ang);
          if (ang > thresholdRad && d < spacing) flagged[t].push_back(idx[j]);
        }
        if (best >= 0) out.local[map[t]] = best;
        maxAngle[t] = bestAngle;
      }
    };
    const tbb::blocked_range<size_t> all(0, pts.size(), 1024);
    if (threads > 0) {
      tbb::task_arena arena(arenaThreads(threads));
      arena.execute([&] { tbb::parallel_for(all, body); });
    } else {
      tbb::parallel_for(all, body);
    }
    for (size_t t = 0; t < pts.size(); ++t)
      for (uint32_t j : leftOut[t]) {
        const auto& lj = leftOut[j];
        const bool mutual = std::find(lj.begin(), lj.end(), static_cast<uint32_t>(t)) != lj.end();
        if (!mutual || t < j) ++out.leftOutPairs;
      }
    for (size_t t = 0; t < pts.size(); ++t) {
      out.maxAngle = std::max(out.maxAngle, maxAngle[t]);
      for (uint32_t j : flagged[t]) {
        // the pair {t, j}: counted at the smaller index, or at j when t is not among j's flags
        const auto& fj = flagged[j];
        const bool mutual = std::find(fj.begin(), fj.end(), static_cast<uint32_t>(t)) != fj.end();
        if (!mutual || t < j) ++out.flaggedPairs;
      }
    }
  }
  out.stats = percentiles(out.local);
  return out;
}

std::vector<double> consecutiveDifferences(const std::vector<float>& f) {
  std::vector<double> d;
  const size_t m = f.size() / 3;
  for (size_t i = 0; i + 1 < m; ++i) {
    const Eigen::Vector3d a(f[3 * i], f[3 * i + 1], f[3 * i + 2]), b(f[3 * i + 3], f[3 * i + 4], f[3 * i + 5]);
    d.push_back((b - a).norm());
  }
  return d;
}

}  // namespace sf
