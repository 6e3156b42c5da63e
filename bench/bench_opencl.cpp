// OpenCL backend: program build time, construction (patches/s) and evaluation (points/s),
// float and double, with kernel time (profiling events) reported apart from transfers and
// host-side conversion; plus the arithmetic of one evaluation, counted by running the shared
// patch math on a counting scalar type, for a roofline note.
//
// Run: build/bench/bench_opencl [--benchmark_format=json]
// Cold program builds: POCL_CACHE_DIR=$(mktemp -d) XDG_CACHE_HOME=$(mktemp -d) bench_opencl
// (otherwise PoCL's kernel cache and ours answer). Warm-up (the first construct / evaluate,
// where PoCL generates the work-group function) is excluded from the timed loops.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/patch_eval.h>
#include "gp_config.h"

// ---------------------------------------------------------------- counting instantiation
// The shared math (gp_vec.h, gp_edge.h, gp_eval.h) once more, with GP_REAL a scalar that
// counts its operations. Only this translation unit sees it.
namespace sf::flops {
struct Counts {
  long add = 0, mul = 0, div = 0, sqrt = 0, trig = 0, cmp = 0;
};
inline Counts g;
struct R {
  double v;
  R() = default;
  R(double x) : v(x) {}  // NOLINT: implicit, as a built-in real converts
};
inline R operator+(R a, R b) { return ++g.add, R(a.v + b.v); }
inline R operator-(R a, R b) { return ++g.add, R(a.v - b.v); }
inline R operator*(R a, R b) { return ++g.mul, R(a.v * b.v); }
inline R operator/(R a, R b) { return ++g.div, R(a.v / b.v); }
inline R operator-(R a) { return R(-a.v); }  // sign flip: not counted
inline R& operator+=(R& a, R b) { return a = a + b; }
inline R& operator-=(R& a, R b) { return a = a - b; }
inline R& operator*=(R& a, R b) { return a = a * b; }
inline bool operator<(R a, R b) { return ++g.cmp, a.v < b.v; }
inline bool operator>(R a, R b) { return ++g.cmp, a.v > b.v; }
inline bool operator<=(R a, R b) { return ++g.cmp, a.v <= b.v; }
inline bool operator>=(R a, R b) { return ++g.cmp, a.v >= b.v; }
inline R fc_sqrt(R a) { return ++g.sqrt, R(std::sqrt(a.v)); }
inline R fc_cos(R a) { return ++g.trig, R(std::cos(a.v)); }
inline R fc_sin(R a) { return ++g.trig, R(std::sin(a.v)); }
inline R fc_fabs(R a) { return R(std::fabs(a.v)); }

#undef GP_SQRT
#undef GP_COS
#undef GP_SIN
#undef GP_FABS
#define GP_SQRT(x) fc_sqrt(x)
#define GP_COS(x) fc_cos(x)
#define GP_SIN(x) fc_sin(x)
#define GP_FABS(x) fc_fabs(x)
#define GP_REAL R
#define GP_IS_DOUBLE 1
// order matters, each part uses the ones before it
// clang-format off
#include "gp_vec.h"
#include "gp_edge.h"
#include "gp_eval.h"
// clang-format on
#undef GP_REAL
#undef GP_IS_DOUBLE
#undef GP_SQRT
#undef GP_COS
#undef GP_SIN
#undef GP_FABS
#define GP_SQRT(x) std::sqrt(x)
#define GP_COS(x) std::cos(x)
#define GP_SIN(x) std::sin(x)
#define GP_FABS(x) std::fabs(x)

/// Operations of one gp_patch_eval on a regular n-gon patch (unit circle, normals tilted
/// outward, so no fallback branch runs) at an interior point.
inline Counts countEval(int n) {
  gp_vec3 V[GP_MAX_N], N[GP_MAX_N];
  int vid[GP_MAX_N];
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    V[k] = gp_v3(std::cos(a), std::sin(a), 0.0);
    const double l = std::sqrt(1.0 + 0.09);
    N[k] = gp_v3(0.3 * std::cos(a) / l, 0.3 * std::sin(a) / l, 1.0 / l);
    vid[k] = k;
  }
  static R recs[GP_MAX_N * GP_E_NFIELDS];
  gp_build_patch(n, V, N, vid, GP_CT_CORRECTED, recs);
  g = Counts{};
  const gp_eval_result r = gp_patch_eval(n, recs, GP_CT_CORRECTED, R(0.13), R(-0.21));
  benchmark::DoNotOptimize(r.pos.x.v);
  return g;
}
}  // namespace sf::flops

