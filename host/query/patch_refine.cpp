// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/query/patch_refine.h>

#include <algorithm>
#include <limits>

#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/lazy_patches.h>

namespace sf {

struct PatchRefiner::RefineState {
  gpd::gp_refine_mesh mesh{};
  gpd::gp_refine_work work{};
  std::vector<float> widen;                   ///< float records of one face before widening
  std::unique_ptr<FacePointEvaluator> pairs;  ///< the finite differences' point pairs (records read in place)
  const PatchCache* cache = nullptr;
  LazyPatches* lazy = nullptr;
  std::vector<double> fieldMajor;  ///< one face's records in double, field-major, for `pairs` (recordPoints)
  int fieldFace = -1;              ///< the prebuilt float cache's face whose widened records fieldMajor holds
  uint32_t fieldStatus = 0;        ///< that face's GP_ST_* bits

  /// The state a seed (a start evaluated, not refined: maxIterations 0) left: its point's
  /// evaluation and second differences. A later seed at exactly that point (the sweep's HIP step
  /// after its approach step, a tracker out of contact) takes them instead of evaluating again.
  gpd::gp_refine_kept seed{};
  void keepSeed() noexcept { seed = work.kept; }
  void takeSeed() noexcept { work.kept = seed; }

  /// gp_refine_mesh's evalPoints hook where the cache's records cannot be read in place (a lazy
  /// store, double or float; a prebuilt float cache): the face's records, widened to double as the
  /// loader widens them, field-major, evaluated as evalPoints does (the bits of gp_patch_eval on
  /// those records). A prebuilt cache's face is kept for the next call on it; a lazy store may
  /// build or rebuild a face's records in place, so its faces are read again every call.
  static void recordPoints(void* user, int f, const double* x, const double* y, int count,
                           gpd::gp_eval_result* out) noexcept;

  /// gp_refine_mesh's evalNative hook for float records: the descent evaluates them in float, as
  /// the cache's own evaluation does (PatchRefiner::eval).
  static gpd::gp_eval_result native(void* user, int f, double x, double y) noexcept;

