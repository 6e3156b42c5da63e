// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_sampling.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <random>
#include <sstream>
#include <string_view>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_seeds.h>
#include "gp_config.h"

namespace sf {

namespace {

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// Domain triangles of face f at `level` rings, the ring layout of tessellatePatches.
void domainTriangles(int n, int L, std::vector<Eigen::Vector2d>& out) {
  auto vtx = [&](int r, int k, int j) -> Eigen::Vector2d {
    if (r == 0) return {0, 0};
    const Eigen::Vector2d a = domainCorner(n, k % n), b = domainCorner(n, (k + 1) % n);
    return (double(r) / L) * (a + (double(j) / r) * (b - a));
  };
  for (int r = 1; r <= L; ++r)
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < r; ++j) {
        out.push_back(vtx(r, k, j));
        out.push_back(vtx(r, k, j + 1));
        out.push_back(vtx(r - 1, k, j));
      }
      for (int j = 0; j + 1 < r; ++j) {
        out.push_back(vtx(r - 1, k, j));
        out.push_back(vtx(r, k, j + 1));
        out.push_back(vtx(r - 1, k, j + 1));
      }
    }
}

size_t pickByCdf(const std::vector<double>& cdf, double u) {
  const double target = u * cdf.back();
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), target);
  return std::min(static_cast<size_t>(it - cdf.begin()), cdf.size() - 1);
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

}  // namespace

std::vector<DepthSpec> parseDepthList(const std::string& text, const std::string& option) {
  std::vector<DepthSpec> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    DepthSpec d;
    d.label = trim(item);
    std::string num = d.label;
    if (!num.empty() && num.back() == '%') {
      d.relative = true;
      num.pop_back();
    }
    // decimal or exponent, an optional '+': no hex (std::stod read 0x10 as 16), no inf or nan
    std::string_view digits(num);
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') digits.remove_prefix(1);
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), d.value);
    if (digits.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size() || !std::isfinite(d.value) ||
        !(d.value > 0))
      throw InputError(option + ": '" + d.label + "' is not a positive length (metres, or percent like 2%)");
    // one result set per depth: a repeat (1%,1% or 0.001,1e-3) would run the same group twice
    for (size_t k = 0; k < out.size(); ++k)
      if (out[k].relative == d.relative && out[k].value == d.value)
        throw InputError(option + ": '" + d.label + "' is listed twice (items " + std::to_string(k + 1) + " and " +
                         std::to_string(out.size() + 1) + ")");
    out.push_back(d);
  }
  if (out.empty()) throw InputError(option + ": empty list");
  return out;
}

std::string depthTag(const std::string& label) {
  std::string t;
  for (char c : label) {
    if (c == '%')
      t += "pct";
    else if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_')
      t += c;
    else
      t += '_';
  }
  if (label.empty() || label.back() != '%') t += "m";
  return t;
}

