// SPDX-License-Identifier: Apache-2.0
#include "surface_tessellation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include "gp_config.h"

namespace sf {
namespace {

/// Error samples of a triangle: its centroid and its three edge midpoints (weights on a, b, c).
constexpr double kW[4][3] = {{1. / 3, 1. / 3, 1. / 3}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};
/// The corners of the edge whose midpoint is sample 1 + e (kW).
constexpr int kEdge[3][2] = {{0, 1}, {1, 2}, {0, 2}};

Eigen::Matrix<double, 3, 2> jacobian(const PatchPoint& p) {
  Eigen::Matrix<double, 3, 2> J;
  J << p.dxi, p.deta;
  return J;
}

/// Radius of the smallest circle holding the domain triangle X: half its longest edge where it
/// has no acute-only angles (right, obtuse or degenerate), its circumradius otherwise. It is the
/// largest value of sqrt(sum_a lambda_a |V_a - X|^2) over the triangle (that sum is R^2 - |X -
/// O|^2 about the circumcentre O), and so of sum_a lambda_a |V_a - X| (Jensen).
double enclosingRadius(const std::array<Eigen::Vector2d, 3>& X) {
  double e2[3];
  for (int a = 0; a < 3; ++a) e2[a] = (X[(a + 1) % 3] - X[a]).squaredNorm();
  const double longest = std::max({e2[0], e2[1], e2[2]});
  const double area2 = std::abs((X[1] - X[0]).x() * (X[2] - X[0]).y() - (X[1] - X[0]).y() * (X[2] - X[0]).x());
  if (2 * longest >= e2[0] + e2[1] + e2[2] || !(area2 > 0)) return 0.5 * std::sqrt(longest);
  return std::sqrt(e2[0] * e2[1] * e2[2]) / (2 * area2);  // abc / (4 area)
}

/// Error of a triangle from its corners (domain X, evaluations c) and its 4 samples s: the larger
/// of twice the sampled deviation |G(X) - linear(X)| and a bound from the Jacobians J. With J =
/// Jl + rho, Jl the linear interpolation of the corners' Jacobians (exact where G is quadratic),
/// the mean value theorem along the segments from X to the corners V_a gives G(X) - linear(X) =
/// -1/2 sum_a lambda_a J_a (V_a - X) - sum_a lambda_a avg(rho) (V_a - X): the first part is the
/// quadratic that vanishes at the corners with midpoint values -(J_a - J_b)(V_a - V_b) / 8, at
/// most 4/3 of the largest (at the centroid), and the second at most r max|rho| (r the radius of
/// the smallest circle holding the domain triangle, at most 0.58 of its longest edge), max|rho|
/// taken at the 4 samples: it sees the folds and turns inside the triangle that the midpoints
/// miss. Infinite when an evaluation is not finite.
///
/// `levelEstimate` (optional) receives the same estimate with the longest domain edge h for r:
/// the tessellation's level is chosen from it (choosePatchSurfaceLevel). The level is also the
/// spacing 1 / level within which the global query's refinements stand in for each other
/// (refineCandidates), and at the coarser levels the tighter bound would choose, candidates of
/// other basins were skipped there (three exactness tests failed): the bounds tighten, the
/// level does not.
double triangleError(const std::array<Eigen::Vector2d, 3>& X, const PatchPoint* c, const PatchPoint* s,
                     double* levelEstimate = nullptr) {
  double dev = 0, rho = 0;
  Eigen::Matrix<double, 3, 2> J[3];
  for (int a = 0; a < 3; ++a) J[a] = jacobian(c[a]);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d lin = kW[k][0] * c[0].pos + kW[k][1] * c[1].pos + kW[k][2] * c[2].pos;
    dev = std::max(dev, (s[k].pos - lin).norm());
    const Eigen::Matrix<double, 3, 2> Jl = kW[k][0] * J[0] + kW[k][1] * J[1] + kW[k][2] * J[2];
    rho = std::max(rho, (jacobian(s[k]) - Jl).norm());
  }
  double h = 0, quadratic = 0;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3;
    h = std::max(h, (X[a] - X[b]).norm());
    quadratic = std::max(quadratic, ((J[a] - J[b]) * (X[a] - X[b])).norm() / 6);
  }
  auto finite = [](double e) { return std::isfinite(e) ? e : std::numeric_limits<double>::infinity(); };
  if (levelEstimate) *levelEstimate = finite(std::max(2 * dev, quadratic + h * rho));
  return finite(std::max(2 * dev, quadratic + enclosingRadius(X) * rho));
}

