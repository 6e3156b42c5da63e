#include <smoothforce/patch/tessellate.h>

#include "gp_config.h"

namespace sf {

void domainRingPoints(int n, int L, std::vector<Eigen::Vector2d>& out) {
  out.emplace_back(0, 0);
  for (int r = 1; r <= L; ++r)
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d a = domainCorner(n, k), b = domainCorner(n, (k + 1) % n);
      for (int j = 0; j < r; ++j) out.push_back((double(r) / L) * (a + (double(j) / r) * (b - a)));
    }
}

TriangleMesh tessellatePatches(const PatchCache& cache, int level, const BatchEvaluator& evaluate) {
  if (level < 1 || level > 256) throw InputError("--level: expected 1..256, got " + std::to_string(level));
  const int L = level;
  TriangleMesh out;
  std::vector<int32_t> qf;
  std::vector<double> qx, qy;
  std::vector<Eigen::Vector2d> dom;
  out.firstVertex.assign(cache.numFaces(), -1);
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & GP_ST_NOT_BUILT) continue;
    const int n = cache.faceSize(f);
    const int base = static_cast<int>(qf.size());
    out.firstVertex[f] = base;
    // ring r (0..L) has n r vertices (1 at the centre): the domain polygon scaled by r/L,
    // each side split in r; vertex (r, k, j) = (r/L) (C_k + j/r (C_{k+1} - C_k)).
    auto ringStart = [&](int r) { return r == 0 ? 0 : 1 + n * r * (r - 1) / 2; };
    auto idx = [&](int r, int k, int j) {  // j may equal r: the next side's first vertex
      if (r == 0) return base;
      return base + ringStart(r) + ((k * r + j) % (n * r));
    };
    dom.clear();
    domainRingPoints(n, L, dom);
    for (const Eigen::Vector2d& p : dom) {
      qf.push_back(f);
      qx.push_back(p.x());
      qy.push_back(p.y());
    }
    for (int r = 1; r <= L; ++r)
      for (int k = 0; k < n; ++k) {
        for (int j = 0; j < r; ++j) {
          out.triangles.push_back({idx(r, k, j), idx(r, k, j + 1), idx(r - 1, k, j)});
          out.face.push_back(f);
        }
        for (int j = 0; j + 1 < r; ++j) {
          out.triangles.push_back({idx(r - 1, k, j), idx(r, k, j + 1), idx(r - 1, k, j + 1)});
          out.face.push_back(f);
        }
      }
  }
  std::vector<PatchPoint> pts(qf.size());
  evaluate(qf.data(), qx.data(), qy.data(), qf.size(), pts.data());
  out.positions.reserve(pts.size());
  out.normals.reserve(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const PatchPoint& p = pts[i];
    out.positions.push_back(p.pos);
    out.normals.push_back(p.normal);
    out.status.push_back(p.status);
    out.fold.push_back((cache.faceStatus[qf[i]] & GP_ST_FOLD) ? 1 : 0);
    out.bulge.push_back(qf[i] < static_cast<int>(cache.faceBulge.size()) ? cache.faceBulge[qf[i]] : 0.0f);
  }
  return out;
}

}  // namespace sf
