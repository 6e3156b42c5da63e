// SPDX-License-Identifier: Apache-2.0
// Crease edges from tags, smoothing groups and a dihedral threshold; smoothing sectors; the
// crease summary of a built surface.
#include <smoothforce/mesh/creases.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <smoothforce/base/error.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/topology.h>
#include "union_find.h"

namespace sf {
namespace {

using Edge = std::array<int32_t, 2>;
Edge key(int32_t a, int32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

std::string where(const PolygonMesh& m, size_t line) {
  return (m.sourcePath.empty() ? std::string("mesh") : m.sourcePath) + (line ? ":" + std::to_string(line) : "");
}

}  // namespace

void checkCreaseOptions(const CreaseOptions& o) {
  if (!(o.angleDeg >= 0 && o.angleDeg < 180))
    throw InputError("crease angle " + std::to_string(o.angleDeg) + " out of range (expected 0 <= degrees < 180; 0 is off)");
}

std::string creaseMarksText(const CreaseOptions& o) {
  std::string s;
  for (auto [on, name] : {std::pair{o.tags, "tags"}, {o.groups, "groups"}, {o.normals, "normals"}})
    if (on) {
      if (!s.empty()) s += ',';
      s += name;
    }
  return s.empty() ? "none" : s;
}

void parseCreaseMarks(const std::string& text, CreaseOptions& o) {
  if (text == "none") {
    o.tags = o.groups = o.normals = false;
    return;
  }
  bool tags = false, groups = false, normals = false;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    if (item == "tags" && !tags)
      tags = true;
    else if (item == "groups" && !groups)
      groups = true;
    else if (item == "normals" && !normals)
      normals = true;
    else
      throw InputError("--creases: expected a list of tags, groups, normals (each once), or none; got '" + text +
                       "'");
    at = comma + 1;
  }
  o.tags = tags;
  o.groups = groups;
  o.normals = normals;
}

bool isCrease(const CreaseSet& c, int32_t v0, int32_t v1) {
  return std::binary_search(c.edges.begin(), c.edges.end(), key(v0, v1));
}

CreaseSet findCreases(const PolygonMesh& mesh, const CreaseOptions& options) {
  checkCreaseOptions(options);
  CreaseSet out;
  std::map<Edge, double> sharp;
  // every edge of the mesh with its faces (up to two kept: creases need a neighbour to matter)
  std::map<Edge, std::array<int32_t, 2>> faces;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0, n = mesh.faceSize(f); k < n; ++k) {
      auto [it, fresh] = faces.try_emplace(key(mesh.faceVertex(f, k), mesh.faceVertex(f, k + 1)), std::array{f, -1});
      if (!fresh && it->second[1] < 0) it->second[1] = f;
    }
  const auto mark = [&](const Edge& e, double s) {
    auto [it, fresh] = sharp.try_emplace(e, s);
    if (!fresh) it->second = std::max(it->second, s);
  };
  if (options.tags) {
    const int nv = mesh.numVertices();
    for (const CreaseTag& t : mesh.creaseTags) {
      if (t.v0 < 0 || t.v0 >= nv || t.v1 < 0 || t.v1 >= nv)
        throw InputError(where(mesh, t.line) + ": crease tag vertex out of range (" + std::to_string(t.v0) + " " +
                         std::to_string(t.v1) + "; " + std::to_string(nv) + " vertices, ids from 0)");
      if (!faces.count(key(t.v0, t.v1)))
        throw InputError(where(mesh, t.line) + ": crease tag " + std::to_string(t.v0) + " " + std::to_string(t.v1) +
                         ": no face has this edge (tag vertex ids start at 0)");
      if (!(t.sharpness > 0)) continue;
      ++out.fromTags;
      out.semiSharp += t.sharpness < kInfiniteSharpness;
      mark(key(t.v0, t.v1), std::min(t.sharpness, kInfiniteSharpness));
    }
    for (const CornerTag& t : mesh.cornerTags) {
      if (t.v < 0 || t.v >= nv)
        throw InputError(where(mesh, t.line) + ": corner tag vertex " + std::to_string(t.v) + " out of range (" +
                         std::to_string(nv) + " vertices, ids from 0)");
      if (t.sharpness > 0) out.corners.push_back(t.v);
    }
    std::sort(out.corners.begin(), out.corners.end());
    out.corners.erase(std::unique(out.corners.begin(), out.corners.end()), out.corners.end());
  }
  const std::vector<int64_t>& groups = mesh.faceSmoothingGroups;
  if (options.groups && !groups.empty()) {
    if (static_cast<int>(groups.size()) != mesh.numFaces())
      throw InputError(where(mesh, 0) + ": " + std::to_string(groups.size()) + " smoothing groups for " +
                       std::to_string(mesh.numFaces()) + " faces");
    out.groupsAllOff = std::all_of(groups.begin(), groups.end(), [](int64_t g) { return g == 0; });
    if (!out.groupsAllOff)
      for (const auto& [e, fs] : faces)
        if (fs[1] >= 0 && (groups[fs[0]] != groups[fs[1]] || groups[fs[0]] == 0)) {
          ++out.fromGroups;
          mark(e, kInfiniteSharpness);
        }
  }
  if (options.angleDeg > 0) {
    const double cosMax = std::cos(options.angleDeg * std::numbers::pi / 180);
    for (const auto& [e, fs] : faces) {
      if (fs[1] < 0) continue;
      const Eigen::Vector3d a = newellNormal(mesh, fs[0]), b = newellNormal(mesh, fs[1]);
      const double la = a.norm(), lb = b.norm();
      if (!(la > 0 && lb > 0)) continue;  // a degenerate face has no dihedral angle
      if (a.dot(b) / (la * lb) < cosMax) {
        ++out.fromAngle;
        mark(e, kInfiniteSharpness);
      }
    }
  }
  out.edges.reserve(sharp.size());
  for (const auto& [e, s] : sharp) {
    out.edges.push_back(e);
    out.sharpness.push_back(s);
  }
  return out;
}

