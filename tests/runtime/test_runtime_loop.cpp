// SPDX-License-Identifier: Apache-2.0
// The servo loop with the fake clock: step counts, percentiles, deadlines, records, no
// allocation; the latency histogram; the end-of-run report.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>

#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/loop_report.h>
#include <smoothforce/runtime/record_writer.h>
#include <smoothforce/runtime/servo_loop.h>

#include "runtime_alloc_counter.h"

using sf::test::tAllocs;
using sf::test::tCountAllocs;

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using namespace sf::rt;

/// A plane z <= 0 renderer that spends fake compute time (k % 100 + 1) us on step k.
class CostlyPlane final : public sf::ForceRenderer {
 public:
  explicit CostlyPlane(FakeClock& c) : clock(c) {}
  FakeClock& clock;
  PlaneRenderer plane{Vector3d::UnitZ(), 0.0, 500.0};
  int64_t k = 0;
  sf::ForceSample step(const Vector3d& hip) noexcept override {
    clock.advance(double(k++ % 100 + 1) * 1e-6);
    return plane.step(hip);
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }
};

/// Goes down through z = 0 and back up every 100 ms: 50 ms in contact per cycle.
class BobbingDevice final : public SimulatedDevice {
 public:
  DeviceState read(double t) noexcept override {
    const long long ms = std::llround(t * 1e3);
    return {Vector3d(0, 0, ms % 100 < 50 ? -0.001 : 0.001), 0};
  }
  std::string describe() const override { return "bobbing"; }
};

TEST(RuntimeHistogram, PercentilesNearestRank) {
  LatencyHistogram h;
  for (int i = 1; i <= 1000; ++i) h.add(i * 1e-6);  // 1 .. 1000 us
  EXPECT_EQ(h.count(), 1000);
  EXPECT_NEAR(h.percentile(50), 500e-6, 500e-6 * 5e-4);
  EXPECT_NEAR(h.percentile(99), 990e-6, 990e-6 * 5e-4);
  EXPECT_NEAR(h.percentile(99.9), 999e-6, 999e-6 * 5e-4);
  EXPECT_DOUBLE_EQ(h.percentile(100), 1000e-6);
  EXPECT_DOUBLE_EQ(h.max(), 1000e-6);
  EXPECT_DOUBLE_EQ(h.min(), 1e-6);
  EXPECT_DOUBLE_EQ(h.percentile(0), 1e-6);
  // Exact below 2 us; negative and NaN count as zero.
  LatencyHistogram g;
  g.add(1.5e-6);
  g.add(-1);
  g.add(std::nan(""));
  EXPECT_DOUBLE_EQ(g.percentile(100), 1.5e-6);
  EXPECT_DOUBLE_EQ(g.percentile(50), 0);
  EXPECT_EQ(g.summaryUs(), "p50 0.0 us, p99 1.5 us, p99.9 1.5 us, max 1.5 us");
}

TEST(RuntimeHistogram, RelativeErrorBound) {
  for (double v : {3e-6, 12.345e-6, 987.6e-6, 0.0123, 1.7}) {
    LatencyHistogram h;
    h.add(v);
    h.add(2 * v);
    EXPECT_NEAR(h.percentile(50), v, v * 5e-4) << v;
  }
}

TEST(RuntimeLoop, FakeClockStepCountAndTiming) {
  FakeClock clock(5.0);  // any origin
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  NullDevice dev(Vector3d(0, 0, 1));
  SafetyFilter safety;
  LoopOptions o;
  o.rate = 1000;
  o.duration = 2.0;
  ServoLoop loop(dev, plane, safety, clock, o);
  loop.run();
  const LoopStats& s = loop.stats();
  EXPECT_EQ(s.ticks, 2000);
  EXPECT_EQ(s.steps, 2000);
  EXPECT_EQ(s.missedDeadlines, 0);
  EXPECT_EQ(s.skippedTicks, 0);
  EXPECT_EQ(s.compute.max(), 0);
  EXPECT_EQ(s.lateness.max(), 0);
  EXPECT_NEAR(s.elapsed, 1.999, 1e-9);  // the last tick starts at 1.999 s
  EXPECT_EQ(dev.writes(), 2000);
}

