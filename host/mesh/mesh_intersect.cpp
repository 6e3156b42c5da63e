// SPDX-License-Identifier: Apache-2.0
// Polygons that intersect each other (triangulated, a box hierarchy, an exact triangle test)
// and polygons whose projected outline crosses itself.
#include <smoothforce/mesh/mesh_intersect.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include <smoothforce/mesh/exact_predicates.h>
#include <smoothforce/mesh/mesh_check.h>

namespace sf {
namespace {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// Faces up to this many corners may be ear-clipped (quadratic or worse); larger ones are fanned.
constexpr int kMaxEarClipCorners = 256;

/// Centroid, Newell normal (not normalised) and an in-plane frame of face f, and its corners
/// projected on that frame about the centroid.
struct FaceFrame {
  Vec3 centroid = Vec3::Zero(), normal = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitY();
  std::vector<Vec2> q;
  bool flat = true;  ///< zero Newell normal: no plane
};

FaceFrame faceFrame(const PolygonMesh& m, int f) {
  FaceFrame fr;
  const int n = m.faceSize(f);
  for (int k = 0; k < n; ++k) fr.centroid += m.positions[m.faceVertex(f, k)];
  fr.centroid /= n;
  for (int k = 0; k < n; ++k)
    fr.normal +=
        (m.positions[m.faceVertex(f, k)] - fr.centroid).cross(m.positions[m.faceVertex(f, k + 1)] - fr.centroid);
  const double len = fr.normal.norm();
  fr.flat = !(len > 0) || !std::isfinite(len);
  if (!fr.flat) {
    const Vec3 nz = fr.normal / len;
    const Vec3 a = std::abs(nz.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    fr.u = (a - a.dot(nz) * nz).normalized();
    fr.v = nz.cross(fr.u);
  }
  fr.q.resize(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 d = m.positions[m.faceVertex(f, k)] - fr.centroid;
    fr.q[k] = {d.dot(fr.u), d.dot(fr.v)};
  }
  return fr;
}

/// p lies in the closed triangle (a, b, c), which turns counter-clockwise.
bool inClosedTriangle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& p) {
  return orient2d(a, b, p) >= 0 && orient2d(b, c, p) >= 0 && orient2d(c, a, p) >= 0;
}

/// Ear clipping of the counter-clockwise outline q; appends corner-index triangles. False when
/// no ear is left (the outline crosses itself or turns clockwise).
bool earClip(const std::vector<Vec2>& q, std::vector<std::array<int, 3>>& out) {
  std::vector<int> rest(q.size());
  std::iota(rest.begin(), rest.end(), 0);
  while (rest.size() > 3) {
    const int n = static_cast<int>(rest.size());
    int ear = -1, flat = -1;
    for (int i = 0; i < n && ear < 0; ++i) {
      const int a = rest[(i + n - 1) % n], b = rest[i], c = rest[(i + 1) % n];
      const int turn = orient2d(q[a], q[b], q[c]);
      if (turn == 0 && flat < 0) flat = i;
      if (turn <= 0) continue;
      bool empty = true;
      for (int j = 0; j < n && empty; ++j) {
        const int p = rest[j];
        if (p != a && p != b && p != c && inClosedTriangle(q[a], q[b], q[c], q[p])) empty = false;
      }
      if (empty) ear = i;
    }
    if (ear < 0) ear = flat;  // a corner on a straight stretch of the outline: a zero-area triangle
    if (ear < 0) return false;
    out.push_back({rest[(ear + n - 1) % n], rest[ear], rest[(ear + 1) % n]});
    rest.erase(rest.begin() + ear);
  }
  out.push_back({rest[0], rest[1], rest[2]});
  return true;
}

/// The three corners are exactly collinear (every coordinate projection collinear).
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return orient2d({a.x(), a.y()}, {b.x(), b.y()}, {c.x(), c.y()}) == 0 &&
         orient2d({a.y(), a.z()}, {b.y(), b.z()}, {c.y(), c.z()}) == 0 &&
         orient2d({a.z(), a.x()}, {b.z(), b.x()}, {c.z(), c.x()}) == 0;
}

/// Closed segments [a, b] and [c, d] share a point (exact).
bool segmentsMeet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d), o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  const auto within = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // r on line pq: inside the segment?
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) && std::min(p.y(), q.y()) <= r.y() &&
           r.y() <= std::max(p.y(), q.y());
  };
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}