namespace {

using namespace sf;

PatchCache meshCache(const std::string& rel, Precision p, bool build) {
  const PolygonMesh m = readMesh(std::string(SF_SHARED_MESHES) + "/" + rel);
  PatchOptions o;
  o.precision = p;
  PatchCache c = preparePatchCache(m, cornerNormals(m, NormalMode::Auto), o, 0);
  if (build) constructPatches(c, Backend::Tbb);
  return c;
}

Precision precisionArg(const benchmark::State& s) { return s.range(0) ? Precision::Double : Precision::Float; }

struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
};
Queries randomQueries(const PatchCache& c, size_t count) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1, 1);
  Queries q;
  while (q.face.size() < count) {
    const int f = static_cast<int>(rng() % c.numFaces());
    const double x = u(rng), y = u(rng);
    if (!insideDomain(c.faceSize(f), x, y)) continue;
    q.face.push_back(f);
    q.xi.push_back(x);
    q.eta.push_back(y);
  }
  return q;
}

// args: precision (0 float, 1 double), binary cache (0 off, 1 on). Time = context + program
// build (or binary-cache load); `first_launch_s` = the first 1-point evaluation after it
// (PoCL generates the work-group function there). `*_1st_s`: the first iteration alone.
void BM_OpenCLProgramBuild(benchmark::State& state) {
  std::string why;
  if (!openclAvailable(&why)) return state.SkipWithError(("no OpenCL device: " + why).c_str());
  const Precision p = precisionArg(state);
  const PatchCache c = meshCache("keenan_crane/spot_control_mesh.obj", p, true);
  OpenCLOptions opt;
  opt.useBinaryCache = state.range(1) != 0;
  double build = 0, first = 0, fromCache = 0, build1 = -1, first1 = -1;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    OpenCLEvaluator ev(c, opt);
    const auto t1 = std::chrono::steady_clock::now();
    PatchPoint out;
    const int32_t f = 0;
    const double x = 0, y = 0;
    ev.evaluate(&f, &x, &y, 1, &out);
    const auto t2 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    build += ev.buildSeconds();
    first += std::chrono::duration<double>(t2 - t1).count();
    fromCache += ev.programFromCache();
    if (build1 < 0) build1 = ev.buildSeconds(), first1 = std::chrono::duration<double>(t2 - t1).count();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["build_s"] = build / n;
  state.counters["first_launch_s"] = first / n;
  state.counters["from_cache"] = fromCache / n;
  state.counters["build_1st_s"] = build1;  // cold when run as the header says
  state.counters["first_launch_1st_s"] = first1;
  state.SetLabel(std::string(toString(p)) + (opt.useBinaryCache ? ", binary cache" : ", no binary cache"));
}
BENCHMARK(BM_OpenCLProgramBuild)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Iterations(3)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// args: precision. Whole construction of spot_quadrangulated (2928 quads): uploads, kernel,
// downloads. Counters: patches/s over wall time and over kernel time alone.
void BM_OpenCLConstruct(benchmark::State& state) {
  std::string why;
  if (!openclAvailable(&why)) return state.SkipWithError(("no OpenCL device: " + why).c_str());
  const Precision p = precisionArg(state);
  PatchCache c = meshCache("keenan_crane/spot_quadrangulated.obj", p, false);
  OpenCLConstructor con;
  con.construct(c);  // warm-up: program build and PoCL's work-group code generation
  double kernel = 0, transfer = 0;
  for (auto _ : state) {
    con.construct(c);
    kernel += con.lastKernelSeconds();
    transfer += con.lastTransferSeconds();
  }
  const double it = static_cast<double>(state.iterations()), nf = c.numFaces();
  state.counters["patches/s"] = benchmark::Counter(nf * it, benchmark::Counter::kIsRate);
  state.counters["kernel_patches/s"] = nf * it / kernel;
  state.counters["kernel_ms"] = 1e3 * kernel / it;
  state.counters["transfer_ms"] = 1e3 * transfer / it;
  state.counters["build_s"] = con.buildSeconds();
  state.SetLabel(std::string(toString(p)) + ", " + std::to_string(c.numFaces()) + " faces, wg " +
                 std::to_string(con.workGroupSize()) + ", " + con.deviceName());
}
BENCHMARK(BM_OpenCLConstruct)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(3);

