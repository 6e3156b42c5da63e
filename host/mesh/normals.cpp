// SPDX-License-Identifier: Apache-2.0
// Vertex normals: file normals (per vertex or per corner), or angle- / area-weighted
// averages of Newell face normals.
#include <smoothforce/mesh/normals.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace sf {
namespace {

std::string where(const PolygonMesh& m) { return m.sourcePath.empty() ? "mesh" : m.sourcePath; }

/// A Newell normal this short (relative to the face's perimeter) means zero area.
bool zeroArea(const PolygonMesh& m, int f, const Eigen::Vector3d& newell) {
  double perimeter = 0;
  for (int k = 0; k < m.faceSize(f); ++k)
    perimeter += (m.positions[m.faceVertex(f, k + 1)] - m.positions[m.faceVertex(f, k)]).norm();
  return !(newell.norm() > 1e-12 * perimeter * perimeter);
}

Eigen::Vector3d unitFileNormal(const Eigen::Vector3d& n, const std::string& what) {
  double len = n.norm();
  if (std::isinf(len) && n.allFinite()) len = n.stableNorm();  // a finite normal beyond 1e154 is a direction too
  if (!std::isfinite(len) || len == 0) throw InputError(what + ": zero or non-finite file normal");
  return n / len;
}

/// File normals per corner; the per-corner ones first unless `perVertexOnly`.
std::vector<Eigen::Vector3d> fileNormals(const PolygonMesh& m, bool perVertexOnly) {
  std::vector<Eigen::Vector3d> out(m.numCorners());
  if (!perVertexOnly && !m.fileCornerNormals.empty()) {
    if (m.fileCornerNormals.size() != out.size()) {
      throw InputError(where(m) + ": " + std::to_string(m.fileCornerNormals.size()) + " corner normals for " +
                       std::to_string(out.size()) + " corners");
    }
    for (int f = 0; f < m.numFaces(); ++f) {
      for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) {
        out[c] = unitFileNormal(m.fileCornerNormals[c], where(m) + ": face " + std::to_string(f) + " corner " +
                                                            std::to_string(c - m.faceOffsets[f]));
      }
    }
    return out;
  }
  if (m.fileNormals.empty()) throw InputError(where(m) + ": normal mode 'file' but the file has no normals");
  if (m.fileNormals.size() != m.positions.size()) {
    throw InputError(where(m) + ": " + std::to_string(m.fileNormals.size()) + " file normals for " +
                     std::to_string(m.positions.size()) + " vertices");
  }
  for (int c = 0; c < m.numCorners(); ++c) {
    const int v = m.faceVertices[c];
    out[c] = unitFileNormal(m.fileNormals[v], where(m) + ": vertex " + std::to_string(v));
  }
  return out;
}

/// First corner (in face order) of every vertex; -1 for unreferenced vertices.
std::vector<int> firstCorners(const PolygonMesh& m) {
  std::vector<int> first(m.numVertices(), -1);
  for (int c = 0; c < m.numCorners(); ++c)
    if (first[m.faceVertices[c]] < 0) first[m.faceVertices[c]] = c;
  return first;
}

/// Angle between two unit vectors (radians, accurate near 0 and pi).
double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

NormalMode parseNormalMode(const std::string& s) {
  if (s == "auto") return NormalMode::Auto;
  if (s == "file") return NormalMode::File;
  if (s == "angle") return NormalMode::Angle;
  if (s == "area") return NormalMode::Area;
  throw InputError("unknown normal mode '" + s + "' (expected auto, file, angle or area)");
}

const char* toString(NormalMode m) {
  switch (m) {
    case NormalMode::Auto:
      return "auto";
    case NormalMode::File:
      return "file";
    case NormalMode::Angle:
      return "angle";
    case NormalMode::Area:
      return "area";
  }
  return "?";
}

Eigen::Vector3d newellNormal(const PolygonMesh& mesh, int f) {
  // Sum of p_k x p_(k+1), written relative to the first corner for accuracy far from 0.
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  if (mesh.faceSize(f) < 3) return n;
  const Eigen::Vector3d& p0 = mesh.positions[mesh.faceVertex(f, 0)];
  for (int k = 1; k + 1 < mesh.faceSize(f); ++k)
    n += (mesh.positions[mesh.faceVertex(f, k)] - p0).cross(mesh.positions[mesh.faceVertex(f, k + 1)] - p0);
  return n;
}

