// SPDX-License-Identifier: Apache-2.0
// Offset-surface force sweeps: many independent probes pressed into the surface
// along its normal, run in parallel, with per-HIP results that shards can write and merge.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/sweep/sweep_reference.h>
#include <smoothforce/sweep/sweep_sampling.h>

namespace sf {

/// One probe's result, packed as stored in the per-HIP files (40 bytes, host byte order =
/// little-endian on every platform we build for). Positions and forces are float32: a sweep
/// computes its metrics from these stored values, so a merged and an unsharded run agree bit
/// for bit.
struct HipResult {
  float force[3] = {0, 0, 0};  ///< N
  float scp[3] = {0, 0, 0};    ///< m, surface contact point (god-object for direct/shading)
  float refDistance = 0;       ///< m, |SCP - reference surface|; NaN without a reference or contact
  int32_t face = -1;
  uint32_t status = 0;      ///< ForceSample::status (GP_ST_* | SF_TRACK_*)
  uint16_t iterations = 0;  ///< of the pressed-in step, saturated at 65535
  uint8_t contact = 0;
  uint8_t done = 0;  ///< 1 when computed (0: another shard's, or interrupted)
};
static_assert(sizeof(HipResult) == 40, "HipResult is a file record");

/// A group of HIPs: one depth below every surface sample, or explicit HIPs (a HIP file).
struct HipGroup {
  std::string label;                  ///< "2%", "0.002", or "file"
  double depth = 0;                   ///< m; 0 for explicit HIPs
  std::vector<Eigen::Vector3d> hips;  ///< explicit HIPs (#samples), else empty
};

/// The deterministic HIP list, group-major: HIP g belongs to group g / N and sample g % N,
/// N = samples.size(); for a depth group HIP = p - depth n (p, n the sample's point and normal).
struct HipSet {
  std::vector<SurfaceSample> samples;
  std::vector<HipGroup> groups;
  double area = 0;      ///< m^2 of the surface the samples were drawn from
  double diagonal = 0;  ///< m, bounding-box diagonal of the base mesh
  size_t perGroup() const { return samples.size(); }
  size_t size() const { return groups.size() * samples.size(); }
  Eigen::Vector3d hip(size_t g) const;
  /// The surface sample HIP g was pressed in from (or, for explicit HIPs, projected onto).
  const SurfaceSample& sample(size_t g) const { return samples[g % samples.size()]; }
  double approachFactor = 1e-3;  ///< eps / depth of the approach point
  /// The out-of-contact point stepped first: p + eps n, eps = approachFactor * depth (depth of an explicit
  /// HIP: |HIP - p|, at least 1e-9 of the diagonal).
  Eigen::Vector3d approach(size_t g) const;
  /// sqrt(area / N), m.
  double spacing() const;
  /// XXH64 of every HIP coordinate in order (provenance for shards).
  uint64_t hash() const;
};

/// Depth groups over `samples`.
HipSet makeDepthHips(std::vector<SurfaceSample> samples, const std::vector<DepthSpec>& depths, double diagonal,
                     double area);
/// One group "file" of explicit HIPs; each one's surface sample is its nearest patch point.
HipSet makeFileHips(const std::vector<Eigen::Vector3d>& hips, const PatchProjector& projector, double diagonal,
                    double area);

/// Makes one renderer for one worker (renderers are stateful and not thread-safe).
using RendererFactory = std::function<std::unique_ptr<ForceRenderer>()>;

struct SweepData;  // sweep_io.h

struct SweepControl {
  int threads = 0;                          ///< oneTBB workers; 0 = oneTBB's default
  const std::atomic<bool>* stop = nullptr;  ///< when set, remaining chunks are skipped
  std::function<void(size_t)> progress;     ///< HIPs just finished; any thread, must be thread-safe
  /// runSweep: called once on the calling thread before the probes, with the probes (HIPs x
  /// methods) left to run now (fewer than the shard's after a resume) and the shard's total.
  std::function<void(uint64_t pending, uint64_t total)> started;
  /// runSweep: called on the calling thread between blocks of probes whenever
  /// checkpointSeconds have passed since the start or the last call, with the data so far
  /// (records of HIPs not yet computed have done = 0). Empty: no checkpoints (each method's
  /// probes run as one block).
  std::function<void(const SweepData&)> checkpoint;
  double checkpointSeconds = 60;  ///< s, > 0
  /// runSweep: a note for the user (one line, no newline; the CLI prints it on stderr), on the
  /// calling thread: e.g. a HIP or trajectory file whose points nearly all lie far from the mesh
  /// (another unit of length?).
  std::function<void(const std::string&)> note;
};

/// Packs a probe's pressed-in step into its record (float32), with |SCP - ref| when ref is
/// given and the sample is in contact (NaN otherwise); done = 1.
void fillHipResult(HipResult& r, const ForceSample& s, const ReferenceSurface* ref);

/// One renderer per oneTBB worker, made on the worker's first use and kept across runProbes
/// calls (a sweep probes in blocks between checkpoints; patches built lazily stay built).
class RendererPool {
 public:
  explicit RendererPool(RendererFactory make) : make_(std::move(make)) {}
  /// The calling worker's renderer.
  ForceRenderer& local();
  /// Sum of the renderers' patchesBuilt() (lazy construction: each builds what its HIPs touch).
  long patchesBuilt() const;

