// SPDX-License-Identifier: Apache-2.0
// The servo step for a foreign loop (times passed in): statistics, deadlines, the own schedule,
// records, device status, no allocation; ServoLoop gives the same records as a hand-driven step.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/servo_loop.h>
#include <smoothforce/runtime/servo_step.h>
#include "runtime_alloc_counter.h"

namespace {

using Eigen::Vector3d;
using namespace sf::rt;
using sf::test::tAllocs;
using sf::test::tCountAllocs;

/// The half-space z <= 0 (k = 500 N/m) that spends cost(k) s of fake compute time on step k.
class TimedPlane final : public sf::ForceRenderer {
 public:
  explicit TimedPlane(FakeClock& c) : clock(c) {}
  FakeClock& clock;
  PlaneRenderer plane{Vector3d::UnitZ(), 0.0, 500.0};
  double (*cost)(int64_t) = [](int64_t k) { return double(k % 100 + 1) * 1e-6; };
  int64_t calls = 0;
  sf::ForceSample step(const Vector3d& hip) noexcept override {
    clock.advance(cost(calls++));
    return plane.step(hip);
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }
};

SafetyOptions noRamp() {
  SafetyOptions o;
  o.rampTime = 0;
  o.maxForceStep = INFINITY;
  return o;
}

/// The HIP of host step k: 1 mm deep for 50 steps, then 1 mm above, repeating.
DeviceState hipAt(int64_t k) {
  DeviceState d;
  d.position = Vector3d(0.01, 0.02, k % 100 < 50 ? -0.001 : 0.001);
  return d;
}

std::vector<StepRecord> drain(SpscRing<StepRecord>& ring) {
  std::vector<StepRecord> v;
  StepRecord r;
  while (ring.tryPop(r)) v.push_back(r);
  return v;
}

TEST(RuntimeStep, TimesPassedInGiveStatisticsAndRecords) {
  FakeClock clock;  // only measures compute time; the host's times are passed in
  TimedPlane r(clock);
  SafetyFilter safety(noRamp());
  SpscRing<StepRecord> ring(8192);
  ServoStep step(r, safety, StepOptions{}, &ring, &clock);
  const int64_t n = 5000;
  const double origin = 1234.5;  // the host clock's own origin
  for (int64_t k = 0; k < n; ++k) {
    StepTime t;
    t.tick = origin + double(k) * 1e-3;
    t.wake = t.tick + (k % 20 == 0 ? 50e-6 : 20e-6);  // 5% of wake-ups 50 us late, the rest 20 us
    const StepOutput out = step.step(t, hipAt(k));
    const double depth = k % 100 < 50 ? 0.001 : 0.0;
    ASSERT_NEAR(out.force.z(), 500 * depth, 1e-12) << k;  // identity transform: device = world
    ASSERT_EQ(out.sample.contact, depth > 0) << k;
  }
  const LoopStats& s = step.stats();
  EXPECT_EQ(s.steps, n);
  EXPECT_EQ(s.missedDeadlines, 0);  // at most 50 + 100 us of a 1 ms period
  EXPECT_NEAR(s.compute.percentile(50) * 1e6, 50, 0.05);
  EXPECT_NEAR(s.compute.percentile(99) * 1e6, 99, 0.05);
  EXPECT_NEAR(s.compute.max() * 1e6, 100, 1e-6);
  EXPECT_NEAR(s.lateness.percentile(50) * 1e6, 20, 0.02);
  EXPECT_NEAR(s.lateness.percentile(99) * 1e6, 50, 0.05);
  EXPECT_EQ(s.contactSteps, n / 2);
  EXPECT_EQ(s.contactOnsets, n / 100);
  const std::vector<StepRecord> recs = drain(ring);
  ASSERT_EQ(recs.size(), size_t(n));
  EXPECT_EQ(s.recordsDropped, 0);
  for (int64_t k = 0; k < n; ++k) {
    const StepRecord& rec = recs[size_t(k)];
    ASSERT_EQ(rec.tick, k);
    ASSERT_NEAR(rec.t, double(k) * 1e-3 + (k % 20 == 0 ? 50e-6 : 20e-6), 1e-9) << "t = wake - the first tick";
    ASSERT_NEAR(rec.compute, double(k % 100 + 1) * 1e-6, 1e-12);
    ASSERT_NEAR(rec.lateness, k % 20 == 0 ? 50e-6 : 20e-6, 1e-9);
    ASSERT_EQ(rec.contact, k % 100 < 50 ? 1 : 0);
    ASSERT_EQ(rec.hip[2], hipAt(k).position.z());
  }
}

TEST(RuntimeStep, MissedDeadlinesLatchTheFaultWithTimesPassedIn) {
  FakeClock clock;
  TimedPlane r(clock);
  r.cost = [](int64_t k) { return k >= 600 ? 1.2e-3 : 1e-6; };  // from step 600 every step overruns
  SafetyFilter safety(noRamp());
  ServoStep step(r, safety, StepOptions{}, nullptr, &clock);
  int faultedAt = -1;
  for (int k = 0; k < 1000; ++k) {
    StepTime t;
    t.tick = t.wake = 10.0 + k * 1e-3;  // the host keeps calling every period
    DeviceState d;
    d.position = Vector3d(0, 0, -0.002);
    const StepOutput out = step.step(t, d);
    if (out.faulted && faultedAt < 0) faultedAt = k;
    if (faultedAt < 0)
      ASSERT_NEAR(out.force.z(), 1.0, 1e-12) << k;
    else
      ASSERT_EQ(out.force, Vector3d::Zero()) << k;  // the latching step already returns zero
  }
  EXPECT_EQ(faultedAt, 609);  // the 10th consecutive miss (SafetyOptions::maxConsecutiveMisses)
  EXPECT_EQ(safety.counters().fault, Fault::MissedDeadlines);
  EXPECT_NEAR(safety.counters().faultTime, 0.609 + 1.2e-3, 1e-9);  // its end, from the first tick
  EXPECT_EQ(step.stats().missedDeadlines, 400);
  EXPECT_EQ(step.stats().steps, 1000);
  // Two-phase use: the host includes its own device write in the timed part.
  FakeClock c2;
  TimedPlane r2(c2);
  SafetyFilter s2(noRamp());
  ServoStep step2(r2, s2, StepOptions{}, nullptr, &c2);
  for (int k = 0; k < 100; ++k) {
    StepTime t;
    t.tick = t.wake = k * 1e-3;
    step2.render(t, hipAt(k));
    EXPECT_FALSE(step2.finish(t.wake + (k % 2 ? 0.9e-3 : 1.1e-3)));  // odd steps in time, even ones late
  }
  EXPECT_EQ(step2.stats().missedDeadlines, 50);
  EXPECT_EQ(s2.counters().maxConsecutiveMisses, 1);
}

// The own schedule (no tick passed): host calls at k / rate + jitter (0 <= jitter < 0.45
// periods) with random gaps of 1-3 ticks. It must recover the tick indices, the jitter as
// lateness and the gaps as skipped ticks.
TEST(RuntimeStep, OwnScheduleRecoversTicksLatenessAndGaps) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(0, 0.45);
  std::uniform_int_distribution<int> gap(1, 3);
  for (double rate : {1000.0, 2000.0, 333.0}) {
    FakeClock clock;
    PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
    SafetyFilter safety(noRamp());
    SpscRing<StepRecord> ring(8192);
    StepOptions so;
    so.rate = rate;
    ServoStep step(plane, safety, so, &ring, &clock);
    const double period = 1 / rate, host0 = 77.0;
    std::vector<int64_t> ticks;
    std::vector<double> late;
    int64_t k = 0, skipped = 0;
    for (int i = 0; i < 4000; ++i) {
      if (i > 0 && i % 97 == 0) {
        const int g = gap(rng);
        k += g;
        skipped += g;
      }
      const double j = i == 0 ? 0 : jitter(rng) * period;  // the first call sets the phase
      StepTime t;
      t.wake = host0 + double(k) * period + j;
      step.step(t, hipAt(i));
      ticks.push_back(k);
      late.push_back(j);
      ++k;
    }
    const std::vector<StepRecord> recs = drain(ring);
    ASSERT_EQ(recs.size(), ticks.size());
    for (size_t i = 0; i < recs.size(); ++i) {
      ASSERT_EQ(recs[i].tick, ticks[i]) << rate << " call " << i;
      ASSERT_NEAR(recs[i].lateness, late[i], 1e-9) << rate << " call " << i;
    }
    EXPECT_EQ(step.stats().skippedTicks, skipped) << rate;
    EXPECT_EQ(step.stats().steps, 4000);
  }
}

