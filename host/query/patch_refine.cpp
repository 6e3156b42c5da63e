// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/patch_refine.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include <smoothforce/base/status.h>
#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/mean_value.h>

namespace sf {
namespace {

/// Domain corner C_k of an n-gon with a patch, k in [0, n] (C_n = C_0)
Eigen::Vector2d corner(int n, int k) { return domainCorner(n, k % n); }

constexpr double kInitialRadius = 0.5;  // domain units (circumradius 1)

}  // namespace

struct PatchRefiner::NewtonState {
  gpd::gp_refine_mesh mesh{};
  gpd::gp_refine_work work{};
  std::vector<float> widen;                   ///< float records of one face before widening
  std::unique_ptr<FacePointEvaluator> pairs;  ///< the finite differences' point pairs (records read in place)
  const PatchCache* cache = nullptr;
  LazyPatches* lazy = nullptr;
  std::vector<double> fieldMajor;  ///< a lazy face's double records, field-major, for `pairs`

  /// The state a seed (a start evaluated, not refined: maxIterations 0) left: its point's
  /// evaluation and second differences. A later seed at exactly that point (the sweep's HIP step
  /// after its approach step, a tracker out of contact) takes them instead of evaluating again.
  gpd::gp_refine_kept seed{};
  void keepSeed() noexcept { seed = work.kept; }
  void takeSeed() noexcept { work.kept = seed; }

  /// gp_refine_mesh's evalPoints hook with a lazy store of double records: the face's records
  /// (built when needed) transposed to field-major, then evaluated as evalPoints does.
  static void lazyPoints(void* user, int f, const double* x, const double* y, int count,
                         gpd::gp_eval_result* out) noexcept;

  /// gp_refine_mesh's loader hook: lazy construction and float records, widened to double.
  static gp_uint load(void* user, int f, double* recs) noexcept {
    auto* st = static_cast<NewtonState*>(user);
    const PatchCache& c = *st->cache;
    const size_t count = static_cast<size_t>(c.faceSize(f)) * GP_E_NFIELDS;
    if (st->lazy) {
      uint32_t status = 0;
      if (!recs) return st->lazy->status(f);
      if (c.options.precision == Precision::Double) {
        const double* r = st->lazy->recordsD(f, status);
        if (r) std::copy_n(r, count, recs);
      } else {
        const float* r = st->lazy->recordsF(f, status);
        if (r) std::copy_n(r, count, recs);
      }
      return status;
    }
    if (recs) {
      gatherRecords(c, f, st->widen.data());
      std::copy_n(st->widen.data(), count, recs);
    }
    return c.faceStatus[f];
  }
};

namespace {
/// PatchPoints as the refinement's gp_eval_results.
void toEvalResults(const PatchPoint* p, int count, gpd::gp_eval_result* out) noexcept {
  for (int k = 0; k < count; ++k) {
    out[k].pos = gpd::gp_v3(p[k].pos.x(), p[k].pos.y(), p[k].pos.z());
    out[k].dxi = gpd::gp_v3(p[k].dxi.x(), p[k].dxi.y(), p[k].dxi.z());
    out[k].deta = gpd::gp_v3(p[k].deta.x(), p[k].deta.y(), p[k].deta.z());
    out[k].normal = gpd::gp_v3(p[k].normal.x(), p[k].normal.y(), p[k].normal.z());
    out[k].status = p[k].status;
  }
}

/// gp_refine_mesh's evalPoints hook: a point and its finite differences side by side on SIMD
/// lanes (FacePointEvaluator; the same bits as the refinement's own evaluation).
void evalPoints(void* user, int f, const double* x, const double* y, int count, gpd::gp_eval_result* out) noexcept {
  PatchPoint p[4];
  count = std::clamp(count, 0, 4);
  static_cast<FacePointEvaluator*>(user)->evaluate(f, x, y, count, p);
  toEvalResults(p, count, out);
}
}  // namespace

void PatchRefiner::NewtonState::lazyPoints(void* user, int f, const double* x, const double* y, int count,
                                           gpd::gp_eval_result* out) noexcept {
  auto* st = static_cast<NewtonState*>(user);
  uint32_t status = 0;
  const double* r = st->lazy->recordsD(f, status);
  const int n = st->cache->faceSize(f);
  count = std::clamp(count, 0, 4);
  if (!r) {  // not buildable: as gp_rf_eval reports it (the refinement evaluates only evaluable faces)
    for (int k = 0; k < count; ++k) out[k] = gpd::gp_patch_eval(0, nullptr, 0, x[k], y[k]);
    return;
  }
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < GP_E_NFIELDS; ++i) st->fieldMajor[size_t(i) * n + k] = r[size_t(k) * GP_E_NFIELDS + i];
  PatchPoint p[4];
  st->pairs->evaluateRecords(n, st->mesh.mode, status, st->fieldMajor.data(), x, y, count, p);
  toEvalResults(p, count, out);
}

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
  newton_ = std::make_unique<NewtonState>();
  NewtonState& ns = *newton_;
  ns.cache = &cache;
  ns.lazy = lazy;
  gpd::gp_refine_mesh& m = ns.mesh;
  m.faceOffsets = cache.faceOffsets.data();
  m.slotTwin = cache.slotTwin.data();
  m.slotFace = slotFace_.data();
  m.numFaces = cache.numFaces();
  m.numSlots = cache.numSlots();
  m.mode = static_cast<int>(cache.options.crossTangent);
  m.scale = scale_;
  if (!lazy && cache.options.precision == Precision::Double && hasPatchData(cache)) {
    m.edgeData = cache.edgeDataD.data();  // read in place
    m.faceStatus = cache.faceStatus.data();
    ns.pairs = std::make_unique<FacePointEvaluator>(cache);
    m.evalPoints = &evalPoints;
    m.pointsUser = ns.pairs.get();
  } else if (lazy || hasPatchData(cache)) {
    ns.widen.resize(GP_MAX_N * GP_E_NFIELDS);
    m.load = &NewtonState::load;
    m.user = &ns;
    if (lazy && cache.options.precision == Precision::Double) {
      ns.pairs = std::make_unique<FacePointEvaluator>();
      ns.fieldMajor.resize(GP_MAX_N * GP_E_NFIELDS);
      m.evalPoints = &NewtonState::lazyPoints;
      m.pointsUser = &ns;
    }
  } else {  // a skeleton without a lazy store: no face is evaluable
    m.load = [](void*, int, double*) noexcept -> gp_uint { return GP_ST_TOO_MANY_SIDES; };
  }
  ns.work.loaded = -1;
  ns.work.sinOf = std::numeric_limits<double>::quiet_NaN();
  ns.work.kept.d2Face = ns.work.kept.lastFace = -1;
  ns.seed.d2Face = ns.seed.lastFace = -1;
}

