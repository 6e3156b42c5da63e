// `smoothforce export MESH|CACHE --level L -o OUT.obj|OUT.ply [--ascii] [--no-weld]`: the patches
// tessellated, welded along shared edges into one surface (tessellate.h).
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
  auto ascii = std::make_shared<bool>(false);
  auto noWeld = std::make_shared<bool>(false);
  x->add_option("INPUT", *input, "mesh file or patch cache")->required();
  x->add_option("--level", *level, "subdivisions per polygon edge")->check(CLI::Range(1, 256))->capture_default_str();
  x->add_option("-o,--output", *output,
                "OUT.obj (a group patch_F per patch) or OUT.ply (binary; per vertex status, fold, bulge; per "
                "triangle patch)")
      ->required();
  x->add_flag("--ascii", *ascii, "PLY: ASCII instead of binary little-endian");
  x->add_flag("--no-weld", *noWeld, "keep every patch's vertices apart (one piece per patch)");
  addPatchArgs(*x, *args);
  x->callback([=] {
    Source src = openSource(*input, *args);
    throwIfInterrupted("export");
    TriangleMesh tm = tessellatePatches(src.cache, *level, makeEvaluator(src.cache, *args));
    throwIfInterrupted("export");
    WeldReport weld;
    if (!*noWeld) weld = weldPatchSeams(src.cache, *level, tm);
    TriangleMeshFormat format;
    format.binary = !*ascii;
    writeTriangleMesh(tm, *output, format);
    std::printf("export: %d patches at level %d -> %s (%zu vertices, %zu triangles)\n", src.cache.numFaces(), *level,
                output->c_str(), tm.positions.size(), tm.triangles.size());
    if (*noWeld)
      std::printf("weld: off (--no-weld): one piece per patch\n");
    else
      std::printf("weld: %zu shared edges, %zu vertices merged, %zu edges left open (patches that do not meet)\n",
                  weld.edgesWelded, weld.merged, weld.openEdges);
  });
}

}  // namespace sf::cli
