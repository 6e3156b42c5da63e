// SPDX-License-Identifier: Apache-2.0
// libFuzzer harness for the patch-cache reader (readPatchCache on a .sfcache file).
//
// A fuzzer cannot forge XXH64 checksums, so unless bit 0 of byte 96 (the first reserved
// header word) is set, the harness first recomputes the payload checksum (over bytes 128..)
// and then the header checksum (over bytes 0..119), as a buggy or hostile writer would:
// the header and structure checks after the checksums are then reached. A cache that loads
// must keep the reader's guarantees, and every face must evaluate without a crash.
#include <cstring>
#include <vector>

#include <smoothforce/base/hash.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/patch_eval.h>
#include "fuzz_common.h"
#include "gp_config.h"  // GP_* status bits and record layout

namespace {

void checkCache(const sf::PatchCache& c) {
  using sf::fuzz::crash;
  const int nv = c.numVertices(), nf = c.numFaces(), ns = c.numSlots();
  if (c.positions.size() != size_t(nv) * 3 || c.cornerNormals.size() != size_t(ns) * 3 ||
      c.slotTwin.size() != size_t(ns) || c.faceStatus.size() != size_t(nf) || c.faceBulge.size() != size_t(nf))
    crash("array sizes disagree with the counts");
  const size_t recs = size_t(GP_E_NFIELDS) * ns;
  if ((c.options.precision == sf::Precision::Double ? c.edgeDataD.size() : c.edgeDataF.size()) != recs)
    crash("edge records miscounted");
  if (c.faceOffsets.front() != 0 || c.faceOffsets.back() != ns) crash("face offsets inconsistent");
  for (int f = 0; f < nf; ++f)
    if (c.faceOffsets[f + 1] - c.faceOffsets[f] < 3) crash("face with fewer than 3 corners");
  for (int s = 0; s < ns; ++s) {
    if (c.faceVertices[s] < 0 || c.faceVertices[s] >= nv) crash("corner vertex out of range");
    if (c.slotTwin[s] < -2 || c.slotTwin[s] >= ns) crash("slot twin out of range");
  }
  for (int f = 0; f < nf && f < 16; ++f) {
    const int n = c.faceSize(f);
    sf::evaluatePatch(c, f, 0, 0);
    if (n >= 3 && n <= GP_MAX_N) {
      const Eigen::Vector2d x = sf::domainCorner(n, 0);
      sf::evaluatePatch(c, f, x.x(), x.y());
      sf::evaluatePatch(c, f, 0.5 * x.x(), 0.25);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> b(data, data + size);
  if (size >= 128 && !(b[96] & 1)) {
    const uint64_t payload = sf::hashBytes(b.data() + 128, size - 128);
    std::memcpy(&b[88], &payload, 8);
    const uint64_t header = sf::hashBytes(b.data(), 120);
    std::memcpy(&b[120], &header, 8);
  }
  const std::string& path = sf::fuzz::writeInput(b.data(), b.size(), ".sfcache");
  sf::isPatchCacheFile(path);
  sf::PatchCache c;
  if (sf::fuzz::accepted(path, [&] { c = sf::readPatchCache(path); })) checkCache(c);
  return 0;
}