/// A batch of points to evaluate.
struct Batch {
  std::vector<int32_t> f;
  std::vector<double> x, y;
  void add(int face, const Eigen::Vector2d& X) {
    f.push_back(face);
    x.push_back(X.x());
    y.push_back(X.y());
  }
  std::vector<PatchPoint> run(const PatchCache& cache, Backend backend = Backend::Tbb) const {
    std::vector<PatchPoint> out(f.size());
    evaluatePatches(cache, f.data(), x.data(), y.data(), f.size(), out.data(), backend);
    return out;
  }
};

void addSamples(Batch& b, int face, const std::array<Eigen::Vector2d, 3>& X) {
  for (int k = 0; k < 4; ++k) b.add(face, kW[k][0] * X[0] + kW[k][1] * X[1] + kW[k][2] * X[2]);
}

}  // namespace

double evaluationNoise(const PatchCache& cache) {
  Eigen::Vector3d lo, hi;
  referencedBox(cache, lo, hi);
  const double far = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  // about 450 roundings of the size (the control net's magnitude), 64 of the coordinates (the
  // weights' sum: measured at 1e7-1e11 m, an evaluation moved by about 10-20 roundings)
  const bool dbl = cache.options.precision == Precision::Double;
  return std::max((dbl ? 1e-13 : 2e-6) * (hi - lo).norm(),  // = boundingDiagonal(cache)
                  (dbl ? 64 * std::numeric_limits<double>::epsilon() : 16 * std::numeric_limits<float>::epsilon()) * far);
}

int64_t trianglesAtLevel(const PatchCache& cache, int L) {
  int64_t n = 0;
  for (int f = 0; f < cache.numFaces(); ++f)
    if (!(cache.faceStatus[f] & GP_ST_NOT_BUILT)) n += int64_t(cache.faceSize(f)) * L * L;
  return n;
}

