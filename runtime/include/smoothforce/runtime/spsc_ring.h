// SPDX-License-Identifier: Apache-2.0
// A bounded lock-free single-producer single-consumer ring buffer.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>

namespace sf::rt {

/// Fixed-capacity FIFO between exactly one producer thread and one consumer thread.
/// Storage is allocated (and touched) once in the constructor; tryPush and tryPop never
/// allocate, lock, block or throw, so the producer can be the real-time loop.
/// Indices are 64-bit counters (never wrap in practice); slot = index & (capacity - 1).
/// The producer publishes a slot with a release store of head_, the consumer frees it with a
/// release store of tail_; each side caches the other's index to avoid cache-line traffic.
template <class T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "records are copied with plain assignment");

 public:
  /// capacity: rounded up to a power of two, at least 2.
  explicit SpscRing(size_t minCapacity) {
    size_t c = 2;
    while (c < minCapacity) c <<= 1;
    mask_ = c - 1;
    buf_.reset(new T[c]());
  }
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  size_t capacity() const noexcept { return mask_ + 1; }

  /// Producer only. False (and nothing stored) when the ring is full.
  bool tryPush(const T& v) noexcept {
    const uint64_t h = head_.load(std::memory_order_relaxed);
    if (h - cachedTail_ > mask_) {
      cachedTail_ = tail_.load(std::memory_order_acquire);
      if (h - cachedTail_ > mask_) return false;
    }
    buf_[h & mask_] = v;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }

  /// Consumer only. False when the ring is empty.
  bool tryPop(T& out) noexcept {
    const uint64_t t = tail_.load(std::memory_order_relaxed);
    if (t == cachedHead_) {
      cachedHead_ = head_.load(std::memory_order_acquire);
      if (t == cachedHead_) return false;
    }
    out = buf_[t & mask_];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }

  /// Approximate number of queued items (exact when neither side is active).
  size_t size() const noexcept {
    return static_cast<size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire));
  }

 private:
  alignas(64) std::atomic<uint64_t> head_{0};  ///< next slot to write (producer)
  uint64_t cachedTail_ = 0;                    ///< producer's copy of tail_
  alignas(64) std::atomic<uint64_t> tail_{0};  ///< next slot to read (consumer)
  uint64_t cachedHead_ = 0;                    ///< consumer's copy of head_
  alignas(64) size_t mask_ = 0;
  std::unique_ptr<T[]> buf_;
};

}  // namespace sf::rt
