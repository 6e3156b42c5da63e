// SPDX-License-Identifier: Apache-2.0
// Catmull-Clark limit positions and normals of a cage's vertices (OpenSubdiv Far), and the
// checks that keep unsupported topology away from OpenSubdiv.
#include <smoothforce/mesh/cage_limit.h>

#include <Eigen/Geometry>
#include <cmath>
#include <set>

#include <opensubdiv/far/primvarRefiner.h>

#include <smoothforce/mesh/normals.h>
#include "osd_cage.h"

namespace sf {

namespace osd_cage {

Sdc::Options sdcOptions() {
  Sdc::Options o;
  o.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  o.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
  o.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
  o.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
  return o;
}

std::string where(const PolygonMesh& mesh) {
  return (mesh.sourcePath.empty() ? std::string("mesh") : mesh.sourcePath) + ": ";
}

Compact compact(const PolygonMesh& mesh) {
  Compact c;
  c.toCompact.assign(mesh.numVertices(), -1);
  for (int v : mesh.faceVertices)
    if (v >= 0 && v < mesh.numVertices()) c.toCompact[v] = 0;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (c.toCompact[v] == 0) {
      c.toCompact[v] = static_cast<int>(c.fromCompact.size());
      c.fromCompact.push_back(v);
    }
  c.faceSizes.resize(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) c.faceSizes[f] = mesh.faceSize(f);
  c.faceVerts.reserve(mesh.faceVertices.size());
  for (int v : mesh.faceVertices) c.faceVerts.push_back(v >= 0 && v < mesh.numVertices() ? c.toCompact[v] : -1);
  return c;
}

std::unique_ptr<Far::TopologyRefiner> makeRefiner(const PolygonMesh& mesh, const MeshReport& report, const Compact& c) {
  if (const std::string why = cageProblem(mesh, report); !why.empty()) throw InputError(where(mesh) + why);
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(c.fromCompact.size());
  desc.numFaces = mesh.numFaces();
  desc.numVertsPerFace = c.faceSizes.data();
  desc.vertIndicesPerFace = c.faceVerts.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  Factory::Options options(Sdc::SCHEME_CATMARK, sdcOptions());
  // validateFullTopology checks what the factory derived; the checks above already excluded
  // what it would refuse, so a refusal here is OpenSubdiv's own limit (reported, never a crash).
  options.validateFullTopology = true;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, options));
  if (!refiner) throw InputError(where(mesh) + "--cage catmull-clark: OpenSubdiv refused the cage's topology");
  return refiner;
}

}  // namespace osd_cage

CageMode parseCageMode(const std::string& s) {
  if (s == "none") return CageMode::None;
  if (s == "catmull-clark") return CageMode::CatmullClark;
  throw InputError("--cage: expected none|catmull-clark, got '" + s + "'");
}

const char* toString(CageMode m) { return m == CageMode::CatmullClark ? "catmull-clark" : "none"; }

std::string cageProblem(const PolygonMesh& mesh, const MeshReport& report) {
  const std::string pre = "--cage catmull-clark: ";
  if (mesh.numFaces() == 0) return pre + "the mesh has no faces";
  for (int f = 0; f < mesh.numFaces(); ++f) {
    std::set<int> seen;
    for (int k = 0; k < mesh.faceSize(f); ++k)
      if (!seen.insert(mesh.faceVertex(f, k)).second)
        return pre + "face " + std::to_string(f) + " repeats vertex " + std::to_string(mesh.faceVertex(f, k)) +
               " (a subdivision cage needs distinct corners)";
  }
  if (!report.nonManifoldEdges.empty())
    return pre + "non-manifold edge " + std::to_string(report.nonManifoldEdges[0][0]) + "-" +
           std::to_string(report.nonManifoldEdges[0][1]) + " (used by more than two faces; " +
           std::to_string(report.nonManifoldEdges.size()) + " such edges)";
  if (!report.nonManifoldVertices.empty())
    return pre + "non-manifold vertex " + std::to_string(report.nonManifoldVertices[0]) +
           " (more than one fan of faces; " + std::to_string(report.nonManifoldVertices.size()) + " such vertices)";
  if (!report.inconsistentEdges.empty())
    return pre + "edge " + std::to_string(report.inconsistentEdges[0][0]) + "-" +
           std::to_string(report.inconsistentEdges[0][1]) +
           " is used twice in one direction (inconsistent face orientation; " +
           std::to_string(report.inconsistentEdges.size()) + " such edges)";
  if (!report.duplicateFaces.empty())
    return pre + "face " + std::to_string(report.duplicateFaces[0]) + " repeats another face's vertices";
  return {};
}

