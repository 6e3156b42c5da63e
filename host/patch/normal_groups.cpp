// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/normal_groups.h>

#include <map>
#include <tuple>

namespace sf {

std::vector<std::vector<int>> facesAtVertices(const PatchCache& c) {
  std::vector<std::vector<int>> at(c.numVertices());
  for (int f = 0; f < c.numFaces(); ++f)
    for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s)
      if (std::vector<int>& a = at[c.faceVertices[s]]; a.empty() || a.back() != f) a.push_back(f);
  return at;
}

std::vector<std::vector<int>> vertexNormalGroups(const PatchCache& c, const std::vector<double>* normals) {
  const std::vector<double>& n = normals ? *normals : c.cornerNormals;
  std::map<std::tuple<int, double, double, double>, int> id;
  std::vector<std::vector<int>> groups;
  for (int s = 0; s < c.numSlots(); ++s) {
    const auto key = std::make_tuple(int(c.faceVertices[s]), n[3 * s], n[3 * s + 1], n[3 * s + 2]);
    const auto [it, fresh] = id.emplace(key, int(groups.size()));
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(s);
  }
  return groups;
}

Eigen::Vector3d minimaxDirection(const std::vector<Eigen::Vector3d>& a, Eigen::Vector3d m, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    size_t arg = 0;
    for (size_t i = 1; i < a.size(); ++i)
      if (m.dot(a[i]) < m.dot(a[arg])) arg = i;
    m = (m + (0.05 / (1 + it * 0.05)) * (a[arg] - m.dot(a[arg]) * m)).normalized();
  }
  return m;
}

}  // namespace sf
