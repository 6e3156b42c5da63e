// Edge adjacency between faces, per corner slot.
#pragma once

#include <cstdint>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// Twin slot value for an edge with no neighbour (mesh boundary).
inline constexpr int32_t kBoundarySlot = -1;
/// Twin slot value for an edge shared by more than two faces, or by two faces that run it
/// in the same direction (inconsistent orientation): no smooth transition across it.
inline constexpr int32_t kNonManifoldSlot = -2;

/// For each slot s (= corner index faceOffsets[f] + k, standing for edge k of face f, from
/// V_k to V_{k+1}) the slot of the same edge in the neighbouring face, which runs it the
/// other way; or kBoundarySlot / kNonManifoldSlot. Output: #C.
std::vector<int32_t> computeSlotTwins(const PolygonMesh& mesh);

/// Face owning slot s (binary search in faceOffsets).
int slotFace(const std::vector<int32_t>& faceOffsets, int32_t slot);

}  // namespace sf
