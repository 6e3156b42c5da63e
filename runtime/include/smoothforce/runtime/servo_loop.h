// SPDX-License-Identifier: Apache-2.0
// The servo loop: device -> ServoStep (renderer, safety, statistics, records) -> device, on
// absolute deadlines (fixed rate) or one step per device sample (device-paced).
#pragma once

#include <atomic>
#include <cstdint>

#include <smoothforce/force/force_method.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/device.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/servo_step.h>
#include <smoothforce/runtime/spsc_ring.h>

namespace sf::rt {

/// Loop timing. Units: Hz, seconds.
struct LoopOptions {
  double rate = 1000;    ///< servo rate, Hz, in [1, 10000] (device-paced: the nominal sample rate, for deadlines)
  double duration = 10;  ///< s (> 0, finite): the loop runs round(duration * rate) ticks (device-paced: this long)
  /// When set and true, the loop stops before its next step (e.g. from a SIGINT handler).
  const std::atomic<bool>* stop = nullptr;
  /// One step per device sample instead of a fixed rate (the device must canPace(), e.g. udp).
  bool devicePaced = false;
  DeviceTransform deviceTransform;  ///< device-to-world transform (device_transform.h)
};

/// Throws InputError naming the option ("--rate: ...") when out of range.
void validate(const LoopOptions& o);

/// Runs the servo loop on a ServoStep. Fixed rate, each step k:
///   1. clock.sleepUntil(t0 + k / rate) (absolute deadlines: no drift; SteadyClock sleeps
///      then spins for the last part), wake = now;
///   2. state = device.read(wake - t0); force = ServoStep::render(...) (servo_step.h: HIP to
///      the world, renderer, safety, force back to the device frame); device.commandForce;
///   3. end = now; ServoStep::finish(end): the step missed its deadline when end > t0 + (k+1)
///      / rate (a fault after too many in a row commands zero force at once); the ticks that
///      have passed are skipped, not run in a burst; statistics and the record.
/// Device-paced (LoopOptions::devicePaced): for `duration` s the loop waits for the device's
/// next sample (device.waitForSample, at most 50 ms at a time so that the stop flag is seen),
/// then runs one step with tick = the sample's arrival (lateness = its age at wake-up) and the
/// deadline one nominal period later. A wait that ends without a sample runs a step only when
/// the device reports Stale (its watchdog latches the fault and zero force is commanded).
/// The constructor allocates everything; run() does not allocate, lock, throw or do I/O
/// (device-paced, the device's wait blocks: udp_device.h).
class ServoLoop {
 public:
  /// Throws InputError for bad options or a devicePaced loop on a device that cannot pace.
  /// The references must outlive the loop.
  ServoLoop(HapticDevice& device, ForceRenderer& renderer, SafetyFilter& safety, Clock& clock,
            const LoopOptions& options, SpscRing<StepRecord>* records = nullptr);
  /// Runs round(duration * rate) ticks, or device-paced for `duration` s (or until stopped).
  /// Call once.
  void run() noexcept;
  const LoopStats& stats() const noexcept { return step_.stats(); }

 private:
  void runFixedRate() noexcept;
  void runPaced() noexcept;
  /// Writes the step's force, finishes it; returns the end time (s since t0).
  double command(const StepOutput& out, double t, double t0) noexcept;

  HapticDevice& device_;
  SafetyFilter& safety_;
  Clock& clock_;
  LoopOptions options_;
  ServoStep step_;
};

}  // namespace sf::rt
