// SPDX-License-Identifier: Apache-2.0
// Helpers for the patch tests: caches from in-code shapes or files, G1 measurement.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include "gp_config.h"  // GP_* status bits and record layout
#include "ref_shapes.h"
#include "shared_mesh_files.h"

namespace sf::test {

inline PolygonMesh toPolygonMesh(const ref::RefMesh& m) {
  PolygonMesh pm;
  pm.positions = m.positions;
  for (const auto& f : m.faces) pm.addFace(std::vector<int32_t>(f.begin(), f.end()));
  return pm;
}

/// A plate [-1, 1]^2 x [0, h] with a round hole of radius r through it, its rim a polygon of m
/// vertices: top and bottom fanned from each rim segment to the nearest corner of the square (with
/// a triangle where the fan turns a corner), the outer sides quads cut into two triangles, the
/// hole's wall m quads cut likewise. The top and bottom triangles at the rim have a curved edge
/// under a crease angle below the wall's (the crease curve through the rim's vertices).
inline std::string holedPlateObj(int m, double r, double h) {
  std::string s;
  int count = 0;
  auto vertex = [&](double x, double y, double z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", x, y, z);
    s += buf;
    return ++count;
  };
  const double pi = std::acos(-1.0);
  int square[2][4], rim[2][64];
  for (int l = 0; l < 2; ++l) {
    for (int q = 0; q < 4; ++q)  // corner q at 45 + 90 q degrees
      square[l][q] = vertex(q == 0 || q == 3 ? 1 : -1, q < 2 ? 1 : -1, l * h);
    for (int i = 0; i < m; ++i) rim[l][i] = vertex(r * std::cos(2 * pi * i / m), r * std::sin(2 * pi * i / m), l * h);
  }
  auto face = [&](std::vector<int> f, bool flip) {
    if (flip) std::reverse(f.begin(), f.end());
    s += "f";
    for (int v : f) s += " " + std::to_string(v);
    s += "\n";
  };
  // the square's corner nearest rim vertex i
  auto cornerOf = [&](int i) { return int(std::lround((360.0 * i / m - 45) / 90)) % 4; };
  for (int l = 0; l < 2; ++l)
    for (int i = 0; i < m; ++i) {
      const int j = (i + 1) % m, q = (cornerOf(i) + 4) % 4, q2 = (cornerOf(j) + 4) % 4;
      face({rim[l][i], rim[l][j], square[l][q]}, l == 0);
      if (q2 != q) face({rim[l][j], square[l][q2], square[l][q]}, l == 0);
    }
  for (int q = 0; q < 4; ++q) {  // outer sides, facing out
    const int n = (q + 1) % 4;
    face({square[0][q], square[1][n], square[0][n]}, false);
    face({square[0][q], square[1][q], square[1][n]}, false);
  }
  for (int i = 0; i < m; ++i) {  // the hole's wall, facing the axis
    const int j = (i + 1) % m;
    face({rim[0][i], rim[0][j], rim[1][j]}, false);
    face({rim[0][i], rim[1][j], rim[1][i]}, false);
  }
  return s;
}

/// Whether a face's records (n x GP_E_NFIELDS, record-major) have a curved edge: an end tangent
/// off its edge's chord by more than `relative` times the chord's length.
inline bool hasCurvedEdge(int n, const double* recs, double relative) {
  for (int k = 0; k < n; ++k) {
    const double* r = recs + k * GP_E_NFIELDS;
    const Eigen::Vector3d chord = Eigen::Vector3d(r + GP_E_V1) - Eigen::Vector3d(r + GP_E_V0);
    if ((Eigen::Vector3d(r + GP_E_M0) - chord).norm() > relative * chord.norm() ||
        (Eigen::Vector3d(r + GP_E_M1) - chord).norm() > relative * chord.norm())
      return true;
  }
  return false;
}

/// A cache built on the CPU from an in-code shape, using the shape's vertex normals.
inline PatchCache cacheFromShape(const ref::RefMesh& m, CrossTangentMode mode = CrossTangentMode::Corrected,
                                 Precision precision = Precision::Double, Backend backend = Backend::Serial) {
  const PolygonMesh pm = toPolygonMesh(m);
  std::vector<Eigen::Vector3d> cn;
  for (int v : pm.faceVertices) cn.push_back(m.normals[v]);
  PatchOptions o;
  o.crossTangent = mode;
  o.precision = precision;
  o.foldRepair = FoldRepairMode::Off;  // no mesh pipeline, so nothing is cut: the plain format 1 cache
  PatchCache c = preparePatchCache(pm, cn, o, 0);
  constructPatches(c, backend);
  return c;
}

/// A cache built from a mesh file with default options (angle-weighted or file normals).
inline PatchCache cacheFromFile(const std::string& path, CrossTangentMode mode = CrossTangentMode::Corrected,
                                Precision precision = Precision::Double) {
  PatchOptions o;
  o.crossTangent = mode;
  o.precision = precision;
  return buildPatchCache(loadMesh(path, o), o, Backend::Tbb);
}

/// Whether the status `on` of a face the default construction built matches `off`, the same face's
/// with the same records under the design page's construction (FoldRepairMode::Off): equal, but
/// where `on` marks the face GP_ST_AFFINE (a flat triangle with straight edges evaluated as its
/// affine map, markAffineTriangles), whose fold and bulge bits are the affine map's (never a fold).
inline bool sameStatusAsDesign(uint32_t on, uint32_t off) {
  if (!(on & GP_ST_AFFINE)) return on == off;
  const uint32_t quality = GP_ST_FOLD | GP_ST_BULGE;
  return (on & ~(GP_ST_AFFINE | quality)) == (off & ~quality) && !(on & GP_ST_FOLD);
}

/// A built cache as a skeleton of itself: the same mesh, normals and options, no patch data and
/// no status (lazy construction builds the patches, lazy_patches.h).
inline PatchCache skeletonOf(const PatchCache& built) {
  PatchCache s = built;
  s.edgeDataD.clear();
  s.edgeDataF.clear();
  std::fill(s.faceStatus.begin(), s.faceStatus.end(), 0u);
  return s;
}

/// The same mesh as a skeleton (no patch built; lazy construction, lazy_patches.h).
inline PatchCache skeletonFromFile(const std::string& path, Precision precision = Precision::Double) {
  PatchOptions o;
  o.precision = precision;
  return preparePatchSkeleton(loadMesh(path, o), o);
}


/// One flat unit quad in z = 0 with normals +z: an open mesh, every edge a boundary edge.
inline PatchCache flatQuadCache() {
  ref::RefMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2, 3}};
  m.normals.assign(4, Eigen::Vector3d::UnitZ());
  return cacheFromShape(m);
}