PatchSurfaceSampler::PatchSurfaceSampler(const PatchCache& cache, int level) : cache_(cache) {
  if (level < 1 || level > 64) throw InputError("sampling level must be in [1, 64], got " + std::to_string(level));
  faces_ = builtFaces(cache);
  if (faces_.empty()) throw InputError("sampling: no patch can be evaluated");
  // Per polygon size n: the small triangles' domain corners (domainTriangles' layout, the same
  // for every n-gon), and the distinct corners among them (a ring point is a corner of up to 6
  // triangles): each face evaluates those once.
  struct Corners {
    std::vector<Eigen::Vector2d> points;  ///< distinct corners, bit for bit
    std::vector<uint32_t> slot;           ///< per corner (3 per triangle): its index in points
  };
  std::vector<Corners> distinct;
  first_.assign(1, 0);
  for (const int32_t f : faces_) {
    const size_t n = static_cast<size_t>(cache.faceSize(f));
    if (dom_.size() <= n) {
      dom_.resize(n + 1);
      distinct.resize(n + 1);
    }
    if (dom_[n].empty()) {
      domainTriangles(static_cast<int>(n), level, dom_[n]);
      std::vector<uint32_t> order(dom_[n].size());
      for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
      const auto& d = dom_[n];
      std::sort(order.begin(), order.end(), [&](uint32_t i, uint32_t j) {
        return d[i].x() < d[j].x() || (d[i].x() == d[j].x() && (d[i].y() < d[j].y() || (d[i].y() == d[j].y() && i < j)));
      });
      Corners& c = distinct[n];
      c.slot.resize(order.size());
      for (size_t k = 0; k < order.size(); ++k) {
        if (k == 0 || d[order[k]] != d[order[k - 1]]) c.points.push_back(d[order[k]]);
        c.slot[order[k]] = static_cast<uint32_t>(c.points.size() - 1);
      }
    }
    first_.push_back(first_.back() + dom_[n].size() / 3);
  }
  // the triangles' areas a few faces at a time (each face's distinct corners evaluated once);
  // the same points as every corner evaluated, so the same values
  std::vector<double> area(first_.back());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, faces_.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<int32_t> qf;
    std::vector<double> qx, qy;
    std::vector<size_t> at;  // each face's first point in the batch
    for (size_t i = r.begin(); i < r.end(); ++i) {
      at.push_back(qf.size());
      for (const Eigen::Vector2d& X : distinct[static_cast<size_t>(cache.faceSize(faces_[i]))].points) {
        qf.push_back(faces_[i]);
        qx.push_back(X.x());
        qy.push_back(X.y());
      }
    }
    std::vector<PatchPoint> pts(qf.size());
    evaluatePatches(cache, qf.data(), qx.data(), qy.data(), qf.size(), pts.data(), Backend::Serial);
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const std::vector<uint32_t>& slot = distinct[static_cast<size_t>(cache.faceSize(faces_[i]))].slot;
      const PatchPoint* p = pts.data() + at[i - r.begin()];
      for (size_t t = first_[i]; t < first_[i + 1]; ++t) {
        const size_t j = 3 * (t - first_[i]);
        const Eigen::Vector3d &a = p[slot[j]].pos, &b = p[slot[j + 1]].pos, &c = p[slot[j + 2]].pos;
        area[t] = 0.5 * (b - a).cross(c - a).norm();
      }
    }
  });
  cdf_.resize(area.size());
  double acc = 0;
  for (size_t t = 0; t < area.size(); ++t) {
    acc += std::isfinite(area[t]) ? area[t] : 0.0;
    cdf_[t] = acc;
  }
  area_ = acc;
  if (!(area_ > 0)) throw InputError("sampling: the patches have zero area");
}

std::vector<SurfaceSample> PatchSurfaceSampler::sample(size_t n, uint64_t seed) const {
  std::mt19937_64 rng(seed);
  std::vector<SurfaceSample> out(n);
  std::vector<size_t> todo(n);
  for (size_t i = 0; i < n; ++i) todo[i] = i;
  std::vector<int32_t> qf;
  std::vector<double> qx, qy;
  std::vector<PatchPoint> pts;
  for (int round = 0; !todo.empty(); ++round) {
    if (round == 64) throw InputError("sampling: patch evaluation keeps failing");
    qf.resize(todo.size());
    qx.resize(todo.size());
    qy.resize(todo.size());
    for (size_t j = 0; j < todo.size(); ++j) {  // serial: one RNG stream, deterministic
      const size_t t = pickByCdf(cdf_, uniform01(rng));
      const size_t i = static_cast<size_t>(std::upper_bound(first_.begin(), first_.end(), t) - first_.begin()) - 1;
      const int32_t f = faces_[i];
      const Eigen::Vector2d* X0 = dom_[static_cast<size_t>(cache_.faceSize(f))].data() + 3 * (t - first_[i]);
      const double s = std::sqrt(uniform01(rng)), v = uniform01(rng);
      const Eigen::Vector2d X = (1 - s) * X0[0] + s * (1 - v) * X0[1] + s * v * X0[2];
      qf[j] = f;
      qx[j] = X.x();
      qy[j] = X.y();
    }
    pts.resize(todo.size());
    evaluatePatches(cache_, qf.data(), qx.data(), qy.data(), todo.size(), pts.data(), Backend::Tbb);
    std::vector<size_t> again;
    for (size_t j = 0; j < todo.size(); ++j) {
      const PatchPoint& p = pts[j];
      if ((p.status & GP_ST_NOT_A_PATCH_POINT) || !p.pos.allFinite() || !p.normal.allFinite() ||
          p.normal.norm() < 0.5) {
        again.push_back(todo[j]);
        continue;
      }
      out[todo[j]] = SurfaceSample{p.pos, p.normal.normalized(), qf[j], qx[j], qy[j]};
    }
    todo.swap(again);
  }
  return out;
}

