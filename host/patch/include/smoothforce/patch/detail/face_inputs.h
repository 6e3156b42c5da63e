// SPDX-License-Identifier: Apache-2.0
// What the construction takes for one face, gathered from a cache (in-tree only).
#pragma once

#include <cstddef>

#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf::detail {

/// The inputs of gp_build_patch_with for face f of c (n = c.faceSize(f) in 3..GP_MAX_N), in the
/// precision of G = Gp<Real>: positions V, corner normals N and vertex ids vid (n each), and PS,
/// PE, the normals the face across each edge has at its ends where face f has a crease edge
/// (faceHasCrease), else N and N[k+1] (which gp_build_patch_with then does not read). Returns
/// whether the face has a crease edge.
template <class G>
bool faceInputs(const PatchCache& c, int f, typename G::vec3* V, typename G::vec3* N, int* vid, typename G::vec3* PS,
                typename G::vec3* PE) {
  const int n = c.faceSize(f), first = c.faceOffsets[f];
  for (int k = 0; k < n; ++k) {
    const int v = c.faceVertices[first + k];
    vid[k] = v;
    V[k] = G::v3(c.positions[3 * size_t(v)], c.positions[3 * size_t(v) + 1], c.positions[3 * size_t(v) + 2]);
    const double* nn = &c.cornerNormals[3 * size_t(first + k)];
    N[k] = G::v3(nn[0], nn[1], nn[2]);
  }
  const bool creased = faceHasCrease(c, f);
  for (int k = 0; k < n; ++k) {
    if (!creased) {
      PS[k] = N[k], PE[k] = N[k + 1 == n ? 0 : k + 1];
      continue;
    }
    int32_t a, b;
    acrossCorners(c, f, k, a, b);
    const double *na = &c.cornerNormals[3 * size_t(a)], *nb = &c.cornerNormals[3 * size_t(b)];
    PS[k] = G::v3(na[0], na[1], na[2]);
    PE[k] = G::v3(nb[0], nb[1], nb[2]);
  }
  return creased;
}

}  // namespace sf::detail
