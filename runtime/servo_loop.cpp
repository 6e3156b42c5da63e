#include <smoothforce/runtime/servo_loop.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <smoothforce/mesh/mesh.h>

namespace sf::rt {

void validate(const LoopOptions& o) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (!(o.rate >= 1 && o.rate <= 10000))
    throw InputError("--rate: expected a rate in [1, 10000] Hz, got " + num(o.rate));
  if (!(o.duration > 0) || !std::isfinite(o.duration))
    throw InputError("--duration: expected a finite duration > 0 s, got " + num(o.duration));
  if (o.duration * o.rate > 9e15) throw InputError("--duration: too long");
}

ServoLoop::ServoLoop(HapticDevice& device, ForceRenderer& renderer, SafetyFilter& safety, Clock& clock,
                     const LoopOptions& options, SpscRing<StepRecord>* records)
    : device_(device), renderer_(renderer), safety_(safety), clock_(clock), options_(options), records_(records) {
  validate(options_);
}

void ServoLoop::run() noexcept {
  const double period = 1.0 / options_.rate;
  const int64_t ticks = std::max<int64_t>(1, std::llround(options_.duration * options_.rate));
  LoopStats& st = stats_;
  st.ticks = ticks;
  bool wasContact = false;
  const double t0 = clock_.now();
  int64_t k = 0;
  while (k < ticks) {
    if (options_.stop && options_.stop->load(std::memory_order_relaxed)) {
      st.stopped = true;
      break;
    }
    const double tick = t0 + static_cast<double>(k) * period;
    clock_.sleepUntil(tick);
    const double wake = clock_.now();
    const double t = wake - t0;

    const DeviceState ds = device_.read(t);
    ForceSample sample;
    if (ds.position.allFinite()) sample = renderer_.step(ds.position);
    uint32_t flags = 0;
    const Eigen::Vector3d force = safety_.filter(t, ds.position, sample.force, &flags);
    device_.writeForce(force);
    const double end = clock_.now();

    const double next = t0 + static_cast<double>(k + 1) * period;
    const bool missed = end > next;
    if (missed) flags |= kSafetyMissedDeadline;
    if (safety_.noteDeadline(missed, end - t0)) {
      device_.writeForce(Eigen::Vector3d::Zero());
      flags |= kSafetyFaulted;
    }

    ++st.steps;
    st.compute.add(end - wake);
    st.lateness.add(wake - tick);
    if (sample.contact) {
      ++st.contactSteps;
      if (!wasContact) ++st.contactOnsets;
    }
    wasContact = sample.contact;

    if (records_) {
      StepRecord r;
      r.tick = k;
      r.t = t;
      for (int i = 0; i < 3; ++i) {
        r.hip[i] = ds.position[i];
        r.force[i] = force[i];
        r.rendered[i] = sample.force[i];
      }
      r.compute = end - wake;
      r.lateness = wake - tick;
      r.flags = flags;
      r.contact = sample.contact ? 1 : 0;
      if (!records_->tryPush(r)) ++st.recordsDropped;
    }

    int64_t nextK = k + 1;
    if (missed) {
      ++st.missedDeadlines;
      // The first tick at or after `end` (tolerating rounding of a millionth of a period).
      const auto firstFuture = static_cast<int64_t>(std::ceil((end - t0) / period - 1e-6));
      if (firstFuture > nextK) {
        st.skippedTicks += std::min(firstFuture, ticks) - nextK;
        nextK = firstFuture;
      }
    }
    k = nextK;
  }
  st.elapsed = clock_.now() - t0;
}

}  // namespace sf::rt
