// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/mesh/polygon_split.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <smoothforce/base/error.h>
#include <smoothforce/mesh/exact_predicates.h>
#include <smoothforce/mesh/mesh_intersect.h>
#include <smoothforce/mesh/normals.h>

namespace sf {

FoldRepairMode parseFoldRepairMode(const std::string& s) {
  if (s == "off") return FoldRepairMode::Off;
  if (s == "on" || s == "split") return FoldRepairMode::On;
  if (s == "search") return FoldRepairMode::Search;
  throw InputError("fold repair must be off, on or search, got '" + s + "'");
}

const char* toString(FoldRepairMode m) {
  return m == FoldRepairMode::Search ? "search" : m == FoldRepairMode::On ? "on" : "off";
}

namespace {

using Vec2 = Eigen::Vector2d;

/// Face f's corners on its Newell plane (about its centroid), counter-clockwise seen along the
/// Newell normal; false for a face without a plane (zero Newell vector or non-finite).
bool projectFace(const PolygonMesh& mesh, int f, std::vector<Vec2>& q, double* planarity = nullptr) {
  const Eigen::Vector3d nn = newellNormal(mesh, f);
  const double len = nn.norm();
  if (!(len > 0) || !std::isfinite(len)) return false;
  const Eigen::Vector3d n = nn / len;
  Eigen::Vector3d a = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  a = (a - n * n.dot(a)).normalized();
  const Eigen::Vector3d b = n.cross(a);  // a x b = n: the Newell orientation is counter-clockwise
  const int m = mesh.faceSize(f);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < m; ++k) c += mesh.positions[mesh.faceVertex(f, k)] / m;
  q.resize(m);
  double height = 0, diameter = 0;
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d d = mesh.positions[mesh.faceVertex(f, k)] - c;
    q[k] = {d.dot(a), d.dot(b)};
    height = std::max(height, std::fabs(d.dot(n)));
    for (int j = 0; j < k; ++j)
      diameter =
          std::max(diameter, (mesh.positions[mesh.faceVertex(f, k)] - mesh.positions[mesh.faceVertex(f, j)]).norm());
  }
  if (planarity) *planarity = diameter > 0 ? height / diameter : 0;
  return true;
}

/// Interior angle (radians, in [0, 2 pi)) at corner i of the counter-clockwise polygon idx.
double cornerAngle(const std::vector<Vec2>& q, const std::vector<int>& idx, size_t i) {
  const size_t m = idx.size();
  const Vec2 e1 = q[idx[(i + m - 1) % m]] - q[idx[i]], e2 = q[idx[(i + 1) % m]] - q[idx[i]];
  double a = std::atan2(e2.x() * e1.y() - e2.y() * e1.x(), e2.dot(e1));
  if (a < 0) a += 2 * std::numbers::pi;
  return a;
}

bool isBad(double angle, double straightDeg = kStraightCornerDeg) {
  return angle >= std::numbers::pi * (1 - straightDeg / 180);
}

bool hasBadCorner(const std::vector<Vec2>& q, const std::vector<int>& idx, double straightDeg = kStraightCornerDeg) {
  for (size_t i = 0; i < idx.size(); ++i)
    if (isBad(cornerAngle(q, idx, i), straightDeg)) return true;
  return false;
}

/// Closed segments pq and rs share a point (exact).
bool segmentsMeet(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s), o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  auto on = [](const Vec2& a, const Vec2& b, const Vec2& c) {  // c on segment ab, given collinear
    return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= c.y() &&
           c.y() <= std::max(a.y(), b.y());
  };
  return (o1 == 0 && on(p, q, r)) || (o2 == 0 && on(p, q, s)) || (o3 == 0 && on(r, s, p)) || (o4 == 0 && on(r, s, q));
}

/// The segment from corner i to corner j of the counter-clockwise polygon idx leaves i into the
/// polygon's interior (O'Rourke, Computational Geometry in C, InCone).
bool inCone(const std::vector<Vec2>& q, const std::vector<int>& idx, size_t i, size_t j) {
  const size_t m = idx.size();
  const Vec2 &a = q[idx[i]], &b = q[idx[j]], &a0 = q[idx[(i + m - 1) % m]], &a1 = q[idx[(i + 1) % m]];
  if (orient2d(a, a1, a0) >= 0) return orient2d(a, b, a0) > 0 && orient2d(b, a, a1) > 0;
  return !(orient2d(a, b, a1) >= 0 && orient2d(b, a, a0) >= 0);
}