/// On a quad mesh: the face two patches away from face 0, across its edge 0 and then across
/// the opposite edge of that neighbour (refinement from face 0 crosses two edges by Eq. 15);
/// -1 where an edge on the way is a boundary.
inline int faceTwoAcross(const PatchCache& c) {
  const int s0 = c.slotTwin[c.faceOffsets[0] + 0];
  if (s0 < 0) return -1;
  const int f1 = slotFace(c.faceOffsets, s0), k1 = (s0 - c.faceOffsets[f1] + 2) % 4;
  const int s1 = c.slotTwin[c.faceOffsets[f1] + k1];
  return s1 < 0 ? -1 : slotFace(c.faceOffsets, s1);
}

/// Domain point at parameter s along domain edge k, moved `delta` inward.
inline Eigen::Vector2d edgePoint(int n, int k, double s, double delta) {
  const Eigen::Vector2d a = domainCorner(n, k), b = domainCorner(n, (k + 1) % n);
  const Eigen::Vector2d p = a + s * (b - a);
  const double ang = (2 * k + 1) * M_PI / n;
  return p - delta * Eigen::Vector2d(std::cos(ang), std::sin(ang));
}

/// Largest tangent-plane angle arccos|n0.n1| (radians) and position gap between the two
/// patches of every manifold shared edge, at points `delta` inside both domains, at
/// edge parameters 0.1 .. 0.9.
struct G1Stats {
  double maxAngle = 0, maxGap = 0;
  int edges = 0;
  int worstFace = -1;
};
inline G1Stats measureG1(const PatchCache& c, double delta, int samples = 9) {
  G1Stats st;
  for (int s = 0; s < c.numSlots(); ++s) {
    const int t = c.slotTwin[s];
    if (t < s) continue;  // boundary, non-manifold, or seen from the other side
    const int f = slotFace(c.faceOffsets, s), g = slotFace(c.faceOffsets, t);
    const int k = s - c.faceOffsets[f], i = t - c.faceOffsets[g];
    ++st.edges;
    for (int j = 1; j <= samples; ++j) {
      const double u = double(j) / (samples + 1);
      const Eigen::Vector2d xf = edgePoint(c.faceSize(f), k, u, delta);
      const Eigen::Vector2d xg = edgePoint(c.faceSize(g), i, 1 - u, delta);
      const PatchPoint pf = evaluatePatch(c, f, xf.x(), xf.y());
      const PatchPoint pg = evaluatePatch(c, g, xg.x(), xg.y());
      const double ang = std::acos(std::min(1.0, std::abs(pf.normal.dot(pg.normal))));
      if (ang > st.maxAngle) {
        st.maxAngle = ang;
        st.worstFace = f;
      }
      st.maxGap = std::max(st.maxGap, (pf.pos - pg.pos).norm());
    }
  }
  return st;
}

/// Face f's edge records (every field, in the cache's precision), status and bulge, bit for bit.
inline bool samePatch(const PatchCache& a, const PatchCache& b, int f) {
  const size_t C = a.faceVertices.size();
  for (int s = a.faceOffsets[f]; s < a.faceOffsets[f + 1]; ++s)
    for (size_t i = 0; i < GP_E_NFIELDS; ++i) {
      const bool same = a.options.precision == Precision::Double
                            ? std::memcmp(&a.edgeDataD[i * C + s], &b.edgeDataD[i * C + s], sizeof(double)) == 0
                            : std::memcmp(&a.edgeDataF[i * C + s], &b.edgeDataF[i * C + s], sizeof(float)) == 0;
      if (!same) return false;
    }
  return a.faceStatus[f] == b.faceStatus[f] && std::memcmp(&a.faceBulge[f], &b.faceBulge[f], sizeof(float)) == 0;
}

/// True when a and b give face f's edge curves the same end tangents (PatchCache::edgeTangents,
/// an empty array giving none).
inline bool sameEndTangents(const PatchCache& a, const PatchCache& b, int f) {
  for (size_t i = 6 * size_t(a.faceOffsets[f]); i < 6 * size_t(a.faceOffsets[f + 1]); ++i)
    if ((a.edgeTangents.empty() ? 0.0 : a.edgeTangents[i]) != (b.edgeTangents.empty() ? 0.0 : b.edgeTangents[i]))
      return false;
  return true;
}

}  // namespace sf::test
