#include "surface_tessellation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include "gp_config.h"

namespace sf {
namespace {

constexpr uint32_t kNotBuilt = GP_ST_TOO_MANY_SIDES | GP_ST_NONFINITE;

/// Error samples of a triangle: its centroid and its three edge midpoints (weights on a, b, c).
constexpr double kW[4][3] = {{1. / 3, 1. / 3, 1. / 3}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};

Eigen::Matrix<double, 3, 2> jacobian(const PatchPoint& p) {
  Eigen::Matrix<double, 3, 2> J;
  J << p.dxi, p.deta;
  return J;
}

/// Error bound of a triangle from its corners (domain X, evaluations c) and its 4 samples s: the
/// larger of twice the sampled deviation |G(X) - linear(X)| and the first-order bound
/// (h / 2) osc(J), h its longest domain edge and osc(J) the largest difference of the Jacobian
/// between the 7 points (mean value theorem along each segment; it sees folds that the midpoints
/// miss). Infinite when an evaluation is not finite.
double triangleError(const std::array<Eigen::Vector2d, 3>& X, const PatchPoint* c, const PatchPoint* s) {
  double dev = 0;
  Eigen::Matrix<double, 3, 2> J[7];
  for (int a = 0; a < 3; ++a) J[a] = jacobian(c[a]);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d lin = kW[k][0] * c[0].pos + kW[k][1] * c[1].pos + kW[k][2] * c[2].pos;
    dev = std::max(dev, (s[k].pos - lin).norm());
    J[3 + k] = jacobian(s[k]);
  }
  double osc = 0;
  for (int a = 0; a < 7; ++a)
    for (int b = 0; b < a; ++b) osc = std::max(osc, (J[a] - J[b]).norm());
  double h = 0;
  for (int a = 0; a < 3; ++a) h = std::max(h, (X[a] - X[(a + 1) % 3]).norm());
  const double e = std::max(2 * dev, 0.5 * h * osc);
  return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
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
  std::vector<PatchPoint> run(const PatchCache& cache) const {
    std::vector<PatchPoint> out(f.size());
    evaluatePatches(cache, f.data(), x.data(), y.data(), f.size(), out.data(), Backend::Tbb);
    return out;
  }
};

void addSamples(Batch& b, int face, const std::array<Eigen::Vector2d, 3>& X) {
  for (int k = 0; k < 4; ++k) b.add(face, kW[k][0] * X[0] + kW[k][1] * X[1] + kW[k][2] * X[2]);
}

/// Ring triangulation of one n-gon's level-L domainRingPoints, indices relative to the face's first vertex.
void ringTriangles(int n, int L, std::vector<std::array<int32_t, 3>>& out) {
  auto ringStart = [&](int r) { return r == 0 ? 0 : 1 + n * r * (r - 1) / 2; };
  auto idx = [&](int r, int k, int j) { return r == 0 ? 0 : ringStart(r) + ((k * r + j) % (n * r)); };
  for (int r = 1; r <= L; ++r)
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < r; ++j) out.push_back({idx(r, k, j), idx(r, k, j + 1), idx(r - 1, k, j)});
      for (int j = 0; j + 1 < r; ++j) out.push_back({idx(r - 1, k, j), idx(r, k, j + 1), idx(r - 1, k, j + 1)});
    }
}

}  // namespace

int64_t trianglesAtLevel(const PatchCache& cache, int L) {
  int64_t n = 0;
  for (int f = 0; f < cache.numFaces(); ++f)
    if (!(cache.faceStatus[f] & kNotBuilt)) n += int64_t(cache.faceSize(f)) * L * L;
  return n;
}