/// Closed non-degenerate 2D triangles (either orientation) share a point (exact).
bool trianglesMeet2d(const Vec2 a[3], const Vec2 b[3]) {
  const auto inside = [](const Vec2 t[3], const Vec2& p) {
    const int s0 = orient2d(t[0], t[1], p), s1 = orient2d(t[1], t[2], p), s2 = orient2d(t[2], t[0], p);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
  };
  for (int i = 0; i < 3; ++i) {
    if (inside(b, a[i]) || inside(a, b[i])) return true;
    for (int j = 0; j < 3; ++j)
      if (segmentsMeet(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])) return true;
  }
  return false;
}

/// Coplanar triangles: projected on the coordinate plane in which p does not degenerate (the
/// plane's normal has a non-zero component there, so q does not either; the projection is an
/// affine bijection of the common plane and keeps every incidence).
bool coplanarTrianglesMeet(const Vec3 p[3], const Vec3 q[3]) {
  for (int axis = 0; axis < 3; ++axis) {
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const Vec2 a[3] = {{p[0][i], p[0][j]}, {p[1][i], p[1][j]}, {p[2][i], p[2][j]}};
    if (orient2d(a[0], a[1], a[2]) == 0) continue;
    const Vec2 b[3] = {{q[0][i], q[0][j]}, {q[1][i], q[1][j]}, {q[2][i], q[2][j]}};
    return trianglesMeet2d(a, b);
  }
  return false;  // p is degenerate: not a triangle this test takes
}

/// Guigue and Devillers' interval test once p1 is alone on its side of q's plane and p2 alone
/// on its side of p's plane (their CHECK_MIN_MAX).
bool checkMinMax(const Vec3& p1, const Vec3& q1, const Vec3& r1, const Vec3& p2, const Vec3& q2, const Vec3& r2) {
  if (orient3d(q2, p2, p1, q1) > 0) return false;
  if (orient3d(r2, p2, r1, p1) > 0) return false;
  return true;
}