// A host clock 0.1% fast calls before each tick is due: the schedule re-anchors on every call,
// lateness stays 0 and no tick is skipped.
TEST(RuntimeStep, OwnScheduleReanchorsOnEarlyCalls) {
  FakeClock clock;
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  SafetyFilter safety(noRamp());
  SpscRing<StepRecord> ring(4096);
  ServoStep step(plane, safety, StepOptions{}, &ring, &clock);
  for (int i = 0; i < 3000; ++i) {
    StepTime t;
    t.wake = i * 0.999e-3;
    step.step(t, hipAt(i));
  }
  const std::vector<StepRecord> recs = drain(ring);
  ASSERT_EQ(recs.size(), 3000u);
  for (size_t i = 0; i < recs.size(); ++i) ASSERT_EQ(recs[i].tick, int64_t(i));
  EXPECT_EQ(step.stats().lateness.max(), 0);
  EXPECT_EQ(step.stats().skippedTicks, 0);
}

TEST(RuntimeStep, DeviceStatusStaleFaultsAndNoSampleRendersNothing) {
  FakeClock clock;
  TimedPlane r(clock);
  SafetyFilter safety(noRamp());
  ServoStep step(r, safety, StepOptions{}, nullptr, &clock);
  int64_t k = 0;
  auto at = [&](DeviceStatus st) {
    DeviceState d = hipAt(0);  // 1 mm deep: 0.5 N when rendered
    d.status = st;
    StepTime t;
    t.wake = t.tick = double(k++) * 1e-3;
    return step.step(t, d);
  };
  for (int i = 0; i < 10; ++i) {
    const StepOutput o = at(DeviceStatus::NoSample);
    EXPECT_EQ(o.force, Vector3d::Zero());
    EXPECT_TRUE(o.flags & kStepNoSample);
    EXPECT_FALSE(o.faulted);
  }
  EXPECT_EQ(r.calls, 0);  // nothing rendered without a sample
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(at(DeviceStatus::Ok).force.z(), 0.5, 1e-12);
  EXPECT_EQ(r.calls, 10);
  const StepOutput stale = at(DeviceStatus::Stale);
  EXPECT_EQ(stale.force, Vector3d::Zero());
  EXPECT_TRUE(stale.faulted);
  EXPECT_TRUE(stale.flags & kStepStale);
  EXPECT_TRUE(stale.flags & kSafetyFaulted);
  EXPECT_EQ(safety.counters().fault, Fault::StaleDevice);
  EXPECT_NEAR(safety.counters().faultTime, 0.020, 1e-12);
  EXPECT_EQ(r.calls, 10);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(at(DeviceStatus::Ok).force, Vector3d::Zero());  // latched
}

