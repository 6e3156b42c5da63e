// `smoothforce eval MESH|CACHE --points IN.csv -o OUT.csv`
#include <charconv>
#include <cstdio>
#include <fstream>

#include "cli_common.h"

namespace sf::cli {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

template <class T>
bool parseField(const std::string& field, T& out) {
  const std::string f = trim(field);
  if (f.empty()) return false;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), out);
  return r.ec == std::errc() && r.ptr == f.data() + f.size();
}

struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
};

/// Reads `face,xi,eta` rows; every problem names the file and line.
Queries readQueries(const std::string& path, const PatchCache& cache) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  Queries q;
  std::string line;
  int lineNo = 0;
  auto fail = [&](const std::string& what) { return InputError(path + ":" + std::to_string(lineNo) + ": " + what); };
  if (!std::getline(in, line)) throw InputError(path + ": empty file (expected header face,xi,eta)");
  ++lineNo;
  {
    std::string h;
    for (char ch : line)
      if (ch != ' ' && ch != '\t' && ch != '\r') h += ch;
    if (h != "face,xi,eta") throw fail("expected header 'face,xi,eta', got '" + trim(line) + "'");
  }
  while (std::getline(in, line)) {
    ++lineNo;
    if (trim(line).empty()) continue;
    std::vector<std::string> cols;
    size_t start = 0;
    for (size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',') {
        cols.push_back(line.substr(start, i - start));
        start = i + 1;
      }
    if (cols.size() != 3) throw fail("expected 3 columns face,xi,eta, got " + std::to_string(cols.size()));
    int32_t f;
    double x, y;
    if (!parseField(cols[0], f)) throw fail("face is not an integer: '" + trim(cols[0]) + "'");
    if (!parseField(cols[1], x) || !std::isfinite(x)) throw fail("xi is not a finite number: '" + trim(cols[1]) + "'");
    if (!parseField(cols[2], y) || !std::isfinite(y)) throw fail("eta is not a finite number: '" + trim(cols[2]) + "'");
    if (f < 0 || f >= cache.numFaces())
      throw fail("face " + std::to_string(f) + " out of range [0, " + std::to_string(cache.numFaces()) + ")");
    if (!insideDomain(cache.faceSize(f), x, y, 1e-12))
      throw fail("(xi, eta) = (" + trim(cols[1]) + ", " + trim(cols[2]) + ") is outside the domain of face " +
                 std::to_string(f) + " (a regular " + std::to_string(cache.faceSize(f)) + "-gon of circumradius 1)");
    q.face.push_back(f);
    q.xi.push_back(x);
    q.eta.push_back(y);
  }
  return q;
}

void run(const std::string& input, const std::string& points, const std::string& output, const PatchArgs& args) {
  Source src = openSource(input, args);
  const Queries q = readQueries(points, src.cache);
  std::vector<PatchPoint> res(q.face.size());
  makeEvaluator(src.cache, args)(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), res.data());
  const std::string tmp = output + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw InputError(output + ": cannot open for writing");
  std::fprintf(f, "face,xi,eta,x,y,z,nx,ny,nz\n");
  for (size_t i = 0; i < res.size(); ++i) {
    const PatchPoint& p = res[i];
    std::fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", q.face[i], q.xi[i], q.eta[i], p.pos.x(),
                 p.pos.y(), p.pos.z(), p.normal.x(), p.normal.y(), p.normal.z());
  }
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad || std::rename(tmp.c_str(), output.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw InputError(output + ": write failed");
  }
  size_t flagged = 0;
  for (const PatchPoint& p : res) flagged += (p.status & (GP_ST_DEGENERATE_MASK | GP_ST_SINGULAR)) != 0;
  std::fprintf(stderr, "eval: %zu points -> %s%s\n", res.size(), output.c_str(),
               flagged ? (" (" + std::to_string(flagged) + " on degenerate patches or singular points)").c_str() : "");
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto* e = app.add_subcommand("eval", "Evaluate patch points and normals at (face, xi, eta) domain points");
  auto input = std::make_shared<std::string>();
  auto points = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto args = std::make_shared<PatchArgs>();
  e->add_option("INPUT", *input, "mesh file or patch cache")->required();
  e->add_option("--points", *points, "CSV with header face,xi,eta (face 0-based in file order)")->required();
  e->add_option("-o,--output", *output, "CSV to write: face,xi,eta,x,y,z,nx,ny,nz (%.17g)")->required();
  addPatchArgs(*e, *args);
  e->callback([=] { run(*input, *points, *output, *args); });
}

}  // namespace sf::cli
