// SPDX-License-Identifier: Apache-2.0
// Trajectory helpers of sweep_sampling.h: CSV points, polyline resampling, the default section loop.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>

#include <smoothforce/base/csv_reader.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/sweep/sweep_sampling.h>

namespace sf {

std::vector<Eigen::Vector3d> readPointsCsv(const std::string& path) {
  const NumericCsv t = readNumericCsv(path, {"x", "y", "z"});
  requirePositions(t, path);
  std::vector<Eigen::Vector3d> pts(t.rows());
  for (size_t r = 0; r < t.rows(); ++r) pts[r] = Eigen::Vector3d(t.at(r, 0), t.at(r, 1), t.at(r, 2));
  return pts;
}

void writePointsCsv(const std::vector<Eigen::Vector3d>& pts, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw InputError(path + ": cannot open for writing");
  std::fprintf(f, "x,y,z\n");
  for (const auto& p : pts) std::fprintf(f, "%.17g,%.17g,%.17g\n", p.x(), p.y(), p.z());
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad) throw InputError(path + ": write failed");
}

double polylineLength(const std::vector<Eigen::Vector3d>& pts) {
  double length = 0;
  for (size_t i = 0; i + 1 < pts.size(); ++i) length += (pts[i + 1] - pts[i]).stableNorm();  // no overflow below 1e308
  return length;
}

std::string resampleLimitError(const std::vector<Eigen::Vector3d>& pts, double step, const std::string& what) {
  const double length = polylineLength(pts);
  if (!(step > 0) || length / step <= kMaxResampledPoints) return {};
  char msg[256];
  std::snprintf(msg, sizeof msg,
                ": the polyline is %.6g m long; resampled every %.6g m it would take %.3g points, more than %.0e "
                "(a larger step, or a shorter polyline)",
                length, step, length / step, kMaxResampledPoints);
  return what + msg;
}

std::vector<Eigen::Vector3d> resamplePolyline(const std::vector<Eigen::Vector3d>& pts, double step) {
  std::vector<Eigen::Vector3d> out;
  if (pts.empty() || !(step > 0)) return out;
  if (const std::string e = resampleLimitError(pts, step, "trajectory"); !e.empty()) throw InputError(e);
  out.reserve(static_cast<size_t>(polylineLength(pts) / step) + 2);
  out.push_back(pts[0]);
  double carried = 0;  // arc length since the last output point
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const Eigen::Vector3d a = pts[i], b = pts[i + 1];
    const double len = (b - a).norm();
    double t = step - carried;  // distance along this segment of the next output point
    while (t <= len) {
      out.push_back(a + (t / len) * (b - a));
      t += step;
    }
    carried = len - (t - step);
  }
  return out;
}

namespace {

/// A box extent at most this fraction of the box's diagonal is flat (rounding of a planar mesh).
constexpr double kFlatExtent = 1e-9;

}  // namespace

std::vector<Eigen::Vector3d> longestSection(const std::vector<Eigen::Vector3d>& P,
                                            const std::vector<std::array<int, 3>>& tri, int axis, double c) {
  std::vector<double> s(P.size());
  for (size_t i = 0; i < P.size(); ++i) {
    s[i] = P[i][axis] - c;
    if (s[i] == 0) s[i] = 1e-300;  // no vertex exactly on the plane
  }
  auto key = [](int u, int v) { return (static_cast<uint64_t>(std::min(u, v)) << 32) | uint32_t(std::max(u, v)); };
  auto cross = [&](int u, int v) { return P[u] + (s[u] / (s[u] - s[v])) * (P[v] - P[u]); };
  std::vector<std::array<uint64_t, 2>> seg;
  std::unordered_map<uint64_t, std::vector<int>> at;
  std::unordered_map<uint64_t, Eigen::Vector3d> point;
  for (const auto& v : tri) {
    uint64_t ends[2];
    int ne = 0;
    for (int e = 0; e < 3; ++e) {
      const int a = v[e], b = v[(e + 1) % 3];
      if ((s[a] > 0) != (s[b] > 0) && ne < 2) {
        ends[ne++] = key(a, b);
        point.emplace(key(a, b), cross(a, b));
      }
    }
    if (ne != 2 || ends[0] == ends[1]) continue;
    const int sid = static_cast<int>(seg.size());
    seg.push_back({ends[0], ends[1]});
    at[ends[0]].push_back(sid);
    at[ends[1]].push_back(sid);
  }
  std::vector<char> used(seg.size(), 0);
  std::vector<Eigen::Vector3d> best;
  double bestLen = 0;
  for (size_t s0 = 0; s0 < seg.size(); ++s0) {
    if (used[s0]) continue;
    std::vector<Eigen::Vector3d> loop;
    uint64_t cur = seg[s0][0];
    int sid = static_cast<int>(s0);
    loop.push_back(point[cur]);
    while (sid >= 0 && !used[sid]) {
      used[sid] = 1;
      cur = seg[sid][0] == cur ? seg[sid][1] : seg[sid][0];
      loop.push_back(point[cur]);
      int next = -1;
      for (int cand : at[cur])
        if (!used[cand]) next = cand;
      sid = next;
    }
    const double len = polylineLength(loop);
    if (len > bestLen) {
      bestLen = len;
      best.swap(loop);
    }
  }
  return best;
}