// args: precision, batch size N. Random interior points on the spot cage (180 quads).
// Counters: points/s over wall time (uploads + kernel + downloads + PatchPoint conversion)
// and over kernel time; kernel GFLOP/s from the counted operations of a quad evaluation.
void BM_OpenCLEvaluate(benchmark::State& state) {
  std::string why;
  if (!openclAvailable(&why)) return state.SkipWithError(("no OpenCL device: " + why).c_str());
  const Precision p = precisionArg(state);
  const size_t n = static_cast<size_t>(state.range(1));
  const PatchCache c = meshCache("keenan_crane/spot_control_mesh.obj", p, true);
  const Queries q = randomQueries(c, n);
  std::vector<PatchPoint> out(n);
  OpenCLEvaluator ev(c);
  ev.evaluate(q.face.data(), q.xi.data(), q.eta.data(), n, out.data());  // warm-up
  double kernel = 0, transfer = 0, host = 0;
  for (auto _ : state) {
    ev.evaluate(q.face.data(), q.xi.data(), q.eta.data(), n, out.data());
    benchmark::DoNotOptimize(out.data());
    kernel += ev.lastKernelSeconds();
    transfer += ev.lastTransferSeconds();
    host += ev.lastHostSeconds();
  }
  const flops::Counts k = flops::countEval(4);
  const double fl = double(k.add + k.mul + k.div + k.sqrt);
  const double it = static_cast<double>(state.iterations());
  state.counters["points/s"] = benchmark::Counter(double(n) * it, benchmark::Counter::kIsRate);
  state.counters["kernel_points/s"] = double(n) * it / kernel;
  state.counters["kernel_us"] = 1e6 * kernel / it;
  state.counters["transfer_us"] = 1e6 * transfer / it;
  state.counters["host_us"] = 1e6 * host / it;
  state.counters["kernel_GFLOP/s"] = fl * double(n) * it / kernel * 1e-9;
  state.SetLabel(std::string(toString(p)) + ", wg " + std::to_string(ev.workGroupSize()));
}
BENCHMARK(BM_OpenCLEvaluate)
    ->ArgsProduct({{0, 1}, {1, 256, 4096, 65536}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Repetitions(3);

// args: face size n. Counted operations of one evaluation, and the bytes it must read
// (n records of GP_E_NFIELDS reals + the query) and write (12 reals + status), in double.
void BM_FlopsPerEvaluation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  flops::Counts k;
  for (auto _ : state) k = flops::countEval(n);
  const double fl = double(k.add + k.mul + k.div + k.sqrt);
  const double bytes = n * GP_E_NFIELDS * 8.0 + 4 + 16 + 12 * 8 + 4;
  state.counters["flops"] = fl;
  state.counters["add"] = double(k.add);
  state.counters["mul"] = double(k.mul);
  state.counters["div"] = double(k.div);
  state.counters["sqrt"] = double(k.sqrt);
  state.counters["cos_sin"] = double(k.trig);
  state.counters["compares"] = double(k.cmp);
  state.counters["bytes_double"] = bytes;
  state.counters["flop_per_byte"] = fl / bytes;
  state.SetLabel(std::to_string(n) + "-gon, corrected cross tangents, interior point");
}
BENCHMARK(BM_FlopsPerEvaluation)->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
