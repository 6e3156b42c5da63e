// SPDX-License-Identifier: Apache-2.0
// One servo tick as an object: render, safety, deadline and step-time statistics, records.
// For host applications whose own 1 kHz callback drives the device (OpenHaptics HD scheduler,
// CHAI3D haptic thread, HAPI, ros2_control update()), and the core of ServoLoop.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>

#include <smoothforce/force/force_method.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/device.h>
#include <smoothforce/runtime/device_transform.h>
#include <smoothforce/runtime/latency_histogram.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/spsc_ring.h>

namespace sf::rt {

/// Options of a servo step. Units: Hz.
struct StepOptions {
  double rate = 1000;      ///< nominal servo rate, Hz, in [1, 10000]: a step is due one period after its tick
  DeviceTransform device;  ///< device-to-world transform: HIPs in, forces out
};

/// Throws InputError naming the option ("--rate: ...") when out of range.
void validate(const StepOptions& o);

/// Step flags beside the SafetyFlag bits (bits 0-7), also written to the record.
enum StepFlag : uint32_t {
  kStepNoSample = 1u << 8,  ///< the device has no sample yet: nothing rendered, zero force
  kStepStale = 1u << 9,     ///< the device's watchdog expired: Fault::StaleDevice latched, zero force
};

/// One step as handed to the record writer (plain data, copied through the ring).
struct StepRecord {
  int64_t tick = 0;         ///< tick index k (fixed rate: deadline t0 + k / rate; device-paced: the step number)
  double t = 0;             ///< wake-up time, s since the loop start
  double hip[3] = {};       ///< HIP, m, world frame
  double force[3] = {};     ///< force commanded (after safety), N, world frame
  double rendered[3] = {};  ///< force from the renderer (before safety), N, world frame
  double compute = 0;       ///< s from wake-up to the force written
  double lateness = 0;      ///< s from the tick to the wake-up
  uint32_t flags = 0;       ///< SafetyFlag | StepFlag bits
  uint8_t contact = 0;      ///< renderer reported contact
  uint64_t sample = 0;      ///< the device's sample number (DeviceState::sample)
  double age = 0;           ///< s from the sample's arrival to the read (DeviceState::age)
};

/// What a run measured.
struct LoopStats {
  int64_t ticks = 0;            ///< ticks scheduled (fixed rate: round(duration * rate); device-paced: steps)
  int64_t steps = 0;            ///< steps run (ticks - skipped, fewer when stopped)
  int64_t missedDeadlines = 0;  ///< steps that ended after the next tick
  int64_t skippedTicks = 0;     ///< ticks that passed during an overrunning step (not run)
  int64_t contactSteps = 0, contactOnsets = 0;
  int64_t recordsDropped = 0;  ///< the ring was full (the writer fell behind)
  LatencyHistogram compute;    ///< wake-up to force written, per step
  LatencyHistogram lateness;   ///< tick to wake-up, per step
  double elapsed = 0;          ///< s from the first tick to the end
  bool stopped = false;        ///< ended by the stop flag
  bool paced = false;          ///< device-paced: one step per device sample
};

/// When a step happens, in seconds on the caller's clock (any origin, e.g. the host SDK's).
struct StepTime {
  double wake = 0;  ///< when the step started (the device was just read)
  /// When the step was due. NaN: from the step's own schedule (see ServoStep).
  double tick = std::numeric_limits<double>::quiet_NaN();
  int64_t index = -1;  ///< tick index for the record; -1: from the own schedule, or the step count
};

/// What a step commands.
struct StepOutput {
  Eigen::Vector3d force{0, 0, 0};       ///< N, device frame, after safety: write this to the device
  Eigen::Vector3d worldForce{0, 0, 0};  ///< N, world frame, after safety
  Eigen::Vector3d hip{0, 0, 0};         ///< HIP, m, world frame
  ForceSample sample;                   ///< the renderer's result, world frame (its force is before safety)
  uint32_t flags = 0;                   ///< SafetyFlag | StepFlag bits
  bool faulted = false;                 ///< a fault is latched: the force is zero
};

/// One servo tick, called by whoever owns the timing. step() does what one ServoLoop tick does
/// between reading the device and writing the force:
///   1. the HIP is mapped device -> world (StepOptions::device); a Stale device latches
///      Fault::StaleDevice, NoSample renders nothing; a non-finite HIP is not rendered;
///   2. sample = renderer.step(hip); force = safety.filter(t, hip, sample.force); the force is
///      rotated back to the device frame (not scaled: device_transform.h);
///   3. the step ended at wake + the compute time measured with the clock; it missed its
///      deadline when it ended after tick + 1 / rate: the safety layer counts it (a fault after
///      too many in a row: step() then returns zero force);
///   4. compute time, lateness, contacts go into preallocated histograms and counters; the
///      step's record goes to the ring (dropped and counted when full).
/// Times: t = wake - origin, s, where the origin is set by start() or else is the first step's
/// tick (or wake). The own schedule (StepTime::tick NaN), for hosts that only know when their
/// callback runs: tick k is origin + k / rate; each call takes the next tick, or, when it
/// comes later than the tick after that, the latest tick at or before it (the ticks between
/// count as skipped); a call before its tick re-anchors the schedule on that call (lateness
/// 0), so lateness is measured against the earliest phase seen.
/// The constructor allocates everything; the step does not allocate, lock, throw or do I/O.
/// One thread at a time calls the step methods.
class ServoStep {
 public:
  /// Throws InputError for bad options. renderer, safety, records and clock must outlive the
  /// step. clock: measures the compute time in step() (nullptr: a monotonic SteadyClock).
  ServoStep(ForceRenderer& renderer, SafetyFilter& safety, const StepOptions& options = {},
            SpscRing<StepRecord>* records = nullptr, Clock* clock = nullptr);
  ServoStep(const ServoStep&) = delete;
  ServoStep& operator=(const ServoStep&) = delete;

  /// Sets the time origin (caller's clock, s) before the first step.
  void start(double origin) noexcept;
  /// One whole step: render(), then finish() at wake + the compute time. Returns the force
  /// to command (zero when the step latched a fault).
  StepOutput step(const StepTime& time, const DeviceState& device) noexcept;
  /// The two halves of step(), for callers that want the device write inside the timed part
  /// (ServoLoop): render() returns the force; write it, then call finish(end) with the time
  /// (caller's clock) the force was written. finish returns true when it latched the
  /// missed-deadline fault: command zero force at once.
  StepOutput render(const StepTime& time, const DeviceState& device) noexcept;
  bool finish(double end) noexcept;

  const LoopStats& stats() const noexcept { return stats_; }
  /// For loops built on the step (ServoLoop): ticks, skipped ticks, elapsed, stopped, paced.
  LoopStats& loopStats() noexcept { return stats_; }
  const StepOptions& options() const noexcept { return options_; }
  double origin() const noexcept { return origin_; }

 private:
  ForceRenderer& renderer_;
  SafetyFilter& safety_;
  StepOptions options_;
  SpscRing<StepRecord>* records_;
  std::unique_ptr<Clock> ownClock_;
  Clock& clock_;
  double period_;
  LoopStats stats_;
  bool started_ = false, wasContact_ = false, pending_ = false;
  double origin_ = 0;
  double anchor_ = 0;       ///< own schedule: time of tick 0
  int64_t lastIndex_ = -1;  ///< own schedule: the last tick taken
  StepRecord rec_;          ///< the step between render() and finish()
  double wake_ = 0, tick_ = 0;
};

}  // namespace sf::rt
