// SPDX-License-Identifier: Apache-2.0
// Lazy patch construction with a bounded LRU set of faces.
#include <smoothforce/patch/lazy_patches.h>

#include <algorithm>

#include <smoothforce/mesh/mesh.h>
#include "gp_config.h"  // GP_* status bits and record layout

namespace sf {

LazyPatches::LazyPatches(std::shared_ptr<const PatchCache> skeleton, int capacity) : skeleton_(std::move(skeleton)) {
  if (!skeleton_) throw InputError("LazyPatches: no mesh");
  const int nf = skeleton_->numFaces();
  int maxN = 3;
  for (int f = 0; f < nf; ++f) maxN = std::max(maxN, std::min(skeleton_->faceSize(f), int(GP_MAX_N)));
  const int cap = std::max(1, capacity <= 0 || capacity > nf ? nf : capacity);
  stride_ = static_cast<size_t>(maxN) * GP_E_NFIELDS;
  if (skeleton_->options.precision == Precision::Double)
    poolD_.assign(cap * stride_, 0.0);
  else
    poolF_.assign(cap * stride_, 0.f);
  faceEntry_.assign(nf, -1);
  entryFace_.assign(cap, -1);
  entryUsed_.assign(cap, 0);
  entryStatus_.assign(cap, 0);
  everBuilt_.assign(nf, 0);
}

int LazyPatches::acquire(int f) noexcept {
  const PatchCache& c = *skeleton_;
  if (f < 0 || f >= c.numFaces()) return -1;
  const int n = c.faceSize(f);
  if (n < 3 || n > GP_MAX_N) return -1;
  int e = faceEntry_[f];
  if (e < 0) {
    // least recently used entry (free entries have stamp 0); linear in the capacity, which
    // is small next to one construction
    e = static_cast<int>(std::min_element(entryUsed_.begin(), entryUsed_.end()) - entryUsed_.begin());
    if (entryFace_[e] >= 0) faceEntry_[entryFace_[e]] = -1;
    entryFace_[e] = f;
    faceEntry_[f] = e;
    entryStatus_[e] = poolD_.empty() ? buildPatchRecords(c, f, poolF_.data() + e * stride_)
                                     : buildPatchRecords(c, f, poolD_.data() + e * stride_);
    ++constructions_;
    if (!everBuilt_[f]) {
      everBuilt_[f] = 1;
      ++distinct_;
    }
  }
  entryUsed_[e] = ++clock_;
  return e;
}

template <class Real>
const Real* LazyPatches::records(int f, uint32_t& status, std::vector<Real>& pool) noexcept {
  const int e = pool.empty() ? -1 : acquire(f);
  if (e < 0) {
    status = GP_ST_TOO_MANY_SIDES;
    return nullptr;
  }
  status = entryStatus_[e];
  return pool.data() + e * stride_;
}

const double* LazyPatches::recordsD(int f, uint32_t& status) noexcept { return records(f, status, poolD_); }
const float* LazyPatches::recordsF(int f, uint32_t& status) noexcept { return records(f, status, poolF_); }

uint32_t LazyPatches::status(int f) noexcept {
  const int e = acquire(f);
  return e < 0 ? GP_ST_TOO_MANY_SIDES : entryStatus_[e];
}

}  // namespace sf