TEST(RuntimeStep, StepDoesNotAllocate) {
  if (!SF_COUNT_ALLOCS) GTEST_SKIP() << "allocation counting is off under sanitizers";
  FakeClock clock;
  TimedPlane r(clock);
  SafetyFilter safety;  // defaults: ramp, rate limit, clamp all active
  SpscRing<StepRecord> ring(512);
  StepOptions so;
  Pose p;
  p.translation = Vector3d(0.1, 0.2, 0.3);
  p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Vector3d(1, 2, 3).normalized()));
  p.scale = 0.001;
  so.device = DeviceTransform(p);
  ServoStep step(r, safety, so, &ring, &clock);
  ServoStep own(r, safety, so, &ring);  // with its own SteadyClock
  tAllocs = 0;
  tCountAllocs = true;
  for (int k = 0; k < 2000; ++k) {
    DeviceState d = hipAt(k);
    d.position = so.device.toDevice(d.position);
    if (k == 1500) d.status = DeviceStatus::Stale;
    StepTime t;
    t.wake = k * 1e-3;  // own schedule
    step.step(t, d);
    t.tick = t.wake;
    own.render(t, d);
    own.finish(t.wake + 1e-5);
  }
  tCountAllocs = false;
  EXPECT_EQ(tAllocs, 0);
  EXPECT_EQ(step.stats().steps, 2000);
  EXPECT_EQ(step.stats().recordsDropped + own.stats().recordsDropped, 4000 - 512);  // the ring filled, no consumer
  EXPECT_EQ(safety.counters().fault, Fault::StaleDevice);
}

