// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/straight_corner_split.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/detail/face_inputs.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/patch_cache.h>

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

/// A cap's corner normals are its plane's normal: within this angle (radians) of it.
constexpr double kCapNormalTolerance = 1e-6;

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
/// triangles, as one outline: empty where they are not a disc whose every vertex is on its
/// boundary (a loop of at most kMaxSplitCorners and GP_MAX_N corners, the triangles two fewer),
/// within kFlatHeight of one plane whose normal all their corner normals are (kCapNormalTolerance).
/// Marks the triangles in `taken`.
Outline flatCap(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const PatchCache& c,
                const std::vector<char>& capTriangle, int seed, std::vector<char>& taken) {
  Outline cap;
  std::vector<int> stack{seed};
  taken[seed] = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    cap.faces.push_back(f);
    for (int k = 0; k < 3; ++k) {
      const int twin = c.slotTwin[mesh.faceOffsets[f] + k];
      if (twin < 0 || isCreaseEdge(c, f, k)) continue;
      const int g = slotFace(mesh.faceOffsets, twin);
      if (capTriangle[g] && !taken[g]) taken[g] = 1, stack.push_back(g);
    }
  }
  std::sort(cap.faces.begin(), cap.faces.end());
  // the boundary: edges whose twin is not one of the cap's triangles, each vertex starting one
  std::vector<std::pair<int, int>> next;  // (start vertex, slot)
  std::vector<int> vertices;
  for (const int f : cap.faces)
    for (int k = 0; k < 3; ++k) {
      const int slot = mesh.faceOffsets[f] + k, twin = c.slotTwin[slot];
      vertices.push_back(mesh.faceVertices[slot]);
      if (twin < 0 || !std::binary_search(cap.faces.begin(), cap.faces.end(), slotFace(mesh.faceOffsets, twin)))
        next.emplace_back(mesh.faceVertices[slot], slot);
    }
  std::sort(next.begin(), next.end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  const int corners = static_cast<int>(next.size());
  const bool disc = cap.faces.size() >= 2 && corners == static_cast<int>(cap.faces.size()) + 2 &&
                    corners == static_cast<int>(vertices.size()) && corners <= std::min(kMaxSplitCorners, GP_MAX_N);
  if (!disc) return {};
  for (int i = 1; i < corners; ++i)
    if (next[i].first == next[i - 1].first) return {};  // a vertex the boundary passes twice
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
  // the loop on its own, for its plane
  PolygonMesh outline;
  outline.positions.reserve(corners);
  std::vector<int32_t> loop(corners);
  for (int k = 0; k < corners; ++k)
    outline.positions.push_back(mesh.positions[mesh.faceVertices[cap.slots[k]]]), loop[k] = k;
  outline.addFace(loop);
  const Vec3 plane = newellNormal(outline, 0);
  if (!isFlatFace(outline, 0)) return {};
  for (const int f : cap.faces)
    for (int k = 0; k < 3; ++k)
      if (angleBetween(cornerNormals[mesh.faceOffsets[f] + k], plane) > kCapNormalTolerance) return {};
  return cap;
}

/// Every face of the mesh as an outline, in order, except that each flat cap (flatCap) holding a
/// triangle with a straight patch corner becomes one outline, at the place of its first triangle.
std::vector<Outline> outlines(const PolygonMesh& mesh, const std::vector<Vec3>& cornerNormals, const PatchCache& c,
                              const std::vector<char>& capTriangle) {
  const int nf = mesh.numFaces();
  std::vector<char> taken(nf, 0);
  std::vector<int> capAt(nf, -1);  // the cap whose first triangle f is
  std::vector<Outline> caps;
  for (int f = 0; f < nf; ++f) {
    if (!capTriangle[f] || taken[f] || !hasStraightPatchCorner(c, f)) continue;
    Outline cap = flatCap(mesh, cornerNormals, c, capTriangle, f, taken);
    if (cap.slots.empty()) continue;
    capAt[cap.faces.front()] = static_cast<int>(caps.size());
    caps.push_back(std::move(cap));
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
    candidates =
        candidates || capTriangle[f] || (mesh.faceSize(f) >= 4 && mesh.faceSize(f) <= GP_MAX_N && isFlatFace(mesh, f));
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

  struct Fan {
    Vec3 centre, normal;
  };
  std::vector<std::optional<Fan>> fans(polygons.size());
  for (size_t i = 0; i < polygons.size(); ++i) {
    const int f = static_cast<int>(i), n = pm.faceSize(f), first = pm.faceOffsets[f];
    if (n < 4 || n > GP_MAX_N || !isFlatFace(pm, f)) continue;
    bool valid = true;  // finite data: the construction flags the rest
    for (int k = 0; k < n && valid; ++k)
      valid = pm.positions[pm.faceVertex(f, k)].allFinite() && pn[first + k].allFinite();
    if (!valid || !hasStraightPatchCorner(pc, f)) continue;
    Fan fan;
    Vec3 centreNormal;
    bool ok = n <= kMaxSplitCorners && patchCentre(pc, f, fan.centre, centreNormal);
    bool oneNormal = true;
    for (int k = 1; k < n; ++k) oneNormal = oneNormal && pn[first + k] == pn[first];
    fan.normal = oneNormal ? pn[first] : centreNormal;
    // every triangle of the fan turns the polygon's way about its Newell normal
    const Vec3 plane = newellNormal(pm, f);
    for (int k = 0; k < n && ok; ++k) {
      const Vec3 &a = pm.positions[pm.faceVertex(f, k)], &b = pm.positions[pm.faceVertex(f, k + 1)];
      ok = (b - a).cross(fan.centre - a).dot(plane) > 0;
    }
    addSources(mesh, polygons[i], ok ? report.fannedFaces : report.unfannedFaces);
    if (ok) fans[i] = fan;
  }
  sortUnique(report.fannedFaces);
  sortUnique(report.unfannedFaces);
  if (std::none_of(fans.begin(), fans.end(), [](const auto& fan) { return fan.has_value(); })) return;

  const bool vertexNormals = !mesh.fileNormals.empty() && mesh.fileNormals.size() == mesh.positions.size();
  FaceRewrite out(mesh, &cornerNormals);
  for (size_t i = 0; i < polygons.size(); ++i) {
    const Outline& o = polygons[i];
    if (!fans[i]) {  // as read: a face, or a cap's triangles
      for (const int f : o.faces) {
        for (int k = 0; k < mesh.faceSize(f); ++k) out.copyCorner(mesh.faceOffsets[f] + k);
        out.closeFace(f);
      }
      continue;
    }
    const int centre = static_cast<int>(mesh.positions.size()), n = static_cast<int>(o.slots.size());
    mesh.positions.push_back(fans[i]->centre);
    if (vertexNormals) mesh.fileNormals.push_back(fans[i]->normal);
    for (int k = 0; k < n; ++k) {
      out.copyCorner(o.slots[k]);
      out.copyCorner(o.slots[(k + 1) % n]);
      out.addCorner(centre, fans[i]->normal);
      out.closeFace(o.faces.front());  // a cap's first triangle: sources stay in order
    }
    report.fanTriangles += n;
    ++report.addedVertices;
  }
  out.commit(mesh, &cornerNormals);
}

}  // namespace sf
