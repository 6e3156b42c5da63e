// SPDX-License-Identifier: Apache-2.0
// `smoothforce eval MESH|CACHE --points IN.csv -o OUT.csv`
#include <cmath>
#include <cstdio>

#include <smoothforce/base/csv_reader.h>
#include "cli_common.h"
#include "cli_exit.h"
#include "cli_output.h"
#include "gp_config.h"  // GP_* status bits and record layout

namespace sf::cli {
namespace {

struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
};

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

/// Reads `face,xi,eta` rows; every problem names the file and line.
Queries readQueries(const std::string& path, const PatchCache& cache) {
  const NumericCsv t = readNumericCsv(path, {"face", "xi", "eta"});
  Queries q;
  for (size_t r = 0; r < t.rows(); ++r) {
    const double fv = t.at(r, 0), x = t.at(r, 1), y = t.at(r, 2);
    const std::string name = csvDisplayName(path);
    if (fv != std::floor(fv)) throwCsvError(name, t.line[r], "face is not an integer: '" + num(fv) + "'");
    if (fv < 0 || fv >= cache.numFaces())
      throwCsvError(name, t.line[r], "face " + num(fv) + " out of range [0, " + std::to_string(cache.numFaces()) + ")");
    const int32_t f = static_cast<int32_t>(fv);
    if (!insideDomain(cache.faceSize(f), x, y, 1e-12))
      throwCsvError(name, t.line[r],
                    "(xi, eta) = (" + num(x) + ", " + num(y) + ") is outside the domain of face " + std::to_string(f) +
                        " (a regular " + std::to_string(cache.faceSize(f)) + "-gon of circumradius 1)");
    q.face.push_back(f);
    q.xi.push_back(x);
    q.eta.push_back(y);
  }
  return q;
}

void run(const std::string& input, const std::string& points, const std::string& output, const PatchArgs& args,
         bool json) {
  Source src = openSource(input, args);
  const Queries q = readQueries(points, src.cache);
  std::vector<PatchPoint> res(q.face.size());
  makeEvaluator(src.cache, args)(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), res.data());
  throwIfInterrupted("eval");
  TextOutput out(output);
  std::FILE* f = out.file();
  std::fprintf(f, "face,xi,eta,x,y,z,nx,ny,nz\n");
  for (size_t i = 0; i < res.size(); ++i) {
    const PatchPoint& p = res[i];
    std::fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", q.face[i], q.xi[i], q.eta[i], p.pos.x(),
                 p.pos.y(), p.pos.z(), p.normal.x(), p.normal.y(), p.normal.z());
  }
  out.commit();
  size_t flagged = 0;
  for (const PatchPoint& p : res) flagged += (p.status & (GP_ST_DEGENERATE_MASK | GP_ST_SINGULAR)) != 0;
  std::FILE* report = reportStream(out.toStdout());
  if (json) {
    printJson(report, {{"input", input},
                       {"points", res.size()},
                       {"output", out.name()},
                       {"flagged", flagged},
                       {"precision", toString(src.cache.options.precision)}});
    return;
  }
  std::fprintf(report, "eval: %zu points -> %s%s\n", res.size(), out.name().c_str(),
               flagged ? (" (" + std::to_string(flagged) + " on degenerate patches or singular points)").c_str() : "");
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto* e = app.add_subcommand("eval", "Evaluate patch points and normals at (face, xi, eta) domain points");
  auto input = std::make_shared<std::string>();
  auto points = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto args = std::make_shared<PatchArgs>();
  auto json = std::make_shared<bool>(false);
  e->add_option("INPUT", *input, "mesh file or patch cache")->required();
  e->add_option("--points", *points, "CSV with header face,xi,eta (face 0-based in file order); - reads stdin")
      ->required();
  e->add_option("-o,--output", *output, "CSV to write: face,xi,eta,x,y,z,nx,ny,nz (%.17g); - writes stdout")
      ->required();
  e->add_flag("--json", *json,
              "summary as one JSON object (input, points, output, flagged, precision); on stderr with -o -");
  addPatchArgs(*e, *args);
  e->callback([=] { run(*input, *points, *output, *args, *json); });
}

}  // namespace sf::cli