 private:
  RendererFactory make_;
  tbb::enumerable_thread_specific<std::shared_ptr<ForceRenderer>> tls_;
};

/// The order in which runProbes visits HIPs [begin, end): offsets from begin sorted along a
/// Morton (Z-order) curve of the HIPs' positions (21 bits per axis over their bounding box;
/// non-finite HIPs last), so that consecutive probes query nearby parts of the BVHs and the
/// same patch records; segment by segment of 2^20 HIPs (each sorted on its own), so that the
/// scratch stays bounded (16 MB) however many HIPs a call gets.
std::vector<uint32_t> probeOrder(const HipSet& set, size_t begin, size_t end);

/// Probes HIPs [begin, end): per HIP, reset(), step(approach), step(hip); out[g - begin] gets
/// the second step's sample (and |SCP - ref| when ref is given). The HIPs run in probeOrder,
/// in chunks of 64 in parallel with one renderer per worker (from `pool`); control.stop is
/// checked per chunk, so a stopped run leaves whole chunks undone (done = 0). Returns the
/// number of HIPs done (end - begin unless stopped). A HIP's record does not depend on the
/// order, the chunking or on what its renderer probed before (reset()), so any split of
/// [begin, end) gives the same bytes.
size_t runProbes(const HipSet& set, size_t begin, size_t end, RendererPool& pool, const ReferenceSurface* ref,
                 HipResult* out, const SweepControl& control);
/// The same with a pool of its own; patchesBuilt, when given, is increased by its renderers'
/// patchesBuilt().
size_t runProbes(const HipSet& set, size_t begin, size_t end, const RendererFactory& make, const ReferenceSurface* ref,
                 HipResult* out, const SweepControl& control, long* patchesBuilt = nullptr);

/// Forces along one trajectory for one method and depth (stateful tracker, no reset between steps).
struct TrajectorySeries {
  uint64_t index = 0;      ///< position in the sweep's list of series (trajectory, method, depth, half)
  std::string trajectory;  ///< name (file name, or "default")
  std::string method;
  std::string depthLabel;
  double depth = 0;          ///< m
  double step = 0;           ///< m, arc length between consecutive HIPs
  bool half = false;         ///< the same path at half the step
  std::vector<float> force;  ///< 3 * #points, N
  std::vector<uint8_t> contact;
  /// per point: 1 where its HIP lies past the medial axis: nearer to the patch surface than 0.999
  /// x depth (PatchProjector), so another part of the surface is nearer than the point it was
  /// pressed in from (the depth exceeds the local feature size there); empty: not computed
  std::vector<uint8_t> pastMedialAxis;
  /// per point: 1 where the path crossed a crease since the previous point (creaseCrossings);
  /// empty: not computed
  std::vector<uint8_t> crease;
};

/// The path resampled at `step` and projected on the patches (nearest patch point).
std::vector<SurfaceSample> trajectorySamples(const std::vector<Eigen::Vector3d>& polyline, double step,
                                             const PatchProjector& projector);
/// reset(); step(p0 + approach depth n0); then step(p_i - depth n_i) for every i, no reset
/// between steps.
void runTrajectory(const std::vector<SurfaceSample>& path, double depth, double approach, ForceRenderer& renderer,
                   TrajectorySeries& out);
/// Fills out.pastMedialAxis for the HIPs p_i - depth n_i of `path` (m): projector.project finds
/// a patch point nearer than 0.999 x depth. A projection is a patch point, so every flag is real
/// (a nearer part the projector misses leaves its point unflagged).
void markPastMedialAxis(const std::vector<SurfaceSample>& path, double depth, const PatchProjector& projector,
                        TrajectorySeries& out);
/// Per point of `path` (TrajectorySeries::crease): 1 at point i > 0 where its patch point and
/// point i-1's lie on two faces that meet at a crease edge (isCreaseEdge), or that share only a
/// vertex a crease edge ends at; 0 elsewhere (the same face, a smooth edge, faces that do not
/// touch). It depends on the path alone: one computation serves every series along it.
std::vector<uint8_t> creaseCrossings(const std::vector<SurfaceSample>& path, const PatchCache& cache);

/// The consecutive differences |F_{j+1} - F_j| of a series that lie away from its crease
/// crossings: difference j is near one when a crossing is at a point within `window` points of
/// j or j + 1. Returns {max away, max near} (N; NaN where there is none).
std::array<double, 2> maxDifferenceByCreases(const TrajectorySeries& series, size_t window);

}  // namespace sf
