// SPDX-License-Identifier: Apache-2.0
// checkMesh: edges, manifoldness, duplicates, degeneracies, boundary loops, orientation,
// components, signed volume, intersecting and self-crossing polygons of a polygon mesh; plus
// face flipping and orientation.
#include <smoothforce/mesh/mesh_check.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <map>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/topology.h>
#include "union_find.h"

namespace sf {
namespace {

/// One face side of an undirected edge: the corners (global ids) at its start and end.
struct HalfEdge {
  uint64_t key;  // (min vertex << 32) | max vertex
  int face, from, to;
};

/// Bad topology is reported, but indices outside the vertex array cannot be looked at.
void validateIndices(const PolygonMesh& m) {
  for (int f = 0; f < m.numFaces(); ++f) {
    for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) {
      if (m.faceVertices[c] < 0 || m.faceVertices[c] >= m.numVertices()) {
        throw InputError((m.sourcePath.empty() ? std::string("mesh") : m.sourcePath) + ": face " + std::to_string(f) +
                         ": vertex index " + std::to_string(m.faceVertices[c]) + " out of range");
      }
    }
  }
}

/// Zero-length edge or zero area (repeated vertices are found by the caller).
bool degenerate(const PolygonMesh& m, int f) {
  const int n = m.faceSize(f);
  if (n < 3) return true;
  double perimeter = 0;
  for (int k = 0; k < n; ++k) {
    const int a = m.faceVertex(f, k), b = m.faceVertex(f, k + 1);
    const double len = (m.positions[b] - m.positions[a]).norm();
    if (len == 0) return true;  // zero-length edge
    perimeter += len;
  }
  // Zero area, relative to the face's size (|Newell| = 2 x area).
  return newellNormal(m, f).norm() <= 1e-12 * perimeter * perimeter;
}

std::string idList(const std::vector<int>& ids, int maxIds) {
  std::string s;
  for (size_t i = 0; i < ids.size() && static_cast<int>(i) < maxIds; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return ids.size() > static_cast<size_t>(maxIds) ? s + ", ..." : s;
}

std::string pairList(const std::vector<std::array<int, 2>>& ids, int maxIds) {
  std::string s;
  for (size_t i = 0; i < ids.size() && static_cast<int>(i) < maxIds; ++i)
    s += (i ? ", " : "") + std::to_string(ids[i][0]) + "-" + std::to_string(ids[i][1]);
  return ids.size() > static_cast<size_t>(maxIds) ? s + ", ..." : s;
}

/// Chains the boundary half-edges into vertex loops. Each step uses up one edge, so this
/// ends on any input. At a junction it prefers an edge in face direction. Where a chain
/// cannot close (a vertex with an odd number of boundary edges, next to a non-manifold
/// edge), it is extended backwards too and reported as an open chain.
std::vector<std::vector<int>> chainLoops(const std::vector<std::array<int, 2>>& edges) {
  std::multimap<int, int> incident;  // vertex -> edge id
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    incident.emplace(edges[e][0], e);
    incident.emplace(edges[e][1], e);
  }
  std::vector<char> used(edges.size(), 0);
  // Walks from `cur` until it reaches `stop` or runs out of edges; appends visited vertices.
  const auto walk = [&](int cur, int stop, bool forward, std::vector<int>& out) {
    while (cur != stop) {
      int pick = -1;
      const auto [lo, hi] = incident.equal_range(cur);
      for (auto it = lo; it != hi; ++it) {
        const int e = it->second;
        if (used[e]) continue;
        const bool inDirection = edges[e][forward ? 0 : 1] == cur;
        if (pick < 0 || (inDirection && edges[pick][forward ? 0 : 1] != cur)) pick = e;
      }
      if (pick < 0) return false;
      used[pick] = 1;
      cur = edges[pick][0] == cur ? edges[pick][1] : edges[pick][0];
      if (cur != stop) out.push_back(cur);
    }
    return true;
  };
  std::vector<std::vector<int>> loops;
  for (int start = 0; start < static_cast<int>(edges.size()); ++start) {
    if (used[start]) continue;
    used[start] = 1;
    const int first = edges[start][0];
    std::vector<int> loop{first, edges[start][1]};
    if (!walk(edges[start][1], first, true, loop)) {
      std::vector<int> back;
      walk(first, -1, false, back);
      loop.insert(loop.begin(), back.rbegin(), back.rend());
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace

bool MeshReport::clean() const {
  return nonManifoldEdges.empty() && nonManifoldVertices.empty() && duplicateFaces.empty() && degenerateFaces.empty() &&
         unreferencedVertices.empty() && inconsistentEdges.empty();
}

std::vector<int> MeshReport::intersectingFaces() const {
  std::vector<int> faces;
  for (const IntersectingPair& p : intersectingPairs) {
    faces.push_back(p.a);
    faces.push_back(p.b);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

double MeshReport::intersectingArea() const {
  std::vector<std::pair<int, double>> faces;
  for (const IntersectingPair& p : intersectingPairs) {
    faces.emplace_back(p.a, p.areaA);
    faces.emplace_back(p.b, p.areaB);
  }
  std::sort(faces.begin(), faces.end());
  double area = 0;
  for (size_t i = 0; i < faces.size(); ++i)
    if (i == 0 || faces[i].first != faces[i - 1].first) area += faces[i].second;
  return area;
}

std::vector<std::string> MeshReport::describeInput(int maxIds) const {
  std::vector<std::string> out;
  if (!intersectingPairs.empty()) {
    std::vector<std::array<int, 2>> pairs;
    for (const IntersectingPair& p : intersectingPairs) pairs.push_back({p.a, p.b});
    const double area = intersectingArea();
    char text[96];
    std::snprintf(text, sizeof text, "%.6g m^2 (%.4g%% of the area)", area,
                  surfaceArea > 0 ? 100 * area / surfaceArea : 0.0);
    out.push_back("intersecting polygons: " + std::to_string(pairs.size()) + " pair" + (pairs.size() == 1 ? "" : "s") +
                  " (first: " + pairList(pairs, maxIds) + ") on " + std::to_string(intersectingFaces().size()) +
                  " faces, " + text);
  }
  if (!selfCrossingFaces.empty())
    out.push_back("self-crossing polygons: " + std::to_string(selfCrossingFaces.size()) +
                  " (first: " + idList(selfCrossingFaces, maxIds) + ")");
  if (selfCrossingUnchecked > 0)
    out.push_back("polygons over " + std::to_string(kMaxSelfCrossingCorners) +
                  " corners not checked for a self-crossing outline: " + std::to_string(selfCrossingUnchecked));
  return out;
}

std::vector<std::string> MeshReport::describe(int maxIds) const {
  std::vector<std::string> out;
  out.push_back("vertices: " + std::to_string(numVertices) + ", faces: " + std::to_string(numFaces) +
                ", edges: " + std::to_string(numEdges));
  std::string sizes;
  for (size_t n = 0; n < faceSizeHistogram.size(); ++n) {
    if (faceSizeHistogram[n] == 0) continue;
    const std::string name = n == 3 ? "tri" : n == 4 ? "quad" : std::to_string(n) + "-gon";
    sizes += (sizes.empty() ? "" : ", ") + std::to_string(faceSizeHistogram[n]) + " " + name;
  }
  out.push_back("face sizes: " + (sizes.empty() ? std::string("none") : sizes));
  const int chi = numVertices - static_cast<int>(unreferencedVertices.size()) - numEdges + numFaces;
  std::string topo = std::string(closed() ? "closed" : "open") + ", " + std::to_string(numComponents) + " component" +
                     (numComponents == 1 ? "" : "s") + ", Euler characteristic " + std::to_string(chi);
  if (closed() && numComponents == 1 && nonManifoldEdges.empty() && nonManifoldVertices.empty())
    topo += ", genus " + std::to_string((2 - chi) / 2);
  char volume[32];
  std::snprintf(volume, sizeof volume, "%.6g", signedVolume);
  out.push_back(topo + ", signed volume " + volume);
  if (!boundaryLoops.empty()) {
    std::string s;
    for (size_t i = 0; i < boundaryLoops.size() && static_cast<int>(i) < maxIds; ++i)
      s += (i ? ", " : "") + std::to_string(boundaryLoops[i].size());
    out.push_back("boundary loops: " + std::to_string(boundaryLoops.size()) + " (lengths: " + s +
                  (boundaryLoops.size() > static_cast<size_t>(maxIds) ? ", ...)" : ")"));
  }
  const auto add = [&](const char* what, size_t n, const std::string& ids) {
    if (n) out.push_back(std::string(what) + ": " + std::to_string(n) + " (first: " + ids + ")");
  };
  add("non-manifold edges", nonManifoldEdges.size(), pairList(nonManifoldEdges, maxIds));
  add("non-manifold vertices", nonManifoldVertices.size(), idList(nonManifoldVertices, maxIds));
  add("duplicate faces", duplicateFaces.size(), idList(duplicateFaces, maxIds));
  add("degenerate faces", degenerateFaces.size(), idList(degenerateFaces, maxIds));
  add("unreferenced vertices", unreferencedVertices.size(), idList(unreferencedVertices, maxIds));
  add("inconsistently oriented edges", inconsistentEdges.size(), pairList(inconsistentEdges, maxIds));
  for (std::string& line : describeInput(maxIds)) out.push_back(std::move(line));
  return out;
}

bool isDegenerateFace(const PolygonMesh& m, int f) {
  const int n = m.faceSize(f);
  if (n < 3) return true;
  std::vector<int> set(m.faceVertices.begin() + m.faceOffsets[f], m.faceVertices.begin() + m.faceOffsets[f + 1]);
  std::sort(set.begin(), set.end());
  return std::adjacent_find(set.begin(), set.end()) != set.end() || degenerate(m, f);
}

MeshReport checkMesh(const PolygonMesh& m, const MeshCheckOptions& options) {
  validateIndices(m);
  MeshReport r;
  r.numVertices = m.numVertices();
  r.numFaces = m.numFaces();
  const int nc = m.numCorners();

  // the signed volume about localOrigin of the mesh's box: about (0,0,0) the products of
  // coordinates near 1e7 m cancelled and the sign came out wrong (the mesh was then flipped
  // inside out); about the origin for a mesh about it (the same bits as before)
  Eigen::Vector3d lo, hi;
  referencedBox(m, lo, hi);
  const Eigen::Vector3d c = localOrigin(lo, hi);
  std::vector<HalfEdge> he;
  he.reserve(nc);
  std::vector<char> referenced(r.numVertices, 0);
  std::map<std::vector<int>, int> faceSets;
  std::vector<int> set;
  for (int f = 0; f < r.numFaces; ++f) {
    const int n = m.faceSize(f), c0 = m.faceOffsets[f];
    if (static_cast<int>(r.faceSizeHistogram.size()) <= n) r.faceSizeHistogram.resize(n + 1, 0);
    ++r.faceSizeHistogram[n];
    set.clear();
    for (int k = 0; k < n; ++k) {
      const int a = m.faceVertex(f, k), b = m.faceVertex(f, k + 1);
      referenced[a] = 1;
      set.push_back(a);
      if (a != b) {
        const auto lo = static_cast<uint64_t>(std::min(a, b)), hi = static_cast<uint64_t>(std::max(a, b));
        he.push_back({lo << 32 | hi, f, c0 + k, c0 + (k + 1) % n});
      }
    }
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    if (!faceSets.emplace(set, f).second) r.duplicateFaces.push_back(f);
    if (static_cast<int>(set.size()) < n || degenerate(m, f)) r.degenerateFaces.push_back(f);
    for (int k = 1; k + 1 < n; ++k) {
      const Eigen::Vector3d p0 = m.positions[m.faceVertex(f, 0)] - c;
      r.signedVolume += p0.dot((m.positions[m.faceVertex(f, k)] - c).cross(m.positions[m.faceVertex(f, k + 1)] - c)) / 6;
    }
  }
  for (int v = 0; v < r.numVertices; ++v) {
    if (!referenced[v]) r.unreferencedVertices.push_back(v);
  }

  std::stable_sort(he.begin(), he.end(), [](const HalfEdge& a, const HalfEdge& b) { return a.key < b.key; });
  UnionFind faces(r.numFaces), corners(nc);
  std::vector<std::array<int, 2>> boundary;  // directed as in the face
  for (size_t i = 0; i < he.size();) {
    size_t j = i;
    while (j < he.size() && he[j].key == he[i].key) ++j;
    const std::array<int, 2> pair{static_cast<int>(he[i].key >> 32), static_cast<int>(he[i].key & 0xffffffffu)};
    ++r.numEdges;
    for (size_t k = i + 1; k < j; ++k) faces.unite(he[i].face, he[k].face);
    if (j - i == 1) {
      boundary.push_back({m.faceVertices[he[i].from], m.faceVertices[he[i].to]});
    } else if (j - i == 2) {
      const HalfEdge &a = he[i], &b = he[i + 1];
      if (m.faceVertices[a.from] == m.faceVertices[b.from]) {
        r.inconsistentEdges.push_back(pair);
        corners.unite(a.from, b.from);
        corners.unite(a.to, b.to);
      } else {
        corners.unite(a.from, b.to);
        corners.unite(a.to, b.from);
      }
    } else {
      r.nonManifoldEdges.push_back(pair);
    }
    i = j;
  }

  // A vertex is non-manifold when its corners fall into more than one fan.
  std::vector<int> fanRoot(r.numVertices, -1);
  std::vector<char> multi(r.numVertices, 0);
  for (int c = 0; c < nc; ++c) {
    const int v = m.faceVertices[c], root = corners.find(c);
    if (fanRoot[v] < 0)
      fanRoot[v] = root;
    else if (fanRoot[v] != root)
      multi[v] = 1;
  }
  for (int v = 0; v < r.numVertices; ++v) {
    if (multi[v]) r.nonManifoldVertices.push_back(v);
  }
  for (int f = 0; f < r.numFaces; ++f) r.numComponents += faces.find(f) == f;
  r.boundaryLoops = chainLoops(boundary);
  if (options.intersections) {
    const MeshTriangles triangles = polygonTriangles(m);
    for (const double a : triangles.faceArea) r.surfaceArea += a;
    r.intersectingPairs = findIntersectingFaces(m, triangles);
    r.selfCrossingFaces = findSelfCrossingFaces(m, &r.selfCrossingUnchecked);
    r.intersectionsChecked = true;
  }
  return r;
}

namespace {

/// Reverses face f's corners after its first (and their corner normals, where the mesh has them).
void flipFace(PolygonMesh& m, int f) {
  const int b = m.faceOffsets[f] + 1, e = m.faceOffsets[f + 1];
  if (e <= b) return;
  std::reverse(m.faceVertices.begin() + b, m.faceVertices.begin() + e);
  if (m.fileCornerNormals.size() == m.faceVertices.size())
    std::reverse(m.fileCornerNormals.begin() + b, m.fileCornerNormals.begin() + e);
}

}  // namespace

void flipFaces(PolygonMesh& m) {
  for (int f = 0; f < m.numFaces(); ++f) flipFace(m, f);
}

std::vector<std::string> OrientationRepair::describe(int maxIds) const {
  std::vector<std::string> out;
  const auto ids = [maxIds](const std::vector<int>& v) { return " " + idList(v, maxIds); };
  if (!turnedFaces.empty())
    out.push_back("orientation: " + std::to_string(turnedFaces.size()) +
                  (turnedFaces.size() == 1
                       ? " face ran against its neighbours: turned to agree with most of its"
                       : " faces ran against their neighbours: turned to agree with most of their") +
                  " component's faces (--orient keep to keep; faces:" + ids(turnedFaces) + ")");
  if (!unorientableFaces.empty())
    out.push_back("orientation: " + std::to_string(unorientableFaces.size()) +
                  (unorientableFaces.size() == 1 ? " component" : " components") +
                  " with no orientation that agrees across every edge (a Moebius strip), left as read (lowest "
                  "faces:" +
                  ids(unorientableFaces) + ")");
  return out;
}

OrientationRepair orientCoherently(PolygonMesh& m) {
  OrientationRepair out;
  const int nf = m.numFaces(), nv = m.numVertices();
  for (const int32_t v : m.faceVertices)
    if (v < 0 || v >= nv) return out;  // checkMesh names the bad index
  // each edge that exactly two faces use: the faces and whether they run along it the same way
  std::vector<std::pair<uint64_t, int>> sides;  // (undirected key, corner)
  std::vector<int> faceOf(m.numCorners()), nextOf(m.numCorners());
  for (int f = 0; f < nf; ++f) {
    const int b = m.faceOffsets[f], e = m.faceOffsets[f + 1];
    for (int c = b; c < e; ++c) {
      faceOf[c] = f;
      nextOf[c] = c + 1 < e ? c + 1 : b;
      const uint32_t u = static_cast<uint32_t>(m.faceVertices[c]), w = static_cast<uint32_t>(m.faceVertices[nextOf[c]]);
      if (u != w) sides.emplace_back((static_cast<uint64_t>(std::min(u, w)) << 32) | std::max(u, w), c);
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<std::vector<std::pair<int, char>>> links(nf);  // (neighbour, 1 if it must turn relative to f)
  bool against = false;
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    while (j < sides.size() && sides[j].first == sides[i].first) ++j;
    if (j - i == 2) {
      const int a = sides[i].second, b = sides[i + 1].second, fa = faceOf[a], fb = faceOf[b];
      const char same = m.faceVertices[a] == m.faceVertices[b];
      if (fa != fb) {
        links[fa].emplace_back(fb, same);
        links[fb].emplace_back(fa, same);
        against |= same != 0;
      }
    }
    i = j;
  }
  if (!against) return out;  // every part already agrees: nothing to turn, nothing unorientable
  // breadth first from each component's lowest face: parity relative to it
  std::vector<signed char> parity(nf, -1);
  std::vector<int> component, queue;
  std::vector<int> turned;
  for (int seed = 0; seed < nf; ++seed) {
    if (parity[seed] >= 0) continue;
    component.clear();
    queue.assign(1, seed);
    parity[seed] = 0;
    bool agrees = true;
    for (size_t q = 0; q < queue.size(); ++q) {
      const int f = queue[q];
      component.push_back(f);
      for (const auto& [g, flip] : links[f]) {
        const signed char want = static_cast<signed char>(parity[f] ^ flip);
        if (parity[g] < 0) {
          parity[g] = want;
          queue.push_back(g);
        } else if (parity[g] != want) {
          agrees = false;
        }
      }
    }
    if (!agrees) {
      out.unorientableFaces.push_back(seed);
      continue;
    }
    size_t odd = 0;
    for (const int f : component) odd += parity[f];
    const signed char turn = odd * 2 > component.size() ? 0 : 1;  // turn the minority (tie: the seed's side stays)
    for (const int f : component)
      if (parity[f] == turn) turned.push_back(f);
  }
  std::sort(turned.begin(), turned.end());
  for (const int f : turned) flipFace(m, f);
  out.turnedFaces = std::move(turned);
  return out;
}

bool applyOrientation(PolygonMesh& m, const MeshReport& r, OrientPolicy policy) {
  // a few faces out of line leave the majority's sign on the volume (the spot cage inward but
  // one face was left inside out, with forces outside and none inside); more, and it says little
  const bool fewInconsistent = r.inconsistentEdges.size() * 10 <= static_cast<size_t>(r.numEdges);
  if (policy != OrientPolicy::Outward || !r.closed() || !fewInconsistent || !(r.signedVolume < 0)) return false;
  flipFaces(m);
  return true;
}

}  // namespace sf
