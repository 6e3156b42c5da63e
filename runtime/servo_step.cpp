// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/servo_step.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/loop_option_text.h>

namespace sf::rt {

void validate(const StepOptions& o) { checkLoopOption("rate", o.rate, OptionSpelling::Flag); }

namespace {
std::unique_ptr<Clock> ownClock(Clock* given) { return given ? nullptr : std::make_unique<SteadyClock>(0.0); }
}  // namespace

ServoStep::ServoStep(ForceRenderer& renderer, SafetyFilter& safety, const StepOptions& options,
                     SpscRing<StepRecord>* records, Clock* clock)
    : renderer_(renderer),
      safety_(safety),
      options_(options),
      records_(records),
      ownClock_(ownClock(clock)),
      clock_(clock ? *clock : *ownClock_),
      period_(0) {
  validate(options_);
  period_ = 1.0 / options_.rate;
}

void ServoStep::start(double origin) noexcept {
  origin_ = origin;
  started_ = true;
}

StepOutput ServoStep::render(const StepTime& time, const DeviceState& ds) noexcept {
  const bool own = std::isnan(time.tick);
  if (!started_) start(own ? time.wake : time.tick);
  double tick;
  int64_t index;
  if (own) {
    // The own schedule: tick k at anchor_ + k * period_ (anchor_ = origin_ until re-anchored).
    if (lastIndex_ < 0) {
      anchor_ = origin_;
      index = std::max<int64_t>(0, static_cast<int64_t>(std::floor((time.wake - anchor_) / period_ + 1e-9)));
    } else {
      index = lastIndex_ + 1;
      if (time.wake < anchor_ + static_cast<double>(index) * period_) {
        anchor_ = time.wake - static_cast<double>(index) * period_;  // early: re-anchor on this call
      } else {
        const auto latest = static_cast<int64_t>(std::floor((time.wake - anchor_) / period_ + 1e-9));
        if (latest > index) {
          stats_.skippedTicks += latest - index;
          index = latest;
        }
      }
    }
    lastIndex_ = index;
    tick = anchor_ + static_cast<double>(index) * period_;
  } else {
    tick = time.tick;
    index = time.index >= 0 ? time.index : stats_.steps;
  }
  const double t = time.wake - origin_;
  wake_ = time.wake;
  tick_ = tick;

  StepOutput out;
  uint32_t flags = 0;
  out.hip = options_.device.toWorld(ds.position);
  if (ds.status == DeviceStatus::Stale) {
    safety_.trip(Fault::StaleDevice, t);
    flags |= kStepStale;
  } else if (ds.status == DeviceStatus::NoSample) {
    flags |= kStepNoSample;
  } else if (out.hip.allFinite()) {
    out.sample = renderer_.step(out.hip);
  }
  uint32_t safetyFlags = 0;
  out.worldForce = safety_.filter(t, out.hip, out.sample.force, &safetyFlags);
  out.force = options_.device.forceToDevice(out.worldForce);
  out.flags = flags | safetyFlags;
  out.faulted = safety_.faulted();

  rec_ = StepRecord{};
  rec_.tick = index;
  rec_.t = t;
  for (int i = 0; i < 3; ++i) {
    rec_.hip[i] = out.hip[i];
    rec_.force[i] = out.worldForce[i];
    rec_.rendered[i] = out.sample.force[i];
  }
  rec_.flags = out.flags;
  rec_.contact = out.sample.contact ? 1 : 0;
  rec_.sample = ds.sample;
  rec_.age = ds.age;
  pending_ = true;
  return out;
}

bool ServoStep::finish(double end) noexcept {
  if (!pending_) return false;
  pending_ = false;
  const bool missed = end > tick_ + period_;
  if (missed) rec_.flags |= kSafetyMissedDeadline;
  const bool latched = safety_.noteDeadline(missed, end - origin_);
  if (latched) rec_.flags |= kSafetyFaulted;

  LoopStats& st = stats_;
  ++st.steps;
  if (missed) ++st.missedDeadlines;
  st.compute.add(end - wake_);
  st.lateness.add(wake_ - tick_);
  if (rec_.contact) {
    ++st.contactSteps;
    if (!wasContact_) ++st.contactOnsets;
  }
  wasContact_ = rec_.contact != 0;
  if (records_) {
    rec_.compute = end - wake_;
    rec_.lateness = wake_ - tick_;
    if (!records_->tryPush(rec_)) ++st.recordsDropped;
  }
  return latched;
}

StepOutput ServoStep::step(const StepTime& time, const DeviceState& device) noexcept {
  const double c0 = clock_.now();
  StepOutput out = render(time, device);
  const double end = time.wake + (clock_.now() - c0);
  if (finish(end)) {
    out.force.setZero();
    out.worldForce.setZero();
    out.faulted = true;
  }
  out.flags = rec_.flags;
  return out;
}

}  // namespace sf::rt
