// SPDX-License-Identifier: Apache-2.0
// OpenCL backend: program build time, construction (patches/s) and evaluation (points/s),
// float and double, with kernel time (profiling events) reported apart from transfers and
// host-side conversion; kernel GFLOP/s from the operations of one evaluation (gp_count.h;
// the per-evaluation counts themselves are in bench_patch's BM_Flops*).
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
#include "gp_count.h"

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

// args: precision, mesh (0: spot_quadrangulated, 2,928 quads; 1: odedstein/bunny_hr, 59,664
// triangles: a batch for a GPU). Whole construction: uploads, kernel, downloads.
// Counters: patches/s over wall time and over kernel time alone.
void BM_OpenCLConstruct(benchmark::State& state) {
  std::string why;
  if (!openclAvailable(&why)) return state.SkipWithError(("no OpenCL device: " + why).c_str());
  const Precision p = precisionArg(state);
  PatchCache c =
      meshCache(state.range(1) ? "odedstein/bunny_hr.obj" : "keenan_crane/spot_quadrangulated.obj", p, false);
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
BENCHMARK(BM_OpenCLConstruct)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(3);

// args: precision, batch size N (up to 2^20: a GPU's size). Random interior points on the spot
// cage (180 faces).
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
  const double fl = double(flops::countEval(4, false).flops());
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
    ->ArgsProduct({{0, 1}, {1, 256, 4096, 65536, 1 << 20}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
