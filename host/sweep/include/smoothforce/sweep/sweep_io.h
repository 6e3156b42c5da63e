// Sweep results on disk: per-HIP files that shards write and sweep-merge joins, and the
// summary (summary.json, PLY point clouds, the printed table) computed from them.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/sweep/sweep.h>

namespace sf {

/// Everything that determines a sweep's HIPs and results; shards must agree on all of it.
struct SweepConfig {
  std::string source;    ///< mesh or cache file as given
  std::string meshHash;  ///< hex XXH64 of the mesh file (from the cache)
  int faces = 0;
  std::string sampleOn = "patch";  ///< patch | reference | file
  uint64_t samples = 0, seed = 1;
  int level = 8;  ///< tessellation level used for sampling and projection
  std::vector<std::string> methods;
  double stiffness = 500;  ///< N/m
  double approach = 1e-3;  ///< probes first step at p + approach * depth * n
  std::string refine = "newton";
  double angleTolerance = 1e-5;          ///< rad, patch refinement (ForceOptions)
  int maxIterations = 50;                ///< patch refinement cap (ForceOptions)
  std::string initialGuess = "polygon";  ///< polygon | tessellation (ForceOptions)
  int guessLevel = 2;                    ///< tessellation level of the initial guess
  std::string preset;                    ///< --preset as given ("" when none)
  std::string backend = "tbb";           ///< tbb | serial | opencl (construction, patch refinement)
  std::string reference, analytic;       ///< reference mesh path, analytic spec ("" when none)
  int knn = 8;
  double thresholdDeg = 10;
  std::vector<std::string> trajectories;  ///< files; empty: the default section loop
  double trajectoryStep = 0;              ///< m
  double diagonal = 0, area = 0;          ///< m, m^2
  std::string hipHash;                    ///< hex HipSet::hash()
  std::vector<std::string> groupLabels;   ///< depth labels ("file" for a HIP file)
  std::vector<double> groupDepths;        ///< m
};

/// One run's or one shard's data: HIPs and results for the global index range [begin, end).
struct SweepData {
  SweepConfig config;
  int shardIndex = 0, shardCount = 1;
  uint64_t begin = 0, end = 0;
  bool interrupted = false;
  std::vector<Eigen::Vector3d> hips;            ///< end - begin
  std::vector<std::vector<HipResult>> results;  ///< per method, end - begin each
  std::vector<TrajectorySeries> trajectories;   ///< shard 0 (or an unsharded run) only
  uint64_t total() const { return config.groupLabels.size() * config.samples; }
};

/// [begin, end) of shard `index` of `count`: contiguous, sizes differ by at most one.
void shardRange(uint64_t total, int index, int count, uint64_t& begin, uint64_t& end);
/// Parses "I/N" (0 <= I < N); throws InputError.
void parseShard(const std::string& text, int& index, int& count);

/// Writes sweep.json, hips.bin, results_METHOD.bin and trajectories.json into dir (created).
/// Throws InputError when a file cannot be written.
void writeSweepData(const SweepData& data, const std::string& dir);
/// Reads what writeSweepData wrote; throws InputError naming the file for a missing,
/// truncated or inconsistent file.
SweepData readSweepData(const std::string& dir);
/// Joins shards into the unsharded run's data. Throws InputError when configurations differ,
/// or the ranges overlap or leave a gap.
SweepData mergeSweepData(std::vector<SweepData> shards);

/// Computes the metrics of a whole run (begin 0, end total) and writes summary.json and one
/// METHOD_DEPTH.ply per method and depth into dir. Returns the table printed for people.
/// summary.json holds no timings or thread counts: merged shards give the same bytes.
std::string writeSweepSummary(const SweepData& data, const std::string& dir);

}  // namespace sf
