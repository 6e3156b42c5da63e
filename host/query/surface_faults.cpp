#include <smoothforce/query/surface_faults.h>

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <smoothforce/query/patch_surface.h>

#include "surface_tessellation.h"

namespace sf {

std::vector<int> SurfaceFaults::faultFaces() const {
  std::vector<int> f;
  for (size_t i = 0; i < faceFault.size(); ++i)
    if (faceFault[i] > 0) f.push_back(static_cast<int>(i));
  std::stable_sort(f.begin(), f.end(), [&](int a, int b) { return faceFault[a] > faceFault[b]; });
  return f;
}

const char* toString(SurfaceVerdict v) {
  switch (v) {
    case SurfaceVerdict::Consistent: return "consistent";
    case SurfaceVerdict::Folded: return "folded";
    case SurfaceVerdict::Overlapping: return "overlapping";
    case SurfaceVerdict::Thin: return "thin";
    case SurfaceVerdict::Degenerate: return "degenerate";
  }
  return "?";
}

SurfaceFaults measureSurfaceFaults(const PatchSurface& surface) {
  SurfaceFaults r;
  const UniformTessellation& u = surface.uniform();
  r.level = surface.level();
  r.closed = surface.closed();
  r.faceFault.assign(surface.cache().numFaces(), 0.0);
  if (!r.closed) return r;
  r.offset = 1e-5 * boundingDiagonal(surface.cache());
  r.verdict.assign(u.tri.size(), SurfaceVerdict::Degenerate);
  std::vector<double> area(u.tri.size(), 0.0);
  tbb::parallel_for(size_t(0), u.tri.size(), [&](size_t t) {
    const Eigen::Vector3d& a = u.vertex[u.tri[t][0]];
    const Eigen::Vector3d& b = u.vertex[u.tri[t][1]];
    const Eigen::Vector3d& c = u.vertex[u.tri[t][2]];
    const Eigen::Vector3d x = (b - a).cross(c - a);
    const double len = x.norm();
    if (!(len > 0) || !std::isfinite(len)) return;
    area[t] = 0.5 * len;
    const Eigen::Vector3d mid = (a + b + c) / 3.0, n = x / len;
    const int front = surface.winding(mid + r.offset * n), back = surface.winding(mid - r.offset * n);
    r.verdict[t] = front == 0 && back == 1 ? SurfaceVerdict::Consistent
                   : front > back          ? SurfaceVerdict::Folded
                   : front < back          ? SurfaceVerdict::Overlapping
                                           : SurfaceVerdict::Thin;
  });
  for (size_t t = 0; t < u.tri.size(); ++t) {
    const auto v = static_cast<size_t>(r.verdict[t]);
    ++r.count[v];
    if (r.verdict[t] == SurfaceVerdict::Degenerate) continue;
    ++r.triangles;
    r.area[v] += area[t];
    r.totalArea += area[t];
    if (r.verdict[t] != SurfaceVerdict::Consistent) r.faceFault[u.triFace[t]] += area[t];
  }
  return r;
}

}  // namespace sf
