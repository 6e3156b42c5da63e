// Patch construction (patches/s by face size, 1 and 2 threads) and evaluation (points/s,
// position + derivatives + normal, float and double) on the CPU backends.
// Run: build/bench/bench_patch [--benchmark_format=json]
#include <benchmark/benchmark.h>

#include "bench_common.h"

namespace {

using namespace sf;

// args: face size n, threads (1 = serial backend, 2 = tbb with 2 threads), precision (0 float, 1 double)
void BM_ConstructByFaceSize(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  const Precision p = state.range(2) ? Precision::Double : Precision::Float;
  PatchCache c = bench::ngonSoup(n, 4096, p);
  for (auto _ : state) {
    constructPatches(c, threads == 1 ? Backend::Serial : Backend::Tbb, threads);
    benchmark::DoNotOptimize(c.faceStatus.data());
  }
  state.counters["patches/s"] =
      benchmark::Counter(double(c.numFaces()) * state.iterations(), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(toString(p)) + ", " + std::to_string(n) + "-gons, " + std::to_string(threads) +
                 " thread(s)");
}
BENCHMARK(BM_ConstructByFaceSize)
    ->ArgsProduct({{3, 4, 5, 6, 8, 12}, {1, 2}, {1}})
    ->ArgsProduct({{4}, {1, 2}, {0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_ConstructSpotCage(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  PatchOptions o;
  const LoadedMesh lm = loadMesh(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", o);
  PatchCache c = preparePatchCache(lm.mesh, lm.cornerNormals, o, 0);
  for (auto _ : state) constructPatches(c, threads == 1 ? Backend::Serial : Backend::Tbb, threads);
  state.counters["patches/s"] =
      benchmark::Counter(double(c.numFaces()) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ConstructSpotCage)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();

// args: precision (0 float, 1 double), threads (1 serial, 2 tbb)
void BM_EvaluateSpotCage(benchmark::State& state) {
  const Precision p = state.range(0) ? Precision::Double : Precision::Float;
  const int threads = static_cast<int>(state.range(1));
  const PatchCache c = bench::meshCache(std::string(SF_DATA_DIR) + "/spot_control_mesh.obj", p);
  const bench::Queries q = bench::randomQueries(c, 1 << 16);
  std::vector<PatchPoint> out(q.face.size());
  for (auto _ : state) {
    evaluatePatches(c, q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), out.data(),
                    threads == 1 ? Backend::Serial : Backend::Tbb, threads);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points/s"] =
      benchmark::Counter(double(q.face.size()) * state.iterations(), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(toString(p)) + ", " + std::to_string(threads) + " thread(s)");
}
BENCHMARK(BM_EvaluateSpotCage)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
