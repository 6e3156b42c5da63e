// SPDX-License-Identifier: Apache-2.0
// weldPatchSeams (tessellate.h): one connected surface from the per-patch tessellations.
#include <algorithm>
#include <numeric>
#include <string>

#include <smoothforce/base/error.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/tessellate.h>

namespace sf {

namespace {

int32_t findRoot(std::vector<int32_t>& parent, int32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

/// Vertex index of boundary point j (0..L) of edge k of face f in tessellatePatches' layout:
/// ring L starts after 1 + n L (L - 1) / 2 vertices; j = L is the next edge's corner.
int32_t boundaryVertex(const TriangleMesh& m, int n, int L, int f, int k, int j) {
  const int ring = 1 + n * L * (L - 1) / 2;
  return m.firstVertex[f] + ring + (k * L + j) % (n * L);
}

}  // namespace

WeldReport weldPatchSeams(const PatchCache& cache, int level, TriangleMesh& m, double tolerance) {
  const int L = level;
  if (m.firstVertex.size() != static_cast<size_t>(cache.numFaces()) || m.status.size() != m.positions.size() ||
      m.fold.size() != m.positions.size() || m.bulge.size() != m.positions.size())
    throw InputError("weldPatchSeams: the tessellation does not belong to this cache");
  if (tolerance <= 0)
    tolerance = (cache.options.precision == Precision::Double ? 1e-9 : 1e-5) * boundingDiagonal(cache);
  const double tol2 = tolerance * tolerance;
  WeldReport report;
  std::vector<int32_t> parent(m.positions.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (m.firstVertex[f] < 0) continue;
    const int n = cache.faceSize(f);
    for (int k = 0; k < n; ++k) {
      const int32_t s = cache.faceOffsets[f] + k, t = cache.slotTwin[s];
      if (t < 0 || t < s) continue;  // boundary, non-manifold, or visited from the twin
      const int g = slotFace(cache.faceOffsets, t);
      if (m.firstVertex[g] < 0) continue;
      const int ng = cache.faceSize(g), kg = t - cache.faceOffsets[g];
      if (m.firstVertex[f] + 1 + n * L * (L + 1) / 2 > static_cast<int>(m.positions.size()) ||
          m.firstVertex[g] + 1 + ng * L * (L + 1) / 2 > static_cast<int>(m.positions.size()))
        throw InputError("weldPatchSeams: the tessellation does not match level " + std::to_string(L));
      ++report.edgesWelded;
      bool open = false;
      for (int j = 0; j <= L; ++j) {  // point j from V_k on f's edge is point L - j on the twin's edge
        const int32_t a = boundaryVertex(m, n, L, f, k, j), b = boundaryVertex(m, ng, L, g, kg, L - j);
        if ((m.positions[a] - m.positions[b]).squaredNorm() > tol2) {
          open = true;
          continue;
        }
        const int32_t ra = findRoot(parent, a), rb = findRoot(parent, b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
      report.openEdges += open;
    }
  }
  // Renumber in order of first appearance; merge the attributes into the representative.
  std::vector<int32_t> remap(m.positions.size(), -1);
  TriangleMesh out;
  out.face = std::move(m.face);
  out.firstVertex.assign(m.firstVertex.size(), -1);
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const int32_t r = findRoot(parent, static_cast<int32_t>(v));
    if (remap[r] < 0) {
      remap[r] = static_cast<int32_t>(out.positions.size());
      out.positions.push_back(m.positions[r]);
      out.normals.push_back(Eigen::Vector3d::Zero());
      out.status.push_back(0);
      out.fold.push_back(0);
      out.bulge.push_back(0);
    }
    const int32_t w = remap[r];
    remap[v] = w;
    out.normals[w] += m.normals[v];
    out.status[w] |= m.status[v];
    out.fold[w] |= m.fold[v];
    out.bulge[w] = std::max(out.bulge[w], m.bulge[v]);
  }
  for (Eigen::Vector3d& nrm : out.normals)
    if (nrm.norm() > 0) nrm.normalize();
  for (size_t f = 0; f < m.firstVertex.size(); ++f)
    if (m.firstVertex[f] >= 0) out.firstVertex[f] = remap[m.firstVertex[f]];
  out.triangles = std::move(m.triangles);
  for (auto& tri : out.triangles)
    for (int32_t& v : tri) v = remap[v];
  report.merged = m.positions.size() - out.positions.size();
  m = std::move(out);
  return report;
}

}  // namespace sf
