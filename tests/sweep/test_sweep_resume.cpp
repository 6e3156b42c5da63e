// SPDX-License-Identifier: Apache-2.0
// Sweep checkpoints and --resume, with fake renderers: a run stopped at any
// point and resumed from what it wrote gives the bytes of the uninterrupted run; checkpoints
// are atomic and self-identifying; trajectory series spread over the shards; sweep-merge
// refuses incomplete shards and names them; damaged per-HIP records are refused naming the HIP.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <smoothforce/sweep/generators.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_run.h>
#include "test_sweep_support.h"
#include "file_bytes.h"

namespace sf {
namespace {

namespace fs = std::filesystem;
using sweeptest::FakeSphere;


const char* const kFiles[] = {"sweep.json", "hips.bin", "results_smooth.bin", "results_faceted.bin",
                              "trajectories.json"};

class SweepResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_resume_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  SweepInputs inputs(int shard = 0, int count = 1) const {
    SweepInputs in;
    in.cache = cache;
    in.config.source = "sphere";
    in.config.methods = {"smooth", "faceted"};
    in.config.samples = 2000;
    in.config.seed = 5;
    in.config.analytic = "sphere:1";
    in.depths = parseDepthList("2%,0.1");
    in.shardIndex = shard;
    in.shardCount = count;
    in.makeRenderer = [](const std::string& m) { return std::make_unique<FakeSphere>(1.0, 500, m == "faceted"); };
    return in;
  }
  /// Runs with a checkpoint every block (checkpointSeconds tiny) and stops after `stopAfter`
  /// probes; returns the data the run ended with (written to out as the CLI does).
  SweepData interruptedRun(SweepInputs in, size_t stopAfter, const fs::path& out, int* checkpoints) {
    std::atomic<bool> stop{false};
    std::atomic<size_t> seen{0};
    SweepWriter writer(out.string());
    SweepControl ctl;
    ctl.threads = 1;
    ctl.stop = &stop;
    ctl.progress = [&](size_t n) {
      if ((seen += n) >= stopAfter) stop = true;
    };
    ctl.checkpointSeconds = 1e-9;
    ctl.checkpoint = [&](const SweepData& d) {
      ++*checkpoints;
      writer.write(d);
    };
    SweepData d = runSweep(std::move(in), ctl);
    writer.write(d);
    return d;
  }
  std::shared_ptr<const PatchCache> cache = sweeptest::sphereCache();
  fs::path dir;
};

TEST_F(SweepResume, StoppedAnywhereAndResumedGivesTheUninterruptedBytes) {
  writeSweepData(runSweep(inputs(), {}), (dir / "whole").string());
  // 4,000 HIPs x 2 methods = 8,000 probes: stop in the first method, at the method boundary,
  // in the second, and (8,000) after every probe but before the trajectory series.
  int cases = 0;
  for (size_t stopAfter : {64, 1000, 4000, 5555, 8000}) {
    const fs::path out = dir / ("run_" + std::to_string(stopAfter));
    int checkpoints = 0;
    const SweepData partial = interruptedRun(inputs(), stopAfter, out, &checkpoints);
    EXPECT_TRUE(partial.interrupted) << stopAfter;
    EXPECT_FALSE(partial.complete()) << stopAfter;
    EXPECT_GE(checkpoints, 1) << stopAfter;
    const std::vector<uint64_t> done = partial.doneCounts();
    EXPECT_GE(done[0] + done[1], std::min<size_t>(stopAfter, 8000)) << stopAfter;
    EXPECT_LT(done[0] + done[1] + partial.trajectories.size(), 8000u + partial.trajectoryTotal) << stopAfter;
    // what is on disk is what the run ended with; resume from it
    SweepData onDisk = readSweepData(out.string());
    EXPECT_EQ(onDisk.doneCounts(), done);
    EXPECT_NE(sf::test::fileBytes(out / "sweep.json").find("\"complete\": false"), std::string::npos);
    SweepInputs again = inputs();
    again.resume = std::move(onDisk);
    SweepTiming tm;
    const SweepData resumed = runSweep(std::move(again), {}, &tm);
    EXPECT_TRUE(resumed.complete());
    EXPECT_EQ(tm.methodDone[0] + tm.methodDone[1], 8000 - done[0] - done[1]) << "only the rest is computed";
    writeSweepData(resumed, out.string());
    for (const char* f : kFiles) EXPECT_EQ(sf::test::fileBytes(dir / "whole" / f), sf::test::fileBytes(out / f)) << stopAfter << " " << f;
    ++cases;
  }
  EXPECT_EQ(cases, 5);
}

TEST_F(SweepResume, CheckpointsAreAtomicAndSelfIdentifying) {
  const fs::path out = dir / "run";
  int checkpoints = 0;
  interruptedRun(inputs(), 3000, out, &checkpoints);
  EXPECT_GE(checkpoints, 2);
  for (const auto& e : fs::directory_iterator(out))  // tmp + rename: no temporaries stay
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  // a per-HIP file of another sweep in the directory is refused, not mixed in
  SweepInputs other = inputs();
  other.config.seed = 6;
  writeSweepData(runSweep(std::move(other), {}), (dir / "other").string());
  fs::copy_file(dir / "other" / "results_faceted.bin", out / "results_faceted.bin",
                fs::copy_options::overwrite_existing);
  try {
    readSweepData(out.string());
    ADD_FAILURE() << "a results file of another sweep was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("results_faceted.bin: written by another sweep"), std::string::npos)
        << e.what();
  }
}

TEST_F(SweepResume, ResumeRefusesAnotherSweepOrShard) {
  const fs::path out = dir / "run";
  int checkpoints = 0;
  interruptedRun(inputs(), 500, out, &checkpoints);
  struct Case {
    SweepInputs in;
    std::string message;
  };
  std::vector<Case> cases;
  cases.push_back({inputs(), "seed (5 vs 9)"});
  cases.back().in.config.seed = 9;
  cases.push_back({inputs(), "stiffness (500.0 vs 800.0)"});
  cases.back().in.config.force.stiffness = 800;
  cases.push_back({inputs(1, 2), "holds shard 0/1, not 1/2"});
  for (Case& c : cases) {
    c.in.resume = readSweepData(out.string());
    try {
      runSweep(std::move(c.in), {});
      ADD_FAILURE() << c.message;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(out.string() + ": holds"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(cases.size(), 3u);
}

TEST_F(SweepResume, TrajectorySeriesAreSpreadOverShards) {
  const SweepData whole = runSweep(inputs(), {});
  // one default loop x 2 methods x 2 depths x 2 steps
  ASSERT_EQ(whole.trajectoryTotal, 8u);
  ASSERT_EQ(whole.trajectories.size(), 8u);
  std::vector<SweepData> shards;
  size_t series = 0;
  for (int i = 0; i < 3; ++i) {
    const fs::path sd = dir / ("shard" + std::to_string(i));
    writeSweepData(runSweep(inputs(i, 3), {}), sd.string());
    shards.push_back(readSweepData(sd.string()));
    const SweepData& s = shards.back();
    EXPECT_EQ(s.trajectoryEnd - s.trajectoryBegin, s.trajectories.size());
    EXPECT_GE(s.trajectories.size(), 2u) << "8 series over 3 shards: 2 or 3 each";
    EXPECT_LE(s.trajectories.size(), 3u);
    for (const auto& t : s.trajectories) {
      const TrajectorySeries& w = whole.trajectories[t.index];
      EXPECT_EQ(t.force, w.force) << t.index;
      EXPECT_EQ(t.method + t.depthLabel, w.method + w.depthLabel) << t.index;
    }
    series += s.trajectories.size();
  }
  EXPECT_EQ(series, 8u);
  const SweepData merged = mergeSweepData(shards);
  writeSweepData(whole, (dir / "whole").string());
  writeSweepData(merged, (dir / "merged").string());
  for (const char* f : kFiles) EXPECT_EQ(sf::test::fileBytes(dir / "whole" / f), sf::test::fileBytes(dir / "merged" / f)) << f;
  // a shard's series missing from the merge is named
  shards[1].trajectories.clear();
  shards[1].trajectoryEnd = shards[1].trajectoryBegin;
  EXPECT_THROW(mergeSweepData(shards), InputError);
}

TEST_F(SweepResume, MergeRefusesIncompleteShardsAndNamesThem) {
  std::vector<SweepData> shards;
  int checkpoints = 0;
  for (int i = 0; i < 4; ++i) {
    const fs::path sd = dir / ("shard" + std::to_string(i));
    if (i == 1 || i == 3)
      interruptedRun(inputs(i, 4), 300, sd, &checkpoints);
    else
      writeSweepData(runSweep(inputs(i, 4), {}), sd.string());
    shards.push_back(readSweepData(sd.string()));
  }
  try {
    mergeSweepData(shards);
    ADD_FAILURE() << "incomplete shards were merged";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("shard 1/4 (" + (dir / "shard1").string() + ")"), std::string::npos) << m;
    EXPECT_NE(m.find("shard 3/4 (" + (dir / "shard3").string() + ")"), std::string::npos) << m;
    EXPECT_EQ(m.find("shard 0/4"), std::string::npos) << m;
    EXPECT_EQ(m.find("shard 2/4"), std::string::npos) << m;
    EXPECT_NE(m.find("sweep --resume"), std::string::npos) << m;
  }
  for (int i : {1, 3}) {  // resumed, they merge to the unsharded run
    SweepInputs in = inputs(i, 4);
    in.resume = std::move(shards[i]);
    writeSweepData(runSweep(std::move(in), {}), (dir / ("shard" + std::to_string(i))).string());
    shards[i] = readSweepData((dir / ("shard" + std::to_string(i))).string());
  }
  writeSweepData(mergeSweepData(shards), (dir / "merged").string());
  writeSweepData(runSweep(inputs(), {}), (dir / "whole").string());
  for (const char* f : kFiles) EXPECT_EQ(sf::test::fileBytes(dir / "whole" / f), sf::test::fileBytes(dir / "merged" / f)) << f;
  // a hand-edited shard index or count is refused naming the field (a count of 1e308 merged)
  const std::string meta = sf::test::fileBytes(dir / "shard2" / "sweep.json");
  int refused = 0;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"\"index\": 2", "\"index\": -1"}, {"\"index\": 2", "\"index\": \"2\""},
           {"\"index\": 2", "\"index\": 4"}, {"\"count\": 4", "\"count\": 1e308"}}) {
    const size_t at = meta.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    std::string edited = meta;
    edited.replace(at, from.size(), to);
    std::ofstream(dir / "shard2" / "sweep.json") << edited;
    try {
      readSweepData((dir / "shard2").string());
      ADD_FAILURE() << to;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("sweep.json: shard." + from.substr(1, 5)), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, 4);
}

// A trajectory or reference file changed under its path between two shards (or before a
// resume) makes another sweep: sweep-merge and --resume refuse it, naming the file (they joined
// such shards into a summary of neither run).
TEST_F(SweepResume, AChangedTrajectoryOrReferenceFileIsRefusedNamingIt) {
  const std::string traj = (dir / "t.csv").string(), ref = (dir / "ref.obj").string();
  auto writeTraj = [&](const char* z) { std::ofstream(traj) << "x,y,z\n0,0,1\n0.3,0," << z << "\n0.5,0,0.87\n"; };
  auto withFiles = [&](int shard) {
    SweepInputs in = inputs(shard, 2);
    in.config.trajectories = {traj};
    in.config.reference = ref;
    return in;
  };
  int refused = 0;
  for (const std::string changed : {"trajectory", "reference"}) {
    writeTraj("0.95");
    writeGeneratedObj(quadSphere(1, 3), ref, "reference");
    const fs::path s0 = dir / (changed + "0"), s1 = dir / (changed + "1");
    writeSweepData(runSweep(withFiles(0), {}), s0.string());
    if (changed == "trajectory")
      writeTraj("0.9");
    else
      writeGeneratedObj(quadSphere(1, 4), ref, "reference");
    writeSweepData(runSweep(withFiles(1), {}), s1.string());
    const std::string named = "the contents of --" + changed + " " + (changed == "trajectory" ? traj : ref);
    try {
      mergeSweepData({readSweepData(s0.string()), readSweepData(s1.string())});
      ADD_FAILURE() << "merged across a changed " << changed;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
      refused += std::string(e.what()).find("the file changed") != std::string::npos;
    }
    SweepInputs again = withFiles(0);
    again.resume = readSweepData(s0.string());
    try {
      runSweep(std::move(again), {});
      ADD_FAILURE() << "resumed across a changed " << changed;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(s0.string() + ": holds another sweep (" + named), std::string::npos)
          << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, 4);
  // unchanged files: the shards merge (and record the contents)
  writeSweepData(runSweep(withFiles(0), {}), (dir / "same0").string());
  const SweepData same0 = readSweepData((dir / "same0").string());
  EXPECT_EQ(same0.config.trajectoryHashes.size(), 1u);
  EXPECT_EQ(same0.config.referenceHash.size(), 16u);
  EXPECT_NO_THROW(mergeSweepData({same0, readSweepData((dir / "reference1").string())}));
}

// Shards written before the file contents were recorded: two of them merge as before (nothing
// to compare); one beside a new shard, or resumed by a new run, is refused saying why.
TEST_F(SweepResume, ShardsWithoutRecordedFileContents) {
  const std::string traj = (dir / "t.csv").string();
  std::ofstream(traj) << "x,y,z\n0,0,1\n0.3,0,0.95\n";
  std::vector<SweepData> old, fresh;
  for (int i = 0; i < 2; ++i) {
    SweepInputs in = inputs(i, 2);
    in.config.trajectories = {traj};
    SweepData d = runSweep(std::move(in), {});
    const fs::path o = dir / ("new" + std::to_string(i)), f = dir / ("old" + std::to_string(i));
    writeSweepData(d, o.string());
    d.config.trajectoryHashes.clear();  // as written before: no "trajectory_hashes" in sweep.json
    writeSweepData(d, f.string());
    EXPECT_EQ(sf::test::fileBytes(f / "sweep.json").find("trajectory_hashes"), std::string::npos);
    fresh.push_back(readSweepData(o.string()));
    old.push_back(readSweepData(f.string()));
  }
  EXPECT_NO_THROW(mergeSweepData(old));
  for (auto pair : {std::vector<SweepData>{fresh[0], old[1]}, std::vector<SweepData>{old[0], fresh[1]}}) {
    try {
      mergeSweepData(pair);
      ADD_FAILURE() << "an old shard merged with a new one";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("recorded in one, not in the other"), std::string::npos) << e.what();
    }
  }
  SweepInputs in = inputs(0, 2);
  in.config.trajectories = {traj};
  in.resume = old[0];
  EXPECT_THROW(runSweep(std::move(in), {}), InputError);
}

