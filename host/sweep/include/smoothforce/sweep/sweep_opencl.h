// SPDX-License-Identifier: Apache-2.0
// Sweep probes of the patch method with the refinement on an OpenCL device:
// `smoothforce sweep --backend opencl`.
#pragma once

#include <memory>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/sweep/sweep.h>

namespace sf {

class PatchSurface;
class PolygonScene;

/// Where an OpenCLPatchProber spent its wall time, s: its set-up, and summed over its runs the
/// runs and their parts. The device's stages (refine, search) run on a thread of their own, beside
/// the CPU stages; what a run spends beyond cpu and wait (the HIPs' Morton order) is serial on the
/// calling thread.
struct OpenCLProbeTiming {
  double setup = 0;        ///< the constructor: polygon scene and patch surface (unless given), beside the
                           ///< device's context, program and cache upload
  double run = 0;          ///< run(), whole
  double cpu = 0;          ///< the CPU stages: each step's global query and contact decision (oneTBB)
  double wait = 0;         ///< the calling thread waiting for the device's stages
  double refine = 0;       ///< refinement calls on the device thread: packing, transfers, kernel, unpacking
  double search = 0;       ///< candidate-search calls on the device thread (OpenCLCandidateSearch)
  double kernel = 0;       ///< of refine and search: device kernel time (profiling events)
  double transfer = 0;     ///< of refine and search: device transfer time (profiling events)
  size_t refinements = 0;  ///< refinement calls (kernel runs)
};

/// runProbes for the patch method with the first refinement of every step of a chunk of HIPs in
/// one kernel run (OpenCLRefiner), and the candidate searches of the seeded steps' global
/// queries in another (OpenCLCandidateSearch, on devices with cl_khr_fp64); the rest of the
/// global queries (the error band, winding number, refinements of further candidates, or the
/// polygon start) and the contact decisions run on the CPU in oneTBB tasks, through the same
/// beginPatchStep / finishPatchStep as the CPU tracker. The records are the CPU path's bits.
/// Per HIP, as runProbes: reset, step(approach), step(hip), in the same Morton order of the
/// HIPs (probeOrder), the step at the HIP bounding its candidate search by the approach step's
/// nearest point as the tracker does; out[g - begin] gets the second step. Set up once (the
/// polygon scene, the patch surface, the device program and the cache upload), then run over
/// any number of HIP ranges. Not thread-safe (one run at a time). Every stage of a run but the
/// device's refinements runs in oneTBB tasks on the host's cores.
class OpenCLPatchProber {
 public:
  /// Throws InputError for invalid options, OpenCLError for device failures.
  /// The polygon scene and the patch surface are built here, while the device's context,
  /// program and cache upload are set up beside them.
  OpenCLPatchProber(std::shared_ptr<const PatchCache> cache, const ForceOptions& options,
                    const OpenCLOptions& opencl = {});
  /// The same with the caller's polygon scene (built with kPlanarTolerance) and patch surface
  /// (built with patchSurfaceOptions(options); unused unless options.initialGuess is Surface),
  /// as a sweep's CPU renderers share theirs, so that nothing is built twice; a null one is
  /// built here. Throws InputError where either was built from another cache.
  OpenCLPatchProber(std::shared_ptr<const PatchCache> cache, std::shared_ptr<const PolygonScene> scene,
                    std::shared_ptr<const PatchSurface> surface, const ForceOptions& options,
                    const OpenCLOptions& opencl = {});
  ~OpenCLPatchProber();
  OpenCLPatchProber(const OpenCLPatchProber&) = delete;
  OpenCLPatchProber& operator=(const OpenCLPatchProber&) = delete;

  /// Probes HIPs [begin, end) of `set` into out[0, end - begin), chunks of `chunk` HIPs;
  /// control.stop is checked and control.progress called per chunk. Returns the HIPs done.
  /// Throws OpenCLError for device failures.
  size_t run(const HipSet& set, size_t begin, size_t end, const ReferenceSurface* ref, HipResult* out,
             const SweepControl& control, size_t chunk = 1 << 16);

  /// Time spent so far, over every run.
  const OpenCLProbeTiming& timing() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// OpenCLPatchProber set up for one run over [begin, end).
size_t runPatchProbesOpenCL(const HipSet& set, size_t begin, size_t end, std::shared_ptr<const PatchCache> cache,
                            const ForceOptions& options, const ReferenceSurface* ref, HipResult* out,
                            const SweepControl& control, const OpenCLOptions& opencl = {}, size_t chunk = 1 << 16);

}  // namespace sf
