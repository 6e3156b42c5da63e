// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/surface_faults.h>

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <smoothforce/query/patch_surface.h>

#include "fault_verdict.h"
#include "surface_tessellation.h"

namespace sf {

std::vector<int> SurfaceFaults::faultFaces() const {
  std::vector<int> f;
  for (size_t i = 0; i < faceFault.size(); ++i)
    if (faceFault[i] > 0) f.push_back(static_cast<int>(i));
  std::stable_sort(f.begin(), f.end(), [&](int a, int b) { return faceFault[a] > faceFault[b]; });
  return f;
}

FaultAttribution attributeFaults(const SurfaceFaults& faults, const std::vector<char>& near) {
  if (!near.empty() && near.size() != faults.faceFault.size())
    throw std::invalid_argument("attributeFaults: " + std::to_string(near.size()) + " face flags for " +
                                std::to_string(faults.faceFault.size()) + " faces");
  FaultAttribution a;
  for (const int f : faults.faultFaces()) {  // largest first, and so are both lists
    const bool input = !near.empty() && near[f];
    (input ? a.inputArea : a.constructionArea) += faults.faceFault[f];
    (input ? a.inputFaces : a.constructionFaces).push_back(f);
  }
  return a;
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

double surfaceProbeOffset(const PatchSurface& surface) { return 1e-5 * boundingDiagonal(surface.cache()); }

SurfaceVerdict triangleVerdict(const PatchSurface& surface, size_t t, double h, double* area2) noexcept {
  const UniformTessellation& u = surface.uniform();
  return faultVerdict(
      u.vertex[u.tri[t][0]], u.vertex[u.tri[t][1]], u.vertex[u.tri[t][2]], h,
      [&](const Eigen::Vector3d& back, const Eigen::Vector3d& dir, double length, int* atBack, int* atFront) {
        surface.windingsAlong(back, dir, length, atBack, atFront);
      },
      area2);
}

std::vector<std::array<Eigen::Vector3d, 3>> faultTriangles(const PatchSurface& surface, const SurfaceFaults& faults) {
  const UniformTessellation& u = surface.uniform();
  std::vector<std::array<Eigen::Vector3d, 3>> out;
  for (size_t t = 0; t < faults.verdict.size() && t < u.tri.size(); ++t)
    if (faults.verdict[t] != SurfaceVerdict::Consistent && faults.verdict[t] != SurfaceVerdict::Degenerate)
      out.push_back({u.vertex[u.tri[t][0]], u.vertex[u.tri[t][1]], u.vertex[u.tri[t][2]]});
  return out;
}

SurfaceFaults measureSurfaceFaults(const PatchSurface& surface) {
  SurfaceFaults r;
  const UniformTessellation& u = surface.uniform();
  r.level = surface.level();
  r.closed = surface.closed();
  r.faceFault.assign(surface.cache().numFaces(), 0.0);
  if (!r.closed) return r;
  r.offset = surfaceProbeOffset(surface);
  r.verdict.assign(u.tri.size(), SurfaceVerdict::Degenerate);
  std::vector<double> area2(u.tri.size(), 0.0);
  tbb::parallel_for(size_t(0), u.tri.size(),
                    [&](size_t t) { r.verdict[t] = triangleVerdict(surface, t, r.offset, &area2[t]); });
  for (size_t t = 0; t < u.tri.size(); ++t) {
    const auto v = static_cast<size_t>(r.verdict[t]);
    ++r.count[v];
    if (r.verdict[t] == SurfaceVerdict::Degenerate) continue;
    const double area = 0.5 * area2[t];
    ++r.triangles;
    r.area[v] += area;
    r.totalArea += area;
    if (r.verdict[t] != SurfaceVerdict::Consistent) r.faceFault[u.triFace[t]] += area;
  }
  return r;
}

}  // namespace sf
