// SPDX-License-Identifier: Apache-2.0
// The per-patch certificate on real meshes: for each mesh, how many patches are proven
// fold-free (certified; of them, how many only cell by cell: regular), proven to turn over
// (folded) or left undecided within the budget,
// the smallest certified margin, the interval evaluations spent and the wall time; and the
// construction's own sampled fold flag (GP_ST_FOLD) beside it.
//   certificate_stats [--start S] [--quad-start Q] [--depth D] [--cells C] [MESH...]   (default: every shared mesh)
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <smoothforce/base/status.h>
#include <smoothforce/patch/patch_certificate.h>
#include "../tests/shared_mesh_files.h"
#include "bench_common.h"

using namespace sf;

namespace {
int run(std::vector<std::string> args) {
  CertificateOptions o;
  std::vector<std::string> meshes;
  for (size_t i = 0; i < args.size(); ++i) {
    if ((args[i] == "--depth" || args[i] == "--cells" || args[i] == "--start" || args[i] == "--quad-start") &&
        i + 1 < args.size()) {
      (args[i] == "--depth"   ? o.maxDepth
       : args[i] == "--cells" ? o.maxCells
       : args[i] == "--start" ? o.startDepth
                              : o.quadStartDepth) = std::stoi(args[i + 1]);
      ++i;
    } else if (args[i].rfind("--", 0) == 0) {
      std::fprintf(stderr, "certificate_stats: unknown option %s\n", args[i].c_str());
      return 2;
    } else {
      meshes.push_back(args[i]);
    }
  }
  if (meshes.empty()) meshes = test::sharedMeshFiles();
  std::printf("%-34s %7s %9s %7s %9s %7s %7s %9s %8s\n", "mesh", "faces", "certified", "regular", "undecided", "folded",
              "sampled", "minMargin", "s");
  for (const std::string& path : meshes) {
    PatchCache cache = bench::meshCache(path, Precision::Double);
    const auto t0 = std::chrono::steady_clock::now();
    const CertificateSummary sum = certifyPatches(cache, 0, o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    int sampled = 0;
    for (uint32_t st : cache.faceStatus) sampled += (st & SF_ST_FOLD) != 0;
    std::printf("%-34s %7d %9d %7d %9d %7d %7d %9.3g %8.3f\n", std::filesystem::path(path).filename().string().c_str(),
                cache.numFaces(), sum.certified, sum.regular, sum.undecided, sum.folded, sampled, sum.minMargin, s);
    if (!sum.uncertifiedFaces.empty() && sum.uncertifiedFaces.size() <= 40) {
      std::printf("  uncertified:");
      for (int f : sum.uncertifiedFaces) std::printf(" %d%s", f, cache.faceCertificate[f] < 0 ? "F" : "");
      std::printf("\n");
    }
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return bench::guardedMain("certificate_stats", [&] { return run(std::vector<std::string>(argv + 1, argv + argc)); });
}
