// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/patch_eval.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <smoothforce/base/thread_limit.h>
#include <smoothforce/patch/detail/gp_traits.h>

#include "patch_simd_detail.h"

namespace sf {

namespace {
/// n has an entry in the kernels' domain table (gp_tables.cpp)
bool tabled(int n) { return n >= 3 && n <= GP_MAX_N; }
/// cos(pi/n): the distance from the centre to every domain edge
double apothem(int n) { return tabled(n) ? gpd::gp_dom_apothem(n) : gpd::gp_domain_calc_apothem(n); }
}  // namespace

Eigen::Vector2d domainCorner(int n, int k) {
  double x, y;
  if (tabled(n) && k >= 0 && k < n)
    gpd::gp_domain_corner(n, k, &x, &y);
  else  // the table's formula for the same corner (k outside [0, n) rounds its angle differently)
    gpd::gp_domain_calc_corner(n, k, &x, &y);
  return {x, y};
}

double domainEdgeMax(int n, const Eigen::Vector2d& X, int& k) noexcept {
  if (tabled(n)) return gpd::gp_dom_edge_max(n, X.x(), X.y(), &k);
  // no table entry: gp_dom_edge_max's loop over the normals the table would hold
  double best = -1e300;  // -GP_BIG of double
  k = 0;
  for (int j = 0; j < n; ++j) {
    double mx, my;
    gpd::gp_domain_calc_normal(n, j, &mx, &my);
    if (const double v = X.x() * mx + X.y() * my; v > best) best = v, k = j;
  }
  return best;
}

bool insideDomain(int n, double xi, double eta, double tol) {
  if (!std::isfinite(xi) || !std::isfinite(eta) || n < 3) return false;
  int k;
  // cos(pi/n) - max_k X . m_k < -tol exactly when some edge has cos(pi/n) - X . m_k < -tol
  // (rounding is monotonic), so this is the test per edge with the kernels' normals
  return !(apothem(n) - domainEdgeMax(n, {xi, eta}, k) < -tol);
}

Eigen::Vector2d clampToDomain(int n, const Eigen::Vector2d& X) noexcept {
  int k;  // gp_dom_clamp, for any n
  const double m = domainEdgeMax(n, X, k), c = apothem(n);
  return m > c ? Eigen::Vector2d(X * (c / m)) : X;
}

namespace {

template <class Real>
void fill(PatchPoint& p, const typename Gp<Real>::result& r, uint32_t faceStatus) {
  p.pos = {r.pos.x, r.pos.y, r.pos.z};
  p.dxi = {r.dxi.x, r.dxi.y, r.dxi.z};
  p.deta = {r.deta.x, r.deta.y, r.deta.z};
  p.normal = {r.normal.x, r.normal.y, r.normal.z};
  p.status = r.status | faceStatus;
}

template <class Real>
PatchPoint evalFace(const PatchCache& c, int f, double xi, double eta) {
  Real recs[GP_MAX_N * GP_E_NFIELDS];
  PatchPoint p;
  const int n = c.faceSize(f);
  if (n < 3 || n > GP_MAX_N) {
    p.status = GP_ST_TOO_MANY_SIDES;
    return p;
  }
  gatherRecords(c, f, recs);
  const int mode = gpd::gp_eval_mode(static_cast<int>(c.options.crossTangent), c.faceStatus[f]);
  fill<Real>(p, Gp<Real>::eval(n, recs, mode, xi, eta), c.faceStatus[f]);
  return p;
}

PatchPoint evalChecked(const PatchCache& c, int f, double xi, double eta) {
  if (c.options.precision == Precision::Double) return evalFace<double>(c, f, xi, eta);
  return evalFace<float>(c, f, xi, eta);
}

/// The scalar path of a group: the face's records gathered once, then one point at a time.
template <class Real>
void evalGroupScalar(const simd_detail::EvalGroup& g) {
  Real recs[GP_MAX_N * GP_E_NFIELDS];
  const Real* data = static_cast<const Real*>(g.data);
  for (int i = 0; i < GP_E_NFIELDS; ++i)
    for (int k = 0; k < g.n; ++k) recs[k * GP_E_NFIELDS + i] = data[static_cast<size_t>(i) * g.numSlots + g.first + k];
  const auto* dom = Gp<Real>::domain(g.n);
  const int mode = gpd::gp_eval_mode(g.mode, g.faceStatus);
  for (size_t j = 0; j < g.count; ++j) {
    fill<Real>(g.sorted ? g.sorted[j] : g.out[g.idx[j]], Gp<Real>::evalDom(dom, recs, mode, g.xs[j], g.ys[j]),
               g.faceStatus);
  }
}

/// Queries per chunk of one face's group: the unit of parallel work.
constexpr uint32_t kChunk = 512;

}  // namespace

PatchPoint evaluatePatch(const PatchCache& cache, int f, double xi, double eta) {
  if (f < 0 || f >= cache.numFaces())
    throw std::out_of_range("face " + std::to_string(f) + " out of range [0, " + std::to_string(cache.numFaces()) +
                            ")");
  return evalChecked(cache, f, xi, eta);
}

namespace {
/// The evaluator of count points (1..16) of one face in precision `dbl`: the narrowest
/// supported target with at least 4 lanes that holds them all, else the widest; the scalar path
/// only where no SIMD target runs. One point takes a vector too: the refinement's calls of 1 to 4
/// points of a face (a point, a point with its finite differences) then share one target, so the
/// face's records stay broadcast between them, and one lane of 4 costs less than the scalar
/// instantiation (bench_patch FacePoints/count:1 1.87 -> 2.31 M points/s on an AMD EPYC Zen 5;
/// the same bits either way, tests/patch/test_patch_simd.cpp).
simd_detail::EvalFn fewPointsFn(bool dbl, int count) {
  struct Pick {
    simd_detail::EvalFn fn[17];
  };
  auto make = [](bool d) {
    Pick p;
    const std::vector<SimdTarget> targets = supportedSimdTargets();  // widest first
    for (int k = 0; k <= 16; ++k) {
      p.fn[k] = d ? evalGroupScalar<double> : evalGroupScalar<float>;
      if (k < 1) continue;
      for (SimdTarget t : targets) {
        const simd_detail::EvalFns* e = t == SimdTarget::Scalar ? nullptr : simd_detail::evalFns(t);
        if (!e) continue;
        const bool fits = (d ? e->lanesD : e->lanesF) >= std::max(k, 4);
        if (fits || p.fn[k] == (d ? evalGroupScalar<double> : evalGroupScalar<float>)) p.fn[k] = d ? e->evalD : e->evalF;
      }
    }
    return p;
  };
  static const Pick pd = make(true), pf = make(false);
  return (dbl ? pd : pf).fn[std::clamp(count, 0, 16)];
}
}  // namespace

/// The records of a face as vectors of the widest target (EvalGroup::laneRecs), aligned.
struct FacePointEvaluator::Scratch {
  static constexpr size_t kAlign = 64, kBytes = size_t(GP_MAX_N) * GP_E_NFIELDS * kAlign;
  void* recs = ::operator new(kBytes, std::align_val_t(kAlign));
  double xs[16 + simd_detail::kPointPad] = {}, ys[16 + simd_detail::kPointPad] = {};
  /// what recs holds: face `face`'s records of the cache data `data` as `fn`'s vectors (face -1:
  /// nothing reusable; evaluateRecords' records, which a lazy store may rewrite in place, never are)
  const void* data = nullptr;
  int face = -1;
  simd_detail::EvalFn fn = nullptr;
  ~Scratch() { ::operator delete(recs, std::align_val_t(kAlign)); }

