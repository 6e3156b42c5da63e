// SPDX-License-Identifier: Apache-2.0
// Sweeps with fake renderers: sampling, the probe protocol, shards, threads, interruption.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_run.h>
#include "test_sweep_support.h"
#include "file_bytes.h"

namespace sf {
namespace {

namespace fs = std::filesystem;
using sweeptest::FakeSphere;


class SweepRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_sweep_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  SweepInputs inputs(size_t samples = 3000) {
    SweepInputs in;
    in.cache = cache;
    in.config.source = "sphere";
    in.config.methods = {"smooth", "faceted"};
    in.config.samples = samples;
    in.config.seed = 42;
    in.config.analytic = "sphere:1";
    in.depths = parseDepthList("2%,0.1");
    in.makeRenderer = [](const std::string& m) { return std::make_unique<FakeSphere>(1.0, 500, m == "faceted"); };
    return in;
  }
  std::shared_ptr<const PatchCache> cache = sweeptest::sphereCache();
  fs::path dir;
};

TEST_F(SweepRun, SamplesOnThePatchesWithOutwardNormals) {
  SweepInputs in = inputs();
  const HipSet set = buildHipSet(in);
  ASSERT_EQ(set.samples.size(), 3000u);
  ASSERT_EQ(set.size(), 6000u);
  for (const auto& s : set.samples) {
    EXPECT_NEAR(s.point.norm(), 1.0, 0.02);  // the patches approximate the unit sphere
    EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
    EXPECT_GT(s.normal.dot(s.point.normalized()), 0.99);
  }
  EXPECT_NEAR(set.area, 4 * M_PI, 0.1);
  EXPECT_NEAR(set.groups[0].depth, 0.02 * boundingDiagonal(*cache), 1e-15);  // 2% of the diagonal
  EXPECT_EQ(set.groups[1].depth, 0.1);
  // deterministic in the seed
  SweepInputs again = inputs();
  EXPECT_EQ(buildHipSet(again).hash(), set.hash());
  SweepInputs other = inputs();
  other.config.seed = 43;
  EXPECT_NE(buildHipSet(other).hash(), set.hash());
}

TEST_F(SweepRun, ProbeProtocolAndAccuracy) {
  SweepInputs in = inputs(500);
  std::atomic<int> made{0}, errors{0};
  in.makeRenderer = [&](const std::string&) {
    ++made;
    return std::make_unique<FakeSphere>(0.97, 500, false, &errors);  // inside the patches
  };
  in.config.analytic = "sphere:0.97";
  in.config.trajectories = {};
  const SweepData d = runSweep(in, {});
  EXPECT_GE(made.load(), 2);
  for (const auto& res : d.results)
    for (const HipResult& r : res) {
      EXPECT_TRUE(r.done && r.contact);
      EXPECT_LT(r.refDistance, 1e-6);  // the fake's SCP is on the analytic sphere
    }
  ASSERT_FALSE(d.trajectories.empty());  // the default section loop
  // Trajectories step on without reset (the fake counts that as a probe protocol error) ...
  EXPECT_GT(errors.load(), 0);
  // ... while probes alone follow reset, approach outside, pressed-in HIP.
  SweepInputs probesOnly = inputs(500);
  std::atomic<int> errors2{0};
  probesOnly.makeRenderer = [&](const std::string&) {
    return std::make_unique<FakeSphere>(0.97, 500, false, &errors2);
  };
  probesOnly.shardCount = 16;  // the 8 trajectory series go to shards 1, 3, 5, ..., 15: shard 0 runs none
  probesOnly.shardIndex = 0;
  runSweep(probesOnly, {});
  EXPECT_EQ(errors2.load(), 0);
}

TEST_F(SweepRun, ShardsMergeToTheUnshardedRun) {
  SweepData whole = runSweep(inputs(), {});
  writeSweepData(whole, (dir / "whole").string());
  const std::string table = writeSweepSummary(whole, (dir / "whole").string());
  EXPECT_NE(table.find("faceted"), std::string::npos);
  std::vector<SweepData> shards;
  for (int i = 0; i < 3; ++i) {
    SweepInputs in = inputs();
    in.shardIndex = i;
    in.shardCount = 3;
    const fs::path sd = dir / ("shard" + std::to_string(i));
    writeSweepData(runSweep(in, {}), sd.string());
    shards.push_back(readSweepData(sd.string()));
  }
  std::swap(shards[0], shards[2]);  // order of the inputs does not matter
  const SweepData merged = mergeSweepData(shards);
  writeSweepData(merged, (dir / "merged").string());
  writeSweepSummary(merged, (dir / "merged").string());
  for (const char* f : {"summary.json", "sweep.json", "hips.bin", "results_smooth.bin", "results_faceted.bin",
                        "trajectories.json", "faceted_2pct.ply"})
    EXPECT_EQ(sf::test::fileBytes(dir / "whole" / f), sf::test::fileBytes(dir / "merged" / f)) << f;
  // A missing shard, and a shard of another run, are refused.
  EXPECT_THROW(mergeSweepData({shards[0], shards[1]}), InputError);
  SweepInputs other = inputs();
  other.config.seed = 7;
  other.shardIndex = 1;
  other.shardCount = 3;
  EXPECT_THROW(mergeSweepData({shards[1], shards[2], runSweep(other, {})}), InputError);
}

TEST_F(SweepRun, ThreadCountsAgree) {
  SweepControl one, two;
  one.threads = 1;
  two.threads = 2;
  const SweepData a = runSweep(inputs(), one), b = runSweep(inputs(), two);
  ASSERT_EQ(a.results.size(), b.results.size());
  for (size_t m = 0; m < a.results.size(); ++m)
    EXPECT_EQ(0, std::memcmp(a.results[m].data(), b.results[m].data(), a.results[m].size() * sizeof(HipResult)));
}

TEST_F(SweepRun, FacetedFieldIsFlaggedSmoothIsNot) {
  const SweepData d = runSweep(inputs(), {});
  writeSweepData(d, dir.string());
  writeSweepSummary(d, dir.string());
  const std::string s = sf::test::fileBytes(dir / "summary.json");
  // results[0]: smooth 2%, [2]: faceted 2% (method-major)
  const auto pairsAt = [&](int k) {
    size_t pos = 0;
    for (int i = 0; i <= k; ++i) pos = s.find("\"flagged_pairs\":", pos + 1);
    return std::stoul(s.substr(pos + 16));
  };
  EXPECT_EQ(pairsAt(0), 0u);
  EXPECT_GT(pairsAt(2), 10u);
}

TEST_F(SweepRun, StopKeepsWhatIsDoneAndSaysPartial) {
  std::atomic<bool> stop{false};
  SweepControl ctl;
  ctl.threads = 1;
  ctl.stop = &stop;
  std::atomic<size_t> seen{0};
  ctl.progress = [&](size_t n) {
    if ((seen += n) >= 1000) stop = true;
  };
  const SweepData d = runSweep(inputs(), ctl);
  EXPECT_TRUE(d.interrupted);
  size_t done = 0;
  for (const auto& r : d.results[0]) done += r.done;
  EXPECT_GE(done, 1000u);
  EXPECT_LT(done, 6000u);
  EXPECT_TRUE(d.trajectories.empty());
  writeSweepData(d, dir.string());
  writeSweepSummary(d, dir.string());
  EXPECT_NE(sf::test::fileBytes(dir / "summary.json").find("\"complete\": false"), std::string::npos);
}

}  // namespace
}  // namespace sf
