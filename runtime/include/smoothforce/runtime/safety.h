// SPDX-License-Identifier: Apache-2.0
// The safety layer between the force renderer and the device.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace sf::rt {

/// Limits of the safety layer. Units: newtons, seconds.
struct SafetyOptions {
  double maxForce = 3.3;          ///< |F| limit, N (> 0); larger forces are scaled down, keeping direction
  double maxForceStep = 0.5;      ///< |F_k - F_{k-1}| limit per step, N (> 0; +inf disables)
  double rampTime = 0.5;          ///< linear force ramp-in from the loop start, s (>= 0; 0 disables)
  int maxConsecutiveMisses = 10;  ///< missed deadlines in a row that latch a fault (>= 1)
};

/// Throws InputError naming the option ("--max-force: ...") when a limit is out of range.
void validate(const SafetyOptions& o);

/// Why the output was latched to zero. StaleDevice: the device's watchdog expired (no fresh
/// sample within its time, e.g. a network device whose sender stopped; DeviceStatus::Stale).
enum class Fault : uint8_t { None, NonFiniteHip, NonFiniteForce, MissedDeadlines, StaleDevice, NonFiniteTime };
const char* toString(Fault f);

/// Per-step flags (bits), also written to the record.
enum SafetyFlag : uint32_t {
  kSafetyClamped = 1u << 0,         ///< |F| exceeded maxForce
  kSafetyRateLimited = 1u << 1,     ///< the change from the last output exceeded maxForceStep
  kSafetyRamping = 1u << 2,         ///< inside the ramp-in
  kSafetyFaulted = 1u << 3,         ///< output latched to zero
  kSafetyMissedDeadline = 1u << 4,  ///< this step ended after the next tick
};

/// Event counts (steps on which each rule fired).
struct SafetyCounters {
  int64_t clamps = 0, rateLimits = 0, nonFinite = 0, missedDeadlines = 0;
  int maxConsecutiveMisses = 0;
  Fault fault = Fault::None;  ///< first latched fault
  double faultTime = 0;       ///< s since the loop start
};

/// Applies, in order, to the renderer's force F at time t (s since the loop start):
///  1. latched fault: output 0 (and nothing else);
///  2. non-finite HIP or F: output 0 and latch a fault;
///  3. clamp: F *= maxForce / |F| when |F| > maxForce (direction kept);
///  4. ramp-in: F *= min(1, t / rampTime);
///  5. rate limit: move from the previous output towards F by at most maxForceStep.
/// The rate limit comes last, so no output ever jumps by more than maxForceStep (except to
/// zero on a fault), and as it interpolates between two forces within maxForce, the output
/// stays within maxForce. noteDeadline latches a fault after maxConsecutiveMisses missed
/// deadlines in a row. A latched fault holds until reset(). All methods except the
/// constructor are real-time safe.
class SafetyFilter {
 public:
  /// Throws InputError for options out of range (see validate).
  explicit SafetyFilter(const SafetyOptions& options = {});

  /// The force to command for renderer force `force` (N) at HIP `hip` (m), time t (s).
  /// flags (optional) receives SafetyFlag bits for this step.
  Eigen::Vector3d filter(double t, const Eigen::Vector3d& hip, const Eigen::Vector3d& force,
                         uint32_t* flags = nullptr) noexcept;
  /// Reports whether the step at time t missed its deadline. True when this call latched
  /// the fault (the caller should command zero force at once).
  bool noteDeadline(bool missed, double t) noexcept;
  /// Latches fault `f` (not None) at time t (s since the loop start) for a condition found
  /// outside the filter (a stale device). True when this call latched it (no earlier fault).
  bool trip(Fault f, double t) noexcept;

  bool faulted() const noexcept { return counters_.fault != Fault::None; }
  const SafetyCounters& counters() const noexcept { return counters_; }
  const SafetyOptions& options() const noexcept { return options_; }
  /// Clears the fault latch, the previous output and the counters (an operator action;
  /// the loop never calls it).
  void reset() noexcept;

 private:
  void latch(Fault f, double t) noexcept;

  SafetyOptions options_;
  SafetyCounters counters_;
  Eigen::Vector3d last_{0, 0, 0};  ///< previous output, N
  int consecutiveMisses_ = 0;
};

}  // namespace sf::rt