UniformTessellation tessellateUniform(const PatchCache& cache, int L, bool errors, const std::vector<int>* only,
                                      std::vector<double>* levelEstimate) {
  UniformTessellation t;
  t.level = L;
  // layout: every built face's ring points and triangles, in face order; first[i]..first[i+1]:
  // face faces[i]'s vertices, tfirst likewise its triangles
  std::vector<int> faces;
  std::vector<size_t> first{0}, tfirst{0};
  std::vector<Eigen::Vector2d> dom;
  std::vector<std::array<int32_t, 3>> local;
  t.faceFirstTri.assign(cache.numFaces(), -1);
  std::vector<char> wanted(cache.numFaces(), only ? 0 : 1);
  if (only)
    for (const int f : *only) wanted[f] = 1;
  for (int f = 0; f < cache.numFaces(); ++f) {
    if ((cache.faceStatus[f] & GP_ST_NOT_BUILT) || !wanted[f]) continue;
    t.faceFirstTri[f] = static_cast<int64_t>(t.tri.size());
    const int n = cache.faceSize(f), base = static_cast<int>(t.domain.size());
    dom.clear();
    domainRingPoints(n, L, dom);
    t.domain.insert(t.domain.end(), dom.begin(), dom.end());
    local.clear();
    ringTriangles(n, L, 0, local);
    for (const auto& tr : local) {
      t.tri.push_back({base + tr[0], base + tr[1], base + tr[2]});
      t.triFace.push_back(f);
    }
    faces.push_back(f);
    first.push_back(t.domain.size());
    tfirst.push_back(t.tri.size());
  }
  t.vertex.resize(t.domain.size());
  t.error.resize(t.tri.size());
  if (levelEstimate) levelEstimate->assign(errors ? t.tri.size() : 0, 0.0);
  // positions and error bounds a few faces at a time: the evaluations of a chunk (its vertices,
  // then the error samples of its triangles) stay in cache instead of one array of every point;
  // the values are the same (PatchEvaluator's results do not depend on how the points are grouped)
  tbb::parallel_for(tbb::blocked_range<size_t>(0, faces.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    const size_t v0 = first[r.begin()], v1 = first[r.end()], t0 = tfirst[r.begin()], t1 = tfirst[r.end()];
    Batch b;
    for (size_t i = r.begin(); i < r.end(); ++i)
      for (size_t v = first[i]; v < first[i + 1]; ++v) b.add(faces[i], t.domain[v]);
    // the error samples (triangleError): each triangle's centroid, then each edge's midpoint once,
    // shared by the two triangles of the chunk along it (0.5 a + 0.5 b: the point either
    // triangle's kW weights give); mid[3 i + e]: the midpoint of triangle t0 + i's edge e (kEdge)
    std::vector<uint32_t> mid;
    if (errors) {
      for (size_t i = t0; i < t1; ++i)
        b.add(t.triFace[i],
              kW[0][0] * t.domain[t.tri[i][0]] + kW[0][1] * t.domain[t.tri[i][1]] + kW[0][2] * t.domain[t.tri[i][2]]);
      std::vector<std::pair<uint64_t, uint32_t>> edges;  // (lower vertex, higher vertex), slot
      edges.reserve(3 * (t1 - t0));
      for (size_t i = t0; i < t1; ++i)
        for (int e = 0; e < 3; ++e) {
          const uint64_t a = uint64_t(t.tri[i][kEdge[e][0]] - v0), c = uint64_t(t.tri[i][kEdge[e][1]] - v0);
          edges.push_back({std::min(a, c) << 32 | std::max(a, c), uint32_t(3 * (i - t0) + e)});
        }
      std::sort(edges.begin(), edges.end());
      mid.resize(edges.size());
      const size_t firstMid = b.f.size();
      for (size_t k = 0; k < edges.size(); ++k) {
        if (k == 0 || edges[k].first != edges[k - 1].first) {
          const size_t lo = v0 + (edges[k].first >> 32), hi = v0 + (edges[k].first & 0xffffffffu);
          b.add(t.triFace[t0 + edges[k].second / 3], 0.5 * t.domain[lo] + 0.5 * t.domain[hi]);
        }
        mid[edges[k].second] = static_cast<uint32_t>(b.f.size() - 1 - firstMid);
      }
    }
    const std::vector<PatchPoint> pts = b.run(cache, Backend::Serial);
    for (size_t v = v0; v < v1; ++v) t.vertex[v] = pts[v - v0].pos;
    if (!errors) return;
    const PatchPoint* centroid = pts.data() + (v1 - v0);
    const PatchPoint* mids = centroid + (t1 - t0);
    for (size_t i = t0; i < t1; ++i) {
      const auto& tr = t.tri[i];
      const PatchPoint c[3] = {pts[tr[0] - v0], pts[tr[1] - v0], pts[tr[2] - v0]};
      const size_t j = i - t0;
      const PatchPoint s[4] = {centroid[j], mids[mid[3 * j]], mids[mid[3 * j + 1]], mids[mid[3 * j + 2]]};
      t.error[i] = triangleError({t.domain[tr[0]], t.domain[tr[1]], t.domain[tr[2]]}, c, s,
                                 levelEstimate ? &(*levelEstimate)[i] : nullptr);
    }
  });
  return t;
}

