// SPDX-License-Identifier: Apache-2.0
// Vertex normals as the corners that share them, and the direction that best agrees with a set
// of normals: what the normal levers of the fold repair move (query/normal_search.h).
#pragma once

#include <Eigen/Core>

#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// The corners (PatchCache::faceVertices slots) of each vertex normal: corners of one vertex
/// with the same normal in `normals` (#C*3; cache.cornerNormals when null) form one group, so a
/// crease, which gives a vertex's sectors their own normals, splits the vertex into several.
/// Groups in order of their first corner; every corner in exactly one.
std::vector<std::vector<int>> vertexNormalGroups(const PatchCache& cache, const std::vector<double>* normals = nullptr);

/// The faces at each vertex (#V lists of face ids, ascending, each face once): the faces whose
/// patches a change at the vertex (its normal, its position) can reach.
std::vector<std::vector<int>> facesAtVertices(const PatchCache& cache);

/// The unit direction m that maximises min_i m . a_i over the unit vectors a (non-empty), by
/// projected subgradient ascent on the sphere from the unit vector `start` (step 0.05 / (1 +
/// 0.05 k) at iteration k): the normal whose tangent plane keeps every a_i on its positive side
/// by the widest margin, where one exists.
Eigen::Vector3d minimaxDirection(const std::vector<Eigen::Vector3d>& a, Eigen::Vector3d start, int iterations = 3000);

}  // namespace sf