UniformTessellation tessellateUniform(const PatchCache& cache, int L) {
  UniformTessellation t;
  t.level = L;
  Batch vb;
  std::vector<Eigen::Vector2d> dom;
  std::vector<std::array<int32_t, 3>> local;
  for (int f = 0; f < cache.numFaces(); ++f) {
    if (cache.faceStatus[f] & kNotBuilt) continue;
    const int n = cache.faceSize(f), base = static_cast<int>(t.domain.size());
    dom.clear();
    domainRingPoints(n, L, dom);
    for (const Eigen::Vector2d& X : dom) {
      t.domain.push_back(X);
      vb.add(f, X);
    }
    local.clear();
    ringTriangles(n, L, local);
    for (const auto& tr : local) {
      t.tri.push_back({base + tr[0], base + tr[1], base + tr[2]});
      t.triFace.push_back(f);
    }
  }
  const std::vector<PatchPoint> pts = vb.run(cache);
  t.vertex.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) t.vertex[i] = pts[i].pos;
  Batch sb;
  for (size_t i = 0; i < t.tri.size(); ++i)
    addSamples(sb, t.triFace[i], {t.domain[t.tri[i][0]], t.domain[t.tri[i][1]], t.domain[t.tri[i][2]]});
  const std::vector<PatchPoint> sp = sb.run(cache);
  t.error.resize(t.tri.size());
  tbb::parallel_for(size_t(0), t.tri.size(), [&](size_t i) {
    const auto& tr = t.tri[i];
    const PatchPoint c[3] = {pts[tr[0]], pts[tr[1]], pts[tr[2]]};
    t.error[i] = triangleError({t.domain[tr[0]], t.domain[tr[1]], t.domain[tr[2]]}, c, &sp[4 * i]);
  });
  return t;
}

std::vector<SurfaceTriangle> tessellateAdaptive(const PatchCache& cache, const UniformTessellation& u, double maxError,
                                                int maxDepth) {
  std::vector<SurfaceTriangle> done, todo;
  for (size_t i = 0; i < u.tri.size(); ++i) {
    SurfaceTriangle s;
    s.face = u.triFace[i];
    for (int a = 0; a < 3; ++a) {
      s.X[a] = u.domain[u.tri[i][a]];
      s.P[a] = u.vertex[u.tri[i][a]];
    }
    s.error = u.error[i];
    (s.error > maxError ? todo : done).push_back(s);
  }
  for (int depth = 0; depth < maxDepth && !todo.empty(); ++depth) {
    // children at the edge midpoints: corners (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)
    Batch mids;
    for (const SurfaceTriangle& s : todo)
      for (int a = 0; a < 3; ++a) mids.add(s.face, 0.5 * (s.X[a] + s.X[(a + 1) % 3]));
    const std::vector<PatchPoint> mp = mids.run(cache);
    std::vector<SurfaceTriangle> kids(4 * todo.size());
    for (size_t i = 0; i < todo.size(); ++i) {
      const SurfaceTriangle& s = todo[i];
      const PatchPoint* m = &mp[3 * i];  // ab, bc, ca
      const std::array<Eigen::Vector2d, 3> mX = {0.5 * (s.X[0] + s.X[1]), 0.5 * (s.X[1] + s.X[2]),
                                                 0.5 * (s.X[2] + s.X[0])};
      const int idx[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};  // 0..2 corners, 3..5 mids
      for (int k = 0; k < 4; ++k) {
        SurfaceTriangle& c = kids[4 * i + k];
        c.face = s.face;
        for (int a = 0; a < 3; ++a) {
          const int j = idx[k][a];
          c.X[a] = j < 3 ? s.X[j] : mX[j - 3];
          c.P[a] = j < 3 ? s.P[j] : m[j - 3].pos;
        }
      }
    }
    // the error bound needs the Jacobians at the corners too: evaluate the children's corners
    Batch cb, sb;
    for (size_t i = 0; i < kids.size(); ++i) {
      for (int a = 0; a < 3; ++a) cb.add(kids[i].face, kids[i].X[a]);
      addSamples(sb, kids[i].face, kids[i].X);
    }
    const std::vector<PatchPoint> cp = cb.run(cache), sp = sb.run(cache);
    tbb::parallel_for(size_t(0), kids.size(),
                      [&](size_t i) { kids[i].error = triangleError(kids[i].X, &cp[3 * i], &sp[4 * i]); });
    todo.clear();
    for (const SurfaceTriangle& c : kids) (c.error > maxError && depth + 1 < maxDepth ? todo : done).push_back(c);
  }
  done.insert(done.end(), todo.begin(), todo.end());
  return done;
}

}  // namespace sf
