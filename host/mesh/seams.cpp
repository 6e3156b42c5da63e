// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/mesh/seams.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_intersect.h>  // weldedVertexIds
#include "union_find.h"

namespace sf {
namespace {

uint64_t pairKey(int a, int b) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

/// The defects a check finds on merged vertices (a class of more than one vertex as read), by
/// root: what joining made, not what the mesh had. Fills `why` with their kinds.
std::vector<char> defectsOfJoins(const PolygonMesh& joined, const MeshReport& r, const std::vector<int>& classSize,
                                 bool turnedFacesAllowed, std::string& why) {
  std::vector<char> bad(classSize.size(), 0);
  const auto mark = [&](int v, const char* kind) {
    if (v < 0 || v >= static_cast<int>(classSize.size()) || classSize[v] < 2) return false;
    bad[v] = 1;
    if (why.find(kind) == std::string::npos) why += (why.empty() ? "" : ", ") + std::string(kind);
    return true;
  };
  const auto markFace = [&](int f, const char* kind) {
    for (int k = 0; k < joined.faceSize(f); ++k) mark(joined.faceVertex(f, k), kind);
  };
  for (const auto& e : r.nonManifoldEdges)
    for (const int v : e) mark(v, "edges used by more than two faces");
  for (const int v : r.nonManifoldVertices) mark(v, "vertices with more than one fan of faces");
  for (const int f : r.degenerateFaces) markFace(f, "faces with a repeated vertex");
  for (const int f : r.duplicateFaces) markFace(f, "faces on the vertices of others");
  if (!turnedFacesAllowed)  // else the orientation repair that follows turns their faces back in line
    for (const auto& e : r.inconsistentEdges)
      for (const int v : e) mark(v, "edges used twice in one direction");
  return bad;
}

}  // namespace

std::vector<std::string> SeamReport::describe(int maxIds) const {
  std::vector<std::string> out;
  const auto edges = [](int n) { return std::to_string(n) + (n == 1 ? " edge" : " edges"); };
  if (seamEdges > 0) {
    std::string ids, turned;
    if (turnedSeams > 0)
      turned = " (" + std::to_string(turnedSeams) + " of them between faces written turned against each other)";
    for (size_t i = 0; i < mergedVertices.size() && static_cast<int>(i) < maxIds; ++i)
      ids += " " + std::to_string(mergedVertices[i][0]) + "->" + std::to_string(mergedVertices[i][1]);
    if (static_cast<int>(mergedVertices.size()) > maxIds) ids += " ...";
    out.push_back("seams: " + edges(seamEdges) + " written twice (boundary edges at the same positions) joined" +
                  turned + "; " + std::to_string(mergedVertices.size()) +
                  (mergedVertices.size() == 1 ? " vertex" : " vertices") +
                  " merged into the first at its position, kept unreferenced:" + ids);
  }
  if (cornerNormals)
    out.push_back(
        "seams: the file's vertex normals differ across them: each corner keeps its own vertex's (as OBJ split "
        "normals)");
  if (openEdges > 0)
    out.push_back("seams: " + edges(openEdges) + " written twice left open: joining them would make " + leftOpen);
  return out;
}

SeamReport stitchSeams(PolygonMesh& m, bool acrossTurnedFaces) {
  SeamReport report;
  const int nv = m.numVertices(), nc = m.numCorners();
  if (nv == 0 || nc == 0) return report;
  for (const int32_t v : m.faceVertices)
    if (v < 0 || v >= nv) return report;  // checkMesh names the bad index

  // half-edges (corner c -> the next corner of its face), by undirected vertex pair
  std::vector<std::pair<uint64_t, int>> undirected;
  std::vector<int> next(nc);
  undirected.reserve(nc);
  for (int f = 0; f < m.numFaces(); ++f) {
    const int b = m.faceOffsets[f], e = m.faceOffsets[f + 1];
    for (int c = b; c < e; ++c) {
      next[c] = c + 1 < e ? c + 1 : b;
      const int u = m.faceVertices[c], w = m.faceVertices[next[c]];
      undirected.emplace_back(pairKey(std::min(u, w), std::max(u, w)), c);
    }
  }
  std::sort(undirected.begin(), undirected.end());
  // boundary half-edges (their vertex pair used once): none on a closed mesh, which needs no weld
  std::vector<int> boundaryCorners;
  for (size_t i = 0; i < undirected.size();) {
    size_t j = i;
    while (j < undirected.size() && undirected[j].first == undirected[i].first) ++j;
    if (j - i == 1) boundaryCorners.push_back(undirected[i].second);
    i = j;
  }
  if (boundaryCorners.size() < 2) return report;
  // keyed by their ends' positions
  const std::vector<int32_t> welded = weldedVertexIds(m);
  std::vector<std::pair<uint64_t, int>> boundary;
  for (const int c : boundaryCorners) {
    const int wa = welded[m.faceVertices[c]], wb = welded[m.faceVertices[next[c]]];
    if (wa != wb) boundary.emplace_back(pairKey(wa, wb), c);
  }
  std::sort(boundary.begin(), boundary.end());
  const auto range = [&](uint64_t key) {
    return std::equal_range(boundary.begin(), boundary.end(), std::make_pair(key, -1),
                            [](const auto& x, const auto& y) { return x.first < y.first; });
  };

  std::vector<std::array<int, 2>> pairs;  // boundary half-edges (first corners) to join
  std::vector<char> sameWay;              // per pair: its two edges run the same way (a turned face)
  for (const auto& [key, c] : boundary) {
    const auto same = range(key);
    const uint64_t back = pairKey(static_cast<int>(key & 0xffffffffu), static_cast<int>(key >> 32));
    const auto partner = range(back);
    const auto ways = same.second - same.first, backs = partner.second - partner.first;
    if (ways == 1 && backs == 1 && partner.first->second > c) {  // once per pair
      pairs.push_back({c, partner.first->second});
      sameWay.push_back(0);
    } else if (acrossTurnedFaces && ways == 2 && backs == 0) {
      const int d = same.first->second == c ? (same.first + 1)->second : same.first->second;
      if (d > c) {
        pairs.push_back({c, d});
        sameWay.push_back(1);
      }
    }
  }
  report.pairsFound = static_cast<int>(pairs.size());
  if (pairs.empty()) return report;

  // join; where joining made a defect on merged vertices, leave the pairs at those vertices open
  // and join again (a few rounds: each leaves open only pairs that touch a defect)
  const MeshCheckOptions topologyOnly{false};
  std::vector<char> open(pairs.size(), 0);
  UnionFind classes(nv);
  PolygonMesh joined;
  for (int round = 0;; ++round) {
    classes = UnionFind(nv);
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (open[i]) continue;
      const auto [c, d] = pairs[i];
      // ends at the same positions: start to end for edges that run the other way, start to
      // start where they run the same way
      classes.unite(m.faceVertices[c], m.faceVertices[sameWay[i] ? d : next[d]]);
      classes.unite(m.faceVertices[next[c]], m.faceVertices[sameWay[i] ? next[d] : d]);
    }
    joined = m;
    for (int32_t& v : joined.faceVertices) v = classes.find(v);
    const MeshReport after = checkMesh(joined, topologyOnly);
    std::vector<int> classSize(nv, 0);
    for (int v = 0; v < nv; ++v) ++classSize[classes.find(v)];
    std::string why;
    const std::vector<char> bad = defectsOfJoins(joined, after, classSize, acrossTurnedFaces, why);
    int opened = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (open[i]) continue;
      const auto [c, d] = pairs[i];
      for (const int corner : {c, next[c], d, next[d]})
        if (bad[classes.find(m.faceVertices[corner])]) {
          open[i] = 1;
          ++opened;
          break;
        }
    }
    if (!why.empty() && report.leftOpen.find(why) == std::string::npos)
      report.leftOpen += (report.leftOpen.empty() ? "" : ", ") + why;
    if (opened == 0 && why.empty()) break;
    if (opened == 0 || round == 3) {  // defects the pairs left open do not explain: join nothing
      open.assign(pairs.size(), 1);
      joined = m;
      classes = UnionFind(nv);
      break;
    }
  }
  for (const char o : open) report.openEdges += o;
  if (report.openEdges == static_cast<int>(pairs.size())) return report;

  report.seamEdges = report.pairsFound - report.openEdges;
  for (size_t i = 0; i < pairs.size(); ++i) report.turnedSeams += sameWay[i] && !open[i];
  bool normalsDiffer = false;
  for (int v = 0; v < nv; ++v) {
    const int r = classes.find(v);
    if (r == v) continue;
    report.mergedVertices.push_back({v, r});
    if (m.fileNormals.size() == static_cast<size_t>(nv) && m.fileNormals[v] != m.fileNormals[r]) normalsDiffer = true;
  }
  if (normalsDiffer && m.fileCornerNormals.empty()) {
    joined.fileCornerNormals.resize(nc);
    for (int c = 0; c < nc; ++c) joined.fileCornerNormals[c] = m.fileNormals[m.faceVertices[c]];
    joined.fileNormals.clear();
    report.cornerNormals = true;
  }
  const auto inRange = [nv](int v) { return v >= 0 && v < nv; };  // the readers check; arrays may not
  for (CreaseTag& t : joined.creaseTags) {
    if (!inRange(t.v0) || !inRange(t.v1)) continue;
    const int a = classes.find(t.v0), b = classes.find(t.v1);
    if (a != b) t.v0 = a, t.v1 = b;
  }
  for (CornerTag& t : joined.cornerTags)
    if (inRange(t.v)) t.v = classes.find(t.v);
  m = std::move(joined);
  return report;
}

}  // namespace sf