// sweep.json of another format version is refused naming the file and both versions (it was
// read as version 1); shards named twice or overlapping are named by their directories.
TEST_F(SweepResume, MergeRefusesAnotherFormatVersionAndNamesOverlappingShards) {
  const std::string s0 = (dir / "s0").string(), s1 = (dir / "s1").string();
  writeSweepData(runSweep(inputs(0, 2), {}), s0);
  writeSweepData(runSweep(inputs(1, 2), {}), s1);
  const std::string meta = sf::test::fileBytes(dir / "s1" / "sweep.json");
  const std::string from = "\"smoothforce_sweep_data\": 1,";
  ASSERT_NE(meta.find(from), std::string::npos);
  int refused = 0;
  for (const auto& [to, says] : std::vector<std::pair<std::string, std::string>>{
           {"\"smoothforce_sweep_data\": 2,", "format version 2; this SmoothForce reads version 1"},
           {"\"smoothforce_sweep_data\": \"1\",", "format version \"1\"; this SmoothForce reads version 1"},
           {"", "format version (none); this SmoothForce reads version 1"}}) {
    std::string edited = meta;
    edited.replace(meta.find(from), from.size(), to);
    std::ofstream(dir / "s1" / "sweep.json") << edited;
    try {
      readSweepData(s1);
      ADD_FAILURE() << to;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(s1 + "/sweep.json: sweep data " + says), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, 3);
  std::ofstream(dir / "s1" / "sweep.json") << meta;
  try {
    mergeSweepData({readSweepData(s0), readSweepData(s1), readSweepData(s1)});
    ADD_FAILURE() << "a shard listed twice was merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("are in two shards: shard 1/2 (" + s1 + ") and shard 1/2 (" + s1 + ")"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(SweepResume, DamagedRecordsAreRefusedNamingTheHip) {
  // a record edited or damaged behind a valid header: a NaN HIP or force, flags other than 0 / 1,
  // a contact not done, a face below -1 (HipResult: force 0, scp 12, ref 24, face 28, status 32,
  // iterations 36, contact 38, done 39; 32-byte headers)
  const std::string s0 = (dir / "s0").string();
  writeSweepData(runSweep(inputs(), {}), s0);
  const std::string hips = sf::test::fileBytes(dir / "s0" / "hips.bin"), res = sf::test::fileBytes(dir / "s0" / "results_smooth.bin");
  auto poke = [](std::string data, size_t at, const void* bytes, size_t n) {
    std::memcpy(&data[at], bytes, n);
    return data;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const float nanf = std::numeric_limits<float>::quiet_NaN();
  const uint8_t seven = 7, one = 1, zero = 0;
  const int32_t minusFive = -5;
  const size_t k = 3, rec = 32 + 40 * k;  // HIP 3
  struct Damage {
    std::string file, data, says;
  };
  const std::vector<Damage> damages = {
      {"hips.bin", poke(hips, 32 + 24 * k, &nan, 8), "hips.bin: HIP 3 is not finite"},
      {"results_smooth.bin", poke(res, rec + 38, &seven, 1),
       "results_smooth.bin: HIP 3: done and contact must be 0 or 1"},
      {"results_smooth.bin", poke(poke(res, rec + 38, &one, 1), rec + 39, &zero, 1),
       "results_smooth.bin: HIP 3: in contact but not done"},
      {"results_smooth.bin", poke(res, rec + 4, &nanf, 4), "results_smooth.bin: HIP 3: force is not finite"},
      {"results_smooth.bin", poke(res, rec + 28, &minusFive, 4), "results_smooth.bin: HIP 3: face -5 outside"}};
  int refused = 0;
  for (const Damage& d : damages) {
    std::ofstream(dir / "s0" / d.file, std::ios::binary) << d.data;
    try {
      readSweepData(s0);
      ADD_FAILURE() << d.says;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(s0 + "/" + d.says), std::string::npos) << e.what();
      ++refused;
    }
    std::ofstream(dir / "s0" / "hips.bin", std::ios::binary) << hips;
    std::ofstream(dir / "s0" / "results_smooth.bin", std::ios::binary) << res;
  }
  EXPECT_EQ(refused, 5);
  EXPECT_NO_THROW(readSweepData(s0));  // the undamaged files read
}

}  // namespace
}  // namespace sf
