// SPDX-License-Identifier: Apache-2.0
#include "query_test_support.h"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/sweep/generators.h>
#include "gp_config.h"

namespace sf::test {

std::vector<std::string> closedShapes() {
  return {"keenan_crane/spot_control_mesh.obj",
          "keenan_crane/spot_quadrangulated.obj",
          "keenan_crane/spot_triangulated.obj",
          "keenan_crane/bob_tri.obj",
          "odedstein/spot_low_resolution.obj",
          "odedstein/spot.obj",
          "odedstein/bunny.obj",
          "odedstein/bunny_hr.obj",
          "odedstein/armadillo.obj",
          "odedstein/torus.obj",
          "odedstein/sphere.obj",
          "polygon_laplacian/hexaSphere.off",
          "polygon_laplacian/quad-sphere.off",
          "polygon_laplacian/sphere2.off",
          "pmp/chamfer-cube.off",
          "lagrange/cube.obj",
          "geomview/dodecahedron.off",
          "geomview/snub_dodecahedron.off",
          "generated:sphere",
          "generated:torus",
          "generated:knot"};
}

std::string shapeTestName(const std::string& name) {
  std::string s;
  for (char c : name) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return s;
}

std::shared_ptr<const PatchCache> closedShapeCache(const std::string& name) {
  PatchOptions o;
  if (name.rfind("generated:", 0) == 0) {
    const std::string what = name.substr(10);
    GeneratedMesh g;
    if (what == "sphere")
      g = quadSphere(1.0, 6);
    else if (what == "torus")
      g = torusMesh(1.0, 0.35, 24, 10);
    else if (what == "knot")
      g = torusKnot(TorusKnotParams{});
    else
      throw std::invalid_argument("unknown generated shape " + what);
    o.normals = NormalMode::File;
    const PolygonMesh pm = g.toPolygonMesh();
    std::vector<Eigen::Vector3d> cn;
    for (int v : pm.faceVertices) cn.push_back(g.normals[v]);
    PatchCache c = preparePatchCache(pm, cn, o, 0);
    constructPatches(c, Backend::Tbb);
    return std::make_shared<const PatchCache>(std::move(c));
  }
  const std::string path = std::string(SF_SHARED_MESHES) + "/" + name;
  return std::make_shared<const PatchCache>(buildPatchCache(loadMesh(path, o), o, Backend::Tbb));
}

// ---- the dense oracle ----

struct DenseOracle::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::unique_ptr<PointIndex> vertices;
  std::vector<int32_t> vertexFace;
  double diag = 1;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

DenseOracle::DenseOracle(const PatchCache& cache, long budget) : impl_(std::make_unique<Impl>()) {
  long corners = 0;
  for (int f = 0; f < cache.numFaces(); ++f) corners += cache.faceSize(f);
  level_ = 16;
  while (level_ > 1 && corners * level_ * level_ > budget) --level_;
  mesh_ = tessellatePatches(cache, level_,
                            [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
                              evaluatePatches(cache, f, x, y, n, out, Backend::Tbb);
                            });
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & GP_ST_NOT_BUILT) continue;
    const size_t before = domain_.size();
    domainRingPoints(cache.faceSize(f), level_, domain_);
    impl_->vertexFace.insert(impl_->vertexFace.end(), domain_.size() - before, f);
  }
  impl_->diag = boundingDiagonal(cache);
  impl_->vertices = std::make_unique<PointIndex>(mesh_.positions);
  impl_->device = rtcNewDevice(nullptr);
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), mesh_.positions.size()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), mesh_.triangles.size()));
  for (size_t i = 0; i < mesh_.positions.size(); ++i)
    for (int a = 0; a < 3; ++a) vb[3 * i + a] = float(mesh_.positions[i][a]);
  for (size_t i = 0; i < mesh_.triangles.size(); ++i)
    for (int a = 0; a < 3; ++a) ib[3 * i + a] = unsigned(mesh_.triangles[i][a]);
  rtcCommitGeometry(g);
  rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(impl_->scene);
}

DenseOracle::~DenseOracle() = default;

