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

/// Runs the plot script; returns "" on success, else why not.
std::string runPlots(const std::string& dir) {
  fs::path script;
  if (const char* env = std::getenv("SF_SWEEP_PLOTS"))
    script = env;
  else
    script = fs::path(__FILE__).parent_path().parent_path() / "sweep_plots.py";  // tools/sweep_plots.py
  if (!fs::exists(script)) return "plot script " + script.string() + " not found (set SF_SWEEP_PLOTS)";
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
  std::vector<std::string> pngs, plys;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (e.path().extension() == ".png") pngs.push_back(n);
    if (e.path().extension() == ".ply") plys.push_back(n);
  }
  std::sort(pngs.begin(), pngs.end());
  std::sort(plys.begin(), plys.end());
  std::ofstream o(dir + "/index.html");
  o << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>SmoothForce sweep</title>\n"
       "<style>body{font-family:sans-serif;margin:2em}pre{background:#f4f4f4;padding:1em;overflow-x:auto}"
       "img{max-width:48%;margin:0.5%}</style></head><body>\n<h1>SmoothForce force sweep</h1>\n"
    << "<p>Metrics: <a href=\"summary.json\">summary.json</a>; per-HIP data: sweep.json, hips.bin, results_*.bin; "
       "trajectory forces: trajectories.json.</p>\n<pre>"
    << htmlEscape(table) << "</pre>\n";
  if (!note.empty()) o << "<p><b>Note:</b> " << htmlEscape(note) << "</p>\n";
  for (const auto& p : pngs) o << "<a href=\"" << p << "\"><img src=\"" << p << "\" alt=\"" << p << "\"></a>\n";
  if (!plys.empty()) {
    o << "<h2>Point clouds (MeshLab, ParaView)</h2>\n<p>HIPs with the force direction as normal; red: local "
         "force-direction discontinuity; blue: no contact.</p>\n<ul>\n";
    for (const auto& p : plys) o << "<li><a href=\"" << p << "\">" << p << "</a></li>\n";
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