/// Corners i and j of the simple polygon idx are joined by a diagonal: inside at both ends and
/// meeting no edge but at its two ends.
bool isDiagonal(const std::vector<Vec2>& q, const std::vector<int>& idx, size_t i, size_t j) {
  if (!inCone(q, idx, i, j) || !inCone(q, idx, j, i)) return false;
  const size_t m = idx.size();
  for (size_t k = 0; k < m; ++k) {
    const size_t k1 = (k + 1) % m;
    if (k == i || k == j || k1 == i || k1 == j) continue;
    if (segmentsMeet(q[idx[i]], q[idx[j]], q[idx[k]], q[idx[k1]])) return false;
  }
  return true;
}

/// Corners i..j (inclusive, cyclic) of idx.
std::vector<int> arc(const std::vector<int>& idx, size_t i, size_t j) {
  std::vector<int> out;
  for (size_t k = i;; k = (k + 1) % idx.size()) {
    out.push_back(idx[k]);
    if (k == j) break;
  }
  return out;
}

/// Cuts idx into pieces without a corner within kPieceStraightCornerDeg of straight where
/// diagonals allow; appends them to out. Returns false when a piece with a bad corner
/// (kStraightCornerDeg) could not be cut.
bool cut(const std::vector<Vec2>& q, const std::vector<int>& idx, std::vector<std::vector<int>>& out) {
  constexpr double D = kPieceStraightCornerDeg;
  if (idx.size() <= 3 || !hasBadCorner(q, idx, D)) {
    out.push_back(idx);
    return idx.size() <= 3 || !hasBadCorner(q, idx);
  }
  const size_t m = idx.size();
  const double minAngle = kCutMinAngleDeg * std::numbers::pi / 180;
  int bestGood = -1;
  bool bestWide = false;  // its smallest angle is at least minAngle
  double bestAngle = -1, bestLength = 0;
  size_t bi = 0, bj = 0;
  for (size_t i = 0; i < m; ++i) {
    if (!isBad(cornerAngle(q, idx, i), D)) continue;
    for (size_t j = 0; j < m; ++j) {
      if (j == i || j == (i + 1) % m || i == (j + 1) % m || !isDiagonal(q, idx, i, j)) continue;
      const std::vector<int> a = arc(idx, i, j), b = arc(idx, j, i);
      const int good = !hasBadCorner(q, a, D) + !hasBadCorner(q, b, D);
      // the four angles the cut makes: at its ends, in both pieces
      const double smallest = std::min(std::min(cornerAngle(q, a, 0), cornerAngle(q, a, a.size() - 1)),
                                       std::min(cornerAngle(q, b, 0), cornerAngle(q, b, b.size() - 1)));
      const double length = (q[idx[i]] - q[idx[j]]).norm();
      const bool wide = smallest >= minAngle;
      const bool better = good != bestGood ? good > bestGood
                          : wide != bestWide ? wide
                          : wide             ? length < bestLength
                                             : smallest > bestAngle;
      if (better) bestGood = good, bestWide = wide, bestAngle = smallest, bestLength = length, bi = i, bj = j;
    }
  }
  if (bestGood < 0) {
    out.push_back(idx);
    return !hasBadCorner(q, idx);
  }
  const bool a = cut(q, arc(idx, bi, bj), out);
  const bool b = cut(q, arc(idx, bj, bi), out);
  return a && b;
}

}  // namespace

bool isFlatFace(const PolygonMesh& mesh, int f) {
  std::vector<Vec2> q;
  double planarity = 0;
  return projectFace(mesh, f, q, &planarity) && planarity <= kFlatHeight;
}

std::vector<double> planarCornerAngles(const PolygonMesh& mesh, int f) {
  std::vector<Vec2> q;
  if (!projectFace(mesh, f, q)) return {};
  std::vector<int> idx(q.size());
  for (size_t k = 0; k < idx.size(); ++k) idx[k] = static_cast<int>(k);
  std::vector<double> out(q.size());
  for (size_t k = 0; k < q.size(); ++k) out[k] = cornerAngle(q, idx, k);
  return out;
}

