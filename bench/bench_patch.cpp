// SPDX-License-Identifier: Apache-2.0
// Patch evaluation (points/s: position, dG/dxi, dG/deta, normal) and construction (patches/s
// by face size, quality included) on the CPU, for every SIMD target this CPU runs (scalar,
// SSE4, AVX2, AVX-512), float and double, 1 and 2 threads; with the FLOPs of one evaluation
// and one construction (gp_count.h) and the fraction of the cores' peak they reach. After the
// runs it prints the ratios (SIMD / scalar, float / double, 2 threads / 1) of the medians.
//
// Run: build/bench/bench_patch [--benchmark_format=json] [--benchmark_filter=Evaluate]
// Defaults: 3 repetitions, medians reported (pass --benchmark_repetitions=N to change).
// Peak: SF_BENCH_GHZ (default 2.0) x SIMD width of the widest target this CPU runs x 2 (FMA) x
// SF_BENCH_FMA_UNITS (default 2) per core; the figure is printed with the results.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_simd.h>

#include "bench_common.h"
#include "gp_count.h"

namespace {

using namespace sf;

double envOr(const char* name, double dflt) {
  const char* v = std::getenv(name);
  return v && *v ? std::atof(v) : dflt;
}

/// Peak GFLOP/s of one core in precision p: frequency x lanes of the widest target this CPU runs
/// (simdLanes of Auto) x FMA units x 2.
double corePeakGflops(Precision p) {
  const double lanes = simdLanes(SimdTarget::Auto, p);
  return envOr("SF_BENCH_GHZ", 2.0) * lanes * 2 * envOr("SF_BENCH_FMA_UNITS", 2);
}

/// Useful FLOPs (the scalar path's count) and executed FLOPs per lane (both sides of every
/// select), averaged over the face sizes of the queries.
struct Flops {
  double useful = 0, lane = 0;
};
Flops evalFlops(const PatchCache& c, const std::vector<int32_t>& faces) {
  std::map<int, long> bySize;
  for (int32_t f : faces) ++bySize[c.faceSize(f)];
  Flops r;
  for (auto [n, count] : bySize) {
    r.useful += double(count) * flops::countEval(n, false).flops();
    r.lane += double(count) * flops::countEval(n, true).flops();
  }
  r.useful /= double(faces.size());
  r.lane /= double(faces.size());
  return r;
}

void setRateCounters(benchmark::State& state, double itemsPerIter, const char* unit, double usefulFlops,
                     double laneFlops, Precision p, int threads) {
  const double items = itemsPerIter * double(state.iterations());
  state.counters[unit] = benchmark::Counter(items, benchmark::Counter::kIsRate);
  state.counters["GFLOP/s"] = benchmark::Counter(items * usefulFlops * 1e-9, benchmark::Counter::kIsRate);
  // fraction of the peak of the cores used (counter divided by seconds: rate of flops / peak)
  state.counters["peak%"] =
      benchmark::Counter(items * usefulFlops * 1e-9 * 100 / (corePeakGflops(p) * threads), benchmark::Counter::kIsRate);
  state.counters["flop/item"] = usefulFlops;
  state.counters["laneflop/item"] = laneFlops;
}

// ---------------------------------------------------------------- evaluation
void evaluate(benchmark::State& state, SimdTarget t, Precision p, int threads) {
  const PatchCache c = bench::meshCache(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", p);
  const bench::Queries q = bench::randomQueries(c, 1 << 16);
  std::vector<PatchPoint> out(q.face.size());
  EvalOptions o;
  o.simd = t;
  o.backend = threads == 1 ? Backend::Serial : Backend::Tbb;
  o.threads = threads;
  PatchEvaluator ev(c, o);
  for (auto _ : state) {
    ev.evaluate(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  const Flops fl = evalFlops(c, q.face);
  setRateCounters(state, double(q.face.size()), "points/s", fl.useful, fl.lane, p, threads);
  state.SetLabel("spot cage, random points, " + std::to_string(simdLanes(t, p)) + " lanes");
}

/// A few points of one face at a time (FacePointEvaluator: the refinement's finite-difference
/// pair is count 2): the random points of evaluate() in runs of `count` on one face each.
void facePoints(benchmark::State& state, int count) {
  const PatchCache c = bench::meshCache(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", Precision::Double);
  const bench::Queries q = bench::randomQueries(c, 1 << 16);
  FacePointEvaluator ev(c);
  PatchPoint out[16];
  const size_t runs = q.face.size() / static_cast<size_t>(count);
  for (auto _ : state) {
    for (size_t r = 0; r < runs; ++r) {
      const size_t i = r * static_cast<size_t>(count);
      ev.evaluate(q.face[i], q.xi.data() + i, q.eta.data() + i, count, out);
      benchmark::DoNotOptimize(out);
    }
  }
  state.counters["points/s"] = benchmark::Counter(double(runs) * count, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel("spot cage, double, " + std::to_string(count) + " points per call");
}

// ---------------------------------------------------------------- construction
void constructNgons(benchmark::State& state, SimdTarget t, Precision p, int n, int threads) {
  PatchCache c = bench::ngonSoup(n, 4096, p);
  BuildOptions o;
  o.simd = t;
  o.backend = threads == 1 ? Backend::Serial : Backend::Tbb;
  o.threads = threads;
  for (auto _ : state) {
    constructPatches(c, o);
    benchmark::DoNotOptimize(c.faceStatus.data());
    benchmark::ClobberMemory();
  }
  setRateCounters(state, double(c.numFaces()), "patches/s", double(flops::countBuild(n, false).flops()),
                  double(flops::countBuild(n, true).flops()), p, threads);
}

void constructSpot(benchmark::State& state, SimdTarget t, int threads) {
  PatchOptions po;
  const LoadedMesh lm = loadMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", po);
  PatchCache c = preparePatchCache(lm.mesh, lm.cornerNormals, po, 0);
  BuildOptions o;
  o.simd = t;
  o.backend = threads == 1 ? Backend::Serial : Backend::Tbb;
  o.threads = threads;
  for (auto _ : state) {
    constructPatches(c, o);
    benchmark::DoNotOptimize(c.faceStatus.data());
  }
  double fl = 0, lane = 0;
  for (int f = 0; f < c.numFaces(); ++f) {
    fl += double(flops::countBuild(c.faceSize(f), false).flops());
    lane += double(flops::countBuild(c.faceSize(f), true).flops());
  }
  setRateCounters(state, double(c.numFaces()), "patches/s", fl / c.numFaces(), lane / c.numFaces(), Precision::Double,
                  threads);
}

// ---------------------------------------------------------------- ratios
/// Forwards to the console or JSON reporter and keeps each benchmark's median rate.
class RatioReporter : public benchmark::BenchmarkReporter {
 public:
  explicit RatioReporter(bool json) {
    if (json)
      inner_ = std::make_unique<benchmark::JSONReporter>();
    else
      inner_ = std::make_unique<benchmark::ConsoleReporter>();
  }
  bool ReportContext(const Context& c) override {
    inner_->SetOutputStream(&GetOutputStream());
    inner_->SetErrorStream(&GetErrorStream());
    return inner_->ReportContext(c);
  }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const bool single = r.run_type == Run::RT_Iteration && r.repetitions <= 1;
      if (!single && !(r.run_type == Run::RT_Aggregate && r.aggregate_name == "median")) continue;
      for (const char* unit : {"points/s", "patches/s"}) {
        auto it = r.counters.find(unit);
        if (it != r.counters.end()) rate[r.run_name.function_name] = {it->second.value, unit};
      }
    }
    inner_->ReportRuns(runs);
  }
  void Finalize() override { inner_->Finalize(); }

  std::map<std::string, std::pair<double, std::string>> rate;  // name -> (median rate, unit)

 private:
  std::unique_ptr<benchmark::BenchmarkReporter> inner_;
};

std::string evalName(SimdTarget t, Precision p, int threads) {
  return std::string("Evaluate/") + toString(t) + "/" + toString(p) + "/threads:" + std::to_string(threads);
}
std::string buildName(SimdTarget t, Precision p, int n, int threads) {
  return std::string("Construct/") + toString(t) + "/" + toString(p) + "/n:" + std::to_string(n) +
         "/threads:" + std::to_string(threads);
}

void printRatios(const RatioReporter& r, const std::vector<SimdTarget>& targets) {
  auto get = [&](const std::string& k) {
    auto it = r.rate.find(k);
    return it == r.rate.end() ? 0.0 : it->second.first;
  };
  auto ratio = [](double a, double b) { return b > 0 && a > 0 ? a / b : 0.0; };
  std::fprintf(stderr, "\nRatios of medians (this run; 0 = not run):\n");
  std::fprintf(stderr, "evaluation, spot cage (M points/s; x = / scalar same precision and threads)\n");
  for (int threads : {1, 2})
    for (Precision p : {Precision::Double, Precision::Float}) {
      const double base = get(evalName(SimdTarget::Scalar, p, threads));
      std::fprintf(stderr, "  %-6s %d thr:", toString(p), threads);
      for (SimdTarget t : targets) {
        const double v = get(evalName(t, p, threads));
        std::fprintf(stderr, "  %s %.2f (x%.2f)", toString(t), v * 1e-6, ratio(v, base));
      }
      std::fprintf(stderr, "\n");
    }
  const SimdTarget best = targets.front();
  std::fprintf(
      stderr, "  float / double (%s): 1 thr x%.2f, 2 thr x%.2f; 2 thr / 1 thr (%s, double): x%.2f\n", toString(best),
      ratio(get(evalName(best, Precision::Float, 1)), get(evalName(best, Precision::Double, 1))),
      ratio(get(evalName(best, Precision::Float, 2)), get(evalName(best, Precision::Double, 2))), toString(best),
      ratio(get(evalName(best, Precision::Double, 2)), get(evalName(best, Precision::Double, 1))));
  std::fprintf(stderr, "construction, n-gon soup, double (k patches/s; x = / scalar)\n");
  for (int threads : {1, 2})
    for (int n : {3, 4, 5, 6, 8, 12}) {
      const double base = get(buildName(SimdTarget::Scalar, Precision::Double, n, threads));
      std::fprintf(stderr, "  n=%-2d %d thr:", n, threads);
      for (SimdTarget t : targets) {
        const double v = get(buildName(t, Precision::Double, n, threads));
        std::fprintf(stderr, "  %s %.1f (x%.2f)", toString(t), v * 1e-3, ratio(v, base));
      }
      std::fprintf(stderr, "\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  bool json = false, reps = false;
  for (int i = 1; i < argc; ++i) {
    json |= std::strcmp(argv[i], "--benchmark_format=json") == 0;
    reps |= std::strncmp(argv[i], "--benchmark_repetitions", 23) == 0;
  }
  static char r5[] = "--benchmark_repetitions=3", agg[] = "--benchmark_report_aggregates_only=true";
  if (!reps) args.insert(args.begin() + 1, {r5, agg});
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());

  const std::vector<SimdTarget> targets = supportedSimdTargets();  // widest first, Scalar last
  for (SimdTarget t : targets)
    for (Precision p : {Precision::Double, Precision::Float})
      for (int threads : {1, 2})
        benchmark::RegisterBenchmark(evalName(t, p, threads).c_str(), evaluate, t, p, threads)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
  for (int count : {1, 2, 4, 8})
    benchmark::RegisterBenchmark(("FacePoints/count:" + std::to_string(count)).c_str(), facePoints, count)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  for (SimdTarget t : targets)
    for (int threads : {1, 2}) {
      for (int m : {3, 4, 5, 6, 8, 12})
        benchmark::RegisterBenchmark(buildName(t, Precision::Double, m, threads).c_str(), constructNgons, t,
                                     Precision::Double, m, threads)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      benchmark::RegisterBenchmark(buildName(t, Precision::Float, 4, threads).c_str(), constructNgons, t,
                                   Precision::Float, 4, threads)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(
          (std::string("ConstructSpotCage/") + toString(t) + "/threads:" + std::to_string(threads)).c_str(),
          constructSpot, t, threads)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }

  std::fprintf(stderr, "FLOPs per item (scalar path; one SIMD lane in brackets: both sides of every select):\n");
  for (int m : {3, 4, 5, 6, 8, 12})
    std::fprintf(stderr, "  n=%-2d evaluation %ld (%ld), construction with quality %ld (%ld)\n", m,
                 flops::countEval(m, false).flops(), flops::countEval(m, true).flops(),
                 flops::countBuild(m, false).flops(), flops::countBuild(m, true).flops());
  std::fprintf(stderr,
               "peak per core assumed: %.0f GFLOP/s double, %.0f float (%d / %d lanes, SF_BENCH_GHZ, "
               "SF_BENCH_FMA_UNITS)\n",
               corePeakGflops(Precision::Double), corePeakGflops(Precision::Float),
               simdLanes(SimdTarget::Auto, Precision::Double), simdLanes(SimdTarget::Auto, Precision::Float));

  RatioReporter rep(json);
  benchmark::RunSpecifiedBenchmarks(&rep);
  printRatios(rep, targets);
  benchmark::Shutdown();
  return 0;
}
