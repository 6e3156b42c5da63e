#include <smoothforce/query/patch_refine.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <smoothforce/base/status.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/mean_value.h>

namespace sf {
namespace {

Eigen::Vector2d corner(int n, int k) {
  const double a = 2.0 * std::numbers::pi * ((k % n + n) % n) / n;
  return {std::cos(a), std::sin(a)};
}

bool outsideDomain(int n, const Eigen::Vector2d& X) {
  int k;
  return domainEdgeMax(n, X, k) > std::cos(std::numbers::pi / n);
}

constexpr double kInitialRadius = 0.5;  // domain units (circumradius 1)
constexpr double kMaxRadius = 2.0;

}  // namespace

PatchRefiner::PatchRefiner(const PatchCache& cache, LazyPatches* lazy)
    : cache_(cache),
      lazy_(lazy),
      slotFace_(cache.numSlots()),
      recsD_(cache.options.precision == Precision::Double ? GP_MAX_N * GP_E_NFIELDS : 0),
      recsF_(cache.options.precision == Precision::Float ? GP_MAX_N * GP_E_NFIELDS : 0) {
  for (int f = 0; f < cache.numFaces(); ++f)
    for (int s = cache.faceOffsets[f]; s < cache.faceOffsets[f + 1]; ++s) slotFace_[s] = f;
  scale_ = cache.numVertices() > 0 ? std::max(boundingDiagonal(cache), 1e-300) : 1.0;
  eps_ = cache.options.precision == Precision::Double ? 1e-6 : 1e-3;
  posNoise_ = (cache.options.precision == Precision::Double ? 1e-14 : 1e-6) * scale_;
}

uint32_t PatchRefiner::faceStatus(int f) const noexcept {
  return lazy_ ? lazy_->status(f) : cache_.faceStatus[f];
}

bool PatchRefiner::evaluable(int f) const noexcept {
  if (f < 0 || f >= cache_.numFaces()) return false;
  const int n = cache_.faceSize(f);
  if (n < 3 || n > GP_MAX_N || !(lazy_ || hasPatchData(cache_))) return false;
  return !(faceStatus(f) & (GP_ST_TOO_MANY_SIDES | GP_ST_NONFINITE));
}

void PatchRefiner::load(int f) noexcept {
  if (loaded_ == f) return;
  const size_t count = static_cast<size_t>(cache_.faceSize(f)) * GP_E_NFIELDS;
  uint32_t st = 0;
  if (lazy_ && cache_.options.precision == Precision::Double)
    std::copy_n(lazy_->recordsD(f, st), count, recsD_.data());  // evaluable(f) held: not null
  else if (lazy_)
    std::copy_n(lazy_->recordsF(f, st), count, recsF_.data());
  else if (cache_.options.precision == Precision::Double)
    gatherRecords(cache_, f, recsD_.data());
  else
    gatherRecords(cache_, f, recsF_.data());
  loaded_ = f;
}

PatchPoint PatchRefiner::eval(int f, const Eigen::Vector2d& X) noexcept {
  PatchPoint p;
  if (!evaluable(f)) {
    p.status = GP_ST_TOO_MANY_SIDES;
    return p;
  }
  load(f);
  const int n = cache_.faceSize(f), mode = static_cast<int>(cache_.options.crossTangent);
  auto copy = [&](const auto& r) {
    p.pos = {r.pos.x, r.pos.y, r.pos.z};
    p.dxi = {r.dxi.x, r.dxi.y, r.dxi.z};
    p.deta = {r.deta.x, r.deta.y, r.deta.z};
    p.normal = {r.normal.x, r.normal.y, r.normal.z};
    p.status = r.status | faceStatus(f);
  };
  if (cache_.options.precision == Precision::Double)
    copy(Gp<double>::eval(n, recsD_.data(), mode, X.x(), X.y()));
  else
    copy(Gp<float>::eval(n, recsF_.data(), mode, X.x(), X.y()));
  return p;
}

PatchRefiner::Iterate PatchRefiner::at(int f, const Eigen::Vector2d& X, const Eigen::Vector3d& hip) noexcept {
  Iterate it{f, -1, X, eval(f, X), std::numeric_limits<double>::infinity()};
  if (!(it.p.status & (GP_ST_OUTSIDE | GP_ST_TOO_MANY_SIDES)) && it.p.pos.allFinite())
    it.f = 0.5 * (it.p.pos - hip).squaredNorm();
  return it;
}

void PatchRefiner::transfer(int& f, Eigen::Vector2d& X, int& edge, int& transitions, uint32_t& status) const noexcept {
  edge = -1;
  const int n = cache_.faceSize(f);
  int k;
  const double m = domainEdgeMax(n, X, k), c = std::cos(std::numbers::pi / n);
  if (!(m > c)) return;
  const Eigen::Vector2d I0 = X * (c / m);  // the ray from the origin meets domain edge k
  const Eigen::Vector2d Ck = corner(n, k), Ck1 = corner(n, k + 1);
  const double s = std::clamp((I0 - Ck1).norm() / (Ck - Ck1).norm(), 0.0, 1.0);
  const int32_t twin = cache_.slotTwin[cache_.faceOffsets[f] + k];
  const int g = twin >= 0 ? slotFace_[twin] : -1;
  if (g < 0 || !evaluable(g)) {  // boundary, non-manifold or unusable neighbour: stay on the edge,
    // at the nearest point of the edge in the domain (a projected step, so it slides along it)
    const Eigen::Vector2d e = Ck1 - Ck;
    X = clampToDomain(n, Ck + std::clamp((X - Ck).dot(e) / e.squaredNorm(), 0.0, 1.0) * e);
    edge = k;
    status |= SF_TRACK_BOUNDARY;
    return;
  }
  const int ng = cache_.faceSize(g), i = twin - cache_.faceOffsets[g];
  const Eigen::Vector2d Ci = corner(ng, i), Ci1 = corner(ng, i + 1);
  X = clampToDomain(ng, Ci + s * (Ci1 - Ci));
  f = g;
  ++transitions;
}

Eigen::Vector2d PatchRefiner::interior(int n, const Eigen::Vector2d& X, double eps) const noexcept {
  int k;
  const double dmin = std::cos(std::numbers::pi / n) - domainEdgeMax(n, X, k);
  if (dmin > 2 * eps) return X;
  const double r = X.norm();     // >= cos(pi/n) - 2 eps > 0.4 near the boundary
  return X * (1 - 3 * eps / r);  // an eps-disc around it fits in the domain for n >= 3
}

bool PatchRefiner::converged(const Iterate& it, const Eigen::Vector3d& hip, double tol) const noexcept {
  const Eigen::Vector3d r = it.p.pos - hip;
  if (r.norm() <= 1e-12 * scale_) return true;
  if (it.edge >= 0) {  // held on a boundary edge: stationary along the edge
    const int n = cache_.faceSize(it.face);
    const Eigen::Vector2d e = (corner(n, it.edge + 1) - corner(n, it.edge)).normalized();
    const Eigen::Vector3d Ge = e.x() * it.p.dxi + e.y() * it.p.deta;
    return std::abs(r.dot(Ge)) < std::sin(tol) * r.norm() * Ge.norm();
  }
  return std::atan2(r.cross(it.p.normal).norm(), std::abs(r.dot(it.p.normal))) < tol;
}

bool PatchRefiner::better(const Iterate& trial, const Iterate& cur, const Eigen::Vector3d& hip) const noexcept {
  if (trial.f < cur.f) return true;
  const double noise = std::sqrt(2 * cur.f) * posNoise_ + posNoise_ * posNoise_ + 1e-13 * cur.f;
  // a step that crossed onto the neighbour lands on the shared edge, often at the same 3D point
  // (the rest of the step is dropped by Eq. 15): take it, so that the next step is computed in
  // the neighbour's domain instead of stalling against the edge
  if (trial.face != cur.face && trial.f <= cur.f + noise) return true;
  // within the evaluation noise of f (float caches: ~1e-7 of the coordinates), accept a step
  // that turns G - HIP closer to the normal, else the noise would stall the descent early
  if (!(trial.f <= cur.f + noise) || trial.edge >= 0 || cur.edge >= 0) return false;
  auto sine = [&](const Iterate& it) {
    const Eigen::Vector3d r = it.p.pos - hip;
    return r.cross(it.p.normal).norm() / r.norm();
  };
  return sine(trial) < sine(cur);
}

bool PatchRefiner::tryStep(Iterate& cur, const Eigen::Vector2d& step, const Eigen::Vector3d& hip, int& transitions,
                           uint32_t& status) noexcept {
  int face = cur.face, tr = 0, edge = -1;
  uint32_t st = 0;
  Eigen::Vector2d X = cur.X + step;
  if (outsideDomain(cache_.faceSize(cur.face), X)) transfer(face, X, edge, tr, st);
  Iterate trial = at(face, X, hip);
  trial.edge = edge;
  if (!better(trial, cur, hip)) return false;
  cur = trial;
  transitions += tr;
  status = (status & ~SF_TRACK_BOUNDARY) | st;
  return true;
}

void PatchRefiner::newtonStep(Iterate& cur, const Eigen::Vector3d& hip, double& radius, int& transitions,
                              uint32_t& status, bool& stalled) noexcept {
  const int n = cache_.faceSize(cur.face);
  const Eigen::Vector3d r = cur.p.pos - hip, a = cur.p.dxi, b = cur.p.deta;
  const Eigen::Vector2d g(a.dot(r), b.dot(r));
  const double A00 = a.dot(a), A01 = a.dot(b), A11 = b.dot(b);
  // second-order part sum r_i d2G_i from forward differences of the exact first derivatives
  const Eigen::Vector2d Xc = interior(n, cur.X, eps_);
  const PatchPoint pc = Xc == cur.X ? cur.p : eval(cur.face, Xc);
  const PatchPoint p1 = eval(cur.face, Xc + Eigen::Vector2d(eps_, 0));
  const PatchPoint p2 = eval(cur.face, Xc + Eigen::Vector2d(0, eps_));
  const double S00 = r.dot(p1.dxi - pc.dxi) / eps_, S11 = r.dot(p2.deta - pc.deta) / eps_;
  const double S01 = 0.5 * r.dot((p1.deta - pc.deta) + (p2.dxi - pc.dxi)) / eps_;
  double H00 = A00 + S00, H01 = A01 + S01, H11 = A11 + S11;
  const double tr = A00 + A11;
  double det = H00 * H11 - H01 * H01;
  if (!(H00 > 0 && det > 1e-10 * tr * tr) || !std::isfinite(det)) {  // not convex here: Gauss-Newton
    const double mu = 1e-9 * tr + 1e-300;
    H00 = A00 + mu;
    H01 = A01;
    H11 = A11 + mu;
    det = H00 * H11 - H01 * H01;
  }
  Eigen::Vector2d step(-(H11 * g.x() - H01 * g.y()) / det, -(-H01 * g.x() + H00 * g.y()) / det);
  double len = step.norm();
  if (!std::isfinite(len) || len == 0) {
    stalled = true;
    return;
  }
  const bool clipped = len > radius;
  if (clipped) {
    step *= radius / len;
    len = radius;
  }
  if (tryStep(cur, step, hip, transitions, status)) {
    if (clipped) radius = std::min(2 * radius, kMaxRadius);
  } else {
    radius = 0.25 * len;
    if (radius < 1e-14) stalled = true;
  }
}

void PatchRefiner::descentStep(Iterate& cur, const Eigen::Vector3d& hip, int& transitions, uint32_t& status,
                               bool& stalled) noexcept {
  const int n = cache_.faceSize(cur.face);
  const Eigen::Vector2d Xc = interior(n, cur.X, eps_);
  const Eigen::Vector3d gxp = eval(cur.face, Xc + Eigen::Vector2d(eps_, 0)).pos;
  const Eigen::Vector3d gxm = eval(cur.face, Xc - Eigen::Vector2d(eps_, 0)).pos;
  const Eigen::Vector3d gyp = eval(cur.face, Xc + Eigen::Vector2d(0, eps_)).pos;
  const Eigen::Vector3d gym = eval(cur.face, Xc - Eigen::Vector2d(0, eps_)).pos;
  const Eigen::Vector2d grad(((gxp - hip).squaredNorm() - (gxm - hip).squaredNorm()) / (2 * eps_),
                             ((gyp - hip).squaredNorm() - (gym - hip).squaredNorm()) / (2 * eps_));
  const Eigen::Vector2d d = -grad;
  const double dn = d.norm();
  if (!(dn > 0) || !std::isfinite(dn)) {
    stalled = true;
    return;
  }
  // tangent of G along d from the same differences; step to the foot of the HIP on it
  const Eigen::Vector3d Gd = (d.x() * (gxp - gxm) + d.y() * (gyp - gym)) / (2 * eps_);
  double alpha = -(cur.p.pos - hip).dot(Gd) / Gd.squaredNorm();
  if (!(alpha > 0) || !std::isfinite(alpha)) alpha = kInitialRadius / dn;
  Eigen::Vector2d step = alpha * d;
  if (step.norm() > kInitialRadius) step *= kInitialRadius / step.norm();
  for (int halving = 0; halving < 40; ++halving, step *= 0.5)
    if (tryStep(cur, step, hip, transitions, status)) return;
  stalled = true;
}

RefineResult PatchRefiner::refine(const Eigen::Vector3d& hip, int face, double xi, double eta,
                                  const RefineOptions& options) noexcept {
  RefineResult out;
  out.face = face;
  if (!hip.allFinite() || !evaluable(face) || !std::isfinite(xi) || !std::isfinite(eta)) {
    out.status = SF_TRACK_DEGENERATE;
    return out;
  }
  const Eigen::Vector2d X0 = clampToDomain(cache_.faceSize(face), {xi, eta});
  Iterate cur;
  if (face == lastFace_ && X0 == lastX_) {  // the previous call ended here: reuse its evaluation
    cur = Iterate{face, lastEdge_, X0, lastP_, 0.5 * (lastP_.pos - hip).squaredNorm()};
  } else {
    cur = at(face, X0, hip);
  }
  if (!std::isfinite(cur.f)) {
    out.status = SF_TRACK_DEGENERATE | cur.p.status;
    return out;
  }
  uint32_t status = 0;
  bool conv = false, stalled = false;
  double radius = kInitialRadius;
  int it = 0;
  for (; it < options.maxIterations; ++it) {
    if ((conv = converged(cur, hip, options.angleTolerance))) break;
    if (options.refine == RefineMethod::Newton)
      newtonStep(cur, hip, radius, out.transitions, status, stalled);
    else
      descentStep(cur, hip, out.transitions, status, stalled);
    if (stalled) break;
  }
  if (!conv) conv = converged(cur, hip, options.angleTolerance);
  if (cur.edge >= 0) status |= SF_TRACK_BOUNDARY;
  status |= conv ? SF_TRACK_CONVERGED : stalled ? SF_TRACK_STALLED : SF_TRACK_MAX_ITER;
  lastFace_ = cur.face;
  lastX_ = cur.X;
  lastP_ = cur.p;
  lastEdge_ = cur.edge;
  out.scp = cur.p.pos;
  out.normal = cur.p.normal;
  out.face = cur.face;
  out.edge = cur.edge;
  out.xi = cur.X.x();
  out.eta = cur.X.y();
  out.distance = (cur.p.pos - hip).norm();
  out.iterations = it;
  out.status = status | cur.p.status;
  return out;
}

RefineResult refineNearestPoint(const PatchCache& cache, const Eigen::Vector3d& hip, int face, double xi, double eta,
                                const RefineOptions& options) {
  PatchRefiner r(cache);
  return r.refine(hip, face, xi, eta, options);
}

}  // namespace sf