int64_t uniformTriangleAt(const UniformTessellation& u, const PatchCache& cache, int f, const Eigen::Vector2d& X) {
  if (f < 0 || f >= cache.numFaces() || static_cast<size_t>(f) >= u.faceFirstTri.size() || u.faceFirstTri[f] < 0 ||
      !X.allFinite())
    return -1;
  const int n = cache.faceSize(f), L = u.level;
  const gpd::gp_domain* dom = Gp<double>::domain(n);
  // sector k: the domain triangle (0, C_k, C_k+1) with X = a C_k + b C_k+1, a, b >= 0 (the
  // first such k; where none is, the one X is least outside of)
  auto cross = [](double ax, double ay, double bx, double by) { return ax * by - ay * bx; };
  const double det = cross(dom->cx[0], dom->cy[0], dom->cx[1 % n], dom->cy[1 % n]);  // sin(2 pi / n)
  int k = 0;
  double a = 0, b = 0, worst = -std::numeric_limits<double>::infinity();
  for (int s = 0; s < n; ++s) {
    const int s1 = s + 1 == n ? 0 : s + 1;
    const double as = cross(X.x(), X.y(), dom->cx[s1], dom->cy[s1]) / det;
    const double bs = cross(dom->cx[s], dom->cy[s], X.x(), X.y()) / det;
    const double m = std::min(as, bs);
    if (m > worst) {
      worst = m;
      k = s;
      a = as;
      b = bs;
    }
    if (m >= 0) break;
  }
  // lattice coordinates of the sector (vertex (r, k, j) of the ring layout is (r - j, j)): cell
  // (i, j) holds the up triangle j of ring i + j + 1 and, above its diagonal, the down triangle j
  // of ring i + j + 2
  const double uu = std::max(a, 0.0) * L, vv = std::max(b, 0.0) * L;
  int i = static_cast<int>(std::min(std::floor(uu), double(L - 1)));
  int j = static_cast<int>(std::min(std::floor(vv), double(L - 1)));
  if (const int over = i + j - (L - 1); over > 0) {  // beyond the outer ring (rounding, X outside): its cells
    const int di = std::min(i, over);
    i -= di;
    j -= over - di;
  }
  const bool down = i + j < L - 1 && (uu - i) + (vv - j) > 1;
  const int r = i + j + (down ? 2 : 1);
  return u.faceFirstTri[f] + int64_t(n) * (r - 1) * (r - 1) + int64_t(k) * (2 * r - 1) + (down ? r + j : j);
}