PatchRefiner::~PatchRefiner() = default;

uint32_t PatchRefiner::faceStatus(int f) const noexcept { return lazy_ ? lazy_->status(f) : cache_.faceStatus[f]; }

bool PatchRefiner::evaluable(int f) const noexcept {
  if (f < 0 || f >= cache_.numFaces()) return false;
  const int n = cache_.faceSize(f);
  if (n < 3 || n > GP_MAX_N || !(lazy_ || hasPatchData(cache_))) return false;
  return !(faceStatus(f) & GP_ST_NOT_BUILT);
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
  const double m = domainEdgeMax(n, X, k), c = gpd::gp_dom_apothem(n);
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

bool PatchRefiner::converged(const Iterate& it, const Eigen::Vector3d& hip, const RefineOptions& o) const noexcept {
  const Eigen::Vector3d r = it.p.pos - hip;
  double residual = r.cross(it.p.normal).norm();
  if (it.edge >= 0) {  // held on a boundary edge: stationary along the edge
    const int n = cache_.faceSize(it.face);
    const Eigen::Vector2d e = corner(n, it.edge + 1) - corner(n, it.edge);
    const Eigen::Vector3d Ge = e.x() * it.p.dxi + e.y() * it.p.deta;
    residual = Ge.norm() > 0 ? std::abs(r.dot(Ge)) / Ge.norm() : r.norm();
  }
  const double noise = 64 * std::numeric_limits<double>::epsilon() * (hip.cwiseAbs().maxCoeff() + scale_);
  const double tol = std::min(std::sin(o.angleTolerance) * r.norm(), o.positionTolerance * scale_);
  return residual <= std::max(tol, std::max(noise, cache_.options.precision == Precision::Float ? posNoise_ : 0.0));
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
  if (!gpd::gp_dom_inside(cache_.faceSize(cur.face), X.x(), X.y())) transfer(face, X, edge, tr, st);
  Iterate trial = at(face, X, hip);
  trial.edge = edge;
  if (!better(trial, cur, hip)) return false;
  cur = trial;
  transitions += tr;
  status = (status & ~SF_TRACK_BOUNDARY) | st;
  return true;
}

void PatchRefiner::descentStep(Iterate& cur, const Eigen::Vector3d& hip, int& transitions, uint32_t& status,
                               bool& stalled) noexcept {
  const int n = cache_.faceSize(cur.face);
  Eigen::Vector2d Xc = cur.X;
  gpd::gp_dom_interior(n, &Xc.x(), &Xc.y(), eps_);
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
                                  const RefineOptions& options, int edge) noexcept {
  return options.refine == RefineMethod::Newton ? refineNewton(hip, face, xi, eta, options, edge, false)
                                                : refineDescent(hip, face, xi, eta, options, edge);
}

RefineResult PatchRefiner::refineNext(const Eigen::Vector3d& hip, int face, double xi, double eta,
                                      const RefineOptions& options, int edge) noexcept {
  return options.refine == RefineMethod::Newton ? refineNewton(hip, face, xi, eta, options, edge, true)
                                                : refineDescent(hip, face, xi, eta, options, edge);
}

RefineResult PatchRefiner::refineNewton(const Eigen::Vector3d& hip, int face, double xi, double eta,
                                        const RefineOptions& options, int edge, bool warm) noexcept {
  gpd::gp_refine_options o;
  o.maxIterations = options.maxIterations;
  o.angleTol = options.angleTolerance;
  o.positionTol = options.positionTolerance * scale_;
  o.modelFinal = options.finalStep == FinalStep::Model;
  // a seed on the face of the last seed: that seed's state, which gp_refine_newton_warm uses only
  // where this start is exactly its point (its evaluation and second differences there: the same
  // bits as evaluating again), and a seed takes no step, so the result is a cold start's
  const bool seed = options.maxIterations == 0 && !warm;
  if (seed && newton_->seed.lastFace == face && face >= 0) {
    newton_->takeSeed();
    warm = true;
  }
  const gpd::gp_refine_result r = gpd::gp_refine_newton_warm(
      &newton_->mesh, &newton_->work, gpd::gp_v3(hip.x(), hip.y(), hip.z()), face, xi, eta, edge, &o, warm ? 1 : 0);
  if (seed) newton_->keepSeed();
  RefineResult out;
  out.scp = {r.scp.x, r.scp.y, r.scp.z};
  out.normal = {r.normal.x, r.normal.y, r.normal.z};
  out.face = r.face;
  out.edge = r.edge;
  out.xi = r.xi;
  out.eta = r.eta;
  out.distance = r.distance;
  out.iterations = r.iterations;
  out.transitions = r.transitions;
  out.status = r.status;
  out.startMinimum = r.startMinimum != 0;
  return out;
}

RefineResult PatchRefiner::refineDescent(const Eigen::Vector3d& hip, int face, double xi, double eta,
                                         const RefineOptions& options, int edge) noexcept {
  RefineResult out;
  out.face = face;
  if (!hip.allFinite() || !evaluable(face) || !std::isfinite(xi) || !std::isfinite(eta)) {
    out.status = SF_TRACK_DEGENERATE;
    return out;
  }
  const int n0 = cache_.faceSize(face);
  Iterate cur = at(face, clampToDomain(n0, {xi, eta}), hip);
  cur.edge = edge >= 0 && edge < n0 ? edge : -1;
  if (!std::isfinite(cur.f)) {
    out.status = SF_TRACK_DEGENERATE | cur.p.status;
    return out;
  }
  uint32_t status = 0;
  bool conv = false, stalled = false;
  int it = 0;
  for (; it < options.maxIterations; ++it) {
    if ((conv = converged(cur, hip, options))) break;
    descentStep(cur, hip, out.transitions, status, stalled);
    if (stalled) break;
  }
  if (!conv) conv = converged(cur, hip, options);
  if (cur.edge >= 0) status |= SF_TRACK_BOUNDARY;
  status |= conv ? SF_TRACK_CONVERGED : stalled ? SF_TRACK_STALLED : SF_TRACK_MAX_ITER;
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
