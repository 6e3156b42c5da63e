// SPDX-License-Identifier: Apache-2.0
// Vertex normals: file normals (per vertex or per corner), or angle- / area-weighted
// averages of Newell face normals.
#include <smoothforce/mesh/normals.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <smoothforce/mesh/topology.h>

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

}  // namespace

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

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

/// Angle- or area-weighted unit normal per group of corners (cornerGroup: #C ids in
/// [0, numGroups); the vertex id for one normal per vertex, a smoothing sector at creases): the
/// weighted sum of the face normals over the group's corners. Unused groups get +z. Groups that
/// needed the first-incident-face fallback add their vertex to `fallbackVertices` (once).
std::vector<Eigen::Vector3d> weightedNormals(const PolygonMesh& mesh, NormalMode mode,
                                             const std::vector<int32_t>& cornerGroup, int numGroups,
                                             std::vector<int>& fallbackVertices) {
  const int ng = numGroups;
  std::vector<Eigen::Vector3d> sum(ng, Eigen::Vector3d::Zero());
  std::vector<double> weight(ng, 0.0);
  std::vector<int> firstGood(ng, -1), firstNonZero(ng, -1), vertexOf(ng, -1);
  std::vector<Eigen::Vector3d> faceUnit(mesh.numFaces(), Eigen::Vector3d::Zero());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d N = newellNormal(mesh, f);
    const double len = N.norm();
    const int n = mesh.faceSize(f);
    if (len > 0 && std::isfinite(len)) faceUnit[f] = N / len;
    const bool skip = zeroArea(mesh, f, N);
    for (int k = 0; k < n; ++k) {
      const int v = mesh.faceVertex(f, k), g = cornerGroup[mesh.faceOffsets[f] + k];
      vertexOf[g] = v;
      if (firstNonZero[g] < 0 && len > 0 && std::isfinite(len)) firstNonZero[g] = f;
      if (skip) continue;
      if (firstGood[g] < 0) firstGood[g] = f;
      if (mode == NormalMode::Area) {
        sum[g] += N;
        weight[g] += len;
        continue;
      }
      // Interior angle at the corner; reflex (> pi) where the corner turns against N.
      const Eigen::Vector3d& p = mesh.positions[v];
      const Eigen::Vector3d eNext = mesh.positions[mesh.faceVertex(f, k + 1)] - p;
      const Eigen::Vector3d ePrev = mesh.positions[mesh.faceVertex(f, k - 1)] - p;
      const Eigen::Vector3d c = eNext.cross(ePrev);
      double angle = std::atan2(c.norm(), eNext.dot(ePrev));
      if (c.dot(N) < 0) angle = 2 * std::numbers::pi - angle;
      sum[g] += angle * faceUnit[f];
      weight[g] += angle;
    }
  }

  std::vector<Eigen::Vector3d> normal(ng, Eigen::Vector3d::UnitZ());
  std::vector<char> reported(mesh.numVertices(), 0);
  for (int g = 0; g < ng; ++g) {
    if (vertexOf[g] < 0) continue;
    const double len = sum[g].norm();
    if (weight[g] > 0 && len > 1e-12 * weight[g] && std::isfinite(len)) {
      normal[g] = sum[g] / len;
      continue;
    }
    const int f = firstGood[g] >= 0 ? firstGood[g] : firstNonZero[g];
    if (f >= 0) normal[g] = faceUnit[f];  // else +z: every incident face has zero Newell
    if (!reported[vertexOf[g]]) fallbackVertices.push_back(vertexOf[g]);
    reported[vertexOf[g]] = 1;
  }
  std::sort(fallbackVertices.begin(), fallbackVertices.end());
  return normal;
}

/// Corner groups for weightedNormals: the vertex, except at the vertices that crease edges or
/// corner tags touch (touched[v] = 1 on return), where each smoothing sector (corners joined
/// across edges that are not creases; a corner vertex's corners all apart) is a group of its own.
std::vector<int32_t> creaseGroups(const PolygonMesh& mesh, const std::vector<int32_t>& twins, const CreaseSet& cs,
                                  std::vector<char>& touched, int& numGroups) {
  std::vector<char> corner(mesh.numVertices(), 0);
  touched.assign(mesh.numVertices(), 0);
  for (const auto& e : cs.edges) touched[e[0]] = touched[e[1]] = 1;
  for (int32_t v : cs.corners) touched[v] = corner[v] = 1;
  int sectors = 0;
  const std::vector<int32_t> sector = cornerSectors(
      mesh, twins,
      [&](int32_t a, int32_t, int32_t slot) {
        const int32_t v = mesh.faceVertices[a];
        const int f = slotFace(mesh.faceOffsets, slot);
        const int k = slot - mesh.faceOffsets[f];
        return !corner[v] && !isCrease(cs, mesh.faceVertex(f, k), mesh.faceVertex(f, k + 1));
      },
      &sectors);
  std::vector<int32_t> group(mesh.numCorners());
  for (int c = 0; c < mesh.numCorners(); ++c) {
    const int v = mesh.faceVertices[c];
    group[c] = touched[v] ? mesh.numVertices() + sector[c] : v;
  }
  numGroups = mesh.numVertices() + sectors;
  return group;
}

}  // namespace