PolygonSplitReport splitBadCorners(PolygonMesh& mesh, std::vector<Eigen::Vector3d>* cornerNormals) {
  PolygonSplitReport report;
  const int nf = mesh.numFaces();
  const std::vector<int> crossing = findSelfCrossingFaces(mesh);
  if (cornerNormals && static_cast<int>(cornerNormals->size()) != mesh.numCorners())
    throw std::invalid_argument("splitBadCorners: need one normal per corner");
  FaceRewrite out(mesh, cornerNormals);
  std::vector<Vec2> q;
  for (int f = 0; f < nf; ++f) {
    const int m = mesh.faceSize(f), first = mesh.faceOffsets[f];
    std::vector<int> idx(m);
    for (int k = 0; k < m; ++k) idx[k] = k;
    std::vector<std::vector<int>> pieces;
    bool whole = true;
    double planarity = 0;
    if (m > 3 && projectFace(mesh, f, q, &planarity) && planarity <= kFlatHeight && hasBadCorner(q, idx)) {
      bool degenerate = m > kMaxSplitCorners || std::binary_search(crossing.begin(), crossing.end(), f);
      for (int k = 0; k < m && !degenerate; ++k) degenerate = q[k] == q[(k + 1) % m];
      if (!degenerate) {
        const bool done = cut(q, idx, pieces);
        whole = pieces.size() <= 1;
        if (!done) report.unsplitFaces.push_back(f);
      } else {
        report.unsplitFaces.push_back(f);
      }
    }
    if (whole)
      pieces.assign(1, idx);
    else
      report.splitFaces.push_back(f), report.pieces += static_cast<int>(pieces.size());
    for (const std::vector<int>& piece : pieces) {
      for (int k : piece) out.copyCorner(first + k);
      out.closeFace(f);
    }
  }
  out.commit(mesh, cornerNormals);
  return report;
}

FaceRewrite::FaceRewrite(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>* cornerNormals)
    : mesh_(mesh),
      normalsIn_(cornerNormals),
      fileCorner_(static_cast<int>(mesh.fileCornerNormals.size()) == mesh.numCorners()),
      groups_(static_cast<int>(mesh.faceSmoothingGroups.size()) == mesh.numFaces()),
      sourced_(static_cast<int>(mesh.faceSource.size()) == mesh.numFaces()) {
  if (cornerNormals && static_cast<int>(cornerNormals->size()) != mesh.numCorners())
    throw std::invalid_argument("FaceRewrite: need one normal per corner");
}

void FaceRewrite::copyCorner(int slot) {
  out_.faceVertices.push_back(mesh_.faceVertices[slot]);
  if (fileCorner_) out_.fileCornerNormals.push_back(mesh_.fileCornerNormals[slot]);
  if (normalsIn_) normals_.push_back((*normalsIn_)[slot]);
}

void FaceRewrite::addCorner(int vertex, const Eigen::Vector3d& normal) {
  out_.faceVertices.push_back(vertex);
  if (fileCorner_) out_.fileCornerNormals.push_back(normal);
  if (normalsIn_) normals_.push_back(normal);
}

void FaceRewrite::closeFace(int f) {
  out_.faceOffsets.push_back(static_cast<int32_t>(out_.faceVertices.size()));
  if (groups_) out_.faceSmoothingGroups.push_back(mesh_.faceSmoothingGroups[f]);
  out_.faceSource.push_back(sourced_ ? mesh_.faceSource[f] : f);
}

void FaceRewrite::commit(PolygonMesh& mesh, std::vector<Eigen::Vector3d>* cornerNormals) {
  mesh.faceOffsets = std::move(out_.faceOffsets);
  mesh.faceVertices = std::move(out_.faceVertices);
  if (fileCorner_) mesh.fileCornerNormals = std::move(out_.fileCornerNormals);
  if (groups_) mesh.faceSmoothingGroups = std::move(out_.faceSmoothingGroups);
  mesh.faceSource = std::move(out_.faceSource);
  if (cornerNormals && normalsIn_) *cornerNormals = std::move(normals_);
}

}  // namespace sf
