// SPDX-License-Identifier: Apache-2.0
// A latest-value mailbox between threads (seqlock): the writer never waits for readers, and
// the real-time reader never waits at all.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace sf::rt {

/// Holds the latest value of a plain-data type T. tryWrite() and tryRead() never allocate,
/// lock, block or throw, so either side can be the servo thread.
///
/// Protocol (Boehm, "Can seqlocks get along with programming language memory models?",
/// MSPC 2012): a writer makes the sequence odd, stores the value's words, makes it even
/// again; a reader loads the sequence, the words, the sequence again, and keeps the copy
/// only when both loads saw the same even number. The value is held in relaxed atomic
/// 64-bit words with fences, so there is no data race in the C++ memory model and a torn
/// copy is never returned. Concurrent writers exclude each other with a compare-exchange on
/// the sequence: the loser's tryWrite returns false and stores nothing.
template <class T>
class SeqlockMailbox {
  static_assert(std::is_trivially_copyable_v<T>, "the mailbox copies T word by word");
  static constexpr size_t kWords = (sizeof(T) + 7) / 8;

 public:
  SeqlockMailbox() = default;
  SeqlockMailbox(const SeqlockMailbox&) = delete;
  SeqlockMailbox& operator=(const SeqlockMailbox&) = delete;

  /// Publishes v. False (nothing stored) when another writer is storing at this moment.
  bool tryWrite(const T& v) noexcept {
    uint64_t s = seq_.load(std::memory_order_relaxed);
    if ((s & 1) || !seq_.compare_exchange_strong(s, s + 1, std::memory_order_relaxed)) return false;
    std::atomic_thread_fence(std::memory_order_release);
    uint64_t w[kWords] = {};
    std::memcpy(w, &v, sizeof(T));
    for (size_t i = 0; i < kWords; ++i) words_[i].store(w[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
    return true;
  }

  /// Copies the latest value into `out` and its version (1 for the first write, 2 for the
  /// second, ...; 0 before any). False (out untouched) when a write overlapped the read.
  bool tryRead(T& out, uint64_t& version) const noexcept {
    const uint64_t s1 = seq_.load(std::memory_order_acquire);
    if (s1 & 1) return false;
    uint64_t w[kWords];
    for (size_t i = 0; i < kWords; ++i) w[i] = words_[i].load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) != s1) return false;
    std::memcpy(static_cast<void*>(&out), w, sizeof(T));
    version = s1 / 2;
    return true;
  }

  /// tryRead up to `attempts` times (a writer holds the sequence odd for a few nanoseconds).
  bool read(T& out, uint64_t& version, int attempts = 64) const noexcept {
    for (int i = 0; i < attempts; ++i)
      if (tryRead(out, version)) return true;
    return false;
  }

  /// Number of completed writes (the version the next successful read returns, or newer).
  uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  alignas(64) std::atomic<uint64_t> seq_{0};
  std::atomic<uint64_t> words_[kWords] = {};
};

}  // namespace sf::rt