AdaptiveTessellation tessellateAdaptive(const PatchCache& cache, const UniformTessellation& u, double maxError,
                                        int maxDepth, size_t budget) {
  constexpr size_t kMaxRef = size_t(std::numeric_limits<int32_t>::max());
  if (u.tri.size() > kMaxRef) throw std::length_error("adaptive tessellation: too many uniform triangles");
  AdaptiveTessellation out;
  // the triangles still to split, and for those of depth 0 the uniform triangle each is (-1 for
  // a piece): one kept whole at the end is stored as that reference
  std::vector<SurfaceTriangle> todo;
  std::vector<int32_t> todoRef;
  auto keep = [&](const SurfaceTriangle& s, int32_t uniformRef) {
    if (uniformRef >= 0) {
      out.ref.push_back(uniformRef);
      return;
    }
    if (out.children.size() >= kMaxRef) throw std::length_error("adaptive tessellation: too many triangles");
    out.ref.push_back(-1 - static_cast<int32_t>(out.children.size()));
    out.children.push_back(s);
  };
  out.ref.reserve(u.tri.size());  // most are kept whole
  for (size_t i = 0; i < u.tri.size(); ++i) {
    if (!(u.error[i] > maxError)) {
      out.ref.push_back(static_cast<int32_t>(i));
      continue;
    }
    SurfaceTriangle s;
    s.face = u.triFace[i];
    for (int a = 0; a < 3; ++a) {
      s.X[a] = u.domain[u.tri[i][a]];
      s.P[a] = u.vertex[u.tri[i][a]];
    }
    s.error = u.error[i];
    todo.push_back(s);
    todoRef.push_back(static_cast<int32_t>(i));
  }
  bool full = false;
  for (int depth = 0; depth < maxDepth && !todo.empty() && !full; ++depth) {
    // each split adds 3 triangles: where the budget cannot take them all, the largest errors first
    const size_t have = out.size() + todo.size();
    const size_t room = budget > have ? (budget - have) / 3 : 0;
    if (room < todo.size()) {
      std::vector<size_t> order(todo.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return todo[a].error > todo[b].error; });
      for (size_t i = room; i < order.size(); ++i) keep(todo[order[i]], todoRef[order[i]]);
      std::vector<SurfaceTriangle> first(room);
      for (size_t i = 0; i < room; ++i) first[i] = todo[order[i]];
      todo = std::move(first);
      full = true;
    }
    todoRef.clear();
    // children at the edge midpoints: corners (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)
    std::vector<SurfaceTriangle> kids(4 * todo.size());
    constexpr int kSamplesPerParent = 13;
    // a chunk of parents at a time: per parent its 3 corners and 3 edge midpoints (the children's
    // corners, with the Jacobians the error bound needs), then the error samples of the corner
    // children (4 each) and the middle one's centroid: its edges are the corner children's inner
    // edges, whose midpoints those hold (0.5 a + 0.5 b either way round); the same points (and
    // so the same values) as evaluating every child's corners and samples on their own
    tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      const int idx[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};  // 0..2 corners, 3..5 mids
      Batch b, sb;
      for (size_t i = r.begin(); i < r.end(); ++i) {
        const SurfaceTriangle& s = todo[i];
        const std::array<Eigen::Vector2d, 3> mX = {0.5 * (s.X[0] + s.X[1]), 0.5 * (s.X[1] + s.X[2]),
                                                   0.5 * (s.X[2] + s.X[0])};
        for (int a = 0; a < 3; ++a) b.add(s.face, s.X[a]);
        for (int a = 0; a < 3; ++a) b.add(s.face, mX[a]);  // ab, bc, ca
        for (int k = 0; k < 4; ++k) {
          SurfaceTriangle& c = kids[4 * i + k];
          c.face = s.face;
          for (int a = 0; a < 3; ++a) c.X[a] = idx[k][a] < 3 ? s.X[idx[k][a]] : mX[idx[k][a] - 3];
          if (k < 3) {
            addSamples(sb, c.face, c.X);
          } else {
            sb.add(c.face, kW[0][0] * c.X[0] + kW[0][1] * c.X[1] + kW[0][2] * c.X[2]);
          }
        }
      }
      const std::vector<PatchPoint> pts = b.run(cache, Backend::Serial), sp = sb.run(cache, Backend::Serial);
      for (size_t i = r.begin(); i < r.end(); ++i) {
        const SurfaceTriangle& s = todo[i];
        const PatchPoint* q = &pts[6 * (i - r.begin())];  // corners a, b, c, then mids ab, bc, ca
        for (int k = 0; k < 4; ++k) {
          SurfaceTriangle& c = kids[4 * i + k];
          PatchPoint corner[3];
          for (int a = 0; a < 3; ++a) {
            const int j = idx[k][a];
            c.P[a] = j < 3 ? s.P[j] : q[j].pos;
            corner[a] = q[j];
          }
          // the middle child (ab, bc, ca): its centroid, then the midpoints of ab-bc (child 1's
          // edge 2), bc-ca (child 2's edge 0) and ab-ca (child 0's edge 1)
          const PatchPoint* own = &sp[kSamplesPerParent * (i - r.begin())];
          const PatchPoint middle[4] = {own[12], own[4 + 3], own[8 + 1], own[0 + 2]};
          c.error = triangleError(c.X, corner, k < 3 ? own + 4 * k : middle);
        }
      }
    });
    todo.clear();
    for (const SurfaceTriangle& c : kids) {
      if (c.error > maxError && depth + 1 < maxDepth && !full) {
        todo.push_back(c);
        todoRef.push_back(-1);
      } else {
        keep(c, -1);
      }
    }
  }
  for (size_t i = 0; i < todo.size(); ++i) keep(todo[i], todoRef[i]);
  return out;
}

}  // namespace sf
