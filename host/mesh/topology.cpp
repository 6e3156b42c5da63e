#include <smoothforce/mesh/topology.h>

#include <algorithm>
#include <unordered_map>

namespace sf {

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

}  // namespace sf
