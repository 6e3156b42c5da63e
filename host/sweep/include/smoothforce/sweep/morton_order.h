// SPDX-License-Identifier: Apache-2.0
// The order of a point set along a Morton (Z-order) curve: points close in space come close in
// the order, so that queries run in it touch the same parts of a BVH or k-d tree in turn.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace sf {

/// Indices 0..#P-1 of `points` (m) sorted by their Morton code: 21 bits per axis over the
/// bounding box of the finite points, interleaved (ties: by index); non-finite points last.
/// At most 2^32 - 1 points. Deterministic for any thread count (the codes are computed in
/// parallel with oneTBB).
std::vector<uint32_t> mortonOrder(const std::vector<Eigen::Vector3d>& points);

}  // namespace sf
