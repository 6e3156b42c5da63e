// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/latency_histogram.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

namespace sf::rt {
namespace {

constexpr int kSubBits = 10;                    // 1024 buckets per power of two
constexpr uint64_t kLinear = 2ull << kSubBits;  // 2048 exact 1-ns buckets
constexpr int kMaxMsb = 62;                     // values saturate at 2^63 - 1 ns
constexpr size_t kBuckets = kLinear + size_t(kMaxMsb - kSubBits) * (1u << kSubBits);

size_t bucketOf(uint64_t v) noexcept {
  if (v < kLinear) return static_cast<size_t>(v);
  const int msb = 63 - std::countl_zero(v);  // >= kSubBits + 1
  const int shift = msb - kSubBits;
  return kLinear + size_t(msb - kSubBits - 1) * (1u << kSubBits) + size_t((v >> shift) - (1ull << kSubBits));
}

/// Centre of bucket b, ns.
double bucketCentre(size_t b) noexcept {
  if (b < kLinear) return static_cast<double>(b);
  const size_t k = b - kLinear;
  const int shift = static_cast<int>(k >> kSubBits) + 1;
  const uint64_t low = ((k & ((1u << kSubBits) - 1)) + (1ull << kSubBits)) << shift;
  return static_cast<double>(low) + 0.5 * static_cast<double>((1ull << shift) - 1);
}

}  // namespace

LatencyHistogram::LatencyHistogram() : counts_(kBuckets, 0) {}

void LatencyHistogram::add(double seconds) noexcept {
  uint64_t ns = 0;
  if (seconds > 0) {  // false for NaN
    const double v = seconds * 1e9;
    ns = v >= 9.2e18 ? (1ull << 63) - 1 : static_cast<uint64_t>(std::llround(v));
  }
  ++counts_[std::min(bucketOf(ns), kBuckets - 1)];
  if (count_ == 0 || ns < minNs_) minNs_ = ns;
  if (count_ == 0 || ns > maxNs_) maxNs_ = ns;
  ++count_;
}

void LatencyHistogram::clear() noexcept {
  std::fill(counts_.begin(), counts_.end(), 0u);
  count_ = 0;
  minNs_ = maxNs_ = 0;
}

double LatencyHistogram::percentile(double p) const {
  if (count_ == 0) return 0;
  p = std::clamp(p, 0.0, 100.0);
  const int64_t rank =
      std::max<int64_t>(1, static_cast<int64_t>(std::ceil(p / 100.0 * static_cast<double>(count_) - 1e-9)));
  int64_t seen = 0;
  for (size_t b = 0; b < counts_.size(); ++b) {
    seen += counts_[b];
    if (seen >= rank) {
      const double v = std::clamp(bucketCentre(b), static_cast<double>(minNs_), static_cast<double>(maxNs_));
      return v * 1e-9;
    }
  }
  return max();
}

std::string LatencyHistogram::summaryUs() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us", percentile(50) * 1e6,
                percentile(99) * 1e6, percentile(99.9) * 1e6, max() * 1e6);
  return buf;
}

}  // namespace sf::rt
