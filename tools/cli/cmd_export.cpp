// SPDX-License-Identifier: Apache-2.0
// `smoothforce export MESH|CACHE --level L -o OUT.obj|OUT.ply [--ascii] [--no-weld]`: the patches
// tessellated, welded along shared edges into one surface (tessellate.h).
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include <smoothforce/patch/tessellate.h>
#include "cli_common.h"
#include "cli_exit.h"

namespace sf::cli {

namespace {

/// Before tessellating: the triangles and (unwelded) vertices level L gives, and the least the
/// file can take (binary PLY: 45 bytes a vertex, 17 a triangle; OBJ and ASCII PLY at least 60 and
/// 20). Large exports are announced on stderr; one that cannot fit in the free space of the
/// output's directory is refused before any work (InputError naming the output).
void checkExportSize(const PatchCache& cache, int L, const std::string& output, bool binary) {
  double triangles = 0, vertices = 0;
  for (int f = 0; f < cache.numFaces(); ++f) {
    const double n = cache.faceSize(f);
    triangles += n * L * L;
    vertices += 1 + n * L * (L + 1) / 2;
  }
  const bool ply = output.size() >= 4 && output.compare(output.size() - 4, 4, ".ply") == 0;
  const double least = ply && binary ? 45 * vertices + 17 * triangles : 60 * vertices + 20 * triangles;
  if (triangles >= 1e7)
    std::fprintf(stderr, "export: level %d gives %.3g triangles and up to %.3g vertices: at least %.3g GB to write\n", L,
                 triangles, vertices, least * 1e-9);
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::absolute(output, ec).parent_path();
  const std::filesystem::space_info sp = std::filesystem::space(dir, ec);
  if (!ec && double(sp.available) < least) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s: level %d needs at least %.3g GB, %.3g GB free there (a lower --level)",
                  output.c_str(), L, least * 1e-9, double(sp.available) * 1e-9);
    throw InputError(buf);
  }
}

}  // namespace

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
    checkExportSize(src.cache, *level, *output, !*ascii);
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
