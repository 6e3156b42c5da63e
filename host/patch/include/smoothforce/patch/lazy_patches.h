// SPDX-License-Identifier: Apache-2.0
// Patches built on demand near the contact point, kept in a bounded least-recently-used set.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <smoothforce/base/memory_bytes.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Lazy patch construction: given only a mesh, patches are built near the contact point and kept
/// in a bounded cache. Holds at most `capacity` faces' edge
/// records (n * GP_E_NFIELDS each, record-major, in the skeleton's precision); a miss builds the
/// face with buildPatchRecords (the same construction as a prebuilt cache, bit for bit) and
/// evicts the least recently used face when full. Memory: capacity * maxFaceSize *
/// GP_E_NFIELDS reals, allocated once in the constructor; records() never allocates, locks or
/// throws, so it may run inside a servo step (a miss costs one patch construction: about
/// 25-40 us for a quad on this project's CI machine). Not thread-safe: one per renderer.
class LazyPatches {
 public:
  /// skeleton: base mesh, normals, adjacency and options (preparePatchSkeleton; its patch
  /// arrays are not read). capacity: faces held at once, >= 1; <= 0 or more than the face count
  /// means every face (unbounded). Throws InputError when the skeleton is null.
  LazyPatches(std::shared_ptr<const PatchCache> skeleton, int capacity);

  /// Face f's records (record-major), built on a miss; nullptr when f is out of range or has
  /// fewer than 3 or more than GP_MAX_N sides. status receives the face's GP_ST_* bits.
  const double* recordsD(int f, uint32_t& status) noexcept;
  const float* recordsF(int f, uint32_t& status) noexcept;

  /// GP_ST_* bits of face f, building it when it is not held (GP_ST_TOO_MANY_SIDES for n
  /// outside 3..GP_MAX_N or f out of range).
  uint32_t status(int f) noexcept;

  int capacity() const noexcept { return static_cast<int>(entryFace_.size()); }
  /// Constructions so far (a face evicted and needed again counts again).
  int constructions() const noexcept { return constructions_; }
  /// Distinct faces ever constructed.
  int distinctFaces() const noexcept { return distinct_; }
  const PatchCache& skeleton() const noexcept { return *skeleton_; }
  /// Bytes held by the entries and the face tables (the skeleton cache not counted).
  size_t bytes() const noexcept {
    return vectorBytes(poolD_, poolF_, faceEntry_, entryFace_, entryUsed_, entryStatus_, everBuilt_);
  }

 private:
  template <class Real>
  const Real* records(int f, uint32_t& status, std::vector<Real>& pool) noexcept;
  /// Entry holding f, building it into the least recently used entry on a miss; -1 when f has
  /// no patch.
  int acquire(int f) noexcept;

  std::shared_ptr<const PatchCache> skeleton_;
  size_t stride_ = 0;                ///< reals per entry: maxFaceSize * GP_E_NFIELDS
  std::vector<double> poolD_;        ///< capacity * stride_ (double skeletons)
  std::vector<float> poolF_;         ///< capacity * stride_ (float skeletons)
  std::vector<int32_t> faceEntry_;   ///< #F: entry holding the face, -1 when not held
  std::vector<int32_t> entryFace_;   ///< capacity: face in the entry, -1 when free
  std::vector<uint64_t> entryUsed_;  ///< capacity: last use (LRU clock)
  std::vector<uint32_t> entryStatus_;
  std::vector<uint8_t> everBuilt_;  ///< #F
  uint64_t clock_ = 0;
  int constructions_ = 0, distinct_ = 0;
};

}  // namespace sf