/// Goes down through z = 0 and back up every 100 ms.
class Bobbing final : public SimulatedDevice {
 public:
  DeviceState read(double t) noexcept override { return hipAt(std::llround(t * 1e3)); }
  std::string describe() const override { return "bobbing"; }
};

// ServoLoop is built on ServoStep: a loop run and a hand-driven step given the same times
// produce the same records, bit for bit.
TEST(RuntimeStep, ServoLoopMatchesAHandDrivenStep) {
  FakeClock c1;
  c1.wakeLatency = [](double deadline) { return std::llround(deadline * 1000) % 7 == 0 ? 30e-6 : 3e-6; };
  TimedPlane r1(c1);
  r1.cost = [](int64_t k) { return k % 250 == 0 ? 1.7e-3 : 2e-6 * double(k % 13); };  // some overruns
  Bobbing dev;
  SafetyFilter s1;
  SpscRing<StepRecord> ring1(4096);
  LoopOptions lo;
  lo.duration = 2.0;
  ServoLoop loop(dev, r1, s1, c1, lo, &ring1);
  loop.run();
  const std::vector<StepRecord> a = drain(ring1);

  FakeClock c2;
  TimedPlane r2(c2);
  r2.cost = r1.cost;
  SafetyFilter s2;
  SpscRing<StepRecord> ring2(4096);
  ServoStep step(r2, s2, StepOptions{}, &ring2, &c2);
  step.start(0);
  for (const StepRecord& ra : a) {  // the loop's own times, replayed
    StepTime t;
    t.wake = ra.t;
    t.tick = double(ra.tick) * 1e-3;
    t.index = ra.tick;
    const double c0 = c2.now();
    step.render(t, dev.read(ra.t));
    step.finish(ra.t + (c2.now() - c0));
  }
  const std::vector<StepRecord> b = drain(ring2);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(loop.stats().missedDeadlines, 0);
  EXPECT_EQ(step.stats().missedDeadlines, loop.stats().missedDeadlines);
  EXPECT_EQ(step.stats().contactOnsets, loop.stats().contactOnsets);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].tick, b[i].tick) << i;
    for (int j = 0; j < 3; ++j) {
      ASSERT_EQ(a[i].force[j], b[i].force[j]) << i;
      ASSERT_EQ(a[i].hip[j], b[i].hip[j]) << i;
    }
    ASSERT_EQ(a[i].flags, b[i].flags) << i;
    ASSERT_NEAR(a[i].compute, b[i].compute, 1e-12) << i;
    ASSERT_NEAR(a[i].lateness, b[i].lateness, 1e-12) << i;
  }
}

}  // namespace