  /// Evaluates the face g describes (n, mode, records, status) at count (1..16) points; face >= 0:
  /// g holds that face's records from the cache, kept as vectors for its next call.
  void run(simd_detail::EvalGroup& g, bool dbl, int f, const double* xi, const double* eta, int count,
           PatchPoint* out) {
    std::copy_n(xi, count, xs);
    std::copy_n(eta, count, ys);
    g.count = static_cast<size_t>(count);
    g.xi = g.xs = xs;
    g.eta = g.ys = ys;
    g.sorted = out;
    g.laneRecs = recs;
    const simd_detail::EvalFn use = fewPointsFn(dbl, count);
    g.laneRecsReady = f >= 0 && f == face && g.data == data && use == fn;
    face = f;
    data = g.data;
    fn = use;
    use(g);
  }
};

FacePointEvaluator::FacePointEvaluator(const PatchCache& cache) : cache_(&cache), scratch_(std::make_unique<Scratch>()) {
  if (!hasPatchData(cache) && cache.numFaces() > 0)
    throw std::invalid_argument("FacePointEvaluator: the cache holds no patches (a skeleton); build them first");
  for (int k = 0; k <= 16; ++k) (void)fewPointsFn(true, k);  // the targets are chosen here, once per process
}

FacePointEvaluator::FacePointEvaluator() : cache_(nullptr), scratch_(std::make_unique<Scratch>()) {
  for (int k = 0; k <= 16; ++k) (void)fewPointsFn(true, k);
}

FacePointEvaluator::~FacePointEvaluator() = default;

namespace {
template <class Real>
void transposeRecords(int n, const Real* recordMajor, double* fieldMajor) noexcept {
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < GP_E_NFIELDS; ++i)
      fieldMajor[static_cast<size_t>(i) * n + k] = recordMajor[static_cast<size_t>(k) * GP_E_NFIELDS + i];
}
}  // namespace

