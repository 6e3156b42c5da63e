// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/straight_corner_split.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

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
  bool creaseCorner = false;  // a corner between two crease edges (edges n-1, 0 and k-1, k)
  for (int k = 0, previous = isCreaseEdge(c, f, n - 1); k < n && !creaseCorner; ++k) {
    const bool crease = isCreaseEdge(c, f, k);
    creaseCorner = previous && crease;
    previous = crease;
  }
  if (!creaseCorner) return false;
  G::vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N], ts[GP_MAX_N], te[GP_MAX_N];
  int vid[GP_MAX_N];
  const bool creased = detail::faceInputs<G>(c, f, V, N, vid, PS, PE);
  gp_uint st = 0;
  gpd::gp_patch_end_tangents(n, V, N, PS, PE, creased ? 1 : 0, vid, ts, te, &st);
  const double straight = std::numbers::pi * (1 - kStraightCornerDeg / 180);
  for (int k = 0; k < n; ++k) {
    if (!isCreaseEdge(c, f, k) || !isCreaseEdge(c, f, k == 0 ? n - 1 : k - 1)) continue;
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

}  // namespace

void splitStraightPatchCorners(PolygonMesh& mesh, std::vector<Eigen::Vector3d>& cornerNormals,
                               const PatchOptions& options, PolygonSplitReport& report) {
  if (static_cast<int>(cornerNormals.size()) != mesh.numCorners())
    throw std::invalid_argument("splitStraightPatchCorners: need one normal per corner");
  const int nf = mesh.numFaces();
  // flat polygons of four or more corners (triangles: the header says why), the only candidates
  std::vector<int> flat;
  for (int f = 0; f < nf; ++f)
    if (mesh.faceSize(f) >= 4 && mesh.faceSize(f) <= GP_MAX_N && isFlatFace(mesh, f)) flat.push_back(f);
  if (flat.empty()) return;
  // the construction's inputs, as buildPatchCache will see them
  PatchCache c;
  c.options = options;
  c.positions.reserve(mesh.positions.size() * 3);
  for (const Vec3& p : mesh.positions) c.positions.insert(c.positions.end(), {p.x(), p.y(), p.z()});
  c.faceOffsets = mesh.faceOffsets;
  c.faceVertices = mesh.faceVertices;
  c.cornerNormals.reserve(cornerNormals.size() * 3);
  for (const Vec3& n : cornerNormals) c.cornerNormals.insert(c.cornerNormals.end(), {n.x(), n.y(), n.z()});
  c.slotTwin = computeSlotTwins(mesh);

  struct Fan {
    int face;
    Vec3 centre, normal;
  };
  std::vector<Fan> fans;
  for (const int f : flat) {
    const int n = mesh.faceSize(f);
    bool valid = true;  // finite data: the construction flags the rest
    for (int k = 0; k < n && valid; ++k)
      valid = mesh.positions[mesh.faceVertex(f, k)].allFinite() && cornerNormals[mesh.faceOffsets[f] + k].allFinite();
    if (!valid || !hasStraightPatchCorner(c, f)) continue;
    const int source = static_cast<int>(mesh.faceSource.size()) == nf ? mesh.faceSource[f] : f;
    Fan fan{f, {}, {}};
    bool ok = n <= kMaxSplitCorners && patchCentre(c, f, fan.centre, fan.normal);
    const int first = mesh.faceOffsets[f];
    bool oneNormal = true;
    for (int k = 1; k < n; ++k) oneNormal = oneNormal && cornerNormals[first + k] == cornerNormals[first];
    if (oneNormal) fan.normal = cornerNormals[first];
    // every triangle of the fan turns the polygon's way about its Newell normal
    const Vec3 plane = newellNormal(mesh, f);
    for (int k = 0; k < n && ok; ++k) {
      const Vec3 &a = mesh.positions[mesh.faceVertex(f, k)], &b = mesh.positions[mesh.faceVertex(f, k + 1)];
      ok = (b - a).cross(fan.centre - a).dot(plane) > 0;
    }
    if (!ok) {
      report.unfannedFaces.push_back(source);
      continue;
    }
    report.fannedFaces.push_back(source);
    fans.push_back(fan);
  }
  std::sort(report.fannedFaces.begin(), report.fannedFaces.end());
  report.fannedFaces.erase(std::unique(report.fannedFaces.begin(), report.fannedFaces.end()), report.fannedFaces.end());
  std::sort(report.unfannedFaces.begin(), report.unfannedFaces.end());
  report.unfannedFaces.erase(std::unique(report.unfannedFaces.begin(), report.unfannedFaces.end()),
                             report.unfannedFaces.end());
  if (fans.empty()) return;

  const bool fileCorner = static_cast<int>(mesh.fileCornerNormals.size()) == mesh.numCorners();
  const bool groups = static_cast<int>(mesh.faceSmoothingGroups.size()) == nf;
  const bool sourced = static_cast<int>(mesh.faceSource.size()) == nf;
  const bool vertexNormals = !mesh.fileNormals.empty() && mesh.fileNormals.size() == mesh.positions.size();
  PolygonMesh out;
  std::vector<Vec3> normals;
  size_t next = 0;
  for (int f = 0; f < nf; ++f) {
    const int n = mesh.faceSize(f), first = mesh.faceOffsets[f];
    auto corner = [&](int slot) {
      out.faceVertices.push_back(mesh.faceVertices[slot]);
      if (fileCorner) out.fileCornerNormals.push_back(mesh.fileCornerNormals[slot]);
      normals.push_back(cornerNormals[slot]);
    };
    auto close = [&] {
      out.faceOffsets.push_back(static_cast<int32_t>(out.faceVertices.size()));
      if (groups) out.faceSmoothingGroups.push_back(mesh.faceSmoothingGroups[f]);
      out.faceSource.push_back(sourced ? mesh.faceSource[f] : f);
    };
    if (next < fans.size() && fans[next].face == f) {
      const Fan& fan = fans[next++];
      const int centre = static_cast<int>(mesh.positions.size());
      mesh.positions.push_back(fan.centre);
      if (vertexNormals) mesh.fileNormals.push_back(fan.normal);
      for (int k = 0; k < n; ++k) {
        corner(first + k);
        corner(first + (k + 1) % n);
        out.faceVertices.push_back(centre);
        if (fileCorner) out.fileCornerNormals.push_back(fan.normal);
        normals.push_back(fan.normal);
        close();
      }
      report.fanTriangles += n;
      ++report.addedVertices;
      continue;
    }
    for (int k = 0; k < n; ++k) corner(first + k);
    close();
  }
  mesh.faceOffsets = std::move(out.faceOffsets);
  mesh.faceVertices = std::move(out.faceVertices);
  if (fileCorner) mesh.fileCornerNormals = std::move(out.fileCornerNormals);
  if (groups) mesh.faceSmoothingGroups = std::move(out.faceSmoothingGroups);
  mesh.faceSource = std::move(out.faceSource);
  cornerNormals = std::move(normals);
}

}  // namespace sf