namespace {

/// A point for OpenSubdiv's primvar interface (Clear, AddWithWeight), in double.
struct Point3 {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point3& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
  Eigen::Vector3d vec() const { return {p[0], p[1], p[2]}; }
};

/// Area-weighted Newell normal of v's faces (not normalised), from `positions`.
Eigen::Vector3d ringNormal(const PolygonMesh& mesh, const std::vector<std::vector<int>>& vertexFaces,
                           const std::vector<Eigen::Vector3d>& positions, int v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f : vertexFaces[v]) {
    const int n = mesh.faceSize(f);
    for (int k = 0; k < n; ++k) sum += positions[mesh.faceVertex(f, k)].cross(positions[mesh.faceVertex(f, k + 1)]);
  }
  return sum;
}

}  // namespace

CageLimit catmullClarkLimit(const PolygonMesh& mesh, const MeshReport& report) {
  const osd_cage::Compact c = osd_cage::compact(mesh);
  std::unique_ptr<osd_cage::Far::TopologyRefiner> refiner = osd_cage::makeRefiner(mesh, report, c);
  // One uniform level turns every face into quads, whose vertices' limit masks Catmark defines
  // (the level-0 masks assume quads around the vertex); the last level must keep its full
  // topology for PrimvarRefiner::Limit. Child vertices of vertices come first in level 1
  // (orderVerticesFromFacesFirst off), so level-0 vertex i is level-1 vertex i.
  osd_cage::Far::TopologyRefiner::UniformOptions uniform(1);
  uniform.orderVerticesFromFacesFirst = false;
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);
  const int n0 = static_cast<int>(c.fromCompact.size());
  const int n1 = refiner->GetLevel(1).GetNumVertices();
  std::vector<Point3> level0(n0), level1(n1), pos(n1), tan1(n1), tan2(n1);
  for (int i = 0; i < n0; ++i) {
    const Eigen::Vector3d& p = mesh.positions[c.fromCompact[i]];
    level0[i] = {{p.x(), p.y(), p.z()}};
  }
  OpenSubdiv::Far::PrimvarRefinerReal<double> primvar(*refiner);
  primvar.Interpolate(1, level0, level1);
  primvar.Limit(level1, pos, tan1, tan2);

  CageLimit out;
  out.positions = mesh.positions;
  out.normals.assign(mesh.numVertices(), Eigen::Vector3d::Zero());
  const auto& base = refiner->GetLevel(0);
  for (int i = 0; i < n0; ++i) {
    const Eigen::Vector3d p = pos[i].vec();
    if (!p.allFinite())
      throw InputError(osd_cage::where(mesh) + "--cage catmull-clark: non-finite limit position at vertex " +
                       std::to_string(c.fromCompact[i]));
    out.positions[c.fromCompact[i]] = p;
    if (base.IsVertexBoundary(i)) ++out.boundaryVertices;
  }
  std::vector<std::vector<int>> vertexFaces(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < mesh.faceSize(f); ++k) vertexFaces[mesh.faceVertex(f, k)].push_back(f);
  for (int i = 0; i < n0; ++i) {
    const int v = c.fromCompact[i];
    const Eigen::Vector3d t1 = tan1[i].vec(), t2 = tan2[i].vec();
    Eigen::Vector3d nrm = t1.cross(t2);
    const Eigen::Vector3d ring = ringNormal(mesh, vertexFaces, out.positions, v);
    // parallel or vanishing tangents (a boundary corner whose two edges are collinear) have no
    // cross product to trust: the moved mesh's own normal there
    if (!nrm.allFinite() || !(nrm.norm() > 1e-12 * t1.norm() * t2.norm())) {
      out.fallbackVertices.push_back(v);
      nrm = ring.norm() > 0 ? ring : ringNormal(mesh, vertexFaces, mesh.positions, v);
      if (!(nrm.norm() > 0) || !nrm.allFinite())
        throw InputError(osd_cage::where(mesh) + "--cage catmull-clark: no limit normal at vertex " +
                         std::to_string(v) + " (its limit tangents and its faces are degenerate)");
    } else if (nrm.dot(ring) < 0) {
      nrm = -nrm;
    }
    out.normals[v] = nrm.normalized();
  }
  return out;
}

}  // namespace sf