  /// gp_refine_mesh's loader hook: lazy construction and float records, widened to double.
  static gp_uint load(void* user, int f, double* recs) noexcept {
    auto* st = static_cast<RefineState*>(user);
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

/// The kernels' stopping rules for RefineOptions on a mesh of bounding-box diagonal `scale` (m).
gpd::gp_refine_options kernelOptions(const RefineOptions& options, double scale) noexcept {
  gpd::gp_refine_options o;
  o.maxIterations = options.maxIterations;
  o.angleTol = options.angleTolerance;
  o.positionTol = options.positionTolerance * scale;
  o.modelFinal = options.finalStep == FinalStep::Model;
  return o;
}

RefineResult toRefineResult(const gpd::gp_refine_result& r) noexcept {
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

/// gp_refine_mesh's evalPoints hook: a point and its finite differences side by side on SIMD
/// lanes (FacePointEvaluator; the same bits as the refinement's own evaluation).
void evalPoints(void* user, int f, const double* x, const double* y, int count, gpd::gp_eval_result* out) noexcept {
  PatchPoint p[4];
  count = std::clamp(count, 0, 4);
  static_cast<FacePointEvaluator*>(user)->evaluate(f, x, y, count, p);
  toEvalResults(p, count, out);
}
}  // namespace

void PatchRefiner::RefineState::recordPoints(void* user, int f, const double* x, const double* y, int count,
                                             gpd::gp_eval_result* out) noexcept {
  auto* st = static_cast<RefineState*>(user);
  const int n = st->cache->faceSize(f);
  count = std::clamp(count, 0, 4);
  if (st->lazy || st->fieldFace != f) {
    uint32_t status = 0;
    bool built = true;
    if (!st->lazy) {
      gatherRecords(*st->cache, f, st->widen.data());
      recordsFieldMajor(n, st->widen.data(), st->fieldMajor.data());
      status = st->cache->faceStatus[f];
    } else if (st->cache->options.precision == Precision::Double) {
      const double* r = st->lazy->recordsD(f, status);
      built = r != nullptr;
      if (built) recordsFieldMajor(n, r, st->fieldMajor.data());
    } else {
      const float* r = st->lazy->recordsF(f, status);
      built = r != nullptr;
      if (built) recordsFieldMajor(n, r, st->fieldMajor.data());
    }
    if (!built) {  // not buildable: as gp_rf_eval reports it (the refinement evaluates only evaluable faces)
      for (int k = 0; k < count; ++k) out[k] = gpd::gp_patch_eval(0, nullptr, 0, x[k], y[k]);
      return;
    }
    st->fieldFace = st->lazy ? -1 : f;
    st->fieldStatus = status;
  }
  PatchPoint p[4];
  st->pairs->evaluateRecords(n, st->mesh.mode, st->fieldStatus, st->fieldMajor.data(), x, y, count, p);
  toEvalResults(p, count, out);
}

gpd::gp_eval_result PatchRefiner::RefineState::native(void* user, int f, double x, double y) noexcept {
  const PatchPoint p = static_cast<PatchRefiner*>(user)->eval(f, {x, y});
  gpd::gp_eval_result r;
  toEvalResults(&p, 1, &r);
  return r;
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
  state_ = std::make_unique<RefineState>();
  RefineState& ns = *state_;
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
  m.floatRecords = cache.options.precision == Precision::Float;
  if (m.floatRecords) {
    m.evalNative = &RefineState::native;
    m.nativeUser = this;
  }
  if (!lazy && cache.options.precision == Precision::Double && hasPatchData(cache)) {
    m.edgeData = cache.edgeDataD.data();  // read in place
    m.faceStatus = cache.faceStatus.data();
    ns.pairs = std::make_unique<FacePointEvaluator>(cache);
    m.evalPoints = &evalPoints;
    m.pointsUser = ns.pairs.get();
  } else if (lazy || hasPatchData(cache)) {
    ns.widen.resize(GP_MAX_N * GP_E_NFIELDS);
    m.load = &RefineState::load;
    m.user = &ns;
    ns.pairs = std::make_unique<FacePointEvaluator>();
    ns.fieldMajor.resize(GP_MAX_N * GP_E_NFIELDS);
    m.evalPoints = &RefineState::recordPoints;
    m.pointsUser = &ns;
  } else {  // a skeleton without a lazy store: no face is evaluable
    m.load = [](void*, int, double*) noexcept -> gp_uint { return GP_ST_TOO_MANY_SIDES; };
  }
  ns.work.loaded = -1;
  ns.work.sinOf = std::numeric_limits<double>::quiet_NaN();
  ns.work.kept.d2Face = ns.work.kept.lastFace = -1;
  ns.seed.d2Face = ns.seed.lastFace = -1;
}

PatchRefiner::~PatchRefiner() = default;

FacePointEvaluator* PatchRefiner::pointEvaluator() noexcept { return state_->pairs.get(); }

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
  const int n = cache_.faceSize(f),
            mode = gpd::gp_eval_mode(static_cast<int>(cache_.options.crossTangent), faceStatus(f));
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
  const gpd::gp_refine_options o = kernelOptions(options, scale_);
  // a seed on the face of the last seed: that seed's state, which gp_refine_newton_warm uses only
  // where this start is exactly its point (its evaluation and second differences there: the same
  // bits as evaluating again), and a seed takes no step, so the result is a cold start's
  const bool seed = options.maxIterations == 0 && !warm;
  if (seed && state_->seed.lastFace == face && face >= 0) {
    state_->takeSeed();
    warm = true;
  }
  const gpd::gp_refine_result r = gpd::gp_refine_newton_warm(
      &state_->mesh, &state_->work, gpd::gp_v3(hip.x(), hip.y(), hip.z()), face, xi, eta, edge, &o, warm ? 1 : 0);
  if (seed) state_->keepSeed();
  return toRefineResult(r);
}

RefineResult PatchRefiner::refineDescent(const Eigen::Vector3d& hip, int face, double xi, double eta,
                                         const RefineOptions& options, int edge) noexcept {
  const gpd::gp_refine_options o = kernelOptions(options, scale_);
  return toRefineResult(gpd::gp_refine_descent(&state_->mesh, &state_->work, gpd::gp_v3(hip.x(), hip.y(), hip.z()),
                                               face, xi, eta, edge, &o));
}

RefineResult refineNearestPoint(const PatchCache& cache, const Eigen::Vector3d& hip, int face, double xi, double eta,
                                const RefineOptions& options) {
  PatchRefiner r(cache);
  return r.refine(hip, face, xi, eta, options);
}

}  // namespace sf
