// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/safety.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/loop_option_text.h>

namespace sf::rt {

void validate(const SafetyOptions& o) { checkSafetyOptions(o, OptionSpelling::Flag); }

const char* toString(Fault f) {
  switch (f) {
    case Fault::None:
      return "none";
    case Fault::NonFiniteHip:
      return "non-finite HIP position";
    case Fault::NonFiniteForce:
      return "non-finite force";
    case Fault::MissedDeadlines:
      return "consecutive missed deadlines";
    case Fault::StaleDevice:
      return "stale device (no sample within the watchdog time)";
    case Fault::NonFiniteTime:
      return "non-finite step time";
  }
  return "?";
}

SafetyFilter::SafetyFilter(const SafetyOptions& options) : options_(options) { validate(options_); }

void SafetyFilter::latch(Fault f, double t) noexcept {
  if (counters_.fault == Fault::None) {
    counters_.fault = f;
    counters_.faultTime = t;
  }
  last_.setZero();
}

Eigen::Vector3d SafetyFilter::filter(double t, const Eigen::Vector3d& hip, const Eigen::Vector3d& force,
                                     uint32_t* flags) noexcept {
  uint32_t fl = 0;
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  if (faulted()) {
    fl |= kSafetyFaulted;
  } else if (!std::isfinite(t) || !hip.allFinite() || !force.allFinite()) {
    // a non-finite time (a caller's clock: the C API, Python) would skip the ramp-in
    ++counters_.nonFinite;
    latch(!std::isfinite(t) ? Fault::NonFiniteTime : (hip.allFinite() ? Fault::NonFiniteForce : Fault::NonFiniteHip), t);
    fl |= kSafetyFaulted;
  } else {
    out = force;
    double mag = out.norm();
    if (std::isinf(mag)) mag = out.stableNorm();  // a finite force beyond 1e154 N: its norm() overflows
    if (mag > options_.maxForce) {
      out *= options_.maxForce / mag;
      ++counters_.clamps;
      fl |= kSafetyClamped;
    }
    if (options_.rampTime > 0 && t < options_.rampTime) {
      out *= t > 0 ? t / options_.rampTime : 0.0;
      fl |= kSafetyRamping;
    }
    const Eigen::Vector3d delta = out - last_;
    double step = delta.norm();
    if (std::isinf(step) && delta.allFinite()) step = delta.stableNorm();
    if (step > options_.maxForceStep) {
      out = last_ + delta * (options_.maxForceStep / step);
      ++counters_.rateLimits;
      fl |= kSafetyRateLimited;
    }
    last_ = out;
  }
  if (flags) *flags = fl;
  return out;
}

bool SafetyFilter::noteDeadline(bool missed, double t) noexcept {
  if (!missed) {
    consecutiveMisses_ = 0;
    return false;
  }
  ++counters_.missedDeadlines;
  ++consecutiveMisses_;
  if (consecutiveMisses_ > counters_.maxConsecutiveMisses) counters_.maxConsecutiveMisses = consecutiveMisses_;
  if (consecutiveMisses_ >= options_.maxConsecutiveMisses && !faulted()) {
    latch(Fault::MissedDeadlines, t);
    return true;
  }
  return false;
}

bool SafetyFilter::trip(Fault f, double t) noexcept {
  if (f == Fault::None || faulted()) return false;
  latch(f, t);
  return true;
}

void SafetyFilter::reset() noexcept {
  counters_ = SafetyCounters{};
  last_.setZero();
  consecutiveMisses_ = 0;
}

}  // namespace sf::rt
