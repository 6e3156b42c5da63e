// The fixed-rate servo loop: device -> renderer -> safety -> device, on absolute deadlines.
#pragma once

#include <atomic>
#include <cstdint>

#include <smoothforce/force/force_method.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/device.h>
#include <smoothforce/runtime/latency_histogram.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/spsc_ring.h>

namespace sf::rt {

/// Loop timing. Units: Hz, seconds.
struct LoopOptions {
  double rate = 1000;    ///< servo rate, Hz, in [1, 10000]
  double duration = 10;  ///< s (> 0, finite): the loop runs round(duration * rate) ticks
  /// When set and true, the loop stops before its next step (e.g. from a SIGINT handler).
  const std::atomic<bool>* stop = nullptr;
};

/// Throws InputError naming the option ("--rate: ...") when out of range.
void validate(const LoopOptions& o);

/// One step as handed to the record writer (plain data, copied through the ring).
struct StepRecord {
  int64_t tick = 0;         ///< tick index k (deadline t0 + k / rate)
  double t = 0;             ///< wake-up time, s since the loop start
  double hip[3] = {};       ///< HIP read from the device, m
  double force[3] = {};     ///< force commanded to the device (after safety), N
  double rendered[3] = {};  ///< force from the renderer (before safety), N
  double compute = 0;       ///< s from wake-up to the force written
  double lateness = 0;      ///< s from the tick to the wake-up
  uint32_t flags = 0;       ///< SafetyFlag bits
  uint8_t contact = 0;      ///< renderer reported contact
};

/// What a run measured.
struct LoopStats {
  int64_t ticks = 0;            ///< ticks scheduled: round(duration * rate)
  int64_t steps = 0;            ///< steps run (ticks - skipped, fewer when stopped)
  int64_t missedDeadlines = 0;  ///< steps that ended after the next tick
  int64_t skippedTicks = 0;     ///< ticks that passed during an overrunning step (not run)
  int64_t contactSteps = 0, contactOnsets = 0;
  int64_t recordsDropped = 0;  ///< the ring was full (the writer fell behind)
  LatencyHistogram compute;    ///< wake-up to force written, per step
  LatencyHistogram lateness;   ///< tick to wake-up, per step
  double elapsed = 0;          ///< s from the first tick to the end
  bool stopped = false;        ///< ended by the stop flag
};

/// Runs the servo loop. Each step k:
///   1. clock.sleepUntil(t0 + k / rate) (absolute deadlines: no drift; SteadyClock sleeps
///      then spins for the last part), wake = now;
///   2. hip = device.read(wake - t0); sample = renderer.step(hip) (skipped when the HIP is
///      not finite);
///   3. force = safety.filter(wake - t0, hip, sample.force); device.writeForce(force);
///   4. end = now; the step missed its deadline when end > t0 + (k+1) / rate: the safety
///      layer counts it (a fault after too many in a row commands zero force at once) and
///      the ticks that have passed are skipped, not run in a burst;
///   5. the step's record goes to the ring (dropped and counted when full) for the writer
///      thread; statistics are updated in preallocated histograms.
/// The constructor allocates everything; run() does not allocate, lock, throw or do I/O.
class ServoLoop {
 public:
  /// Throws InputError for bad options. The references must outlive the loop.
  ServoLoop(HapticDevice& device, ForceRenderer& renderer, SafetyFilter& safety, Clock& clock,
            const LoopOptions& options, SpscRing<StepRecord>* records = nullptr);
  /// Runs round(duration * rate) ticks (or until stopped). Call once.
  void run() noexcept;
  const LoopStats& stats() const noexcept { return stats_; }

 private:
  HapticDevice& device_;
  ForceRenderer& renderer_;
  SafetyFilter& safety_;
  Clock& clock_;
  LoopOptions options_;
  SpscRing<StepRecord>* records_;
  LoopStats stats_;
};

}  // namespace sf::rt
