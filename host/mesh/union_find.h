// SPDX-License-Identifier: Apache-2.0
// Union-find over ids 0..n-1 for the mesh module (private): components, vertex fans, crease
// sectors, merged seam vertices.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace sf {

/// Disjoint sets of ids 0..n-1 whose root is the smallest id of its set (path halving).
struct UnionFind {
  std::vector<int32_t> parent;
  explicit UnionFind(int n) : parent(static_cast<size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace sf