std::vector<SurfaceSample> sampleTriangleSoup(const TriangleSoup& soup, size_t n, uint64_t seed) {
  std::vector<double> cdf(soup.triangles.size());
  double acc = 0;
  for (size_t t = 0; t < cdf.size(); ++t) {
    const auto& T = soup.triangles[t];
    acc +=
        0.5 * (soup.positions[T[1]] - soup.positions[T[0]]).cross(soup.positions[T[2]] - soup.positions[T[0]]).norm();
    cdf[t] = acc;
  }
  if (!(acc > 0)) throw InputError("reference mesh has zero area");
  std::mt19937_64 rng(seed);
  std::vector<SurfaceSample> out(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t t = pickByCdf(cdf, uniform01(rng));
    const double s = std::sqrt(uniform01(rng)), v = uniform01(rng);
    const double w0 = 1 - s, w1 = s * (1 - v), w2 = s * v;
    const auto& T = soup.triangles[t];
    const auto& N = soup.cornerNormals[t];
    out[i].point = w0 * soup.positions[T[0]] + w1 * soup.positions[T[1]] + w2 * soup.positions[T[2]];
    Eigen::Vector3d nrm = w0 * N[0] + w1 * N[1] + w2 * N[2];
    if (!(nrm.norm() > 1e-12))
      nrm = (soup.positions[T[1]] - soup.positions[T[0]]).cross(soup.positions[T[2]] - soup.positions[T[0]]);
    out[i].normal = nrm.normalized();
  }
  return out;
}

struct PatchProjector::Impl {
  const PatchCache& cache;
  PatchSeeds seeds;
  RefineOptions options;
  /// One refiner per thread (project() is const and runs in parallel; a refiner is not
  /// thread-safe): the project's one Newton refinement (kernels/gp_refine.h), crossing patch
  /// edges by Eq. 15, so a point near an edge projects onto the neighbour when that is nearer.
  mutable tbb::enumerable_thread_specific<std::unique_ptr<PatchRefiner>> refiners;
  Impl(const PatchCache& c, int level)
      : cache(c), seeds(c, level), refiners([&c] { return std::make_unique<PatchRefiner>(c); }) {
    options.refine = RefineMethod::Newton;
    options.angleTolerance = 1e-12;  // rad: the nearest point itself, not a haptic tolerance
    options.maxIterations = 100;
  }

  SurfaceSample refine(const Eigen::Vector3d& q, int f, const Eigen::Vector2d& X) const {
    const RefineResult r = refiners.local()->refine(q, f, X.x(), X.y(), options);
    if (r.face >= 0 && r.scp.allFinite() && r.normal.norm() > 0.5)
      return SurfaceSample{r.scp, r.normal, r.face, r.xi, r.eta};
    const PatchPoint p = evaluatePatch(cache, f, X.x(), X.y());  // no refinement: the seed itself
    return SurfaceSample{p.pos, p.normal.normalized(), f, X.x(), X.y()};
  }
};

PatchProjector::PatchProjector(const PatchCache& cache, int level) : impl_(std::make_unique<Impl>(cache, level)) {
  if (impl_->seeds.size() == 0) throw InputError("projection: no patch can be evaluated");
}

PatchProjector::~PatchProjector() = default;

SurfaceSample PatchProjector::project(const Eigen::Vector3d& q) const {
  PatchSeed seeds[8];
  const size_t k = impl_->seeds.knn(q, 8, seeds);
  SurfaceSample best;
  double bestD = 1e300;
  int tried[8], nTried = 0;
  for (size_t i = 0; i < k; ++i) {
    const int f = seeds[i].face;
    if (std::find(tried, tried + nTried, f) != tried + nTried) continue;
    tried[nTried++] = f;
    const SurfaceSample s = impl_->refine(q, f, seeds[i].X);
    const double d = (s.point - q).squaredNorm();
    if (d < bestD) {
      bestD = d;
      best = s;
    }
  }
  return best;
}

}  // namespace sf
