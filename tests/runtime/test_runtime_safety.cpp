// SPDX-License-Identifier: Apache-2.0
// Unit tests of the safety layer: each rule fires, directly and inside the loop (fake clock).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/servo_loop.h>

namespace {

using Eigen::Vector3d;
using namespace sf::rt;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const Vector3d kHip(0, 0, 0);

SafetyOptions noRampNoRate() {
  SafetyOptions o;
  o.rampTime = 0;
  o.maxForceStep = std::numeric_limits<double>::infinity();
  return o;
}

/// A renderer whose force is a function of the step index; it can spend fake compute time.
class FnRenderer final : public sf::ForceRenderer {
 public:
  std::function<Vector3d(int64_t)> force;
  std::function<double(int64_t)> cost;  ///< fake compute time of step k, s
  FakeClock* clock = nullptr;
  int64_t k = 0;
  sf::ForceSample step(const Vector3d&) noexcept override {
    sf::ForceSample s;
    s.force = force ? force(k) : Vector3d::Zero();
    s.contact = s.force.squaredNorm() > 0;
    if (clock && cost) clock->advance(cost(k));
    ++k;
    return s;
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }
};

/// A device that reports a fixed HIP (or NaN from a given step) and keeps every force.
class RecordingDevice final : public HapticDevice {
 public:
  int64_t nanFrom = -1;
  int64_t reads = 0;
  std::vector<Vector3d> forces;
  DeviceState read(double) noexcept override {
    const bool nan = nanFrom >= 0 && reads >= nanFrom;
    ++reads;
    return {nan ? Vector3d(kNaN, 0, 0) : Vector3d(0.01, 0.02, 0.03), 0};
  }
  void writeForce(const Vector3d& f) noexcept override { forces.push_back(f); }
  std::string describe() const override { return "recording"; }
};

struct LoopRun {
  RecordingDevice device;
  FnRenderer renderer;
  FakeClock clock;
  LoopStats stats;
  SafetyCounters safety;
  void run(const SafetyOptions& so, double duration, double rate = 1000) {
    renderer.clock = &clock;
    device.forces.reserve(size_t(duration * rate * 2 + 16));
    SafetyFilter filter(so);
    LoopOptions lo;
    lo.rate = rate;
    lo.duration = duration;
    ServoLoop loop(device, renderer, filter, clock, lo);
    loop.run();
    stats = loop.stats();
    safety = filter.counters();
  }
};

TEST(RuntimeSafety, ClampKeepsDirection) {
  SafetyFilter f(noRampNoRate());
  uint32_t flags = 0;
  const Vector3d in(10, 20, 20);  // |in| = 30 N
  const Vector3d out = f.filter(1.0, kHip, in, &flags);
  EXPECT_NEAR(out.norm(), 3.3, 1e-12);
  EXPECT_NEAR(out.normalized().dot(in.normalized()), 1.0, 1e-12);
  EXPECT_TRUE(flags & kSafetyClamped);
  EXPECT_EQ(f.counters().clamps, 1);
  const Vector3d small(1, 0, 0);
  EXPECT_EQ(f.filter(1.0, kHip, small, &flags), small);
  EXPECT_FALSE(flags & kSafetyClamped);
}

TEST(RuntimeSafety, RateLimitPerStep) {
  SafetyOptions o = noRampNoRate();
  o.maxForceStep = 0.5;
  SafetyFilter f(o);
  uint32_t flags = 0;
  const Vector3d target(0, 0, 3);
  for (int k = 1; k <= 5; ++k) {
    const Vector3d out = f.filter(1.0, kHip, target, &flags);
    EXPECT_NEAR(out.z(), 0.5 * k, 1e-12) << "step " << k;
    EXPECT_TRUE(flags & kSafetyRateLimited);
  }
  EXPECT_EQ(f.filter(1.0, kHip, target, &flags), target);  // the last 0.5 N step is allowed
  EXPECT_FALSE(flags & kSafetyRateLimited);
  EXPECT_EQ(f.counters().rateLimits, 5);
  // Going down is limited too.
  EXPECT_NEAR(f.filter(1.0, kHip, Vector3d::Zero(), &flags).z(), 2.5, 1e-12);
}

TEST(RuntimeSafety, RampInIsLinear) {
  SafetyOptions o = noRampNoRate();
  o.rampTime = 0.5;
  SafetyFilter f(o);
  uint32_t flags = 0;
  const Vector3d one(1, 0, 0);
  EXPECT_EQ(f.filter(0.0, kHip, one, &flags), Vector3d::Zero());
  EXPECT_NEAR(f.filter(0.125, kHip, one, &flags).x(), 0.25, 1e-12);
  EXPECT_TRUE(flags & kSafetyRamping);
  EXPECT_NEAR(f.filter(0.25, kHip, one, &flags).x(), 0.5, 1e-12);
  EXPECT_NEAR(f.filter(0.5, kHip, one, &flags).x(), 1.0, 1e-12);
  EXPECT_FALSE(flags & kSafetyRamping);
}

TEST(RuntimeSafety, NonFiniteForceLatchesFault) {
  SafetyFilter f(noRampNoRate());
  uint32_t flags = 0;
  EXPECT_EQ(f.filter(1.0, kHip, Vector3d(1, 0, 0), &flags), Vector3d(1, 0, 0));
  EXPECT_EQ(f.filter(1.001, kHip, Vector3d(kNaN, 0, 0), &flags), Vector3d::Zero());
  EXPECT_TRUE(flags & kSafetyFaulted);
  EXPECT_EQ(f.counters().fault, Fault::NonFiniteForce);
  EXPECT_DOUBLE_EQ(f.counters().faultTime, 1.001);
  // Latched: finite forces afterwards still give zero.
  EXPECT_EQ(f.filter(1.002, kHip, Vector3d(1, 0, 0), &flags), Vector3d::Zero());
  EXPECT_EQ(f.filter(1.003, kHip, Vector3d(0, std::numeric_limits<double>::infinity(), 0)), Vector3d::Zero());
  EXPECT_EQ(f.counters().nonFinite, 1);
  f.reset();
  EXPECT_FALSE(f.faulted());
  EXPECT_EQ(f.filter(2.0, kHip, Vector3d(1, 0, 0)), Vector3d(1, 0, 0));
}

TEST(RuntimeSafety, NonFiniteHipLatchesFault) {
  SafetyFilter f(noRampNoRate());
  EXPECT_EQ(f.filter(1.0, Vector3d(0, kNaN, 0), Vector3d(1, 0, 0)), Vector3d::Zero());
  EXPECT_EQ(f.counters().fault, Fault::NonFiniteHip);
  EXPECT_EQ(f.filter(1.0, kHip, Vector3d(1, 0, 0)), Vector3d::Zero());
}

// A non-finite step time (a library caller's clock) would skip the ramp-in: it latches a fault.
TEST(RuntimeSafety, NonFiniteTimeLatchesFault) {
  int checked = 0;
  for (const double t : {kNaN, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    SafetyFilter f(SafetyOptions{});  // the defaults: ramp-in 0.5 s
    uint32_t flags = 0;
    EXPECT_EQ(f.filter(0.0, kHip, Vector3d(1, 0, 0), &flags), Vector3d::Zero());  // ramp starts at 0
    EXPECT_EQ(f.filter(t, kHip, Vector3d(1, 0, 0), &flags), Vector3d::Zero()) << t;
    EXPECT_TRUE(flags & kSafetyFaulted);
    EXPECT_EQ(f.counters().fault, Fault::NonFiniteTime);
    EXPECT_STREQ(toString(f.counters().fault), "non-finite step time");
    EXPECT_EQ(f.filter(1.0, kHip, Vector3d(1, 0, 0)), Vector3d::Zero()) << "latched";
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

// Finite forces of any magnitude are clamped to maxForce along their direction, and rate-limited,
// never zeroed by an overflowing norm (a stiffness of 1e155 N/m gave 1e153 N and a zero force).
TEST(RuntimeSafety, HugeFiniteForcesAreClampedNotZeroed) {
  int checked = 0;
  for (const double mag : {10.0, 1e100, 1e154, 1e160, 1e300, 1.7e308}) {
    SafetyOptions o = noRampNoRate();
    SafetyFilter clamp(o);
    const Vector3d dir = Vector3d(1, -2, 2) / 3;
    const Vector3d out = clamp.filter(1.0, kHip, mag / 2 * Vector3d(1, -2, 2) / 1.5);
    EXPECT_NEAR(out.norm(), o.maxForce, 1e-12) << mag;
    EXPECT_NEAR(out.normalized().dot(dir), 1.0, 1e-12) << mag;
    o.maxForceStep = 0.5;
    SafetyFilter rate(o);
    EXPECT_NEAR(rate.filter(1.0, kHip, mag * Vector3d(0, 0, 1)).z(), 0.5, 1e-12) << mag;
    ++checked;
  }
  EXPECT_EQ(checked, 6);
}

TEST(RuntimeSafety, ConsecutiveMissedDeadlinesLatchFault) {
  SafetyOptions o = noRampNoRate();
  o.maxConsecutiveMisses = 3;
  SafetyFilter f(o);
  EXPECT_FALSE(f.noteDeadline(true, 0.1));
  EXPECT_FALSE(f.noteDeadline(true, 0.2));
  EXPECT_FALSE(f.noteDeadline(false, 0.3));  // the run is broken
  EXPECT_FALSE(f.noteDeadline(true, 0.4));
  EXPECT_FALSE(f.noteDeadline(true, 0.5));
  EXPECT_FALSE(f.faulted());
  EXPECT_TRUE(f.noteDeadline(true, 0.6));
  EXPECT_EQ(f.counters().fault, Fault::MissedDeadlines);
  EXPECT_DOUBLE_EQ(f.counters().faultTime, 0.6);
  EXPECT_EQ(f.counters().missedDeadlines, 5);
  EXPECT_EQ(f.counters().maxConsecutiveMisses, 3);
  EXPECT_EQ(f.filter(1.0, kHip, Vector3d(1, 0, 0)), Vector3d::Zero());
}

TEST(RuntimeSafety, BadOptionsRejected) {
  auto msg = [](SafetyOptions o) {
    try {
      SafetyFilter f(o);
    } catch (const sf::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  SafetyOptions o;
  o.maxForce = 0;
  EXPECT_NE(msg(o).find("--max-force:"), std::string::npos);
  o = {};
  o.maxForceStep = -1;
  EXPECT_NE(msg(o).find("--max-force-step:"), std::string::npos);
  o = {};
  o.rampTime = kNaN;
  EXPECT_NE(msg(o).find("--ramp:"), std::string::npos);
  o = {};
  o.maxConsecutiveMisses = 0;
  EXPECT_NE(msg(o).find("--max-missed:"), std::string::npos);
}

// ---- The same rules inside the loop, driven by the fake clock ----

TEST(RuntimeSafetyLoop, ClampFires) {
  LoopRun r;
  r.renderer.force = [](int64_t) { return Vector3d(0, 0, 10); };
  SafetyOptions o;  // defaults: ramp 0.5 s, 0.5 N/step
  r.run(o, 1.0);
  EXPECT_EQ(r.stats.steps, 1000);
  EXPECT_EQ(r.safety.clamps, 1000);
  EXPECT_NEAR(r.device.forces.back().z(), 3.3, 1e-12);
  for (const Vector3d& f : r.device.forces) EXPECT_LE(f.norm(), 3.3 + 1e-12);
}

TEST(RuntimeSafetyLoop, RampFiresOverHalfASecond) {
  LoopRun r;
  r.renderer.force = [](int64_t) { return Vector3d(1, 0, 0); };
  r.run(SafetyOptions{}, 1.0);
  // Step k wakes at k ms: force k / 500 N until 0.5 s (the 0.5 N/step limit never binds).
  EXPECT_NEAR(r.device.forces[0].x(), 0.0, 1e-12);
  EXPECT_NEAR(r.device.forces[100].x(), 0.2, 1e-9);
  EXPECT_NEAR(r.device.forces[250].x(), 0.5, 1e-9);
  EXPECT_NEAR(r.device.forces[600].x(), 1.0, 1e-12);
  EXPECT_EQ(r.safety.rateLimits, 0);
}

TEST(RuntimeSafetyLoop, RateLimitFires) {
  LoopRun r;
  r.renderer.force = [](int64_t k) { return k >= 700 ? Vector3d(0, 3, 0) : Vector3d::Zero(); };
  r.run(SafetyOptions{}, 1.0);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r.device.forces[700 + i].y(), 0.5 * (i + 1), 1e-12);
  EXPECT_NEAR(r.device.forces[706].y(), 3.0, 1e-12);
  EXPECT_EQ(r.safety.rateLimits, 5);  // the 6th step lands exactly on the target
}

TEST(RuntimeSafetyLoop, NonFiniteForceFaultsAndStaysZero) {
  LoopRun r;
  r.renderer.force = [](int64_t k) { return k == 800 ? Vector3d(kNaN, 0, 0) : Vector3d(0, 0, 1); };
  r.run(SafetyOptions{}, 1.0);
  EXPECT_EQ(r.safety.fault, Fault::NonFiniteForce);
  EXPECT_NEAR(r.safety.faultTime, 0.8, 1e-12);
  EXPECT_NEAR(r.device.forces[799].z(), 1.0, 1e-12);
  for (size_t i = 800; i < r.device.forces.size(); ++i) EXPECT_EQ(r.device.forces[i], Vector3d::Zero());
}

TEST(RuntimeSafetyLoop, NonFiniteHipFaultsWithoutCallingTheRenderer) {
  LoopRun r;
  r.renderer.force = [](int64_t) { return Vector3d(0, 0, 1); };
  r.device.nanFrom = 900;
  r.run(SafetyOptions{}, 1.0);
  EXPECT_EQ(r.safety.fault, Fault::NonFiniteHip);
  EXPECT_EQ(r.renderer.k, 900);  // never stepped with a NaN HIP
  EXPECT_EQ(r.device.forces.back(), Vector3d::Zero());
}

TEST(RuntimeSafetyLoop, MissedDeadlinesFault) {
  LoopRun r;
  r.renderer.force = [](int64_t) { return Vector3d(0, 0, 1); };
  // From step 600 on every step takes 1.2 periods: each misses its deadline.
  r.renderer.cost = [](int64_t k) { return k >= 600 ? 1.2e-3 : 0.0; };
  r.run(SafetyOptions{}, 1.0);
  EXPECT_EQ(r.safety.fault, Fault::MissedDeadlines);
  EXPECT_EQ(r.safety.maxConsecutiveMisses, r.stats.missedDeadlines);
  // Step 600 + 9 is the 10th miss; its zero force is written at once after the step.
  EXPECT_NEAR(r.safety.faultTime, 0.600 + 9 * 2e-3 + 1.2e-3, 1e-9);
  EXPECT_EQ(r.device.forces.back(), Vector3d::Zero());
  // 600 on-time steps, then steps at 600, 602, ...: every other tick is skipped.
  EXPECT_EQ(r.stats.steps, 800);
  EXPECT_EQ(r.stats.skippedTicks, 200);
}

}  // namespace
