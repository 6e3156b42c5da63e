// SPDX-License-Identifier: Apache-2.0
// Face f of a built cache as the independent reference's patch (tests/reference).
#pragma once

#include <smoothforce/patch/patch_cache.h>

#include "gregory_reference.h"

namespace sf::test {

/// The reference patch of face f: its positions and corner normals, and the end tangents the
/// fold repair's untangled fans give its edges (PatchCache::edgeTangents, where there are any).
inline ref::RefPatch referencePatchOf(const PatchCache& c, int f, ref::CrossTangent mode = ref::CrossTangent::Corrected) {
  ref::RefPatch rp;
  rp.mode = mode;
  for (int k = 0; k < c.faceSize(f); ++k) {
    const size_t s = size_t(c.faceOffsets[f]) + k;
    rp.V.push_back(Eigen::Vector3d::Map(&c.positions[3 * size_t(c.faceVertices[s])]));
    rp.N.push_back(Eigen::Vector3d::Map(&c.cornerNormals[3 * s]));
    if (!c.edgeTangents.empty()) {
      rp.TS.push_back(Eigen::Vector3d::Map(&c.edgeTangents[6 * s]));
      rp.TE.push_back(Eigen::Vector3d::Map(&c.edgeTangents[6 * s + 3]));
    }
  }
  return rp;
}

}  // namespace sf::test
