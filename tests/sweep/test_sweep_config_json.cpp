// SPDX-License-Identifier: Apache-2.0
// A sweep's configuration has one JSON writer and one reader (sweep_io.cpp describeConfig), which
// config.json and summary.json share: every setting survives the round trip, every setting
// changed alone changes the configuration and its hash, and the force options in the file are
// read by the shared reader (force_option_text.h) with its message.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include <smoothforce/force/force_option_text.h>
#include <smoothforce/sweep/sweep_io.h>

#include "test_hostile_support.h"

namespace sf {
namespace {

/// A sweep configuration with every setting away from its default.
SweepConfig unusualConfig() {
  SweepConfig c;
  c.source = "mesh.obj";
  c.meshHash = "0123456789abcdef";
  c.faces = 12;
  c.sampleOn = "reference";
  c.samples = 77;
  c.seed = 9;
  c.level = 5;
  c.methods = {"patch", "shading"};
  c.force.stiffness = 812.5;
  c.approach = 2e-3;
  c.force.refine = RefineMethod::Newton;
  c.force.angleTolerance = 1.25e-7;
  c.force.maxIterations = 17;
  c.force.positionTolerance = 3e-9;
  c.force.initialGuess = InitialGuess::Polygon;
  c.force.tessellationLevel = 6;
  c.force.finalStep = FinalStep::Model;
  c.preset = "balanced";
  c.backend = "serial";
  c.reference = "dense.obj";
  c.analytic = "sphere:1";
  c.knn = 5;
  c.thresholdDeg = 12.5;
  c.trajectories = {"a.csv"};
  c.trajectoryHashes = {"fedcba9876543210"};
  c.referenceHash = "00112233aabbccdd";
  c.trajectoryStep = 0.01;
  c.diagonal = 2.5;
  c.area = 3.75;
  c.hipHash = "feedfacecafebeef";
  c.groupLabels = {"1%", "2%"};
  c.groupDepths = {0.025, 0.05};
  return c;
}

TEST(SweepConfigJson, OneWriterAndOneReaderKeepEverySetting) {
  hostile::TempDir dir("sf_sweep_config_json");
  const SweepConfig c = unusualConfig();
  SweepData d;
  d.config = c;
  d.results.resize(c.methods.size());  // an empty shard: the configuration alone
  writeSweepData(d, dir.path.string());
  const SweepConfig back = readSweepData(dir.path.string()).config;
  EXPECT_EQ(sweepConfigDifference(c, back), "");
  EXPECT_EQ(back.source, c.source);
  // the force options, each through the shared reader
  ForceSettings a{ForceMethod::Patch, c.force, c.preset}, b{ForceMethod::Patch, back.force, back.preset};
  int same = 0;
  for (const OptionSpec& s : kForceOptionSpecs) same += forceOptionValue(a, s.key) == forceOptionValue(b, s.key);
  EXPECT_EQ(same, 12);
  EXPECT_EQ(sweepConfigHash(back), sweepConfigHash(c));
  // every setting changed alone changes the configuration (so the reader cannot drop one)
  int differ = 0, settings = 0;
  auto changed = [&](auto&& edit) {
    SweepConfig e = c;
    edit(e);
    ++settings;
    differ += !sweepConfigDifference(c, e).empty() && sweepConfigHash(e) != sweepConfigHash(c);
  };
  changed([](SweepConfig& e) { e.force.stiffness = 900; });
  changed([](SweepConfig& e) { e.force.angleTolerance = 1e-6; });
  changed([](SweepConfig& e) { e.force.maxIterations = 18; });
  changed([](SweepConfig& e) { e.force.positionTolerance = 4e-9; });
  changed([](SweepConfig& e) { e.force.initialGuess = InitialGuess::Surface; });
  changed([](SweepConfig& e) { e.force.tessellationLevel = 7; });
  changed([](SweepConfig& e) { e.force.finalStep = FinalStep::Evaluated; });
  changed([](SweepConfig& e) { e.force.refine = RefineMethod::PaperDescent; });
  changed([](SweepConfig& e) { e.force.surfaceIndex = SurfaceIndex::Bounds; });
  changed([](SweepConfig& e) { e.preset = "fast"; });
  changed([](SweepConfig& e) { e.trajectoryStep = 0.02; });
  changed([](SweepConfig& e) { e.diagonal = 2.6; });
  changed([](SweepConfig& e) { e.area = 3.8; });
  EXPECT_EQ(differ, settings);
}

TEST(SweepConfigJson, ABadForceValueInTheFileGetsTheSharedMessage) {
  hostile::TempDir dir("sf_sweep_config_bad");
  SweepData d;
  d.config = unusualConfig();
  d.results.resize(d.config.methods.size());
  writeSweepData(d, dir.path.string());
  const std::string file = (dir.path / "sweep.json").string();
  std::string text;
  {
    std::ifstream in(file);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string from = "\"refine\": \"newton\"";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, from.size(), "\"refine\": \"gauss\"");
  std::ofstream(file) << text;
  try {
    readSweepData(dir.path.string());
    ADD_FAILURE() << "read a sweep with refine 'gauss'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("refine: expected newton|paper, got 'gauss'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sf