/// Their TRI_TRI_3D: q's vertices permuted into the canonical form.
bool triTri3d(const Vec3& p1, const Vec3& q1, const Vec3& r1, const Vec3& p2, const Vec3& q2, const Vec3& r2, int dp2,
              int dq2, int dr2, const Vec3 P[3], const Vec3 Q[3]) {
  if (dp2 > 0) {
    if (dq2 > 0) return checkMinMax(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return checkMinMax(p1, r1, q1, q2, r2, p2);
    return checkMinMax(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0) {
    if (dq2 < 0) return checkMinMax(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0) return checkMinMax(p1, q1, r1, q2, r2, p2);
    return checkMinMax(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0) {
    if (dr2 >= 0) return checkMinMax(p1, r1, q1, q2, r2, p2);
    return checkMinMax(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0) {
    if (dr2 > 0) return checkMinMax(p1, r1, q1, p2, q2, r2);
    return checkMinMax(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0) return checkMinMax(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0) return checkMinMax(p1, r1, q1, r2, p2, q2);
  return coplanarTrianglesMeet(P, Q);
}

struct Box {
  Vec3 lo, hi;
  bool overlaps(const Box& o) const {
    return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y() && lo.z() <= o.hi.z() &&
           o.lo.z() <= hi.z();
  }
};

/// A bounding-box hierarchy over items (median split on the longer centroid extent).
class BoxTree {
 public:
  explicit BoxTree(const std::vector<Box>& boxes) : boxes_(boxes), order_(boxes.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    if (boxes.empty()) return;
    nodes_.emplace_back();
    build(0, 0, static_cast<int>(boxes.size()));
  }

  /// Calls visit(j) for every item j whose box overlaps `box` (closed).
  template <class Visit>
  void query(const Box& box, Visit&& visit) const {
    if (nodes_.empty()) return;
    int stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!n.box.overlaps(box)) continue;
      if (n.count > 0) {
        for (int i = n.first; i < n.first + n.count; ++i)
          if (boxes_[order_[i]].overlaps(box)) visit(order_[i]);
      } else {
        stack[top++] = n.first;
        stack[top++] = n.first + 1;
      }
    }
  }

 private:
  struct Node {
    Box box;
    int first = 0, count = 0;  ///< leaf: items order_[first, first + count); inner: children first, first + 1
  };
  static constexpr int kLeaf = 4;

  /// Fills node `id` with the items order_[begin, end); an inner node's two children are
  /// appended next to each other.
  void build(int id, int begin, int end) {
    Box box = boxes_[order_[begin]];
    Vec3 cmin = box.lo + box.hi, cmax = cmin;
    for (int i = begin; i < end; ++i) {
      const Box& b = boxes_[order_[i]];
      box.lo = box.lo.cwiseMin(b.lo);
      box.hi = box.hi.cwiseMax(b.hi);
      cmin = cmin.cwiseMin(b.lo + b.hi);
      cmax = cmax.cwiseMax(b.lo + b.hi);
    }
    nodes_[id].box = box;
    if (end - begin <= kLeaf) {
      nodes_[id].first = begin;
      nodes_[id].count = end - begin;
      return;
    }
    int axis = 0;
    (cmax - cmin).maxCoeff(&axis);
    const int mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
      return boxes_[a].lo[axis] + boxes_[a].hi[axis] < boxes_[b].lo[axis] + boxes_[b].hi[axis];
    });
    const int left = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[id].first = left;
    nodes_[id].count = 0;
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  const std::vector<Box>& boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

/// Per face, its sorted welded vertex ids (compressed rows).
struct FaceVertexSets {
  std::vector<int32_t> offsets{0}, ids;
  FaceVertexSets(const PolygonMesh& m, const std::vector<int32_t>& welded) {
    for (int f = 0; f < m.numFaces(); ++f) {
      const size_t first = ids.size();
      for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) ids.push_back(welded[m.faceVertices[c]]);
      std::sort(ids.begin() + first, ids.end());
      ids.erase(std::unique(ids.begin() + first, ids.end()), ids.end());
      offsets.push_back(static_cast<int32_t>(ids.size()));
    }
  }
  bool share(int a, int b) const {
    const int32_t *i = &ids[0] + offsets[a], *ie = &ids[0] + offsets[a + 1];
    const int32_t *j = &ids[0] + offsets[b], *je = &ids[0] + offsets[b + 1];
    while (i < ie && j < je) {
      if (*i == *j) return true;
      if (*i < *j)
        ++i;
      else
        ++j;
    }
    return false;
  }
};

}  // namespace

MeshTriangles polygonTriangles(const PolygonMesh& m) {
  MeshTriangles t;
  t.points = m.positions;
  t.faceArea.assign(m.numFaces(), 0.0);
  std::vector<std::array<int, 3>> ears;
  const auto add = [&](int f, int32_t a, int32_t b, int32_t c) {
    const Vec3 &A = t.points[a], &B = t.points[b], &C = t.points[c];
    if (collinear(A, B, C)) return;
    t.tri.push_back({a, b, c});
    t.triFace.push_back(f);
    t.faceArea[f] += 0.5 * (B - A).cross(C - A).norm();
  };
  for (int f = 0; f < m.numFaces(); ++f) {
    const int n = m.faceSize(f);
    if (n < 3) continue;
    if (n == 3) {
      add(f, m.faceVertex(f, 0), m.faceVertex(f, 1), m.faceVertex(f, 2));
      continue;
    }
    const FaceFrame fr = faceFrame(m, f);
    bool star = !fr.flat;
    for (int k = 0; k < n && star; ++k) star = orient2d(Vec2::Zero(), fr.q[k], fr.q[(k + 1) % n]) > 0;
    ears.clear();
    if (!star && !fr.flat && n <= kMaxEarClipCorners && earClip(fr.q, ears)) {
      for (const auto& e : ears) add(f, m.faceVertex(f, e[0]), m.faceVertex(f, e[1]), m.faceVertex(f, e[2]));
      continue;
    }
    const auto c = static_cast<int32_t>(t.points.size());
    t.points.push_back(fr.centroid);
    for (int k = 0; k < n; ++k) add(f, c, m.faceVertex(f, k), m.faceVertex(f, k + 1));
  }
  return t;
}

bool trianglesIntersect(const Vec3 p[3], const Vec3 q[3]) noexcept {
  const Vec3 &p1 = p[0], &q1 = p[1], &r1 = p[2], &p2 = q[0], &q2 = q[1], &r2 = q[2];
  const int dp1 = orient3d(p1, p2, q2, r2), dq1 = orient3d(q1, p2, q2, r2), dr1 = orient3d(r1, p2, q2, r2);
  if (dp1 * dq1 > 0 && dp1 * dr1 > 0) return false;  // p strictly on one side of q's plane
  const int dp2 = orient3d(p2, p1, q1, r1), dq2 = orient3d(q2, p1, q1, r1), dr2 = orient3d(r2, p1, q1, r1);
  if (dp2 * dq2 > 0 && dp2 * dr2 > 0) return false;
  // p's vertices permuted so that p1 is alone on its side (Guigue and Devillers, 2003)
  if (dp1 > 0) {
    if (dq1 > 0) return triTri3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, p, q);
    if (dr1 > 0) return triTri3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, p, q);
    return triTri3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, p, q);
  }
  if (dp1 < 0) {
    if (dq1 < 0) return triTri3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, p, q);
    if (dr1 < 0) return triTri3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, p, q);
    return triTri3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, p, q);
  }
  if (dq1 < 0) {
    if (dr1 >= 0) return triTri3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, p, q);
    return triTri3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, p, q);
  }
  if (dq1 > 0) {
    if (dr1 > 0) return triTri3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, p, q);
    return triTri3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, p, q);
  }
  if (dr1 > 0) return triTri3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, p, q);
  if (dr1 < 0) return triTri3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, p, q);
  return coplanarTrianglesMeet(p, q);
}

std::vector<int32_t> weldedVertexIds(const PolygonMesh& m) {
  const int nv = m.numVertices();
  std::vector<int32_t> order(nv), welded(nv);
  std::iota(order.begin(), order.end(), 0);
  const auto less = [&](int a, int b) {
    const Vec3 &p = m.positions[a], &q = m.positions[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (int i = 0; i < nv;) {
    int j = i;
    while (j < nv && m.positions[order[j]] == m.positions[order[i]]) welded[order[j++]] = order[i];
    i = j;
  }
  return welded;
}

bool facesShareVertex(const PolygonMesh& m, const std::vector<int32_t>& welded, int a, int b) {
  for (int i = m.faceOffsets[a]; i < m.faceOffsets[a + 1]; ++i)
    for (int j = m.faceOffsets[b]; j < m.faceOffsets[b + 1]; ++j)
      if (welded[m.faceVertices[i]] == welded[m.faceVertices[j]]) return true;
  return false;
}

std::vector<IntersectingPair> findIntersectingFaces(const PolygonMesh& m) {
  return findIntersectingFaces(m, polygonTriangles(m));
}

std::vector<IntersectingPair> findIntersectingFaces(const PolygonMesh& m, const MeshTriangles& t) {
  const int nt = static_cast<int>(t.tri.size());
  // Copies (triangles on the same three positions: duplicate faces, or one face repeated many
  // times) are tested once: the hierarchy holds the first of each group, and an intersection
  // found is expanded to the copies' faces. Without this, n copies of one face cost n^2 tests.
  using Key = std::array<double, 9>;  // the corners' coordinates, corners in lexicographic order
  std::vector<Key> key(nt);
  for (int i = 0; i < nt; ++i) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = t.points[t.tri[i][k]];
      c[k] = {v.x(), v.y(), v.z()};
    }
    std::sort(c.begin(), c.end());
    for (int k = 0; k < 9; ++k) key[i][k] = c[k / 3][k % 3];
  }
  std::vector<int32_t> order(nt);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
  std::vector<int32_t> groupOffsets{0}, members;  // group g: triangles members[groupOffsets[g] ..]
  for (int i = 0; i < nt;) {
    int j = i;
    while (j < nt && key[order[j]] == key[order[i]]) members.push_back(order[j++]);
    groupOffsets.push_back(static_cast<int32_t>(members.size()));
    i = j;
  }
  const int ng = static_cast<int>(groupOffsets.size()) - 1;
  std::vector<Box> boxes(ng);
  for (int g = 0; g < ng; ++g) {
    const Key& c = key[members[groupOffsets[g]]];
    const Vec3 a(c[0], c[1], c[2]), b(c[3], c[4], c[5]), d(c[6], c[7], c[8]);
    boxes[g] = {a.cwiseMin(b).cwiseMin(d), a.cwiseMax(b).cwiseMax(d)};
  }
  const BoxTree tree(boxes);
  const FaceVertexSets sets(m, weldedVertexIds(m));
  std::vector<std::array<int, 2>> found;
  const auto triangle = [&](int i, Vec3 out[3]) {
    for (int k = 0; k < 3; ++k) out[k] = t.points[t.tri[i][k]];
  };
  for (int g = 0; g < ng; ++g) {
    const int ti = members[groupOffsets[g]], fi = t.triFace[ti];
    const bool single = groupOffsets[g + 1] - groupOffsets[g] == 1;
    Vec3 p[3], q[3];
    triangle(ti, p);
    tree.query(boxes[g], [&](int h) {
      if (h <= g) return;
      const int tj = members[groupOffsets[h]], fj = t.triFace[tj];
      if (single && groupOffsets[h + 1] - groupOffsets[h] == 1) {  // the common case: neighbours skipped first
        if (fj == fi) return;
        const std::array<int, 2> pair{std::min(fi, fj), std::max(fi, fj)};
        if (!found.empty() && found.back() == pair) return;  // this face pair is already known
        if (sets.share(fi, fj)) return;
        triangle(tj, q);
        if (trianglesIntersect(p, q)) found.push_back(pair);
        return;
      }
      triangle(tj, q);
      if (!trianglesIntersect(p, q)) return;
      for (int a = groupOffsets[g]; a < groupOffsets[g + 1]; ++a)
        for (int b = groupOffsets[h]; b < groupOffsets[h + 1]; ++b) {
          const int fa = t.triFace[members[a]], fb = t.triFace[members[b]];
          if (fa != fb && !sets.share(fa, fb)) found.push_back({std::min(fa, fb), std::max(fa, fb)});
        }
    });
  }
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  std::vector<IntersectingPair> out;
  out.reserve(found.size());
  for (const auto& [a, b] : found) out.push_back({a, b, t.faceArea[a], t.faceArea[b]});
  return out;
}

