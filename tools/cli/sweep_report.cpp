// SPDX-License-Identifier: Apache-2.0
#include "sweep_report.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

namespace sf::cli {

namespace fs = std::filesystem;

namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string htmlEscape(const std::string& s) {
  std::string o;
  for (char c : s) o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  return o;
}

/// The plot script: $SF_SWEEP_PLOTS; else next to the running binary, BIN/../share/smoothforce/
/// (the installed layout); else, for the binary of the build tree, the source tree's tools/.
/// Returns "" when none exists; `tried` gets the paths looked at.
fs::path findPlotScript(std::string& tried) {
  if (const char* env = std::getenv("SF_SWEEP_PLOTS")) {
    tried = std::string(env) + " (SF_SWEEP_PLOTS)";
    return fs::exists(env) ? fs::path(env) : fs::path();
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / SF_PLOTS_SHARE_DIR / "sweep_plots.py";
    tried = installed.string();
    if (fs::exists(installed)) return installed;
    if (fs::equivalent(exe.parent_path(), SF_PLOTS_BUILD_DIR, ec)) {
      const fs::path source = fs::path(SF_PLOTS_SOURCE_DIR) / "sweep_plots.py";
      tried += ", " + source.string();
      if (fs::exists(source)) return source;
    }
  }
  return {};
}

/// Runs the plot script; returns "" on success, else why not.
std::string runPlots(const std::string& dir) {
  std::string tried;
  const fs::path script = findPlotScript(tried);
  if (script.empty()) return "plot script sweep_plots.py not found (looked at " + tried + "; set SF_SWEEP_PLOTS)";
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    const std::string probe = std::string(py) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) != 0) continue;
    const std::string cmd = std::string(py) + " " + shellQuote(script.string()) + " " + shellQuote(dir);
    if (std::system(cmd.c_str()) == 0) return "";
    return "the plot script failed (" + cmd + ")";
  }
  return "no python3 with matplotlib found (apt-get install python3-matplotlib): no plots";
}

void writeIndex(const std::string& dir, const std::string& table, const std::string& note) {
  std::vector<std::string> pngs, clouds, arrays;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string(), x = e.path().extension().string();
    if (x == ".png") pngs.push_back(n);
    if (x == ".ply" || x == ".vtp") clouds.push_back(n);
    if (x == ".npy") arrays.push_back(n);
  }
  std::sort(pngs.begin(), pngs.end());
  std::sort(clouds.begin(), clouds.end());
  std::sort(arrays.begin(), arrays.end());
  std::ofstream o(dir + "/index.html");
  o << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>SmoothForce sweep</title>\n"
       "<style>body{font-family:sans-serif;margin:2em}pre{background:#f4f4f4;padding:1em;overflow-x:auto}"
       "figure{display:inline-block;width:48%;margin:0.5%}img{width:100%}</style></head><body>\n"
       "<h1>SmoothForce force sweep</h1>\n"
    << "<p>Metrics: <a href=\"summary.json\">summary.json</a>; per-HIP data: sweep.json, hips.bin, results_*.bin; "
       "trajectory forces: trajectories.json.</p>\n<pre>"
    << htmlEscape(table) << "</pre>\n";
  if (!note.empty()) o << "<p><b>Note:</b> " << htmlEscape(note) << "</p>\n";
  for (const auto& p : pngs) {
    const std::string stem = p.substr(0, p.size() - 4);
    o << "<figure><a href=\"" << p << "\"><img src=\"" << p << "\" alt=\"" << p << "\"></a><figcaption>" << p;
    for (const char* vec : {".pdf", ".svg"})
      if (fs::exists(dir + "/" + stem + vec)) o << " <a href=\"" << stem << vec << "\">" << (vec + 1) << "</a>";
    o << "</figcaption></figure>\n";
  }
  if (!clouds.empty()) {
    o << "<h2>Point clouds (ParaView, MeshLab)</h2>\n<p>.vtp: point arrays force, force_magnitude, discontinuity, "
         "contact, missed, face, status, iterations, ref_distance, scp, hip_index (colour by any in ParaView). .ply: "
         "normal = force direction, red = local force-direction discontinuity, blue = no contact, quality = "
         "discontinuity in rad/m.</p>\n<ul>\n";
    for (const auto& p : clouds) o << "<li><a href=\"" << p << "\">" << p << "</a></li>\n";
    o << "</ul>\n";
  }
  if (!arrays.empty()) {
    o << "<h2>Per-HIP arrays (NumPy: <code>numpy.load(FILE)</code>)</h2>\n<ul>\n";
    for (const auto& p : arrays) o << "<li><a href=\"" << p << "\">" << p << "</a></li>\n";
    o << "</ul>\n";
  }
  o << "</body></html>\n";
  if (!o) throw InputError(dir + "/index.html: write failed");
}

}  // namespace

void finishSweepOutputs(const SweepData& data, const std::string& dir, bool plots) {
  const std::string table = writeSweepSummary(data, dir);
  std::fputs(table.c_str(), stdout);
  std::fflush(stdout);
  const std::string note = plots ? runPlots(dir) : "plots not requested (--no-plots)";
  if (!note.empty() && plots) std::fprintf(stderr, "sweep: %s\n", note.c_str());
  writeIndex(dir, table, note);
  std::printf("sweep: %s/summary.json, %s/index.html\n", dir.c_str(), dir.c_str());
}

}  // namespace sf::cli