TEST(RuntimeLoop, ComputeAndLatenessPercentiles) {
  FakeClock clock;
  // Tick k (at k / 2000 s) wakes 50 us late when k % 20 == 0 (5% of ticks), else 20 us late.
  clock.wakeLatency = [](double deadline) { return std::llround(deadline * 2000) % 20 == 0 ? 50e-6 : 20e-6; };
  CostlyPlane r(clock);
  NullDevice dev;
  SafetyFilter safety;
  LoopOptions o;
  o.rate = 2000;
  o.duration = 5.0;
  ServoLoop loop(dev, r, safety, clock, o);
  loop.run();
  const LoopStats& s = loop.stats();
  EXPECT_EQ(s.steps, 10000);
  // Compute time of step k is (k % 100 + 1) us: uniform over 1..100 us.
  EXPECT_NEAR(s.compute.percentile(50) * 1e6, 50, 0.05);
  EXPECT_NEAR(s.compute.percentile(99) * 1e6, 99, 0.05);
  EXPECT_NEAR(s.compute.percentile(99.9) * 1e6, 100, 0.05);
  EXPECT_NEAR(s.compute.max() * 1e6, 100, 1e-6);
  // p50 20 us, p99 50 us.
  EXPECT_NEAR(s.lateness.percentile(50) * 1e6, 20, 0.02);
  EXPECT_NEAR(s.lateness.percentile(99) * 1e6, 50, 0.05);
  EXPECT_EQ(s.missedDeadlines, 0);  // 50 + 100 us < 500 us period
}

TEST(RuntimeLoop, OverrunSkipsTicksInsteadOfBursting) {
  FakeClock clock;
  struct Stall final : sf::ForceRenderer {
    FakeClock* c;
    int64_t k = 0;
    sf::ForceSample step(const Vector3d&) noexcept override {
      if (k++ == 5) c->advance(3.5e-3);  // step 5 takes 3.5 periods
      return {};
    }
    void reset() noexcept override {}
    int patchesBuilt() const noexcept override { return 0; }
  } r;
  r.c = &clock;
  NullDevice dev;
  SafetyFilter safety;
  LoopOptions o;
  o.duration = 0.02;
  ServoLoop loop(dev, r, safety, clock, o);
  loop.run();
  const LoopStats& s = loop.stats();
  EXPECT_EQ(s.ticks, 20);
  EXPECT_EQ(s.missedDeadlines, 1);
  EXPECT_EQ(s.skippedTicks, 3);  // step 5 ends at 8.5 ms: ticks 6, 7, 8 are skipped
  EXPECT_EQ(s.steps, 17);
  EXPECT_EQ(safety.counters().missedDeadlines, 1);
  EXPECT_FALSE(safety.faulted());
  EXPECT_EQ(s.lateness.max(), 0);  // the step after runs at tick 9, on time
}

TEST(RuntimeLoop, ContactsCounted) {
  FakeClock clock;
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  BobbingDevice dev;
  SafetyFilter safety;
  LoopOptions o;
  o.duration = 1.0;
  ServoLoop loop(dev, plane, safety, clock, o);
  loop.run();
  EXPECT_EQ(loop.stats().contactOnsets, 10);
  EXPECT_EQ(loop.stats().contactSteps, 500);
}

TEST(RuntimeLoop, StopFlagEndsEarly) {
  FakeClock clock;
  std::atomic<bool> stop{true};
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  NullDevice dev;
  SafetyFilter safety;
  LoopOptions o;
  o.stop = &stop;
  ServoLoop loop(dev, plane, safety, clock, o);
  loop.run();
  EXPECT_TRUE(loop.stats().stopped);
  EXPECT_EQ(loop.stats().steps, 0);
}

