// SPDX-License-Identifier: Apache-2.0
// Distance from the patch surface of `--cage catmull-clark` to the cage's Catmull-Clark limit
// surface (OpenSubdiv Bfr), per mesh file, in percent of the bounding-box diagonal
// (measureLimitDistance, limit_distance.h; `cache info --faults` gives the surface faults).
//
// usage: cage_distance [--level L] [--approx A] [MESH...]
//   default MESH: the shared spot cage. L: tessellation segments per edge of both surfaces
//   (default 16). A: Bfr's approximation level of irregular regions (default 8).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <smoothforce/patch/limit_distance.h>
#include <smoothforce/patch/mesh_pipeline.h>

int main(int argc, char** argv) {
  int level = 16, approx = 8;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--level" && i + 1 < argc) {
      level = std::atoi(argv[++i]);
    } else if (a == "--approx" && i + 1 < argc) {
      approx = std::atoi(argv[++i]);
    } else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "usage: cage_distance [--level L] [--approx A] [MESH...]\n");
      return 2;
    } else {
      meshes.push_back(a);
    }
  }
  if (meshes.empty()) meshes.push_back(std::string(SF_SHARED_MESHES) + "/keenan_crane/spot_control_mesh.obj");
  std::printf("%-48s %6s %12s %12s %12s %12s %8s %9s\n", "mesh", "faces", "p->L max %", "p->L mean %", "L->p max %",
              "L->p mean %", "worst", "seconds");
  for (const std::string& path : meshes) {
    try {
      sf::PatchOptions o;
      o.cage = sf::CageMode::CatmullClark;
      const sf::LoadedMesh loaded = sf::loadMesh(path, o);
      const sf::PatchCache cache = sf::buildPatchCache(loaded, o, sf::Backend::Tbb);
      const auto t0 = std::chrono::steady_clock::now();
      const sf::LimitDistance d = sf::measureLimitDistance(cache, loaded, level, approx);
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%-48s %6d %12.4f %12.5f %12.4f %12.5f %8d %9.2f\n", path.c_str(), d.facesMeasured,
                  100 * d.maxPatchToLimit, 100 * d.meanPatchToLimit, 100 * d.maxLimitToPatch, 100 * d.meanLimitToPatch,
                  d.worstFace, secs);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), e.what());
      return 1;
    }
  }
  return 0;
}
