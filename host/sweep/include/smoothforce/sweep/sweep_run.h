// SPDX-License-Identifier: Apache-2.0
// A whole sweep (or one shard of it): HIPs, probes per method, trajectories -> SweepData.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/sweep/sweep.h>
#include <smoothforce/sweep/sweep_io.h>

namespace sf {

/// What to sweep. config carries the knobs (methods, samples, seed, level, stiffness, refine,
/// knn, thresholdDeg, trajectories, trajectoryStep (0: diagonal / 400), reference, analytic,
/// sampleOn, source, backend); runSweep fills the derived fields (diagonal, area, hip hash,
/// depth groups, faces, mesh hash).
struct SweepInputs {
  std::shared_ptr<const PatchCache> cache;
  SweepConfig config;
  std::vector<DepthSpec> depths;  ///< unless hipsFile
  std::string hipsFile;           ///< CSV x,y,z: explicit HIPs (config.sampleOn = "file")
  int shardIndex = 0, shardCount = 1;
  /// Device for config.backend == "opencl", where the patch method's refinements run
  /// (runPatchProbesOpenCL; trajectories and the other methods stay on the CPU).
  OpenCLOptions opencl;
  /// Makes a renderer for a method name; default: makeForceRenderer(cache, method, options).
  std::function<std::unique_ptr<ForceRenderer>(const std::string& method)> makeRenderer;
  /// A checkpoint of this sweep and shard (readSweepData of a previous run's output): its
  /// records with done = 1 and its finished trajectory series are kept, the rest computed.
  /// runSweep throws InputError when it holds another sweep, shard or series range.
  std::optional<SweepData> resume;
};

/// Why a method list is not one result set per method: empty, or a method named twice (the
/// message names it and its two positions); empty string when it is fine. The CLI reports it as
/// a usage error, runSweep as InputError.
std::string methodListProblem(const std::vector<std::string>& methods);

struct SweepTiming {
  double setupSeconds = 0;            ///< sampling, projection, reference
  std::vector<double> methodSeconds;  ///< probes, per method
  double trajectorySeconds = 0;
  uint64_t hipsRun = 0;              ///< HIPs of the shard, per method
  std::vector<uint64_t> methodDone;  ///< HIPs computed by this run per method (fewer when stopped or resumed)
  /// Patch constructions per method when the cache is a skeleton (lazy, summed over the
  /// workers, each of which builds what its HIPs touch); 0 for a prebuilt cache.
  std::vector<long> methodPatchesBuilt;
};

/// Runs the shard's probes, method by method, in blocks (checkpoints between blocks, see
/// SweepControl), then its trajectory series, in parallel. Stops early when control.stop is
/// set: the data then holds the records and series done (interrupted = true). Progress
/// covers the probes (methods x HIPs of the shard left to run). Throws InputError for bad input
/// (OptionError for option values, --hips with --trajectory included: a HIP file gives no
/// depth to run trajectories at).
SweepData runSweep(SweepInputs inputs, const SweepControl& control, SweepTiming* timing = nullptr);

/// The HIP list alone (deterministic), with the derived config fields filled.
HipSet buildHipSet(SweepInputs& inputs, std::unique_ptr<ReferenceSurface>* reference = nullptr);

}  // namespace sf
