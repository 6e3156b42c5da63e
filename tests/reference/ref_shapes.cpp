// SPDX-License-Identifier: Apache-2.0
#include "ref_shapes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>

namespace sf::ref {
namespace {

/// Order the vertices of a convex face of an origin-centred polytope counter-clockwise
/// seen from outside (outside = direction of the face centroid).
std::vector<int> orderCcw(const std::vector<Eigen::Vector3d>& P, std::vector<int> idx) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int i : idx) c += P[i];
  c /= static_cast<double>(idx.size());
  const Eigen::Vector3d nrm = c.normalized();
  const Eigen::Vector3d u = (P[idx[0]] - c).normalized();
  const Eigen::Vector3d w = nrm.cross(u);  // (u, w, nrm) right-handed
  auto angle = [&](int i) { return std::atan2((P[i] - c).dot(w), (P[i] - c).dot(u)); };
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return angle(a) < angle(b); });
  return idx;
}

void radialNormals(RefMesh& m) {
  m.normals.clear();
  for (const auto& p : m.positions) m.normals.push_back(p.normalized());
}

/// Uniform in [0, 1) from the raw (standardised) mt19937 output.
double uniform01(std::mt19937& g) { return g() / 4294967296.0; }

Eigen::Vector3d randomInBall(std::mt19937& g) {
  for (;;) {
    const Eigen::Vector3d v(2 * uniform01(g) - 1, 2 * uniform01(g) - 1, 2 * uniform01(g) - 1);
    if (v.squaredNorm() <= 1.0) return v;
  }
}

}  // namespace

RefMesh refUnitSphereCube() {
  RefMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(Eigen::Vector3d((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1) / std::sqrt(3.0));
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      std::vector<int> f;
      for (int i = 0; i < 8; ++i)
        if (m.positions[i][axis] * sign > 0) f.push_back(i);
      m.faces.push_back(orderCcw(m.positions, f));
    }
  radialNormals(m);
  return m;
}

RefMesh refIcosahedron() {
  RefMesh m;
  const double phi = std::numbers::phi;
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      m.positions.emplace_back(0, s1, s2 * phi);
      m.positions.emplace_back(s1, s2 * phi, 0);
      m.positions.emplace_back(s2 * phi, 0, s1);
    }
  for (auto& p : m.positions) p.normalize();
  const int nv = static_cast<int>(m.positions.size());
  // Faces: the triples whose three sides all have the (minimal) edge length.
  double edge = 1e9;  // the shortest distance between two vertices
  for (int a = 0; a < nv; ++a)
    for (int b = a + 1; b < nv; ++b) edge = std::min(edge, (m.positions[a] - m.positions[b]).norm());
  auto isEdge = [&](int a, int b) { return std::abs((m.positions[a] - m.positions[b]).norm() - edge) < 1e-9; };
  for (int a = 0; a < nv; ++a)
    for (int b = a + 1; b < nv; ++b)
      for (int c = b + 1; c < nv; ++c)
        if (isEdge(a, b) && isEdge(b, c) && isEdge(a, c)) m.faces.push_back(orderCcw(m.positions, {a, b, c}));
  radialNormals(m);
  return m;
}

RefMesh refDodecahedron() {
  // Dual of the icosahedron: a vertex per icosahedron face (its normalised centroid), a
  // pentagon per icosahedron vertex (the five faces around it).
  const RefMesh ico = refIcosahedron();
  RefMesh m;
  for (const auto& f : ico.faces)
    m.positions.push_back((ico.positions[f[0]] + ico.positions[f[1]] + ico.positions[f[2]]).normalized());
  for (int v = 0; v < static_cast<int>(ico.positions.size()); ++v) {
    std::vector<int> ring;
    for (int f = 0; f < static_cast<int>(ico.faces.size()); ++f)
      if (std::find(ico.faces[f].begin(), ico.faces[f].end(), v) != ico.faces[f].end()) ring.push_back(f);
    m.faces.push_back(orderCcw(m.positions, ring));
  }
  radialNormals(m);
  return m;
}

Eigen::Vector3d refTiltToward(const Eigen::Vector3d& n, const Eigen::Vector3d& dir, double deg) {
  const Eigen::Vector3d p = (dir - dir.dot(n) * n).normalized();
  const double a = deg * std::numbers::pi / 180.0;
  return (std::cos(a) * n + std::sin(a) * p).normalized();
}

RefMesh refJitteredPolytope(unsigned seed, int base, double jitter, double normalTiltDeg) {
  RefMesh m = base == 0 ? refUnitSphereCube() : refIcosahedron();
  std::mt19937 g(seed);
  for (auto& p : m.positions) p += jitter * randomInBall(g);
  m.normals.clear();
  for (const auto& p : m.positions) {
    const Eigen::Vector3d r = p.normalized();
    Eigen::Vector3d dir;
    do dir = randomInBall(g);
    while ((dir - dir.dot(r) * r).norm() < 0.1);
    m.normals.push_back(refTiltToward(r, dir, normalTiltDeg));
  }
  return m;
}

RefMesh refTwistedStrip() {
  RefMesh m;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      m.positions.emplace_back(i, j, 0);
      m.normals.emplace_back(0, 0, 1);
    }
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) m.faces.push_back({j * 3 + i, j * 3 + i + 1, (j + 1) * 3 + i + 1, (j + 1) * 3 + i});
  const double a = 75 * std::numbers::pi / 180, b = 60 * std::numbers::pi / 180;
  m.normals[4] = {std::sin(a), std::cos(a) * std::sin(b), std::cos(a) * std::cos(b)};
  m.normals[5] = {0, -std::sin(b), std::cos(b)};
  return m;
}

RefPatch refFacePatch(const RefMesh& m, int f, CrossTangent mode) {
  RefPatch p;
  for (int i : m.faces[f]) {
    p.V.push_back(m.positions[i]);
    p.N.push_back(m.normals[i]);
  }
  p.mode = mode;
  return p;
}

std::vector<std::vector<RefEdgeNeighbour>> refEdgeNeighbours(const RefMesh& m) {
  std::map<std::pair<int, int>, RefEdgeNeighbour> directed;
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) {
    const auto& F = m.faces[f];
    const int n = static_cast<int>(F.size());
    for (int k = 0; k < n; ++k) directed[{F[k], F[(k + 1) % n]}] = {f, k};
  }
  std::vector<std::vector<RefEdgeNeighbour>> out(m.faces.size());
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) {
    const auto& F = m.faces[f];
    const int n = static_cast<int>(F.size());
    for (int k = 0; k < n; ++k) {
      auto it = directed.find({F[(k + 1) % n], F[k]});
      out[f].push_back(it == directed.end() ? RefEdgeNeighbour{} : it->second);
    }
  }
  return out;
}

}  // namespace sf::ref