TEST(RuntimeLoop, BadOptionsRejected) {
  auto msg = [](double rate, double duration) {
    LoopOptions o;
    o.rate = rate;
    o.duration = duration;
    try {
      validate(o);
    } catch (const sf::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(msg(1000, 1), "");
  EXPECT_EQ(msg(0.5, 1).rfind("--rate:", 0), 0u);
  EXPECT_EQ(msg(20000, 1).rfind("--rate:", 0), 0u);
  EXPECT_EQ(msg(std::nan(""), 1).rfind("--rate:", 0), 0u);
  EXPECT_EQ(msg(1000, 0).rfind("--duration:", 0), 0u);
  EXPECT_EQ(msg(1000, INFINITY).rfind("--duration:", 0), 0u);
}

TEST(RuntimeLoop, RunDoesNotAllocate) {
  if (!SF_COUNT_ALLOCS) GTEST_SKIP() << "allocation counting is off under sanitizers";
  FakeClock clock;
  CostlyPlane r(clock);
  BobbingDevice dev;
  SafetyFilter safety;
  SpscRing<StepRecord> ring(1024);
  LoopOptions o;
  o.duration = 2.0;  // 2000 records and no consumer: the ring fills and drops, also without allocating
  ServoLoop loop(dev, r, safety, clock, o, &ring);
  tAllocs = 0;
  tCountAllocs = true;
  loop.run();
  tCountAllocs = false;
  EXPECT_EQ(tAllocs, 0);
  EXPECT_EQ(loop.stats().steps, 2000);
  EXPECT_EQ(loop.stats().recordsDropped, 2000 - 1024);
  // Control: counting works.
  static int* volatile sink;
  tCountAllocs = true;
  sink = new int(3);
  tCountAllocs = false;
  delete sink;
  EXPECT_EQ(tAllocs, 1);
}

TEST(RuntimeLoop, RecordsWrittenInOrder) {
  const fs::path dir = fs::temp_directory_path() / ("sf_rt_rec_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "rec.csv").string();
  FakeClock clock;
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  BobbingDevice dev;
  SafetyFilter safety;
  SpscRing<StepRecord> ring(64);  // small: the writer must keep up or records are dropped
  LoopOptions o;
  o.duration = 0.05;
  {
    RecordWriter writer(out, ring, 0.0005);
    ServoLoop loop(dev, plane, safety, clock, o, &ring);
    loop.run();
    writer.finish();
    EXPECT_EQ(writer.written() + loop.stats().recordsDropped, 50);
  }
  std::ifstream in(out);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, kRecordCsvHeader);
  long long prev = -1, rows = 0;
  while (std::getline(in, line)) {
    const long long tick = std::stoll(line.substr(0, line.find(',')));
    EXPECT_GT(tick, prev);
    prev = tick;
    ++rows;
  }
  EXPECT_EQ(rows, 50);  // 50 records fit in a 64-slot ring even if the writer slept throughout
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  fs::remove_all(dir);
}

TEST(RuntimeLoop, RecordWriterBadPath) {
  SpscRing<StepRecord> ring(4);
  EXPECT_THROW(RecordWriter("/nonexistent-dir/x.csv", ring), sf::InputError);
}

/// The costly plane and the bobbing device on a fake clock, run for `duration` s: the loop whose
/// statistics the report tests format.
struct ReportLoop {
  FakeClock clock;
  CostlyPlane r{clock};
  BobbingDevice dev;
  SafetyFilter safety;
  LoopOptions o;
  std::unique_ptr<ServoLoop> loop;
  explicit ReportLoop(double duration) {
    o.duration = duration;
    loop = std::make_unique<ServoLoop>(dev, r, safety, clock, o);
    loop->run();
  }
};

TEST(RuntimeLoop, ReportFormat) {
  const ReportLoop run(1.0);
  const std::string rep = loopReport(run.loop->stats(), run.o.rate, run.safety.counters(), 12, 34, 1000);
  std::istringstream in(rep);
  std::string l1, l2;
  std::getline(in, l1);
  std::getline(in, l2);
  EXPECT_EQ(l1, "step compute: p50 50.0 us, p99 99.0 us, p99.9 100.0 us, max 100.0 us");
  EXPECT_EQ(l2, "wake-up lateness: p50 0.0 us, p99 0.0 us, p99.9 0.0 us, max 0.0 us");
  EXPECT_NE(rep.find("missed deadlines: 0 (max consecutive 0, skipped ticks 0)"), std::string::npos);
  EXPECT_NE(rep.find("contacts: 500 steps in contact, 10 onsets"), std::string::npos);
  EXPECT_NE(rep.find("\npatch constructions: 12 for 34 faces (a face evicted and needed again is built again)\n"),
            std::string::npos)
      << rep;
  EXPECT_NE(rep.find("fault: none"), std::string::npos);
  EXPECT_NE(rep.find("records: 1000 written, 0 dropped"), std::string::npos);
}

// With a small --patch-capacity a face evicted and needed again is built again, and the line
// read "patches built: 40 of 6 faces". It counts constructions and says so, for every count.
TEST(RuntimeLoop, ReportCountsPatchConstructionsNotFaces) {
  const ReportLoop run(0.01);
  int checked = 0;
  for (const int built : {0, 5, 6, 7, 40, 1000}) {
    const std::string rep = loopReport(run.loop->stats(), run.o.rate, run.safety.counters(), built, 6);
    EXPECT_NE(rep.find("\npatch constructions: " + std::to_string(built) +
                       " for 6 faces (a face evicted and needed again is built again)\n"),
              std::string::npos)
        << rep;
    EXPECT_EQ(rep.find("patches built"), std::string::npos) << rep;
    EXPECT_EQ(rep.find(" of 6 faces"), std::string::npos) << rep;
    ++checked;
  }
  EXPECT_EQ(checked, 6);
}

}  // namespace