std::vector<int32_t> cornerSectors(const PolygonMesh& mesh, const std::vector<int32_t>& slotTwin,
                                   const std::function<bool(int32_t, int32_t, int32_t)>& join, int* count) {
  const int nc = mesh.numCorners();
  UnionFind sectors(nc);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int first = mesh.faceOffsets[f], n = mesh.faceSize(f);
    for (int k = 0; k < n; ++k) {
      const int32_t s = first + k, t = slotTwin[s];
      if (t < 0 || t < s) continue;  // each shared edge once
      const int32_t sNext = first + (k + 1 == n ? 0 : k + 1);
      int32_t atStart, atEnd;  // the other face's corners at V_k (as s) and V_{k+1} (as sNext)
      acrossCorners(mesh.faceOffsets, slotTwin, f, k, atStart, atEnd);
      if (join(s, atStart, s)) sectors.unite(s, atStart);
      if (join(sNext, atEnd, s)) sectors.unite(sNext, atEnd);
    }
  }
  // sectors numbered in order of first corner
  std::vector<int32_t> id(nc, -1), out(nc);
  int next = 0;
  for (int32_t c = 0; c < nc; ++c) {
    const int32_t r = sectors.find(c);
    if (id[r] < 0) id[r] = next++;
    out[c] = id[r];
  }
  if (count) *count = next;
  return out;
}

CreaseSummary summarizeCreases(const PolygonMesh& mesh, const std::vector<int32_t>& slotTwin,
                               const double* cornerNormals) {
  CreaseSummary out;
  const auto differ = [&](int32_t a, int32_t b) {
    const double *x = cornerNormals + 3 * static_cast<size_t>(a), *y = cornerNormals + 3 * static_cast<size_t>(b);
    return x[0] != y[0] || x[1] != y[1] || x[2] != y[2];
  };
  std::vector<int> touching(mesh.numVertices(), 0);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int first = mesh.faceOffsets[f], n = mesh.faceSize(f);
    for (int k = 0; k < n; ++k) {
      const int32_t s = first + k, t = slotTwin[s];
      if (t < 0 || t < s) continue;
      const int32_t sNext = first + (k + 1 == n ? 0 : k + 1);
      int32_t atStart, atEnd;
      acrossCorners(mesh.faceOffsets, slotTwin, f, k, atStart, atEnd);
      if (!differ(s, atStart) && !differ(sNext, atEnd)) continue;
      const int32_t a = mesh.faceVertices[s], b = mesh.faceVertices[sNext];
      out.edges.push_back(key(a, b));
      ++touching[a], ++touching[b];
    }
  }
  std::sort(out.edges.begin(), out.edges.end());
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (touching[v] == 1) out.darts.push_back(v);
    if (touching[v] == 2) out.creaseVertices.push_back(v);
    if (touching[v] >= 3) out.corners.push_back(v);
  }
  return out;
}

std::vector<std::string> CreaseSummary::describe(int maxIds) const {
  std::vector<std::string> out;
  if (edges.empty()) return out;
  const auto ids = [&](const std::vector<int32_t>& v) {
    std::string s;
    for (size_t i = 0; i < v.size() && static_cast<int>(i) < maxIds; ++i) {
      s += ' ';
      s += std::to_string(v[i]);
    }
    if (v.size() > static_cast<size_t>(maxIds)) s += " ...";
    return s;
  };
  std::string e;
  for (size_t i = 0; i < edges.size() && static_cast<int>(i) < maxIds; ++i) {
    e += ' ';
    e += std::to_string(edges[i][0]);
    e += '-';
    e += std::to_string(edges[i][1]);
  }
  if (edges.size() > static_cast<size_t>(maxIds)) e += " ...";
  out.push_back("crease edges: " + std::to_string(edges.size()) + " (vertex pairs:" + e +
                "): one shared curve, a tangent plane per side");
  out.push_back("crease vertices: " + std::to_string(creaseVertices.size()) + ids(creaseVertices) +
                (creaseVertices.empty() ? "" : ";") + " corners: " + std::to_string(corners.size()) + ids(corners) +
                (corners.empty() ? "" : ";") + " darts: " + std::to_string(darts.size()) + ids(darts));
  return out;
}

}  // namespace sf
