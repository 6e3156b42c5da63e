// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/servo_loop.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/loop_option_text.h>

namespace sf::rt {

void validate(const LoopOptions& o) {
  checkLoopOption("rate", o.rate, OptionSpelling::Flag);
  checkLoopOption("duration", o.duration, OptionSpelling::Flag);
  if (o.duration * o.rate > 9e15) throw InputError("--duration: too long");
}

namespace {
StepOptions stepOptions(const LoopOptions& o) {
  validate(o);
  StepOptions s;
  s.rate = o.rate;
  s.device = o.deviceTransform;
  return s;
}
}  // namespace

ServoLoop::ServoLoop(HapticDevice& device, ForceRenderer& renderer, SafetyFilter& safety, Clock& clock,
                     const LoopOptions& options, SpscRing<StepRecord>* records)
    : device_(device),
      safety_(safety),
      clock_(clock),
      options_(options),
      step_(renderer, safety, stepOptions(options), records, &clock) {
  if (options_.devicePaced && !device_.canPace())
    throw InputError("--paced: the device (" + device_.describe() + ") cannot pace the loop; use a udp: device");
}

void ServoLoop::run() noexcept {
  if (options_.devicePaced)
    runPaced();
  else
    runFixedRate();
}

double ServoLoop::command(const StepOutput& out, double t, double t0) noexcept {
  ForceStatus status;
  status.loopTime = t;
  status.flags = out.flags;
  status.fault = safety_.counters().fault;
  status.contact = out.sample.contact;
  device_.commandForce(out.force, status);
  const double end = clock_.now() - t0;
  if (step_.finish(end)) {
    status.flags |= kSafetyFaulted;
    status.fault = safety_.counters().fault;
    device_.commandForce(Eigen::Vector3d::Zero(), status);
  }
  return end;
}

void ServoLoop::runFixedRate() noexcept {
  const double period = 1.0 / options_.rate;
  const int64_t ticks = std::max<int64_t>(1, std::llround(options_.duration * options_.rate));
  LoopStats& st = step_.loopStats();
  st.ticks = ticks;
  const double t0 = clock_.now();
  step_.start(0);
  int64_t k = 0;
  while (k < ticks) {
    if (options_.stop && options_.stop->load(std::memory_order_relaxed)) {
      st.stopped = true;
      break;
    }
    const double tick = static_cast<double>(k) * period;
    clock_.sleepUntil(t0 + tick);
    const double t = clock_.now() - t0;
    StepTime time;
    time.wake = t;
    time.tick = tick;
    time.index = k;
    const StepOutput out = step_.render(time, device_.read(t));
    const double end = command(out, t, t0);

    int64_t nextK = k + 1;
    if (end > static_cast<double>(k + 1) * period) {
      // The first tick at or after `end` (tolerating rounding of a millionth of a period).
      const auto firstFuture = static_cast<int64_t>(std::ceil(end / period - 1e-6));
      if (firstFuture > nextK) {
        st.skippedTicks += std::min(firstFuture, ticks) - nextK;
        nextK = firstFuture;
      }
    }
    k = nextK;
  }
  st.elapsed = clock_.now() - t0;
}

void ServoLoop::runPaced() noexcept {
  LoopStats& st = step_.loopStats();
  st.paced = true;
  const double t0 = clock_.now();
  step_.start(0);
  int64_t k = 0;
  for (;;) {
    if (options_.stop && options_.stop->load(std::memory_order_relaxed)) {
      st.stopped = true;
      break;
    }
    const double left = options_.duration - (clock_.now() - t0);
    if (!(left > 0)) break;
    const bool fresh = device_.waitForSample(std::min(left, 0.05));
    const double t = clock_.now() - t0;
    const DeviceState ds = device_.read(t);
    if (!fresh && ds.status != DeviceStatus::Stale) continue;
    StepTime time;
    time.wake = t;
    time.tick = t - std::max(0.0, ds.age);
    time.index = k++;
    const StepOutput out = step_.render(time, ds);
    command(out, t, t0);
  }
  st.ticks = st.steps;
  st.elapsed = clock_.now() - t0;
}

}  // namespace sf::rt