void recordsFieldMajor(int n, const double* recordMajor, double* fieldMajor) noexcept {
  transposeRecords(n, recordMajor, fieldMajor);
}
void recordsFieldMajor(int n, const float* recordMajor, double* fieldMajor) noexcept {
  transposeRecords(n, recordMajor, fieldMajor);
}

void FacePointEvaluator::evaluateRecords(int n, int mode, uint32_t faceStatus, const double* recs, const double* xi,
                                         const double* eta, int count, PatchPoint* out) noexcept {
  count = std::clamp(count, 0, 16);
  if (count == 0) return;
  simd_detail::EvalGroup g;
  g.n = n;
  g.mode = mode;
  g.data = recs;
  g.numSlots = static_cast<size_t>(n);
  g.first = 0;
  g.faceStatus = faceStatus;
  scratch_->run(g, true, -1, xi, eta, count, out);
}

void FacePointEvaluator::evaluate(int f, const double* xi, const double* eta, int count, PatchPoint* out) noexcept {
  const PatchCache& c = *cache_;
  count = std::clamp(count, 0, 16);
  if (count == 0) return;
  const bool dbl = c.options.precision == Precision::Double;
  simd_detail::EvalGroup g;
  g.n = c.faceSize(f);
  g.mode = static_cast<int>(c.options.crossTangent);
  g.data = dbl ? static_cast<const void*>(c.edgeDataD.data()) : static_cast<const void*>(c.edgeDataF.data());
  g.numSlots = static_cast<size_t>(c.numSlots());
  g.first = c.faceOffsets[f];
  g.faceStatus = c.faceStatus[f];
  scratch_->run(g, dbl, f, xi, eta, count, out);
}

PatchEvaluator::PatchEvaluator(const PatchCache& cache, const EvalOptions& options)
    : cache_(&cache), options_(options), target_(resolveSimdTarget(options.simd)) {
  if (options.backend == Backend::OpenCL)
    throw std::invalid_argument("PatchEvaluator: use the OpenCL backend's batch evaluator (opencl_backend.h)");
  if (!hasPatchData(cache) && cache.numFaces() > 0)
    throw std::invalid_argument("PatchEvaluator: the cache holds no patches (a skeleton); build them first");
}

