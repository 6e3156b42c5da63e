// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/mesh/topology.h>

#include <algorithm>
#include <unordered_map>

namespace sf {

bool referencedBox(const double* xyz, const int32_t* cornerVertices, size_t corners, Eigen::Vector3d& lo,
                   Eigen::Vector3d& hi) {
  lo = hi = Eigen::Vector3d::Zero();
  for (size_t c = 0; c < corners; ++c) {
    const double* p = xyz + 3 * size_t(cornerVertices[c]);
    const Eigen::Vector3d v(p[0], p[1], p[2]);
    lo = c == 0 ? v : Eigen::Vector3d(lo.cwiseMin(v));
    hi = c == 0 ? v : Eigen::Vector3d(hi.cwiseMax(v));
  }
  return corners > 0;
}

bool referencedBox(const PolygonMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double));
  return referencedBox(mesh.positions.empty() ? nullptr : mesh.positions.data()->data(), mesh.faceVertices.data(),
                       mesh.faceVertices.size(), lo, hi);
}

std::vector<int32_t> computeSlotTwins(const PolygonMesh& mesh) {
  const int nc = mesh.numCorners();
  std::vector<int32_t> twin(nc, kBoundarySlot);
  // undirected edge key -> slots using it
  std::unordered_map<uint64_t, std::vector<int32_t>> uses;
  uses.reserve(static_cast<size_t>(nc));
  auto key = [](uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<uint64_t>(a) << 32) | b;
  };
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < mesh.faceSize(f); ++k)
      uses[key(mesh.faceVertex(f, k), mesh.faceVertex(f, k + 1))].push_back(mesh.faceOffsets[f] + k);
  for (const auto& [edge, slots] : uses) {
    if (slots.size() == 1) continue;
    bool ok = slots.size() == 2;
    if (ok) {
      // the two faces must run the edge in opposite directions
      const int32_t a = slots[0], b = slots[1];
      const int fa = slotFace(mesh.faceOffsets, a), fb = slotFace(mesh.faceOffsets, b);
      const int ka = a - mesh.faceOffsets[fa], kb = b - mesh.faceOffsets[fb];
      ok = fa != fb && mesh.faceVertex(fa, ka) == mesh.faceVertex(fb, kb + 1) &&
           mesh.faceVertex(fa, ka + 1) == mesh.faceVertex(fb, kb);
      if (ok) {
        twin[a] = b;
        twin[b] = a;
        continue;
      }
    }
    for (int32_t s : slots) twin[s] = kNonManifoldSlot;
  }
  return twin;
}

int slotFace(const std::vector<int32_t>& faceOffsets, int32_t slot) {
  auto it = std::upper_bound(faceOffsets.begin(), faceOffsets.end(), slot);
  return static_cast<int>(it - faceOffsets.begin()) - 1;
}

void acrossCorners(const std::vector<int32_t>& faceOffsets, const std::vector<int32_t>& slotTwin, int f, int k,
                   int32_t& atStart, int32_t& atEnd) {
  const int32_t first = faceOffsets[f], s = first + k;
  atStart = s;
  atEnd = s + 1 == faceOffsets[f + 1] ? first : s + 1;
  const int32_t t = slotTwin[s];
  if (t < 0) return;
  // the twin runs V_{k+1} -> V_k in its face g: its slot is g's corner at V_{k+1}, the next one V_k
  const int g = slotFace(faceOffsets, t);
  atEnd = t;
  atStart = t + 1 == faceOffsets[g + 1] ? faceOffsets[g] : t + 1;
}

}  // namespace sf
