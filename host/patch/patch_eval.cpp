#include <smoothforce/patch/patch_eval.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include <smoothforce/patch/detail/gp_traits.h>

namespace sf {

Eigen::Vector2d domainCorner(int n, int k) {
  const double a = 2.0 * std::numbers::pi * k / n;
  return {std::cos(a), std::sin(a)};
}

bool insideDomain(int n, double xi, double eta, double tol) {
  if (!std::isfinite(xi) || !std::isfinite(eta) || n < 3) return false;
  const double c = std::cos(std::numbers::pi / n);
  for (int k = 0; k < n; ++k) {
    const double a = (2 * k + 1) * std::numbers::pi / n;
    if (c - (xi * std::cos(a) + eta * std::sin(a)) < -tol) return false;
  }
  return true;
}

namespace {

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
  const auto r = Gp<Real>::eval(n, recs, static_cast<int>(c.options.crossTangent), xi, eta);
  p.pos = {r.pos.x, r.pos.y, r.pos.z};
  p.dxi = {r.dxi.x, r.dxi.y, r.dxi.z};
  p.deta = {r.deta.x, r.deta.y, r.deta.z};
  p.normal = {r.normal.x, r.normal.y, r.normal.z};
  p.status = r.status | c.faceStatus[f];
  return p;
}

PatchPoint evalChecked(const PatchCache& c, int f, double xi, double eta) {
  if (c.options.precision == Precision::Double) return evalFace<double>(c, f, xi, eta);
  return evalFace<float>(c, f, xi, eta);
}

}  // namespace

PatchPoint evaluatePatch(const PatchCache& cache, int f, double xi, double eta) {
  if (f < 0 || f >= cache.numFaces())
    throw std::out_of_range("face " + std::to_string(f) + " out of range [0, " + std::to_string(cache.numFaces()) +
                            ")");
  return evalChecked(cache, f, xi, eta);
}

void evaluatePatches(const PatchCache& cache, const int32_t* faces, const double* xi, const double* eta, size_t count,
                     PatchPoint* out, Backend backend, int threads) {
  if (backend == Backend::OpenCL)
    throw std::invalid_argument("evaluatePatches: use the OpenCL backend's batch evaluator");
  auto one = [&](size_t i) {
    if (faces[i] < 0 || faces[i] >= cache.numFaces()) {
      out[i] = PatchPoint{};
      out[i].status = GP_ST_OUTSIDE;
    } else {
      out[i] = evalChecked(cache, faces[i], xi[i], eta[i]);
    }
  };
  if (backend == Backend::Serial) {
    for (size_t i = 0; i < count; ++i) one(i);
    return;
  }
  // The thread limit applies to this call only (an arena), not to the host process's other TBB work.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) one(i);
    });
  });
}

}  // namespace sf
