// SPDX-License-Identifier: Apache-2.0
// A fixed-size log-linear histogram of durations, for percentiles of the servo loop.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sf::rt {

/// Counts durations in nanosecond buckets: exact (1 ns wide) below 2048 ns, then 1024
/// buckets per power of two, so a reported value is within 0.05% of the true one (half a
/// bucket). Memory is allocated once in the constructor (~220 KB); add() is real-time safe.
/// min and max are kept exactly.
class LatencyHistogram {
 public:
  LatencyHistogram();
  /// Adds a duration in seconds; negative and non-finite values count as 0, values above
  /// ~146 years saturate.
  void add(double seconds) noexcept;
  void clear() noexcept;
  int64_t count() const noexcept { return count_; }
  /// Exact extremes, s (0 when empty).
  double max() const noexcept { return count_ ? maxNs_ * 1e-9 : 0; }
  double min() const noexcept { return count_ ? minNs_ * 1e-9 : 0; }
  /// Nearest-rank percentile, s: the smallest recorded value v such that at least p% of the
  /// values are <= v (p in [0, 100]; p = 0 gives the minimum). Reported as the centre of
  /// v's bucket, capped to [min, max]. 0 when empty.
  double percentile(double p) const;
  /// "p50 A us, p99 B us, p99.9 C us, max D us" (values in microseconds, 1 decimal).
  std::string summaryUs() const;

 private:
  std::vector<uint32_t> counts_;
  int64_t count_ = 0;
  uint64_t minNs_ = 0, maxNs_ = 0;
};

}  // namespace sf::rt