namespace {

/// Angle- or area-weighted unit normal per vertex (#V by 3; +z for unreferenced vertices).
/// Vertices that needed the first-incident-face fallback are appended to `fallbackVertices`.
std::vector<Eigen::Vector3d> weightedVertexNormals(const PolygonMesh& mesh, NormalMode mode,
                                                   std::vector<int>& fallbackVertices) {
  const int nv = mesh.numVertices();
  std::vector<Eigen::Vector3d> sum(nv, Eigen::Vector3d::Zero());
  std::vector<double> weight(nv, 0.0);
  std::vector<int> firstGood(nv, -1), firstNonZero(nv, -1);
  std::vector<Eigen::Vector3d> faceUnit(mesh.numFaces(), Eigen::Vector3d::Zero());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d N = newellNormal(mesh, f);
    const double len = N.norm();
    const int n = mesh.faceSize(f);
    if (len > 0 && std::isfinite(len)) faceUnit[f] = N / len;
    const bool skip = zeroArea(mesh, f, N);
    for (int k = 0; k < n; ++k) {
      const int v = mesh.faceVertex(f, k);
      if (firstNonZero[v] < 0 && len > 0 && std::isfinite(len)) firstNonZero[v] = f;
      if (skip) continue;
      if (firstGood[v] < 0) firstGood[v] = f;
      if (mode == NormalMode::Area) {
        sum[v] += N;
        weight[v] += len;
        continue;
      }
      // Interior angle at the corner; reflex (> pi) where the corner turns against N.
      const Eigen::Vector3d& p = mesh.positions[v];
      const Eigen::Vector3d eNext = mesh.positions[mesh.faceVertex(f, k + 1)] - p;
      const Eigen::Vector3d ePrev = mesh.positions[mesh.faceVertex(f, k - 1)] - p;
      const Eigen::Vector3d c = eNext.cross(ePrev);
      double angle = std::atan2(c.norm(), eNext.dot(ePrev));
      if (c.dot(N) < 0) angle = 2 * std::numbers::pi - angle;
      sum[v] += angle * faceUnit[f];
      weight[v] += angle;
    }
  }

  std::vector<Eigen::Vector3d> vertexNormal(nv, Eigen::Vector3d::UnitZ());
  std::vector<char> used(nv, 0);
  for (int v : mesh.faceVertices) used[v] = 1;
  for (int v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    const double len = sum[v].norm();
    if (weight[v] > 0 && len > 1e-12 * weight[v] && std::isfinite(len)) {
      vertexNormal[v] = sum[v] / len;
      continue;
    }
    const int f = firstGood[v] >= 0 ? firstGood[v] : firstNonZero[v];
    if (f >= 0) vertexNormal[v] = faceUnit[f];  // else +z: every incident face has zero Newell
    fallbackVertices.push_back(v);
  }
  return vertexNormal;
}

}  // namespace

std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode, NormalReport& report) {
  report = NormalReport{};
  report.mode = mode;
  report.fileHasNormals = !mesh.fileNormals.empty() || !mesh.fileCornerNormals.empty();
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int c = mesh.faceOffsets[f]; c < mesh.faceOffsets[f + 1]; ++c) {
      if (mesh.faceVertices[c] < 0 || mesh.faceVertices[c] >= mesh.numVertices()) {
        throw InputError(where(mesh) + ": face " + std::to_string(f) + ": vertex index " +
                         std::to_string(mesh.faceVertices[c]) + " out of range");
      }
    }
  }
  const std::vector<int> first = firstCorners(mesh);
  std::vector<Eigen::Vector3d> out;
  const bool usable = !mesh.fileCornerNormals.empty() || mesh.fileNormals.size() == mesh.positions.size();
  const bool fileMode = mode == NormalMode::File || (mode == NormalMode::Auto && usable);
  if (fileMode && !mesh.fileCornerNormals.empty()) {
    out = fileNormals(mesh, false);
    std::vector<char> split(mesh.numVertices(), 0);
    for (int c = 0; c < mesh.numCorners(); ++c) {
      const int v = mesh.faceVertices[c];
      if (!split[v] && angleBetween(out[c], out[first[v]]) > kSameNormalAngle) split[v] = 1;
    }
    for (int v = 0; v < mesh.numVertices(); ++v)
      if (split[v]) report.splitVertices.push_back(v);
    if (mode == NormalMode::File) {
      report.source = NormalSource::FileCorners;
    } else if (report.splitVertices.empty()) {
      report.source = NormalSource::FileFaceRefs;
      for (int c = 0; c < mesh.numCorners(); ++c) out[c] = out[first[mesh.faceVertices[c]]];  // first <= c
    } else {
      // Split vertices take the angle-weighted normal; every other vertex its first corner's.
      report.source = NormalSource::FileAndAngle;
      std::vector<int> fallbacks;
      const std::vector<Eigen::Vector3d> angle = weightedVertexNormals(mesh, NormalMode::Angle, fallbacks);
      for (int v : fallbacks)
        if (split[v]) report.fallbackVertices.push_back(v);
      for (int c = 0; c < mesh.numCorners(); ++c) {  // in place: first[v] <= c keeps its value
        const int v = mesh.faceVertices[c];
        out[c] = split[v] ? angle[v] : out[first[v]];
      }
    }
  } else if (fileMode) {
    out = fileNormals(mesh, true);
    report.source = NormalSource::FileVertexOrder;
  } else {
    if (mode == NormalMode::Auto) mode = NormalMode::Angle;
    report.source = mode == NormalMode::Area ? NormalSource::Area : NormalSource::Angle;
    const std::vector<Eigen::Vector3d> vn = weightedVertexNormals(mesh, mode, report.fallbackVertices);
    out.resize(mesh.numCorners());
    for (int c = 0; c < mesh.numCorners(); ++c) out[c] = vn[mesh.faceVertices[c]];
  }
  if (fileMode) {
    for (int v = 0; v < mesh.numVertices(); ++v) report.fileVertices += first[v] >= 0;
    report.fileVertices -= static_cast<int>(report.splitVertices.size());
  }
  // Creases: corners whose normal differs from the first corner's of the same vertex.
  for (int c = 0; c < mesh.numCorners(); ++c)
    report.creaseCorners += (out[c] - out[first[mesh.faceVertices[c]]]).norm() > 1e-12;
  return out;
}

