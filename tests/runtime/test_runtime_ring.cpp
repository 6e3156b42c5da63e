// SPDX-License-Identifier: Apache-2.0
// The lock-free SPSC ring: FIFO order, full/empty behaviour, producer/consumer stress.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <smoothforce/runtime/servo_loop.h>
#include <smoothforce/runtime/spsc_ring.h>

namespace {

using sf::rt::SpscRing;

TEST(RuntimeRing, CapacityIsPowerOfTwo) {
  EXPECT_EQ(SpscRing<int>(0).capacity(), 2u);
  EXPECT_EQ(SpscRing<int>(5).capacity(), 8u);
  EXPECT_EQ(SpscRing<int>(1024).capacity(), 1024u);
}

TEST(RuntimeRing, FifoFullAndEmpty) {
  SpscRing<int> r(4);
  int v = -1;
  EXPECT_FALSE(r.tryPop(v));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(r.tryPush(i));
  EXPECT_FALSE(r.tryPush(99));  // full: nothing stored
  EXPECT_EQ(r.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(r.tryPop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(r.tryPop(v));
  // Wrap around many times.
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(r.tryPush(i));
    ASSERT_TRUE(r.tryPop(v));
    ASSERT_EQ(v, i);
  }
}

/// One producer, one consumer, a small ring (so both sides hit full and empty often),
/// records carrying a sequence number and a checksum of their payload. Bounded: stops after
/// 300 ms or 2 million records, whichever first.
TEST(RuntimeRing, ProducerConsumerStressKeepsOrder) {
  struct Rec {
    int64_t seq;
    double payload[6];
    uint64_t check;
  };
  SpscRing<Rec> ring(64);
  constexpr int64_t kMax = 2'000'000;
  std::atomic<bool> stopProducing{false};
  std::atomic<int64_t> produced{0};
  std::thread producer([&] {
    int64_t seq = 0;
    while (seq < kMax && !stopProducing.load(std::memory_order_relaxed)) {
      Rec r;
      r.seq = seq;
      for (int i = 0; i < 6; ++i) r.payload[i] = double(seq * 7 + i);
      r.check = uint64_t(seq) * 0x9E3779B97F4A7C15ull;
      if (ring.tryPush(r))
        ++seq;
      else
        std::this_thread::yield();
    }
    produced.store(seq, std::memory_order_release);
  });
  int64_t expect = 0, bad = 0;
  const auto start = std::chrono::steady_clock::now();
  bool timeUp = false;
  for (;;) {
    Rec r;
    if (ring.tryPop(r)) {
      bool ok = r.seq == expect && r.check == uint64_t(r.seq) * 0x9E3779B97F4A7C15ull;
      for (int i = 0; i < 6; ++i) ok = ok && r.payload[i] == double(r.seq * 7 + i);
      bad += !ok;
      expect = r.seq + 1;
      continue;
    }
    if (!timeUp && std::chrono::steady_clock::now() - start > std::chrono::milliseconds(300)) {
      timeUp = true;
      stopProducing.store(true);
    }
    const int64_t p = produced.load(std::memory_order_acquire);
    if (p > 0 && expect == p) break;  // producer finished and everything was drained
    if (expect == kMax) break;
    std::this_thread::yield();
  }
  producer.join();
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(expect, produced.load());
  EXPECT_GT(expect, 1000);  // it did run
  RecordProperty("records", std::to_string(expect));
}

TEST(RuntimeRing, StepRecordIsPlainData) {
  static_assert(std::is_trivially_copyable_v<sf::rt::StepRecord>);
  SpscRing<sf::rt::StepRecord> r(8);
  sf::rt::StepRecord a;
  a.tick = 42;
  a.force[2] = 1.5;
  ASSERT_TRUE(r.tryPush(a));
  sf::rt::StepRecord b;
  ASSERT_TRUE(r.tryPop(b));
  EXPECT_EQ(b.tick, 42);
  EXPECT_EQ(b.force[2], 1.5);
}

}  // namespace
