// SPDX-License-Identifier: Apache-2.0
// Sweep results on disk: per-HIP files that shards write and sweep-merge joins, and the
// summary (summary.json, PLY point clouds, the printed table) computed from them.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/sweep/sweep.h>

namespace sf {

/// Everything that determines a sweep's HIPs and results; shards must agree on all of it. As
/// JSON (config.json's and summary.json's "config"), written and read by one description of its
/// keys (sweep_io.cpp, describeConfig).
struct SweepConfig {
  std::string source;    ///< mesh or cache file as given
  std::string meshHash;  ///< hex XXH64 of the mesh file (from the cache)
  int faces = 0;
  std::string sampleOn = "patch";  ///< patch | reference | file
  uint64_t samples = 0, seed = 1;
  int level = 8;  ///< tessellation level used for sampling and projection
  std::vector<std::string> methods;
  /// Stiffness (N/m) and the refinement options (method-independent; patchCapacity unused: a
  /// sweep keeps every patch a worker touches). Written and read through force_option_text.h.
  ForceOptions force;
  double approach = 1e-3;  ///< probes first step at p + approach * depth * n
  std::string preset;      ///< --preset as given ("" when none)
  std::string backend = "tbb";           ///< tbb | serial | opencl (construction, patch refinement)
  std::string reference, analytic;       ///< reference mesh path, analytic spec ("" when none)
  int knn = 8;
  double thresholdDeg = 10;
  std::vector<std::string> trajectories;  ///< files; empty: the default section loop
  /// Hex XXH64 of each trajectory file's points as read (trajectories[i]), so that a file changed
  /// under the same path between shards or before a resume is refused; empty without files,
  /// and in sweeps written before they were recorded.
  std::vector<std::string> trajectoryHashes;
  /// Hex XXH64 of the --reference mesh as read (its triangles and corner normals); "" without
  /// one, and in sweeps written before it was recorded.
  std::string referenceHash;
  double trajectoryStep = 0;             ///< m
  double diagonal = 0, area = 0;         ///< m, m^2
  std::string hipHash;                   ///< hex HipSet::hash()
  std::vector<std::string> groupLabels;  ///< depth labels ("file" for a HIP file)
  std::vector<double> groupDepths;       ///< m
};

/// One run's or one shard's data: HIPs and results for the global index range [begin, end),
/// complete or a checkpoint (records with done = 0 are still to compute).
struct SweepData {
  SweepConfig config;
  int shardIndex = 0, shardCount = 1;
  uint64_t begin = 0, end = 0;
  bool interrupted = false;           ///< the run that wrote it stopped on a signal
  std::vector<Eigen::Vector3d> hips;  ///< end - begin
  /// Unit outward normal of each HIP's surface sample (end - begin), or empty (a sweep directory
  /// written before normals.bin existed): the discontinuity metric leaves out neighbour pairs
  /// whose sample normals disagree (opposite sides of a thin part).
  std::vector<Eigen::Vector3d> normals;
  std::vector<std::vector<HipResult>> results;  ///< per method, end - begin each
  /// Trajectory series: the sweep has trajectoryTotal of them (trajectory x method x depth x
  /// step, TrajectorySeries::index); this shard runs [trajectoryBegin, trajectoryEnd) of them
  /// (shardRange); `trajectories` holds those finished, by increasing index.
  uint64_t trajectoryTotal = 0, trajectoryBegin = 0, trajectoryEnd = 0;
  std::vector<TrajectorySeries> trajectories;
  std::string directory;  ///< the directory readSweepData read ("" otherwise), for messages
  uint64_t total() const { return config.groupLabels.size() * config.samples; }
  /// HIPs computed (done = 1), per method.
  std::vector<uint64_t> doneCounts() const;
  /// Every HIP of [begin, end) done for every method, every series of the shard's range finished.
  bool complete() const;
  /// "shard I/N" plus " (DIRECTORY)" when read from one.
  std::string label() const;
};

/// XXH64 of the configuration without `source` (what shards and resumed runs must share);
/// stored in every per-HIP file's header.
uint64_t sweepConfigHash(const SweepConfig& c);
/// "" when a and b describe the same sweep (all but `source` equal), else the first
/// differing setting, e.g. "seed (1 vs 2)"; a changed trajectory or reference file is named
/// ("the contents of --trajectory t.csv (XXH64 ... vs ...)"), and so is a configuration written
/// before the file contents were recorded.
std::string sweepConfigDifference(const SweepConfig& a, const SweepConfig& b);

/// [begin, end) of shard `index` of `count`: contiguous, sizes differ by at most one.
void shardRange(uint64_t total, int index, int count, uint64_t& begin, uint64_t& end);
/// Parses "I/N" (0 <= I < N); throws InputError.
void parseShard(const std::string& text, int& index, int& count);

/// Writes sweep.json, hips.bin, results_METHOD.bin and trajectories.json into dir (created),
/// each atomically (PATH.tmp.PID, fsync, rename; sweep.json last), so that a reader sees
/// whole files of one checkpoint or the next, and done flags that are true. Throws
/// InputError when a file cannot be written.
void writeSweepData(const SweepData& data, const std::string& dir);

/// Writes checkpoints of one run into one directory: the first write() writes every file,
/// later ones only the files whose content changed (results of methods with new HIPs done,
/// new trajectory series) and sweep.json. Same atomicity as writeSweepData.
class SweepWriter {
 public:
  explicit SweepWriter(std::string dir) : dir_(std::move(dir)) {}
  void write(const SweepData& data);

 private:
  std::string dir_;
  bool first_ = true;
  std::vector<uint64_t> done_;  ///< per method, at the last write
  size_t series_ = 0;           ///< trajectory series at the last write
};

/// The version of sweep.json's layout ("smoothforce_sweep_data") that writeSweepData writes
/// and readSweepData reads.
inline constexpr int kSweepDataVersion = 1;

/// Reads what writeSweepData wrote (complete or a checkpoint); throws InputError naming the
/// file for a missing, truncated or inconsistent file (a per-HIP file of another sweep
/// included) and for a sweep.json of another format version.
SweepData readSweepData(const std::string& dir);
/// Joins complete shards into the unsharded run's data. Throws InputError naming every
/// incomplete shard (interrupted or killed: resume it with `sweep --resume`), and when
/// configurations differ, or the HIP ranges or trajectory series overlap or leave a gap.
SweepData mergeSweepData(std::vector<SweepData> shards);

/// Computes the metrics of a whole run (begin 0, end total) and writes summary.json, one
/// METHOD_DEPTH.ply and one METHOD_DEPTH.vtp per method and depth, and results_METHOD.npy per
/// method into dir (sweep_outputs.h). Returns the table printed for people.
/// summary.json holds no timings or thread counts: merged shards give the same bytes.
std::string writeSweepSummary(const SweepData& data, const std::string& dir);

}  // namespace sf
