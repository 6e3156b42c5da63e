// SPDX-License-Identifier: Apache-2.0
// Shared by the force tests: HIP paths that slide across patch edges at constant depth.
#pragma once

#include <Eigen/Core>
#include <vector>

#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/patch_eval.h>
#include "patch_test_support.h"

namespace sf::test {

/// A HIP path at constant depth under the patches, sliding across edges: from the centre of
/// face f0 through its edge k0 into the neighbour, then through each face's opposite edge,
/// for `faces` faces, `perHalf` samples from an edge midpoint to the domain centre. HIP =
/// G(X) - depth N(X). It starts with an approach along the normal from `depth` outside.
struct SlidePath {
  std::vector<Eigen::Vector3d> hips;
  size_t slideBegin = 0;
  int faces = 0;
};
inline SlidePath slidePath(const PatchCache& c, int f0, int k0, int faces, int perHalf, double depth) {
  SlidePath p;
  auto hip = [&](int f, const Eigen::Vector2d& X) {
    const PatchPoint q = evaluatePatch(c, f, X.x(), X.y());
    return Eigen::Vector3d(q.pos - depth * q.normal);
  };
  auto mid = [&](int f, int k) {
    const int n = c.faceSize(f);
    return Eigen::Vector2d(0.5 * (domainCorner(n, k) + domainCorner(n, (k + 1) % n)));
  };
  const PatchPoint q0 = evaluatePatch(c, f0, 0, 0);
  for (int j = 0; j < 2 * perHalf; ++j) p.hips.push_back(q0.pos + depth * (1 - double(j) / perHalf) * q0.normal);
  p.slideBegin = p.hips.size() - 1;
  int f = f0, in = -1, out = k0;
  for (p.faces = 0; p.faces < faces; ++p.faces) {
    const Eigen::Vector2d a = in < 0 ? Eigen::Vector2d(0, 0) : mid(f, in), b = mid(f, out);
    if (in >= 0)
      for (int j = 0; j < perHalf; ++j) p.hips.push_back(hip(f, a * (1 - double(j) / perHalf)));
    for (int j = 0; j < perHalf; ++j) p.hips.push_back(hip(f, b * (double(j) / perHalf)));
    const int twin = c.slotTwin[c.faceOffsets[f] + out];
    if (twin < 0) break;
    f = slotFace(c.faceOffsets, twin);
    in = twin - c.faceOffsets[f];
    out = (in + c.faceSize(f) / 2) % c.faceSize(f);
  }
  return p;
}

}  // namespace sf::test
