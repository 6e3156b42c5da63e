// SPDX-License-Identifier: Apache-2.0
// Servo loop timing: the loop's own overhead per step (device + safety + ring buffer +
// statistics, with an analytic plane as the renderer) over 10^5 steps without sleeping, and
// a short real-clock run at 1 kHz (wake-up lateness, missed deadlines).
//
//   bench_loop --benchmark_format=json
//
// Counters: ns_per_step = wall time / steps (fake clock: everything but sleeping; with
// record=1 every step also pushes its record into a ring large enough to hold all of them);
// compute_p50/p99/p999/max_ns = the loop's own per-step histogram (FastForwardClock: real
// time while computing, sleeps skipped); lateness_*_us, missed = real-clock run.
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/servo_loop.h>

namespace {

using Eigen::Vector3d;
using namespace sf::rt;

constexpr int64_t kSteps = 100000;

/// A circle of radius 5 cm, 2 mm below the plane z = 0, at 0.1 m/s (contact throughout).
ScriptedPath circle() {
  ScriptedPath p;
  for (int i = 0; i <= 64; ++i) {
    const double a = 2 * M_PI * i / 64;
    p.points.emplace_back(0.05 * std::cos(a), 0.05 * std::sin(a), -0.002);
  }
  p.closed = true;
  p.description = "bench circle";
  return p;
}

/// Drains the ring on a second thread, as the record writer does (without the file I/O).
struct Drain {
  SpscRing<StepRecord>& ring;
  std::atomic<bool> done{false};
  int64_t popped = 0;
  std::thread th;
  explicit Drain(SpscRing<StepRecord>& r) : ring(r) {
    th = std::thread([this] {
      StepRecord rec;
      while (!done.load(std::memory_order_acquire)) {
        while (ring.tryPop(rec)) ++popped;
        std::this_thread::yield();  // keeps up with a loop that never sleeps (as far as it can)
      }
      while (ring.tryPop(rec)) ++popped;
    });
  }
  ~Drain() {
    done.store(true, std::memory_order_release);
    th.join();
  }
};

void setPercentiles(benchmark::State& state, const LatencyHistogram& h, const char* prefix, double unit) {
  const std::string p(prefix);
  state.counters[p + "_p50"] = h.percentile(50) / unit;
  state.counters[p + "_p99"] = h.percentile(99) / unit;
  state.counters[p + "_p999"] = h.percentile(99.9) / unit;
  state.counters[p + "_max"] = h.max() / unit;
}

/// 10^5 steps with the fake clock: wall time per step is the loop's pure overhead.
void BM_LoopFakeClock(benchmark::State& state) {
  const bool record = state.range(0) != 0;
  int64_t steps = 0, dropped = 0;
  double runSeconds = 0;
  for (auto _ : state) {
    state.PauseTiming();
    FakeClock clock;
    PathDevice device(circle(), 0.1);
    PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
    SafetyFilter safety;
    SpscRing<StepRecord> ring(record ? kSteps : 2);  // holds every record: each push succeeds
    LoopOptions o;
    o.duration = kSteps / o.rate;
    ServoLoop loop(device, plane, safety, clock, o, record ? &ring : nullptr);
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    loop.run();
    runSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.PauseTiming();
    steps += loop.stats().steps;
    dropped += loop.stats().recordsDropped;
    state.ResumeTiming();
  }
  state.SetItemsProcessed(steps);
  state.counters["ns_per_step"] = steps ? 1e9 * runSeconds / double(steps) : 0.0;
  state.counters["dropped"] = double(dropped);
}
BENCHMARK(BM_LoopFakeClock)->Arg(0)->Arg(1)->ArgName("record")->Unit(benchmark::kMillisecond)->UseRealTime();

/// 10^5 steps with the fast-forward clock: the loop's own per-step compute histogram.
void BM_LoopComputePercentiles(benchmark::State& state) {
  LatencyHistogram last;
  for (auto _ : state) {
    FastForwardClock clock;
    PathDevice device(circle(), 0.1);
    PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
    SafetyFilter safety;
    SpscRing<StepRecord> ring(1 << 14);
    Drain drain(ring);
    LoopOptions o;
    o.duration = kSteps / o.rate;
    ServoLoop loop(device, plane, safety, clock, o, &ring);
    loop.run();
    last = loop.stats().compute;
    state.counters["missed"] = double(loop.stats().missedDeadlines);
  }
  setPercentiles(state, last, "compute_ns", 1e-9);
}
BENCHMARK(BM_LoopComputePercentiles)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

/// A short real-time run: 0.5 s at 1 kHz on the monotonic clock (sleep, then 200 us spin).
void BM_LoopRealClock(benchmark::State& state) {
  for (auto _ : state) {
    SteadyClock clock(200e-6);
    PathDevice device(circle(), 0.1);
    PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
    SafetyFilter safety;
    SpscRing<StepRecord> ring(1 << 12);
    Drain drain(ring);
    LoopOptions o;
    o.duration = 0.5;
    ServoLoop loop(device, plane, safety, clock, o, &ring);
    loop.run();
    const LoopStats& s = loop.stats();
    setPercentiles(state, s.lateness, "lateness_us", 1e-6);
    setPercentiles(state, s.compute, "compute_us", 1e-6);
    state.counters["steps"] = double(s.steps);
    state.counters["missed"] = double(s.missedDeadlines);
  }
}
BENCHMARK(BM_LoopRealClock)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
