// SPDX-License-Identifier: Apache-2.0
// The patch surface's candidate search (PatchSurface::candidates: the tessellation triangles
// over which the patch point nearest a query can lie) for a batch of queries on an OpenCL
// device: a BVH over the adaptive triangles with boxes grown by their error bounds, walked by one
// work-item per query (kernels/candidates.cl) with the host's exact point-triangle distance
// (kernels/gp_closest.h, the same code and rounding on both sides).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/query/patch_surface.h>

namespace sf {

/// PatchSurface::candidates for many queries at once on an OpenCL device. Built once per surface
/// (the BVH here, in about 0.1 s per million triangles, then uploaded: 120 bytes per triangle
/// and about 60 per node); search() then runs one kernel per batch. The triangles found for a
/// query are those PatchSurface::candidates(q, out, cap) finds, in the same order: a BVH box is
/// skipped only where it lies farther from q than the smallest (distance + error bound) seen,
/// and the distances round as the host's. The distances are double: on a device without
/// cl_khr_fp64 the search is not usable(). Errors: OpenCLError (opencl_context.h) for device
/// failures. The surface must outlive the search.
class OpenCLCandidateSearch {
 public:
  /// Largest `cap` search() takes.
  static constexpr int kMaxCap = 64;

  explicit OpenCLCandidateSearch(const PatchSurface& surface, const OpenCLOptions& options = {});
  ~OpenCLCandidateSearch();
  OpenCLCandidateSearch(const OpenCLCandidateSearch&) = delete;
  OpenCLCandidateSearch& operator=(const OpenCLCandidateSearch&) = delete;

  /// False where the device search cannot promise the host's candidates: the device has no
  /// cl_khr_fp64, the surface has no adaptive triangles, or one with a non-finite corner or error
  /// bound (the host's BVH boxes leave such a bound out). search() then searches nothing.
  bool usable() const;

  /// For queries q[0, n) (m): count[i] = how many candidates q[i] has, at most cap (1..kMaxCap;
  /// cap: there may be more), and ids[offset[i], offset[i] + count[i]) their triangle indices
  /// (PatchSurface::pointTriangle, SurfaceCandidate::triangle) in (lower bound, index) order,
  /// as PatchSurface::candidates(q[i], out, cap) lists them (PatchSurface::candidateOf gives each
  /// one's record); ids is resized to hold them all. count[i] = -1 where the device did not
  /// search: q[i] outside the coordinate range (inCoordinateRange), the walk's stack full, or the
  /// search not usable(); the caller searches those on the host. Throws std::invalid_argument for
  /// cap out of range.
  void search(const Eigen::Vector3d* q, size_t n, int cap, int32_t* count, uint32_t* offset,
              std::vector<int32_t>& ids);

  std::string deviceName() const;
  /// BVH nodes and triangles uploaded; of the last search(): kernel and transfer time, s.
  size_t numNodes() const;
  size_t numTriangles() const;
  double lastKernelSeconds() const;
  double lastTransferSeconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf
