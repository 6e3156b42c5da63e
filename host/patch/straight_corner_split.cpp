// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/straight_corner_split.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/detail/face_inputs.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/tangent_fans.h>

namespace sf {

namespace {

using Vec3 = Eigen::Vector3d;
using G = Gp<double>;

Vec3 toEigen(const G::vec3& v) { return {v.x, v.y, v.z}; }

/// Face f's patch has a corner between two crease edges whose edge curves leave the vertex
/// within kStraightCornerDeg of straight (either way) in the corner's tangent plane (the
/// construction's own end tangents, gp_patch_end_tangents).
bool hasStraightPatchCorner(const PatchCache& c, int f) {
  const int n = c.faceSize(f);
  bool crease[GP_MAX_N];
  for (int k = 0; k < n; ++k) crease[k] = isCreaseEdge(c, f, k);
  // corners between two crease edges (corner k between edges k-1 and k)
  bool creaseCorner = false;
  for (int k = 0; k < n && !creaseCorner; ++k) creaseCorner = crease[k] && crease[k == 0 ? n - 1 : k - 1];
  if (!creaseCorner) return false;
  G::vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N], ts[GP_MAX_N], te[GP_MAX_N];
  int vid[GP_MAX_N];
  const bool creased = detail::faceInputs<G>(c, f, V, N, vid, PS, PE);
  gp_uint st = 0;
  gpd::gp_patch_end_tangents(n, V, N, PS, PE, creased ? 1 : 0, vid, ts, te, &st);
  const double straight = std::numbers::pi * (1 - kStraightCornerDeg / 180);
  for (int k = 0; k < n; ++k) {
    if (!crease[k] || !crease[k == 0 ? n - 1 : k - 1]) continue;
    const Vec3 out = toEigen(ts[k]), in = -toEigen(te[k == 0 ? n - 1 : k - 1]), normal = toEigen(N[k]);
    if (out.squaredNorm() == 0 || in.squaredNorm() == 0) continue;  // a zero edge: flagged by construction
    // (-pi, pi]: straight within kStraightCornerDeg either way (turned a hair past straight by
    // rounding or a slightly bent crease); corners turned further are the fans' to untangle
    const double angle = std::atan2(out.cross(in).dot(normal), out.dot(in));
    if (std::fabs(angle) >= straight) return true;
  }
  return false;
}

/// The centre of face f's patch (the design page's construction: no end tangents given) and its
/// normal there; false where the patch is not built or its centre is not finite.
bool patchCentre(const PatchCache& c, int f, Vec3& point, Vec3& normal) {
  const int n = c.faceSize(f);
  G::vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N];
  int vid[GP_MAX_N];
  double recs[GP_MAX_N * GP_E_NFIELDS];
  const bool creased = detail::faceInputs<G>(c, f, V, N, vid, PS, PE);
  const int mode = static_cast<int>(c.options.crossTangent);
  const gp_uint st = G::buildWith(n, V, N, PS, PE, creased, nullptr, nullptr, vid, mode, recs);
  if (st & GP_ST_NOT_BUILT) return false;
  const G::result r = G::eval(n, recs, mode, 0.0, 0.0);
  point = toEigen(r.pos), normal = toEigen(r.normal);
  return point.allFinite() && normal.allFinite() && normal.squaredNorm() > 0.5;
}

/// A cubic Bezier curve: an edge curve of the construction (Hermite with end derivatives the
/// chord length times the unit end tangents: control points V0 + L t0 / 3, V1 - L t1 / 3) or a
/// straight cut.
using Bezier = std::array<Vec3, 4>;

Vec3 bezierPoint(const Bezier& b, double t) {
  const double u = 1 - t;
  return u * u * u * b[0] + 3 * u * u * t * b[1] + 3 * u * t * t * b[2] + t * t * t * b[3];
}

Vec3 bezierDerivative(const Bezier& b, double t) {
  const double u = 1 - t;
  return 3 * (u * u * (b[1] - b[0]) + 2 * u * t * (b[2] - b[1]) + t * t * (b[3] - b[2]));
}

/// A flat polygon as the construction bounds it: its corners, each edge's curve (edge k from
/// V_k to V_k+1) and its unit Newell normal, for face f of c.
struct CurvedOutline {
  std::vector<Vec3> corners;
  std::vector<Bezier> curves;
  Vec3 plane;
};

CurvedOutline curvedOutline(const PatchCache& c, int f, const Vec3& plane) {
  const int n = c.faceSize(f);
  G::vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N], ts[GP_MAX_N], te[GP_MAX_N];
  int vid[GP_MAX_N];
  const bool creased = detail::faceInputs<G>(c, f, V, N, vid, PS, PE);
  gp_uint st = 0;
  gpd::gp_patch_end_tangents(n, V, N, PS, PE, creased ? 1 : 0, vid, ts, te, &st);
  CurvedOutline o;
  o.plane = plane;
  for (int k = 0; k < n; ++k) {
    const Vec3 a = toEigen(V[k]), b = toEigen(V[k + 1 == n ? 0 : k + 1]);
    const double len = (b - a).norm();
    o.corners.push_back(a);
    o.curves.push_back({a, a + toEigen(ts[k]) * (len / 3), b - toEigen(te[k]) * (len / 3), b});
  }
  return o;
}

/// The edges of a piece of outline o, its corners `piece` (indices into o.corners, in order): the
/// outline's own curve between consecutive corners, a straight cut between the others.
/// Which of them are cuts in *cuts.
std::vector<Bezier> pieceEdges(const CurvedOutline& o, const std::vector<int>& piece, std::vector<char>* cuts) {
  const int n = static_cast<int>(o.corners.size()), m = static_cast<int>(piece.size());
  std::vector<Bezier> edges;
  cuts->assign(m, 0);
  for (int i = 0; i < m; ++i) {
    const int a = piece[i], b = piece[(i + 1) % m];
    if (b == (a + 1) % n) {
      edges.push_back(o.curves[a]);
    } else {
      const Vec3 &p = o.corners[a], &q = o.corners[b];
      edges.push_back({p, p + (q - p) / 3, p + (q - p) * (2.0 / 3), q});
      (*cuts)[i] = 1;
    }
  }
  return edges;
}

/// How well a fan about `centre` keeps a polygon's edge curves `edges` (in order, turning about
/// `plane`, its unit normal), as a sine: positive where the fan is sound, the smaller of two margins.
/// - The curves: the smallest, over the edges k and 33 points C_k(t) of each (t = 0, 1/32, .., 1),
///   of the sine of the angle at which `centre` sees the curve pass, ((C_k - centre) x C_k') .
///   plane / (|C_k - centre| |C_k'|). Positive: each fan triangle (V_k, V_k+1, centre) sees its
///   edge curve turn one way about the centre, corners included, so its outline of the curve and
///   two spokes does not cross itself (a centre beyond a curve that bows in gives a negative
///   value: those triangles fold, whatever their patch).
/// - The spokes: the sine of the smallest margin, over the edges, by which the angle the chord
///   V_k V_k+1 subtends at `centre` exceeds kFanTangledGapDeg or falls short of 180 minus it.
///   Spokes closer than that are a tangled fan at the new vertex (tangent_fans.h), and turning
///   them apart bends them across the fan's triangles: a slab's parallelogram quad of 3-degree
///   corners sees its short edges at under a degree from any centre, and its fan, untangled by
///   4.9 degrees, folded on 16 of 16 faces (75% of the area at fault); a long flat slot cap sees
///   its far arc at under a degree from its centre, and that fan, untangled by 34-38 degrees,
///   folded on every triangle.
/// -1 where the data is not finite.
double fanMargin(const std::vector<Bezier>& edges, const Vec3& centre, const Vec3& plane) {
  const double least = kFanTangledGapDeg * std::numbers::pi / 180;
  double worst = 1;
  for (const Bezier& e : edges) {
    for (int i = 0; i <= 32; ++i) {
      const Vec3 r = bezierPoint(e, i / 32.0) - centre, d = bezierDerivative(e, i / 32.0);
      const double norms = r.norm() * d.norm();
      const double sine = norms > 0 ? r.cross(d).dot(plane) / norms : -1;
      if (!std::isfinite(sine)) return -1;
      worst = std::min(worst, sine);
    }
    const Vec3 ra = e[0] - centre, rb = e[3] - centre;
    const double gap = std::atan2(ra.cross(rb).dot(plane), ra.dot(rb));
    if (!std::isfinite(gap)) return -1;
    worst = std::min(worst, std::sin(std::min(gap - least, std::numbers::pi - least - gap)));
  }
  return worst;
}

/// How well a piece bounded by `edges` (in order about `plane`) stands as one polygon, as a sine:
/// positive where every corner, the angle between its two edges' tangents there, lies between
/// kFanTangledGapDeg and 180 - kPieceStraightCornerDeg degrees (no straight corner, as the first
/// cut's pieces), the piece has at most GP_MAX_N corners and no cut crosses another edge (16
/// chords per curve; `cuts` flags the edges that are cuts).
double pieceMargin(const std::vector<Bezier>& edges, const std::vector<char>& cuts, const Vec3& plane) {
  const int m = static_cast<int>(edges.size());
  if (m < 3 || m > GP_MAX_N) return -1;
  const double lo = kFanTangledGapDeg * std::numbers::pi / 180,
               hi = std::numbers::pi * (1 - kPieceStraightCornerDeg / 180);
  double worst = 1;
  for (int i = 0; i < m; ++i) {
    const Vec3 in = bezierDerivative(edges[(i + m - 1) % m], 1), out = bezierDerivative(edges[i], 0);
    // the interior angle: pi minus the turn from the incoming direction to the outgoing one
    const double angle = std::numbers::pi - std::atan2(in.cross(out).dot(plane), in.dot(out));
    if (!std::isfinite(angle)) return -1;
    worst = std::min(worst, std::sin(std::min(angle - lo, hi - angle)));
  }
  // a cut (straight) against every edge it does not meet at a corner, both on the plane
  auto cross2 = [&](const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a).dot(plane); };
  for (int i = 0; i < m && worst > 0; ++i) {
    if (!cuts[i]) continue;
    const Bezier& cut = edges[i];
    for (int j = 0; j < m && worst > 0; ++j) {
      if (j == i || j == (i + 1) % m || (j + 1) % m == i) continue;
      for (int s = 0; s < 16 && worst > 0; ++s) {
        const Vec3 p = bezierPoint(edges[j], s / 16.0), q = bezierPoint(edges[j], (s + 1) / 16.0);
        const bool crosses = cross2(cut[0], cut[3], p) * cross2(cut[0], cut[3], q) <= 0 &&
                             cross2(p, q, cut[0]) * cross2(p, q, cut[3]) <= 0;
        if (crosses) worst = -1;
      }
    }
  }
  return worst;
}

/// The area centroid of a polygon of m corners, corner(i) for i < m, on `plane` (unit): its
/// triangles about its first corner, their areas signed along the plane; NaN where the area is not
/// positive.
template <class Corner>
Vec3 areaCentroid(int m, const Corner& corner, const Vec3& plane) {
  Vec3 weighted = Vec3::Zero();
  double area = 0;
  for (int i = 1; i + 1 < m; ++i) {
    const Vec3 &a = corner(0), &b = corner(i), &c = corner(i + 1);
    const double w = (b - a).cross(c - a).dot(plane);
    weighted += w * (a + b + c) / 3, area += w;
  }
  return area > 0 ? Vec3(weighted / area) : Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

/// The area centroid of the polygon of a piece's corners on `plane`.
Vec3 pieceCentroid(const CurvedOutline& o, const std::vector<int>& piece) {
  return areaCentroid(
      static_cast<int>(piece.size()), [&](int i) -> const Vec3& { return o.corners[piece[i]]; }, o.plane);
}

/// A piece of a fanned polygon: its corners (indices into the polygon's, in order) and, where it
/// is fanned, the centre it is fanned about.
struct FanPiece {
  std::vector<int> corners;
  bool fanned = false;
  Vec3 centre = Vec3::Zero();
};

/// The margin (a sine: 1 degree) by which a fan or a piece must stand (fanMargin, pieceMargin):
/// a 6-degree slab quad's fan about its centre, seen at 0.47 degrees beyond the spokes' limit,
/// certified but left 0.18% of the slab's area thin in the surface check where the quad left
/// whole had none; the tests' caps stand by 20 degrees and more.
constexpr double kStandMargin = 0.017452406437283512;

/// How well a piece stands: as one polygon (pieceMargin) where it can, else as a fan about its
/// area centroid (fanMargin); the centre in *centre where fanned.
double pieceScore(const CurvedOutline& o, const std::vector<int>& piece, bool* fanned, Vec3* centre) {
  std::vector<char> cuts;
  const std::vector<Bezier> edges = pieceEdges(o, piece, &cuts);
  const double whole = pieceMargin(edges, cuts, o.plane);
  *fanned = !(whole > 0);
  if (!*fanned) return whole;
  *centre = pieceCentroid(o, piece);
  return centre->allFinite() ? fanMargin(edges, *centre, o.plane) : -1;
}

/// The pieces of outline o's corners `piece` that stand (pieceScore > kStandMargin): the piece itself, or
/// the two sides of the cut between two of its corners whose worse side stands best, each cut
/// again where it does not stand, at most `depth` cuts deep. False where no plan stands.
bool planPieces(const CurvedOutline& o, const std::vector<int>& piece, int depth, std::vector<FanPiece>& out) {
  FanPiece p{piece};
  if (pieceScore(o, piece, &p.fanned, &p.centre) > kStandMargin) {
    out.push_back(std::move(p));
    return true;
  }
  const int m = static_cast<int>(piece.size());
  if (depth == 0 || m < 4) return false;
  double best = -2;
  std::vector<int> bestA, bestB;
  for (int i = 0; i < m; ++i)
    for (int j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;  // an edge, not a cut
      const std::vector<int> a(piece.begin() + i, piece.begin() + j + 1);
      std::vector<int> b(piece.begin() + j, piece.end());
      b.insert(b.end(), piece.begin(), piece.begin() + i + 1);
      bool fa, fb;
      Vec3 ca, cb;
      const double score = std::min(pieceScore(o, a, &fa, &ca), pieceScore(o, b, &fb, &cb));
      if (score > best) best = score, bestA = a, bestB = b;
    }
  if (bestA.empty()) return false;
  return planPieces(o, bestA, depth - 1, out) && planPieces(o, bestB, depth - 1, out);
}

/// The construction's inputs for `mesh`'s faces, as buildPatchCache will see them.
PatchCache constructionInputs(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals,
                              const PatchOptions& options) {
  PatchCache c;
  c.options = options;
  c.positions.reserve(mesh.positions.size() * 3);
  for (const Vec3& p : mesh.positions) c.positions.insert(c.positions.end(), {p.x(), p.y(), p.z()});
  c.faceOffsets = mesh.faceOffsets;
  c.faceVertices = mesh.faceVertices;
  c.cornerNormals.reserve(cornerNormals.size() * 3);
  for (const Vec3& n : cornerNormals) c.cornerNormals.insert(c.cornerNormals.end(), {n.x(), n.y(), n.z()});
  c.slotTwin = computeSlotTwins(mesh);
  return c;
}

/// A polygon the fan may replace: its corners as slots of the mesh, in order, and the faces of
/// the mesh it stands for (one face, or the triangles of a flat cap merged into one polygon).
struct Outline {
  std::vector<int> slots;
  std::vector<int> faces;
};

/// The most cuts deep planPieces goes (a long slot's cap: one cut off each end).
constexpr int kMaxFanCuts = 6;

/// A cap's corner normals are its plane's normal: within this angle (radians) of it.
constexpr double kCapNormalTolerance = 1e-6;

/// A flat polygon of more corners than this whose corner normals are all its plane's is fanned
/// whether or not it has a straight patch corner. Its patch is the flat polygon, yet the
/// certificate's interval bounds (products of n - 2 squared edge distances per weight) decide it
/// ever more slowly as n grows: a 24-gon left undecided after 109 s, flat caps of 7-11 corners
/// certified in 0.6-3.1 s with margins down to 9e-6.
constexpr int kFanManyCorners = 12;

/// Triangle f's corner normals all lie within kCapNormalTolerance of its plane's normal.
bool isFlatCapTriangle(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, int f) {
  if (mesh.faceSize(f) != 3) return false;
  const Vec3 plane = newellNormal(mesh, f);
  if (!plane.allFinite() || plane.squaredNorm() == 0) return false;
  for (int k = 0; k < 3; ++k) {
    const Vec3& n = cornerNormals[mesh.faceOffsets[f] + k];
    if (!n.allFinite() || angleBetween(n, plane) > kCapNormalTolerance) return false;
  }
  return true;
}

/// The triangles joined to triangle `seed` across edges that are not creases, all flat cap
/// triangles (capTriangle), ascending. Marks them in `taken`.
std::vector<int> flatRegion(const PolygonMesh& mesh, const PatchCache& c, const std::vector<char>& capTriangle,
                            int seed, std::vector<char>& taken) {
  std::vector<int> faces, stack{seed};
  taken[seed] = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    faces.push_back(f);
    for (int k = 0; k < 3; ++k) {
      const int twin = c.slotTwin[mesh.faceOffsets[f] + k];
      if (twin < 0 || isCreaseEdge(c, f, k)) continue;
      const int g = slotFace(mesh.faceOffsets, twin);
      if (capTriangle[g] && !taken[g]) taken[g] = 1, stack.push_back(g);
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// An outline within kFlatHeight of one plane whose normal every corner normal of its triangles is
/// (kCapNormalTolerance).
bool flatOutline(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const Outline& o) {
  const int corners = static_cast<int>(o.slots.size());
  PolygonMesh outline;
  outline.positions.reserve(corners);
  std::vector<int32_t> loop(corners);
  for (int k = 0; k < corners; ++k)
    outline.positions.push_back(mesh.positions[mesh.faceVertices[o.slots[k]]]), loop[k] = k;
  outline.addFace(loop);
  const Vec3 plane = newellNormal(outline, 0);
  if (!isFlatFace(outline, 0)) return false;
  for (const int f : o.faces)
    for (int k = 0; k < 3; ++k)
      if (angleBetween(cornerNormals[mesh.faceOffsets[f] + k], plane) > kCapNormalTolerance) return false;
  return true;
}

/// The boundary of a flat region (flatRegion's sorted triangles): its edges, those whose twin is
/// not one of the region's triangles, as (start vertex, slot) sorted by vertex; how many distinct
/// vertices start them; and the region's distinct vertices, sorted.
struct RegionBoundary {
  std::vector<std::pair<int, int>> edges;
  int rimVertices = 0;
  std::vector<int> vertices;
};

RegionBoundary regionBoundary(const PolygonMesh& mesh, const PatchCache& c, const std::vector<int>& faces) {
  RegionBoundary b;
  for (const int f : faces)
    for (int k = 0; k < 3; ++k) {
      const int slot = mesh.faceOffsets[f] + k, twin = c.slotTwin[slot];
      b.vertices.push_back(mesh.faceVertices[slot]);
      if (twin < 0 || !std::binary_search(faces.begin(), faces.end(), slotFace(mesh.faceOffsets, twin)))
        b.edges.emplace_back(mesh.faceVertices[slot], slot);
    }
  std::sort(b.edges.begin(), b.edges.end());
  for (size_t i = 0; i < b.edges.size(); ++i) b.rimVertices += i == 0 || b.edges[i].first != b.edges[i - 1].first;
  std::sort(b.vertices.begin(), b.vertices.end());
  b.vertices.erase(std::unique(b.vertices.begin(), b.vertices.end()), b.vertices.end());
  return b;
}

/// The flat region `faces` (flatRegion) with boundary `b` (regionBoundary) as the outline of its
/// boundary: empty where it is not a disc whose every vertex is on its boundary (one loop, the
/// triangles two fewer than its corners; any number of corners: a cap of more than GP_MAX_N is
/// fanned without a patch of its own) or not flat (flatOutline).
Outline discOutline(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const std::vector<int>& faces,
                    const RegionBoundary& b) {
  Outline cap;
  cap.faces = faces;
  const std::vector<std::pair<int, int>>& next = b.edges;
  const int corners = static_cast<int>(next.size());
  // each vertex on the boundary, and starting one boundary edge (none that it passes twice)
  const bool disc = cap.faces.size() >= 2 && corners == static_cast<int>(cap.faces.size()) + 2 &&
                    corners == static_cast<int>(b.vertices.size()) && corners == b.rimVertices;
  if (!disc) return {};
  auto endVertex = [&](int slot) {
    const int f = slotFace(mesh.faceOffsets, slot), k = slot - mesh.faceOffsets[f];
    return mesh.faceVertex(f, k + 1);
  };
  // one loop through every boundary edge: `corners` steps from the first edge lead back to it (each
  // vertex starts one edge, so a walk that closes on its first edge repeats none)
  int slot = next.front().second;
  for (int step = 0; step < corners; ++step) {
    cap.slots.push_back(slot);
    const int end = endVertex(slot);
    const auto it = std::lower_bound(next.begin(), next.end(), std::make_pair(end, -1));
    if (it == next.end() || it->first != end) return {};
    slot = it->second;
    if (slot == next.front().second && step + 1 < corners) return {};  // more than one loop
  }
  if (slot != next.front().second) return {};
  if (!flatOutline(mesh, cornerNormals, cap)) return {};
  return cap;
}

/// The flat region `faces` (flatRegion, boundary `b`) that is not a disc of its rim but has every
/// vertex on its boundary (an annulus triangulated from its two rims) cut into convex pieces of its
/// own triangles (none where a vertex lies inside the region): starting from the triangles, two pieces are merged
/// across the longest edge they share (not a crease: the region has none inside) while the merged outline stays convex
/// at both ends of that edge (no corner within kStraightCornerDeg of straight or beyond, on the region's plane), passes
/// no vertex twice and has at most kMaxSplitCorners and GP_MAX_N corners (Hertel and Mehlhorn's greedy partition, at
/// most four times the fewest convex pieces). Returns the pieces of two or more triangles that are flat (flatOutline);
/// the other triangles stay as they are.
std::vector<Outline> convexPieces(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const PatchCache& c,
                                  const std::vector<int>& faces, const RegionBoundary& b) {
  const int m = static_cast<int>(faces.size());
  // triangulated from its rims alone: every vertex on the boundary (a cap already fanned about a
  // vertex inside it has no straight corner and stays as it is)
  if (b.rimVertices != static_cast<int>(b.vertices.size())) return {};
  auto local = [&](int f) { return static_cast<int>(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin()); };
  auto vertexAt = [&](int slot) { return mesh.faceVertices[slot]; };
  Vec3 normal = Vec3::Zero();
  for (const int f : faces) normal += newellNormal(mesh, f);
  if (!(normal.norm() > 0) || !normal.allFinite()) return {};
  normal.normalize();
  std::vector<Outline> piece(m);
  std::vector<int> owner(m);  // the piece that holds triangle i (union by relabelling)
  for (int i = 0; i < m; ++i) {
    piece[i].faces = {faces[i]};
    for (int k = 0; k < 3; ++k) piece[i].slots.push_back(mesh.faceOffsets[faces[i]] + k);
    owner[i] = i;
  }
  struct Shared {
    double length;
    int slot, twin;
  };
  std::vector<Shared> shared;
  for (const int f : faces)
    for (int k = 0; k < 3; ++k) {
      const int slot = mesh.faceOffsets[f] + k, twin = c.slotTwin[slot];
      if (twin < 0 || twin < slot || isCreaseEdge(c, f, k)) continue;
      const int g = slotFace(mesh.faceOffsets, twin);
      if (!std::binary_search(faces.begin(), faces.end(), g)) continue;
      const double length = (mesh.positions[mesh.faceVertex(f, k + 1)] - mesh.positions[vertexAt(slot)]).norm();
      shared.push_back({length, slot, twin});
    }
  std::sort(shared.begin(), shared.end(), [](const Shared& a, const Shared& b) {
    return a.length != b.length ? a.length > b.length : a.slot < b.slot;
  });
  const double straight = std::numbers::pi * (1 - kStraightCornerDeg / 180);
  // the interior angle at b of the corner a -> b -> c, on the region's plane, in [0, 2 pi)
  auto convex = [&](int a, int b, int cc) {
    const Vec3 e1 = mesh.positions[a] - mesh.positions[b], e2 = mesh.positions[cc] - mesh.positions[b];
    double angle = std::atan2(e2.cross(e1).dot(normal), e2.dot(e1));
    if (angle < 0) angle += 2 * std::numbers::pi;
    return angle < straight;
  };
  const int maxCorners = std::min(kMaxSplitCorners, GP_MAX_N);
  for (const Shared& e : shared) {
    const int p = owner[local(slotFace(mesh.faceOffsets, e.slot))],
              q = owner[local(slotFace(mesh.faceOffsets, e.twin))];
    if (p == q) continue;
    const std::vector<int>&ps = piece[p].slots, &qs = piece[q].slots;
    const int np = static_cast<int>(ps.size()), nq = static_cast<int>(qs.size());
    if (np + nq - 2 > maxCorners) continue;
    const int ip = static_cast<int>(std::find(ps.begin(), ps.end(), e.slot) - ps.begin());
    const int iq = static_cast<int>(std::find(qs.begin(), qs.end(), e.twin) - qs.begin());
    if (ip == np || iq == nq) continue;
    // p's edges from the shared edge's end round to its start, then q's the same way
    std::vector<int> loop;
    loop.reserve(np + nq - 2);
    for (int j = 1; j < np; ++j) loop.push_back(ps[(ip + j) % np]);
    for (int j = 1; j < nq; ++j) loop.push_back(qs[(iq + j) % nq]);
    std::vector<int> vertices(loop.size());
    std::transform(loop.begin(), loop.end(), vertices.begin(), vertexAt);
    std::vector<int> sorted = vertices;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
    // the two corners the merge changes: at the shared edge's ends (loop positions 0 and np - 1)
    const int nl = static_cast<int>(loop.size());
    auto cornerOk = [&](int j) { return convex(vertices[(j + nl - 1) % nl], vertices[j], vertices[(j + 1) % nl]); };
    if (!cornerOk(0) || !cornerOk(np - 1)) continue;
    piece[p].slots = std::move(loop);
    piece[p].faces.insert(piece[p].faces.end(), piece[q].faces.begin(), piece[q].faces.end());
    for (const int f : piece[q].faces) owner[local(f)] = p;
    piece[q] = {};
  }
  std::vector<Outline> out;
  for (Outline& o : piece) {
    if (o.faces.size() < 2) continue;
    std::sort(o.faces.begin(), o.faces.end());
    if (static_cast<int>(o.slots.size()) <= maxCorners && flatOutline(mesh, cornerNormals, o))
      out.push_back(std::move(o));
  }
  return out;
}

/// Every face of the mesh as an outline, in order, except in the flat regions of cap triangles
/// (flatRegion): a disc one of whose triangles has a straight patch corner becomes one outline
/// (discOutline), a region that is no disc its convex pieces (convexPieces, which the fan takes only
/// where they have a straight patch corner), each at the place of its first triangle.
std::vector<Outline> outlines(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const PatchCache& c,
                              const std::vector<char>& capTriangle) {
  const int nf = mesh.numFaces();
  std::vector<char> taken(nf, 0);
  std::vector<int> capAt(nf, -1);  // the cap whose first triangle f is
  std::vector<Outline> caps;
  for (int f = 0; f < nf; ++f) {
    if (!capTriangle[f] || taken[f]) continue;
    const std::vector<int> region = flatRegion(mesh, c, capTriangle, f, taken);
    if (region.size() < 2) continue;
    const RegionBoundary boundary = regionBoundary(mesh, c, region);
    Outline disc = discOutline(mesh, cornerNormals, region, boundary);
    std::vector<Outline> pieces;
    if (disc.slots.empty())  // pieces without a straight patch corner are not fanned: they keep their triangles
      pieces = convexPieces(mesh, cornerNormals, c, region, boundary);
    else if (std::any_of(region.begin(), region.end(), [&](int g) { return hasStraightPatchCorner(c, g); }))
      pieces.push_back(std::move(disc));
    for (Outline& cap : pieces) {
      capAt[cap.faces.front()] = static_cast<int>(caps.size());
      caps.push_back(std::move(cap));
    }
  }
  std::vector<char> merged(nf, 0);
  for (const Outline& cap : caps)
    for (const int f : cap.faces) merged[f] = 1;
  std::vector<Outline> out;
  out.reserve(nf);
  for (int f = 0; f < nf; ++f) {
    if (capAt[f] >= 0) {
      out.push_back(std::move(caps[capAt[f]]));
    } else if (!merged[f]) {
      Outline face{std::vector<int>(mesh.faceSize(f)), {f}};
      for (int k = 0; k < mesh.faceSize(f); ++k) face.slots[k] = mesh.faceOffsets[f] + k;
      out.push_back(std::move(face));
    }
  }
  return out;
}

void addSources(const PolygonMesh& mesh, const Outline& o, std::vector<int>& to) {
  const bool sourced = mesh.faceSource.size() == mesh.faceOffsets.size() - 1;
  for (const int f : o.faces) to.push_back(sourced ? mesh.faceSource[f] : f);
}

void sortUnique(std::vector<int>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

void splitStraightPatchCorners(PolygonMesh& mesh, std::vector<Eigen::Vector3d>& cornerNormals,
                               const PatchOptions& options, PolygonSplitReport& report) {
  if (static_cast<int>(cornerNormals.size()) != mesh.numCorners())
    throw std::invalid_argument("splitStraightPatchCorners: need one normal per corner");
  const int nf = mesh.numFaces();
  // the only candidates: flat polygons of four or more corners, and triangles of flat caps
  std::vector<char> capTriangle(nf, 0);
  bool candidates = false;
  for (int f = 0; f < nf; ++f) {
    capTriangle[f] = isFlatCapTriangle(mesh, cornerNormals, f);
    candidates = candidates || capTriangle[f] || (mesh.faceSize(f) >= 4 && isFlatFace(mesh, f));
  }
  if (!candidates) return;
  const PatchCache asRead = constructionInputs(mesh, cornerNormals, options);
  const std::vector<Outline> polygons = outlines(mesh, cornerNormals, asRead, capTriangle);
  // the mesh with its flat caps merged, whose patches decide the fans
  const bool caps = static_cast<int>(polygons.size()) != nf;
  PolygonMesh merged;
  std::vector<Vec3> mergedNormals;
  if (caps) {
    merged.positions = mesh.positions;
    for (const Outline& o : polygons) {
      for (const int slot : o.slots) merged.faceVertices.push_back(mesh.faceVertices[slot]);
      for (const int slot : o.slots) mergedNormals.push_back(cornerNormals[slot]);
      merged.faceOffsets.push_back(static_cast<int32_t>(merged.faceVertices.size()));
    }
  }
  const PolygonMesh& pm = caps ? merged : mesh;
  const PatchCache c = caps ? constructionInputs(merged, mergedNormals, options) : PatchCache{};
  const PatchCache& pc = caps ? c : asRead;
  const std::vector<Vec3>& pn = caps ? mergedNormals : cornerNormals;

  // each polygon fanned: its pieces (one fan about its centre, or the plan of cuts and fans that
  // planPieces makes) and the normal of its new vertices
  struct Fan {
    std::vector<FanPiece> pieces;
    Vec3 normal;
  };
  std::vector<std::optional<Fan>> fans(polygons.size());
  for (size_t i = 0; i < polygons.size(); ++i) {
    const int f = static_cast<int>(i), n = pm.faceSize(f), first = pm.faceOffsets[f];
    if (n < 4 || !isFlatFace(pm, f)) continue;
    bool valid = true;  // finite data: the construction flags the rest
    for (int k = 0; k < n && valid; ++k)
      valid = pm.positions[pm.faceVertex(f, k)].allFinite() && pn[first + k].allFinite();
    if (!valid) continue;
    Fan fan;
    FanPiece whole;
    for (int k = 0; k < n; ++k) whole.corners.push_back(k);
    whole.fanned = true;
    const Vec3 plane = newellNormal(pm, f);
    bool oneNormal = true;
    for (int k = 1; k < n; ++k) oneNormal = oneNormal && pn[first + k] == pn[first];
    // a polygon of many corners on its plane's one normal (a gear's face, its teeth cut off by
    // splitBadCorners): its patch is the polygon itself, which the fan's affine triangles keep,
    // but the certificate's bounds of a patch of so many corners seldom decide it (minutes each)
    const bool many = oneNormal && n > kFanManyCorners && angleBetween(pn[first], plane) <= kCapNormalTolerance;
    bool ok = true;
    if (n > GP_MAX_N) {
      // no patch of its own: a cap merged from more triangles than a patch takes corners (a finely
      // divided cylinder's, triangulated from its rim; only a disc cap one of whose triangles has a
      // straight patch corner is merged that large: outlines, convex pieces stop at GP_MAX_N), or a
      // flat polygon read with that many corners (such a cap as one face, whose patch would be a
      // hole in the surface), is fanned about its area centroid, with its corners' one normal or,
      // where they differ (a cap without a creased rim), its plane's
      const Outline& o = polygons[i];
      bool positive = true;  // a merged cap's area (a face as read: areaCentroid's NaN says it)
      if (o.faces.size() >= 2) {
        Vec3 weighted = Vec3::Zero();
        double area = 0;
        for (const int g : o.faces) {
          const Vec3 &a = mesh.positions[mesh.faceVertex(g, 0)], &b = mesh.positions[mesh.faceVertex(g, 1)],
                     &c3 = mesh.positions[mesh.faceVertex(g, 2)];
          const double w = (b - a).cross(c3 - a).norm();
          weighted += w * (a + b + c3) / 3;
          area += w;
        }
        whole.centre = weighted / area;
        positive = area > 0;
      } else {
        whole.centre = areaCentroid(
            n, [&](int k) -> const Vec3& { return pm.positions[pm.faceVertex(f, k)]; }, Vec3(plane.normalized()));
      }
      fan.normal = oneNormal ? pn[first] : Vec3(plane.normalized());
      ok = positive && whole.centre.allFinite();
      // every triangle of the fan turns the polygon's way about its Newell normal
      for (int k = 0; k < n && ok; ++k) {
        const Vec3 &a = pm.positions[pm.faceVertex(f, k)], &b = pm.positions[pm.faceVertex(f, k + 1)];
        ok = (b - a).cross(whole.centre - a).dot(plane) > 0;
      }
      if (ok) fan.pieces.push_back(std::move(whole));
    } else {
      if (!many && !hasStraightPatchCorner(pc, f)) continue;
      Vec3 centreNormal;
      ok = patchCentre(pc, f, whole.centre, centreNormal);
      fan.normal = oneNormal ? pn[first] : centreNormal;
      const CurvedOutline outline = curvedOutline(pc, f, plane.normalized());
      std::vector<char> cuts;
      if (ok && fanMargin(pieceEdges(outline, whole.corners, &cuts), whole.centre, outline.plane) > kStandMargin) {
        fan.pieces.push_back(std::move(whole));  // the fan about the patch's centre
      } else if (oneNormal) {
        // a polygon whose centre does not see every edge (a long slot's cap, a thin one): cut on
        // diagonals into pieces that stand whole or fan about their own centroids, on its plane
        ok = planPieces(outline, whole.corners, kMaxFanCuts, fan.pieces);
      } else {
        ok = false;
      }
    }
    addSources(mesh, polygons[i], ok ? report.fannedFaces : report.unfannedFaces);
    if (ok) fans[i] = std::move(fan);
  }
  sortUnique(report.fannedFaces);
  sortUnique(report.unfannedFaces);
  if (std::none_of(fans.begin(), fans.end(), [](const auto& fan) { return fan.has_value(); })) return;

  const bool vertexNormals = !mesh.fileNormals.empty() && mesh.fileNormals.size() == mesh.positions.size();
  // faces as read in order: each fan at the place of its polygon's first face, the rest as read
  std::vector<int> fanAt(nf, -1);
  std::vector<char> fanned(nf, 0);
  for (size_t i = 0; i < polygons.size(); ++i) {
    if (!fans[i]) continue;
    fanAt[polygons[i].faces.front()] = static_cast<int>(i);
    for (const int f : polygons[i].faces) fanned[f] = 1;
  }
  FaceRewrite out(mesh, &cornerNormals);
  for (int f = 0; f < nf; ++f) {
    if (!fanned[f]) {
      for (int k = 0; k < mesh.faceSize(f); ++k) out.copyCorner(mesh.faceOffsets[f] + k);
      out.closeFace(f);
      continue;
    }
    if (fanAt[f] < 0) continue;  // a merged cap's other triangle
    const size_t i = static_cast<size_t>(fanAt[f]);
    const Outline& o = polygons[i];
    for (const FanPiece& piece : fans[i]->pieces) {
      const int m = static_cast<int>(piece.corners.size());
      if (!piece.fanned) {
        for (const int k : piece.corners) out.copyCorner(o.slots[k]);
        out.closeFace(o.faces.front());  // a cap's first triangle: sources stay in order
        ++report.fanPieces;
        continue;
      }
      const int centre = static_cast<int>(mesh.positions.size());
      mesh.positions.push_back(piece.centre);
      if (vertexNormals) mesh.fileNormals.push_back(fans[i]->normal);
      for (int k = 0; k < m; ++k) {
        out.copyCorner(o.slots[piece.corners[k]]);
        out.copyCorner(o.slots[piece.corners[(k + 1) % m]]);
        out.addCorner(centre, fans[i]->normal);
        out.closeFace(o.faces.front());
      }
      report.fanTriangles += m;
      ++report.addedVertices;
    }
  }
  out.commit(mesh, &cornerNormals);
}

}  // namespace sf
