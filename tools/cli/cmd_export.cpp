// `smoothforce export MESH|CACHE --level L -o OUT.obj|OUT.ply`
#include <cstdio>

#include <smoothforce/patch/tessellate.h>
#include "cli_common.h"
#include "cli_exit.h"

namespace sf::cli {

void addExportCommand(CLI::App& app) {
  auto* x = app.add_subcommand("export", "Tessellate the patches into a triangle mesh with normals");
  auto input = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto level = std::make_shared<int>(8);
  auto args = std::make_shared<PatchArgs>();
  x->add_option("INPUT", *input, "mesh file or patch cache")->required();
  x->add_option("--level", *level, "subdivisions per polygon edge")->check(CLI::Range(1, 256))->capture_default_str();
  x->add_option("-o,--output", *output, "OUT.obj or OUT.ply")->required();
  addPatchArgs(*x, *args);
  x->callback([=] {
    Source src = openSource(*input, *args);
    throwIfInterrupted("export");
    const TriangleMesh tm = tessellatePatches(src.cache, *level, makeEvaluator(src.cache, *args));
    throwIfInterrupted("export");
    writeTriangleMesh(tm, *output);
    std::printf("export: %d patches at level %d -> %s (%zu vertices, %zu triangles)\n", src.cache.numFaces(), *level,
                output->c_str(), tm.positions.size(), tm.triangles.size());
  });
}

}  // namespace sf::cli