void PatchEvaluator::evaluate(const int32_t* faces, const double* xi, const double* eta, size_t count,
                              PatchPoint* out) noexcept {
  const PatchCache& c = *cache_;
  const int nf = c.numFaces();
  // group the queries by face: order_ lists them face by face, chunks_ cuts it into groups
  order_.resize(count);
  size_t valid = 0;
  auto usable = [&](int f) { return f >= 0 && f < nf && c.faceSize(f) >= 3 && c.faceSize(f) <= GP_MAX_N; };
  for (size_t i = 0; i < count; ++i) {
    if (usable(faces[i])) {
      ++valid;
      continue;
    }
    out[i] = PatchPoint{};
    out[i].status = faces[i] >= 0 && faces[i] < nf ? GP_ST_TOO_MANY_SIDES : GP_ST_OUTSIDE;
  }
  chunks_.clear();
  auto addChunks = [&](int32_t f, uint32_t b, uint32_t e) {
    for (; b < e; b += kChunk) chunks_.push_back({f, b, std::min(e, b + kChunk)});
  };
  if (count >= static_cast<size_t>(nf) / 4) {  // counting sort
    start_.assign(static_cast<size_t>(nf) + 1, 0);
    for (size_t i = 0; i < count; ++i)
      if (usable(faces[i])) ++start_[faces[i] + 1];
    for (int f = 0; f < nf; ++f) start_[f + 1] += start_[f];
    for (int f = 0; f < nf; ++f) addChunks(f, start_[f], start_[f + 1]);
    for (size_t i = 0; i < count; ++i)
      if (usable(faces[i])) order_[start_[faces[i]]++] = static_cast<uint32_t>(i);
  } else {  // few queries on many faces
    size_t m = 0;
    for (size_t i = 0; i < count; ++i)
      if (usable(faces[i])) order_[m++] = static_cast<uint32_t>(i);
    std::sort(order_.begin(), order_.begin() + valid, [&](uint32_t a, uint32_t b) { return faces[a] < faces[b]; });
    for (uint32_t b = 0; b < valid;) {
      const int32_t f = faces[order_[b]];
      uint32_t e = b + 1;
      while (e < valid && faces[order_[e]] == f) ++e;
      addChunks(f, b, e);
      b = e;
    }
  }
  const bool dbl = c.options.precision == Precision::Double;
  simd_detail::EvalFn fn = dbl ? evalGroupScalar<double> : evalGroupScalar<float>;
  if (target_ != SimdTarget::Scalar) {
    const simd_detail::EvalFns* t = simd_detail::evalFns(target_);
    fn = dbl ? t->evalD : t->evalF;
  }
  const void* data = dbl ? static_cast<const void*>(c.edgeDataD.data()) : static_cast<const void*>(c.edgeDataF.data());
  auto run = [&](size_t i) {
    const Chunk& ch = chunks_[i];
    simd_detail::EvalGroup g;
    g.n = c.faceSize(ch.face);
    g.mode = static_cast<int>(c.options.crossTangent);
    g.data = data;
    g.numSlots = static_cast<size_t>(c.numSlots());
    g.first = c.faceOffsets[ch.face];
    g.faceStatus = c.faceStatus[ch.face];
    g.idx = order_.data() + ch.begin;
    g.count = ch.end - ch.begin;
    g.xi = xi;
    g.eta = eta;
    // the chunk's points in its order, gathered by the thread that evaluates them
    thread_local std::vector<double> xs(kChunk + simd_detail::kPointPad), ys(kChunk + simd_detail::kPointPad);
    for (size_t j = 0; j < g.count; ++j) {
      xs[j] = xi[g.idx[j]];
      ys[j] = eta[g.idx[j]];
    }
    std::fill_n(xs.begin() + g.count, simd_detail::kPointPad, 0.0);
    std::fill_n(ys.begin() + g.count, simd_detail::kPointPad, 0.0);
    g.xs = xs.data();
    g.ys = ys.data();
    g.out = out;
    fn(g);
  };
  if (options_.backend == Backend::Serial || chunks_.size() < 2) {
    for (size_t i = 0; i < chunks_.size(); ++i) run(i);
    return;
  }
  // Threads scatter into `out` directly, as the serial path does: measured faster than results
  // in face order and a second, permuting pass (the lines two threads share, neighbouring
  // queries of other faces, are rarely written at once).
  auto all = [&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks_.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) run(i);
    });
  };
  if (options_.threads > 0) {
    tbb::task_arena arena(arenaThreads(options_.threads));
    arena.execute(all);
  } else {
    all();
  }
}

void evaluatePatches(const PatchCache& cache, const int32_t* faces, const double* xi, const double* eta, size_t count,
                     PatchPoint* out, Backend backend, int threads) {
  EvalOptions o;
  o.backend = backend;
  o.threads = threads;
  PatchEvaluator(cache, o).evaluate(faces, xi, eta, count, out);
}

}  // namespace sf