namespace {

/// The welded level-L tessellation of faces[0..count) (their ring points in order, each point's
/// weld key its position rounded to a grid of `tol` m; a key's first point is the vertex) into
/// (P, tri): triangles with three distinct vertices, in order.
void weldedRings(const PatchCache& cache, int level, const std::vector<int32_t>& faces, double tol,
                 const BatchEvaluator& evaluate, std::vector<Eigen::Vector3d>& P,
                 std::vector<std::array<int, 3>>& tri) {
  struct KeyHash {  // XXH64 of the three grid coordinates
    size_t operator()(const std::array<long long, 3>& k) const noexcept {
      return static_cast<size_t>(hashBytes(k.data(), sizeof k));
    }
  };
  std::unordered_map<std::array<long long, 3>, int, KeyHash> weld;
  std::vector<int> id;
  std::vector<std::array<int32_t, 3>> local;
  P.clear();
  tri.clear();
  visitRingPoints(cache, level, faces.data(), faces.size(), evaluate,
                  [&](size_t i, const Eigen::Vector2d*, const PatchPoint* pts, size_t m) {
                    id.resize(m);
                    for (size_t v = 0; v < m; ++v) {
                      std::array<long long, 3> key;
                      for (int a = 0; a < 3; ++a) key[a] = std::llround(pts[v].pos[a] / tol);
                      auto [it, fresh] = weld.emplace(key, static_cast<int>(P.size()));
                      if (fresh) P.push_back(pts[v].pos);
                      id[v] = it->second;
                    }
                    local.clear();
                    ringTriangles(cache.faceSize(faces[i]), level, 0, local);
                    for (const auto& t : local) {
                      const std::array<int, 3> w = {id[t[0]], id[t[1]], id[t[2]]};
                      if (w[0] != w[1] && w[1] != w[2] && w[0] != w[2]) tri.push_back(w);
                    }
                  });
}

}  // namespace

std::vector<Eigen::Vector3d> defaultTrajectory(const PatchCache& cache, int level) {
  const std::vector<int32_t> built = builtFaces(cache);
  if (level < 1 || level > 256) throw InputError("--level: expected 1..256, got " + std::to_string(level));
  if (built.empty()) return {};
  const BatchEvaluator evaluate = [&](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    evaluatePatches(cache, f, x, y, n, out, Backend::Tbb);
  };
  // The section is that of the whole welded level-L tessellation, but only the faces near the
  // cutting plane take part in it: each face's ring points are evaluated once for its box (and
  // the whole tessellation's, which places the plane), and the faces near the plane again for
  // the weld and the section (on a 70k-face mesh 0.5 s instead of 6 s, and no array of every
  // point). Min and max in the order of the points, as over the whole tessellation: a NaN first
  // point keeps the box NaN, later NaNs are passed over.
  std::vector<Eigen::Vector3d> faceLo(built.size()), faceHi(built.size());
  std::vector<char> finite(built.size(), 1);
  Eigen::Vector3d lo, hi;
  visitRingPoints(cache, level, built.data(), built.size(), evaluate, [&](size_t i, const Eigen::Vector2d*, const PatchPoint* pts, size_t m) {
    if (i == 0) lo = hi = pts[0].pos;
    Eigen::Vector3d a = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), b = -a;
    for (size_t v = 0; v < m; ++v) {
      a = a.cwiseMin(pts[v].pos);
      b = b.cwiseMax(pts[v].pos);
      finite[i] = finite[i] && pts[v].pos.allFinite();
    }
    faceLo[i] = a;
    faceHi[i] = b;
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  });
  // Weld the patches' shared boundary vertices (each patch has its own copies).
  const double tol = 1e-7 * std::max((hi - lo).norm(), 1e-300);
  // the box's axes from the shortest: a flat mesh lies in the plane normal to its shortest axis
  // (within rounding: a section there is rounding noise, so that axis is passed over), and the
  // next axis cuts across it
  const Eigen::Vector3d extent = hi - lo;
  std::array<int, 3> axes = {0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return extent[a] < extent[b]; });
  std::vector<Eigen::Vector3d> P;
  std::vector<std::array<int, 3>> tri;
  for (const int axis : axes) {
    if (!(extent[axis] > kFlatExtent * extent.norm())) continue;
    const double c = 0.5 * (lo[axis] + hi[axis]);
    // A triangle crosses the plane where its welded vertices do; each lies in the weld cell
    // (diagonal sqrt(3) tol) of every copy of it, so its face's points reach within that of the
    // plane. Such a face's points lie within `reach` of the plane, and every point welded with
    // one of them (an earlier copy gives the vertex's position) within reach + sqrt(3) tol: the
    // faces with points there are welded, in order, as in the whole tessellation; a face with
    // a non-finite point always is.
    const double near = 2 * tol;
    double reach = near;
    for (size_t i = 0; i < built.size(); ++i)
      if (finite[i] && faceLo[i][axis] <= c + near && faceHi[i][axis] >= c - near)
        reach = std::max(reach, std::max(faceHi[i][axis] - c, c - faceLo[i][axis]));
    reach += 2 * tol;
    std::vector<int32_t> faces;
    for (size_t i = 0; i < built.size(); ++i)
      if (!finite[i] || (faceLo[i][axis] <= c + reach && faceHi[i][axis] >= c - reach)) faces.push_back(built[i]);
    weldedRings(cache, level, faces, tol, evaluate, P, tri);
    std::vector<Eigen::Vector3d> best = longestSection(P, tri, axis, c);
    if (!best.empty()) return best;
  }
  return {};
}

}  // namespace sf