std::vector<std::string> NormalReport::describe(int maxIds) const {
  const auto ids = [&](const std::vector<int>& v) {
    std::string s;
    for (size_t i = 0; i < v.size() && static_cast<int>(i) < maxIds; ++i) {
      if (i) s += ' ';
      s += std::to_string(v[i]);
    }
    return s + (v.size() > static_cast<size_t>(maxIds) ? " ..." : "");
  };
  const std::string nSplit = std::to_string(splitVertices.size());
  std::vector<std::string> out;
  switch (source) {
    case NormalSource::FileVertexOrder:
      out.push_back("the file's normals, one per vertex (in vertex order)");
      break;
    case NormalSource::FileFaceRefs:
      out.push_back("the file's normals, one per vertex (through face references)");
      break;
    case NormalSource::FileCorners:
      out.push_back("the file's normals per corner, as given");
      break;
    case NormalSource::FileAndAngle:
      out.push_back("the file's normals at " + std::to_string(fileVertices) + " vertices; angle-weighted at " + nSplit +
                    " vertices whose corners carry different file normals");
      break;
    case NormalSource::Angle:
    case NormalSource::Area:
      out.push_back(std::string(source == NormalSource::Angle ? "angle" : "area") + "-weighted Newell normals" +
                    (fileHasNormals ? "" : " (the file has no vertex normals)"));
      break;
    case NormalSource::CageLimit:
      out.push_back(std::string("Catmull-Clark limit normals of the cage (--cage catmull-clark)") +
                    (fileHasNormals ? "; the file's normals are not used" : ""));
      break;
  }
  if (!splitVertices.empty()) {
    char tol[32];
    std::snprintf(tol, sizeof tol, "%g", kSameNormalAngle);
    out.push_back(
        "split vertices: " + nSplit + " (first: " + ids(splitVertices) +
        "): their corners carry file normals more than " + tol + " rad apart" +
        (mode == NormalMode::Auto ? "; auto used the angle-weighted normal there (--normals file keeps them)" : ""));
  }
  if (creaseCorners) {
    out.push_back("crease corners: " + std::to_string(creaseCorners) +
                  " (normal differs from another corner of the same vertex): the edges there are not shared "
                  "curves, so the surface is open along them");
  }
  if (!fallbackVertices.empty()) {
    out.push_back("no well-defined normal: " + std::to_string(fallbackVertices.size()) +
                  " vertices (first: " + ids(fallbackVertices) + "): used an incident face's normal");
  }
  return out;
}

std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode,
                                           std::vector<int>* fallbackVertices) {
  NormalReport report;
  std::vector<Eigen::Vector3d> out = cornerNormals(mesh, mode, report);
  if (fallbackVertices) *fallbackVertices = std::move(report.fallbackVertices);
  return out;
}

}  // namespace sf