int DenseOracle::winding(const Eigen::Vector3d& q, bool* agree) const {
  static const Eigen::Vector3d kDir[3] = {Eigen::Vector3d(0.3, 0.5, 0.81).normalized(),
                                          Eigen::Vector3d(-0.6, 0.7, -0.2).normalized(),
                                          Eigen::Vector3d(0.1, -0.9, 0.4).normalized()};
  int w[3];
  for (int k = 0; k < 3; ++k) {
    w[k] = 0;
    float tnear = 0;
    for (int hits = 0; hits < 100000; ++hits) {  // every crossing, nearest first
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      RTCRayHit rh{};
      rh.ray.org_x = float(q.x());
      rh.ray.org_y = float(q.y());
      rh.ray.org_z = float(q.z());
      rh.ray.dir_x = float(kDir[k].x());
      rh.ray.dir_y = float(kDir[k].y());
      rh.ray.dir_z = float(kDir[k].z());
      rh.ray.tnear = tnear;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = 0xFFFFFFFFu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(impl_->scene, &ctx, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      const auto& t = mesh_.triangles[rh.hit.primID];
      const Eigen::Vector3d& a = mesh_.positions[t[0]];
      const double s = (mesh_.positions[t[1]] - a).cross(mesh_.positions[t[2]] - a).dot(kDir[k]);
      w[k] += s > 0 ? 1 : -1;
      // past this hit: a crossing shared by two triangles (an edge) is counted once
      tnear = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity()) + float(1e-7 * impl_->diag);
    }
  }
  if (agree) *agree = w[0] == w[1] && w[1] == w[2];
  return (w[0] == w[1] || w[0] == w[2]) ? w[0] : w[1];
}

DenseOracle::Nearest DenseOracle::nearest(const Eigen::Vector3d& q, PatchRefiner& refiner) const {
  // the nearest of: the 24 nearest dense vertices, and the refinements from the nearest of them
  // on each face they lie on (a sheet of another patch can pass nearer than the vertex spacing)
  constexpr size_t kK = 24;
  uint32_t idx[kK];
  double d2[kK];
  const size_t k = impl_->vertices->knn(q, kK, idx, d2);
  Nearest out;
  out.distance = std::numeric_limits<double>::infinity();
  ForceOptions o;
  o.angleTolerance = 1e-12;
  o.positionTolerance = 1e-14;
  o.maxIterations = 200;
  int triedFace[kK], nTried = 0;
  Eigen::Vector2d triedX[kK];
  for (size_t i = 0; i < k; ++i) {
    const uint32_t v = idx[i];
    if (std::sqrt(d2[i]) < out.distance) {
      out.point = mesh_.positions[v];
      out.normal = mesh_.normals[v];
      out.distance = std::sqrt(d2[i]);
      out.face = impl_->vertexFace[v];
    }
    const int f = impl_->vertexFace[v];
    bool seen = false;  // a start within two vertex spacings of one tried on the same face
    for (int j = 0; j < nTried && !seen; ++j)
      seen = triedFace[j] == f && (triedX[j] - domain_[v]).norm() < 2.0 / level_;
    if (seen) continue;
    triedFace[nTried] = f;
    triedX[nTried++] = domain_[v];
    const RefineResult r = refiner.refine(q, f, domain_[v].x(), domain_[v].y(), o);
    if (r.status & SF_TRACK_DEGENERATE) continue;
    const bool below = (q - r.scp).dot(r.normal) < 0 && !(r.status & SF_TRACK_FOLD_EDGE);
    const bool above = (q - r.scp).dot(r.normal) >= 0 && !(r.status & SF_TRACK_FOLD_EDGE);
    if (below) out.nearestBelow = std::min(out.nearestBelow, r.distance);
    if (above) out.nearestAbove = std::min(out.nearestAbove, r.distance);
    if (r.status & SF_TRACK_FOLD_EDGE) out.foldEdge = std::min(out.foldEdge, r.distance);
    if (r.distance < out.distance) {
      out.point = r.scp;
      out.normal = r.normal;
      out.distance = r.distance;
      out.face = r.face;
    }
  }
  return out;
}

SurfacePath walkSurface(const PatchCache& cache, PatchRefiner& refiner, int face, const Eigen::Vector2d& X,
                        const Eigen::Vector3d& direction, double step, int count) {
  SurfacePath path;
  ForceOptions o;
  o.angleTolerance = 1e-12;
  o.positionTolerance = 1e-14;
  o.maxIterations = 200;
  PatchPoint p = evaluatePatch(cache, face, X.x(), X.y());
  Eigen::Vector3d pos = p.pos, n = p.normal.normalized();
  Eigen::Vector3d t = (direction - direction.dot(n) * n).normalized();
  Eigen::Vector2d x = X;
  for (int i = 0; i < count; ++i) {
    path.point.push_back(pos);
    path.normal.push_back(n);
    path.face.push_back(face);
    const RefineResult r = refiner.refine(pos + step * t, face, x.x(), x.y(), o);
    if ((r.status & (SF_TRACK_DEGENERATE | SF_TRACK_FOLD_EDGE | SF_TRACK_BOUNDARY)) ||
        !(r.status & SF_TRACK_CONVERGED) || (r.scp - pos).norm() > 2 * step)
      break;
    path.faceChanges += r.face != face;
    n = r.normal.normalized();
    t = (t - t.dot(n) * n).normalized();
    pos = r.scp;
    face = r.face;
    x = {r.xi, r.eta};
  }
  return path;
}

}  // namespace sf::test
