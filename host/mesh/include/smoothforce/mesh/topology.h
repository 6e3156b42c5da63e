// SPDX-License-Identifier: Apache-2.0
// Edge adjacency between faces, per corner slot.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

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

/// The box (lo, hi, m) of the vertices that faces reference, from #V*3 coordinates and the #C
/// corners' vertex ids (in range): unreferenced vertices, which the readers keep, do not count
/// (one stray vertex at 1e14 m set every size-relative tolerance). False, lo = hi = 0, when no
/// corner is given.
bool referencedBox(const double* xyz, const int32_t* cornerVertices, size_t corners, Eigen::Vector3d& lo,
                   Eigen::Vector3d& hi);
/// The same for a mesh.
bool referencedBox(const PolygonMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

/// Face owning slot s (binary search in faceOffsets).
int slotFace(const std::vector<int32_t>& faceOffsets, int32_t slot);

/// For edge k of face f (slot faceOffsets[f] + k, V_k -> V_{k+1}): the corners of the face
/// across the edge (computeSlotTwins) at V_k (atStart) and at V_{k+1} (atEnd); face f's own
/// corners there when the edge has no single neighbour (boundary, non-manifold).
void acrossCorners(const std::vector<int32_t>& faceOffsets, const std::vector<int32_t>& slotTwin, int f, int k,
                   int32_t& atStart, int32_t& atEnd);

}  // namespace sf