std::vector<Eigen::Vector3d> cornerNormals(const PolygonMesh& mesh, NormalMode mode, NormalReport& report,
                                           const CreaseOptions& creaseOptions) {
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
  report.creases = findCreases(mesh, creaseOptions);
  const CreaseSet& cs = report.creases;
  const std::vector<int> first = firstCorners(mesh);
  std::vector<Eigen::Vector3d> out;
  const bool usable = !mesh.fileCornerNormals.empty() || mesh.fileNormals.size() == mesh.positions.size();
  const bool fileMode = mode == NormalMode::File || (mode == NormalMode::Auto && usable);
  std::vector<int32_t> twins;
  if (!cs.empty() || !mesh.fileCornerNormals.empty()) twins = computeSlotTwins(mesh);
  // Weighted normals per group of corners: one per vertex, and one per smoothing sector at the
  // vertices that marked creases touch (every mode but File); computed once, where needed.
  std::vector<char> touched(mesh.numVertices(), 0);
  std::vector<int32_t> sectorGroups;
  int numGroups = mesh.numVertices();
  if (!cs.empty() && mode != NormalMode::File) sectorGroups = creaseGroups(mesh, twins, cs, touched, numGroups);
  const std::vector<int32_t>& groups = sectorGroups.empty() ? mesh.faceVertices : sectorGroups;
  std::vector<Eigen::Vector3d> weighted;
  std::vector<int> weightedFallbacks;
  const auto weigh = [&] {
    const NormalMode weight = mode == NormalMode::Area ? NormalMode::Area : NormalMode::Angle;
    weighted = weightedNormals(mesh, weight, groups, numGroups, weightedFallbacks);
  };
  // the corners where keep(v) holds take their group's weighted normal
  const auto useWeighted = [&](auto keep) {
    for (int c = 0; c < mesh.numCorners(); ++c)
      if (keep(mesh.faceVertices[c])) out[c] = weighted[groups[c]];
    for (int v : weightedFallbacks)
      if (keep(v)) report.fallbackVertices.push_back(v);
  };
  const auto atCreases = [&](int v) { return touched[v] != 0; };
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
    } else if (report.splitVertices.empty() && cs.empty()) {
      report.source = NormalSource::FileFaceRefs;
      for (int c = 0; c < mesh.numCorners(); ++c) out[c] = out[first[mesh.faceVertices[c]]];  // first <= c
    } else if (!creaseOptions.normals) {
      // Split vertices (and crease sectors) take the angle-weighted normal; every other vertex
      // its first corner's.
      report.source = report.splitVertices.empty() ? NormalSource::FileFaceRefs : NormalSource::FileAndAngle;
      for (int c = 0; c < mesh.numCorners(); ++c) out[c] = out[first[mesh.faceVertices[c]]];  // first <= c
      weigh();
      useWeighted([&](int v) { return split[v] || touched[v]; });
    } else {
      // One file normal per smoothing sector: corners joined across edges where their file
      // normals agree; the sector takes its first corner's normal. Split vertices keep their
      // creases; the marked creases take angle-weighted sector normals.
      report.source = NormalSource::FileSectors;
      int count = 0;
      const std::vector<int32_t> sector = cornerSectors(
          mesh, twins,
          [&](int32_t a, int32_t b, int32_t) { return angleBetween(out[a], out[b]) <= kSameNormalAngle; }, &count);
      std::vector<int32_t> firstOf(count, -1);
      for (int c = 0; c < mesh.numCorners(); ++c)
        if (firstOf[sector[c]] < 0) firstOf[sector[c]] = c;
      for (int c = 0; c < mesh.numCorners(); ++c) out[c] = out[firstOf[sector[c]]];  // firstOf <= c
      if (!sectorGroups.empty()) {
        weigh();
        useWeighted(atCreases);
      }
    }
  } else if (fileMode) {
    out = fileNormals(mesh, true);
    report.source = NormalSource::FileVertexOrder;
    if (!sectorGroups.empty()) {
      weigh();
      useWeighted(atCreases);
    }
  } else {
    report.source = mode == NormalMode::Area ? NormalSource::Area : NormalSource::Angle;
    out.resize(mesh.numCorners());
    weigh();
    useWeighted([](int) { return true; });
  }
  std::sort(report.fallbackVertices.begin(), report.fallbackVertices.end());
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
    case NormalSource::FileSectors:
      out.push_back("the file's normals at " + std::to_string(fileVertices) + " vertices; one per smoothing sector at " +
                    nSplit + " vertices whose corners carry different file normals (creases)");
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
        (source == NormalSource::FileAndAngle
             ? "; auto used the angle-weighted normal there (--creases with normals, or --normals file, keeps them as "
               "creases)"
             : " (creases)"));
  }
  if (!creases.empty()) {
    std::string from;
    const auto add = [&](int n, const char* what) {
      if (n) from += std::string(from.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(creases.fromTags, "by tags");
    add(creases.fromGroups, "by smoothing groups");
    add(creases.fromAngle, "by the crease angle");
    add(static_cast<int>(creases.corners.size()), "corner tags");
    out.push_back("marked creases: " + std::to_string(creases.edges.size()) + " edges (" + from + ")" +
                  (creases.semiSharp ? "; " + std::to_string(creases.semiSharp) + " semi-sharp tags made sharp" : "") +
                  (mode == NormalMode::File ? "; not applied: --normals file uses the file's normals as given" : ""));
  }
  if (creaseCorners) {
    out.push_back("crease corners: " + std::to_string(creaseCorners) +
                  " (normal differs from another corner of the same vertex): each crease edge is one curve "
                  "shared by its two faces, with a tangent plane per side");
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
  std::vector<Eigen::Vector3d> out = cornerNormals(mesh, mode, report, CreaseOptions{});
  if (fallbackVertices) *fallbackVertices = std::move(report.fallbackVertices);
  return out;
}

}  // namespace sf
