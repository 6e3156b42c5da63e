// SPDX-License-Identifier: Apache-2.0
// Clocks for the servo loop: the real monotonic clock (sleep, then spin), a fake clock for
// deterministic tests, and a fast-forward clock for overhead benchmarks.
#pragma once

#include <functional>

namespace sf::rt {

/// Time source and absolute-deadline waiting of the servo loop. Times are seconds on the
/// clock's own monotonic axis (any origin). Both calls are real-time safe: no allocation,
/// locking, throwing or I/O.
class Clock {
 public:
  virtual ~Clock() = default;
  /// Current time, s.
  virtual double now() noexcept = 0;
  /// Returns at or after `deadline` (s); immediately when the deadline has passed.
  virtual void sleepUntil(double deadline) noexcept = 0;
};

/// CLOCK_MONOTONIC, seconds since the object was constructed. sleepUntil sleeps with
/// clock_nanosleep(TIMER_ABSTIME) until `spin` seconds before the deadline, then busy-waits
/// for the rest: the OS wake-up jitter (tens of us on a loaded machine) is absorbed by the
/// spin, at the price of one core being busy for `spin` per period.
class SteadyClock final : public Clock {
 public:
  /// spin: busy-wait before each deadline, s (>= 0; 200 us by default).
  explicit SteadyClock(double spin = 200e-6);
  double now() noexcept override;
  void sleepUntil(double deadline) noexcept override;
  double spin() const { return spin_; }

 private:
  double spin_;
  long long originNs_;  ///< CLOCK_MONOTONIC at construction, ns
};

/// Deterministic time for tests: time moves only when told. sleepUntil(d) jumps to
/// max(now, d) + wakeLatency(d) (the hook simulates late wake-ups; zero when empty);
/// advance(dt) simulates compute time (call it from a fake renderer or device).
class FakeClock final : public Clock {
 public:
  explicit FakeClock(double start = 0) : t_(start) {}
  double now() noexcept override { return t_; }
  void sleepUntil(double deadline) noexcept override;
  /// Moves time forward by dt >= 0 s.
  void advance(double dt) noexcept { t_ += dt; }
  /// Lateness added to each wake-up, s, given the deadline (tests only; may be empty).
  std::function<double(double deadline)> wakeLatency;

 private:
  double t_;
};

/// Real time while computing, no time while sleeping: now() is the monotonic clock plus an
/// offset, and sleepUntil(d) adds d - now() to the offset instead of sleeping. The loop then
/// measures its true per-step compute time while running as fast as the CPU allows
/// (benchmarks of loop overhead; offline runs).
class FastForwardClock final : public Clock {
 public:
  double now() noexcept override { return real_.now() + offset_; }
  void sleepUntil(double deadline) noexcept override;

 private:
  SteadyClock real_{0};
  double offset_ = 0;
};

}  // namespace sf::rt