std::vector<int> findSelfCrossingFaces(const PolygonMesh& m, int* unchecked) {
  std::vector<int> out;
  int skipped = 0;
  for (int f = 0; f < m.numFaces(); ++f) {
    const int n = m.faceSize(f);
    if (n < 4 || isDegenerateFace(m, f)) continue;  // a non-degenerate triangle is simple
    if (n > kMaxSelfCrossingCorners) {
      ++skipped;
      continue;
    }
    const FaceFrame fr = faceFrame(m, f);
    const std::vector<Vec2>& q = fr.q;
    bool crossing = false;
    for (int i = 0; i < n && !crossing; ++i) {
      const Vec2 &a = q[i], &b = q[(i + 1) % n], &c = q[(i + 2) % n];
      // neighbouring edges a-b and b-c fold back onto each other
      if (orient2d(a, b, c) == 0 && (a - b).dot(c - b) > 0) crossing = true;
      for (int j = i + 2; j < n && !crossing; ++j) {
        if ((j + 1) % n == i) continue;  // edge j ends where edge i starts: neighbours
        crossing = segmentsMeet(a, b, q[j], q[(j + 1) % n]);
      }
    }
    if (crossing) out.push_back(f);
  }
  if (unchecked) *unchecked = skipped;
  return out;
}

std::vector<char> facesNearIntersections(const PolygonMesh& m, const std::vector<IntersectingPair>& pairs) {
  std::vector<char> near(m.numFaces(), 0);
  if (pairs.empty()) return near;
  const std::vector<int32_t> welded = weldedVertexIds(m);
  std::vector<char> marked(m.numVertices(), 0);
  for (const IntersectingPair& p : pairs) {
    for (const int f : {p.a, p.b})
      for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1]; ++c) marked[welded[m.faceVertices[c]]] = 1;
  }
  for (int f = 0; f < m.numFaces(); ++f)
    for (int c = m.faceOffsets[f]; c < m.faceOffsets[f + 1] && !near[f]; ++c)
      near[f] = marked[welded[m.faceVertices[c]]];
  return near;
}

}  // namespace sf
