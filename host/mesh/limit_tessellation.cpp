// SPDX-License-Identifier: Apache-2.0
// The Catmull-Clark limit surface of a cage sampled face by face with OpenSubdiv Bfr, for
// measuring how far another surface lies from it.
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>

#include <Eigen/Geometry>

#include <smoothforce/mesh/cage_limit.h>
#include "osd_cage.h"

namespace sf {

namespace Bfr = OpenSubdiv::Bfr;

LimitTessellation tessellateLimitSurface(const PolygonMesh& mesh, const MeshReport& report, int rate, int approxLevel) {
  if (rate < 1 || rate > 256) throw InputError("limit tessellation: rate " + std::to_string(rate) + " outside 1..256");
  if (approxLevel < 1 || approxLevel > 10)
    throw InputError("limit tessellation: approximation level " + std::to_string(approxLevel) + " outside 1..10");
  const osd_cage::Compact c = osd_cage::compact(mesh);
  const std::unique_ptr<osd_cage::Far::TopologyRefiner> refiner = osd_cage::makeRefiner(mesh, report, c);
  Bfr::RefinerSurfaceFactory<>::Options options;
  options.SetApproxLevelSmooth(approxLevel).SetApproxLevelSharp(approxLevel);
  const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);

  std::vector<double> meshPoints(c.fromCompact.size() * 3);
  for (size_t i = 0; i < c.fromCompact.size(); ++i)
    for (int d = 0; d < 3; ++d) meshPoints[3 * i + d] = mesh.positions[c.fromCompact[i]][d];

  LimitTessellation out;
  out.faceFirstPoint.assign(1, 0);
  Bfr::Surface<double> surface;
  std::vector<double> patchPoints, uv;
  std::vector<int> facets;
  const Bfr::Surface<double>::PointDescriptor desc(3);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    // a face without limit surface (none with EDGE_AND_CORNER boundaries and no holes) stays empty
    if (factory.InitVertexSurface(f, &surface)) {
      patchPoints.resize(size_t(surface.GetNumPatchPoints()) * 3);
      surface.PreparePatchPoints(meshPoints.data(), desc, patchPoints.data(), desc);
      const Bfr::Tessellation tess(surface.GetParameterization(), rate);
      uv.resize(size_t(tess.GetNumCoords()) * 2);
      tess.GetCoords(uv.data());
      facets.resize(size_t(tess.GetNumFacets()) * 3);
      tess.GetFacets(facets.data());
      const int32_t first = static_cast<int32_t>(out.positions.size());
      for (int i = 0; i < tess.GetNumCoords(); ++i) {
        double P[3], Du[3], Dv[3];
        surface.Evaluate(&uv[2 * i], patchPoints.data(), desc, P, Du, Dv);
        const Eigen::Vector3d du(Du[0], Du[1], Du[2]), dv(Dv[0], Dv[1], Dv[2]);
        const Eigen::Vector3d n = du.cross(dv);
        out.positions.emplace_back(P[0], P[1], P[2]);
        out.normals.push_back(n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero());
      }
      for (int t = 0; t < tess.GetNumFacets(); ++t) {
        out.triangles.push_back({first + facets[3 * t], first + facets[3 * t + 1], first + facets[3 * t + 2]});
        out.face.push_back(f);
      }
    }
    out.faceFirstPoint.push_back(static_cast<int32_t>(out.positions.size()));
  }
  return out;
}

}  // namespace sf
