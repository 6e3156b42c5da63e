#include <smoothforce/patch/tessellate.h>

#include <cstdio>
#include <fstream>

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
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & (GP_ST_TOO_MANY_SIDES | GP_ST_NONFINITE)) continue;
    const int n = cache.faceSize(f);
    const int base = static_cast<int>(qf.size());
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
  for (const PatchPoint& p : pts) {
    out.positions.push_back(p.pos);
    out.normals.push_back(p.normal);
  }
  return out;
}

void writeTriangleMesh(const TriangleMesh& m, const std::string& path) {
  const auto dot = path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  if (ext != ".obj" && ext != ".ply") throw InputError(path + ": output must end in .obj or .ply");
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw InputError(path + ": cannot open for writing");
  if (ext == ".obj") {
    std::fprintf(f, "# SmoothForce patch tessellation: %zu vertices, %zu triangles\n", m.positions.size(),
                 m.triangles.size());
    for (const auto& p : m.positions) std::fprintf(f, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    for (const auto& n : m.normals) std::fprintf(f, "vn %.6g %.6g %.6g\n", n.x(), n.y(), n.z());
    for (const auto& t : m.triangles)
      std::fprintf(f, "f %d//%d %d//%d %d//%d\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1);
  } else {
    std::fprintf(f,
                 "ply\nformat ascii 1.0\ncomment SmoothForce patch tessellation\nelement vertex %zu\n"
                 "property double x\nproperty double y\nproperty double z\nproperty float nx\n"
                 "property float ny\nproperty float nz\nelement face %zu\n"
                 "property list uchar int vertex_indices\nproperty int patch\nend_header\n",
                 m.positions.size(), m.triangles.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
      const auto& p = m.positions[i];
      const auto& n = m.normals[i];
      std::fprintf(f, "%.9g %.9g %.9g %.6g %.6g %.6g\n", p.x(), p.y(), p.z(), n.x(), n.y(), n.z());
    }
    for (size_t t = 0; t < m.triangles.size(); ++t)
      std::fprintf(f, "3 %d %d %d %d\n", m.triangles[t][0], m.triangles[t][1], m.triangles[t][2], m.face[t]);
  }
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad) throw InputError(path + ": write failed");
}

}  // namespace sf
