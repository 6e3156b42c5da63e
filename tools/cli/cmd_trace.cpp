// `smoothforce trace (--cache C | --mesh M) --method M --hips IN.csv -o OUT.csv`
#include "cmd_trace.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/query/embree_scene.h>
#include "cli_common.h"

namespace sf::cli {
namespace {

struct TraceArgs {
  std::string cache, mesh, method = "patch", hips, output;
  double stiffness = ForceOptions{}.stiffness;
  int patchCapacity = 256;
  PatchArgs patch;
  RefineArgs refine;
};

bool parseDouble(const char* b, const char* e, double& out) {
  while (b < e && (*b == ' ' || *b == '\t')) ++b;
  while (e > b && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r')) --e;
  if (b == e) return false;
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e && std::isfinite(out);
}

/// Reads the `x,y,z` rows of `path`; every problem names file:line.
std::vector<Eigen::Vector3d> readHips(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  std::vector<Eigen::Vector3d> hips;
  size_t pos = 0;
  int lineNo = 0;
  bool header = false;
  auto fail = [&](const std::string& what) { return InputError(path + ":" + std::to_string(lineNo) + ": " + what); };
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const char* b = text.data() + pos;
    const char* e = text.data() + end;
    pos = end + 1;
    ++lineNo;
    std::string_view line(b, e - b);
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    if (!header) {
      std::string h;
      for (char ch : line)
        if (ch != ' ' && ch != '\t' && ch != '\r') h += ch;
      if (h != "x,y,z") throw fail("expected header 'x,y,z', got '" + std::string(line) + "'");
      header = true;
      continue;
    }
    const char* c1 = static_cast<const char*>(memchr(b, ',', e - b));
    const char* c2 = c1 ? static_cast<const char*>(memchr(c1 + 1, ',', e - c1 - 1)) : nullptr;
    if (!c1 || !c2 || memchr(c2 + 1, ',', e - c2 - 1)) throw fail("expected 3 columns x,y,z");
    Eigen::Vector3d p;
    if (!parseDouble(b, c1, p.x())) throw fail("x is not a finite number: '" + std::string(b, c1) + "'");
    if (!parseDouble(c1 + 1, c2, p.y())) throw fail("y is not a finite number: '" + std::string(c1 + 1, c2) + "'");
    if (!parseDouble(c2 + 1, e, p.z())) throw fail("z is not a finite number: '" + std::string(c2 + 1, e) + "'");
    hips.push_back(p);
  }
  if (!header) throw InputError(path + ": empty file (expected header x,y,z)");
  return hips;
}

void run(const TraceArgs& a) {
  ForceOptions opt;
  opt.stiffness = a.stiffness;
  a.refine.apply(opt);
  opt.patchCapacity = a.patchCapacity;
  const ForceMethod method = parseForceMethod(a.method);
  validateForceOptions(opt);
  const std::string& input = a.cache.empty() ? a.mesh : a.cache;
  if (!a.cache.empty() && !isPatchCacheFile(a.cache)) throw InputError(a.cache + ": not a patch cache file");
  if (!a.mesh.empty() && isPatchCacheFile(a.mesh)) throw InputError(a.mesh + ": is a patch cache; use --cache");
  const std::vector<Eigen::Vector3d> hips = readHips(a.hips);
  PatchArgs patch = a.patch;
  patch.precision = toString(a.refine.precision(parsePrecision(a.patch.precision)));
  Source src = openSource(input, patch, /*lazy=*/true);  // a mesh: patches built where the HIPs go
  auto cache = std::make_shared<const PatchCache>(std::move(src.cache));
  auto scene = std::make_shared<const PolygonScene>(*cache);
  auto renderer = makeForceRenderer(cache, scene, method, opt);

  std::vector<ForceSample> out(hips.size());
  std::vector<double> stepSeconds(hips.size());
  for (size_t i = 0; i < hips.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    out[i] = renderer->step(hips[i]);
    stepSeconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  const std::string tmp = a.output + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw InputError(a.output + ": cannot open for writing");
  std::vector<char> buf(1 << 20);
  std::setvbuf(f, buf.data(), _IOFBF, buf.size());
  std::fprintf(f, "x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status\n");
  size_t inContact = 0, starts = 0, maxAt = 0;
  double maxDiff = 0, total = 0, worst = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const ForceSample& s = out[i];
    const Eigen::Vector3d& h = hips[i];
    std::fprintf(f, "%.17g,%.17g,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%u\n", h.x(), h.y(),
                 h.z(), s.contact ? 1 : 0, s.contact ? s.face : -1, s.xi, s.eta, s.scp.x(), s.scp.y(), s.scp.z(),
                 s.force.x(), s.force.y(), s.force.z(), s.iterations, s.status);
    inContact += s.contact;
    starts += (s.status & SF_TRACK_ENTER) != 0 && s.contact;
    if (i > 0) {
      const double d = (s.force - out[i - 1].force).norm();
      if (d > maxDiff) {
        maxDiff = d;
        maxAt = i;
      }
    }
    total += stepSeconds[i];
    worst = std::max(worst, stepSeconds[i]);
  }
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad || std::rename(tmp.c_str(), a.output.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw InputError(a.output + ": write failed");
  }
  std::fprintf(stderr,
               "trace: %zu steps (%s%s%s%s%s), %zu in contact, %zu contacts, max consecutive force difference "
               "%.6g N (step %zu), compute %.3g us/step mean, %.3g us max -> %s\n",
               hips.size(), toString(method), method == ForceMethod::Patch ? ", refine " : "",
               method == ForceMethod::Patch ? toString(opt.refine) : "", a.refine.preset.empty() ? "" : ", preset ",
               a.refine.preset.c_str(), inContact, starts, maxDiff, maxAt,
               hips.empty() ? 0.0 : 1e6 * total / hips.size(), 1e6 * worst, a.output.c_str());
  if (!a.mesh.empty())
    std::fprintf(stderr, "trace: patches built lazily: %d of %d faces (at most %s held)\n", renderer->patchesBuilt(),
                 cache->numFaces(), a.patchCapacity > 0 ? std::to_string(a.patchCapacity).c_str() : "all");
}

}  // namespace

void addTraceCommand(CLI::App& app) {
  auto* t = app.add_subcommand("trace", "Render forces along a HIP sequence with contact tracking (one row per step)");
  auto a = std::make_shared<TraceArgs>();
  auto* cache = t->add_option("--cache", a->cache, "patch cache file");
  auto* mesh = t->add_option("--mesh", a->mesh, "mesh file (patches built lazily where the HIPs go)");
  t->add_option("--patch-capacity", a->patchCapacity,
                "with --mesh: patches held at once, least recently used evicted (<= 0: no bound)")
      ->capture_default_str();
  cache->excludes(mesh);
  mesh->excludes(cache);
  t->add_option("--method", a->method, "patch|direct|shading")
      ->check(CLI::IsMember({"patch", "direct", "shading"}))
      ->capture_default_str();
  t->add_option("--hips", a->hips, "CSV with header x,y,z: one HIP (m) per servo step")->required();
  t->add_option("-o,--output", a->output,
                "CSV to write: x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status")
      ->required();
  t->add_option("--stiffness", a->stiffness, "k in N/m (F = k (SCP - HIP))")->capture_default_str();
  addPatchArgs(*t, a->patch);
  addRefineArgs(*t, a->refine);
  t->callback([a] {
    if (a->cache.empty() == a->mesh.empty()) throw CLI::RequiredError("exactly one of --cache or --mesh");
    run(*a);
  });
}

}  // namespace sf::cli
