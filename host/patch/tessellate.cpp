// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/tessellate.h>

#include <string>

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

void ringTriangles(int n, int L, int32_t base, std::vector<std::array<int32_t, 3>>& out) {
  // ring r (0..L) has n r vertices (1 at the centre): the domain polygon scaled by r/L, each
  // side split in r; vertex (r, k, j) = (r/L) (C_k + j/r (C_{k+1} - C_k)).
  auto ringStart = [&](int r) { return r == 0 ? 0 : 1 + n * r * (r - 1) / 2; };
  auto idx = [&](int r, int k, int j) {  // j may equal r: the next side's first vertex
    return base + (r == 0 ? 0 : ringStart(r) + ((k * r + j) % (n * r)));
  };
  for (int r = 1; r <= L; ++r)
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < r; ++j) out.push_back({idx(r, k, j), idx(r, k, j + 1), idx(r - 1, k, j)});
      for (int j = 0; j + 1 < r; ++j) out.push_back({idx(r - 1, k, j), idx(r, k, j + 1), idx(r - 1, k, j + 1)});
    }
}

std::vector<int32_t> builtFaces(const PatchCache& cache) {
  std::vector<int32_t> faces;
  for (int f = 0; f < cache.numFaces(); ++f)
    if (!(cache.faceStatus[f] & GP_ST_NOT_BUILT)) faces.push_back(f);
  return faces;
}

void visitRingPoints(
    const PatchCache& cache, int level, const int32_t* faces, size_t count, const BatchEvaluator& evaluate,
    const std::function<void(size_t i, const Eigen::Vector2d* X, const PatchPoint* points, size_t m)>& visit) {
  if (level < 1 || level > 256) throw InputError("--level: expected 1..256, got " + std::to_string(level));
  constexpr size_t kBatchPoints = size_t(1) << 18;
  std::vector<int32_t> qf;
  std::vector<double> qx, qy;
  std::vector<size_t> first;  // the batch's faces' first points
  std::vector<Eigen::Vector2d> dom;
  std::vector<PatchPoint> pts;
  for (size_t b = 0; b < count;) {
    qf.clear();
    qx.clear();
    qy.clear();
    first.clear();
    dom.clear();
    size_t e = b;
    for (; e < count && (e == b || qf.size() < kBatchPoints); ++e) {
      first.push_back(qf.size());
      domainRingPoints(cache.faceSize(faces[e]), level, dom);
      for (size_t v = first.back(); v < dom.size(); ++v) {
        qf.push_back(faces[e]);
        qx.push_back(dom[v].x());
        qy.push_back(dom[v].y());
      }
    }
    first.push_back(qf.size());
    pts.resize(qf.size());
    evaluate(qf.data(), qx.data(), qy.data(), qf.size(), pts.data());
    for (size_t i = b; i < e; ++i)
      visit(i, dom.data() + first[i - b], pts.data() + first[i - b], first[i - b + 1] - first[i - b]);
    b = e;
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
    dom.clear();
    domainRingPoints(n, L, dom);
    for (const Eigen::Vector2d& p : dom) {
      qf.push_back(f);
      qx.push_back(p.x());
      qy.push_back(p.y());
    }
    const size_t t0 = out.triangles.size();
    ringTriangles(n, L, base, out.triangles);
    out.face.insert(out.face.end(), out.triangles.size() - t0, f);
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
