// SPDX-License-Identifier: Apache-2.0
// smoothforce.sweep (an offset-surface force sweep) and smoothforce.read_sweep (its directory).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <unistd.h>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <smoothforce/base/hash.h>
#include <smoothforce/base/thread_limit.h>
#include <smoothforce/force/force_option_text.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_option_text.h>
#include <smoothforce/sweep/sweep_run.h>
#include "py_common.h"

namespace sf::py {
namespace {

namespace fs = std::filesystem;

pyb::dtype hipResultDtype() {
  return structDtype({{"force", "(3,)<f4", offsetof(HipResult, force)},
                      {"scp", "(3,)<f4", offsetof(HipResult, scp)},
                      {"ref_distance", "<f4", offsetof(HipResult, refDistance)},
                      {"face", "<i4", offsetof(HipResult, face)},
                      {"status", "<u4", offsetof(HipResult, status)},
                      {"iterations", "<u2", offsetof(HipResult, iterations)},
                      {"contact", "u1", offsetof(HipResult, contact)},
                      {"done", "u1", offsetof(HipResult, done)}},
                     sizeof(HipResult));
}

/// A NumPy array owning a moved vector (no copy).
template <class T>
pyb::array owning(std::vector<T>&& v, const pyb::dtype& dt, std::vector<ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(v));
  pyb::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pyb::array(dt, std::move(shape), {}, heap->data(), owner);
}

pyb::object readJson(const fs::path& p) {
  if (!fs::exists(p)) return pyb::none();
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return pyb::module_::import("json").attr("loads")(s.str());
}

pyb::dict toPython(SweepData&& d, const std::string& dir, const std::string& table) {
  pyb::dict r;
  r["directory"] = dir;
  r["config"] = readJson(fs::path(dir) / "sweep.json");
  r["summary"] = readJson(fs::path(dir) / "summary.json");
  r["table"] = table.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(table));
  r["complete"] = d.complete();
  r["begin"] = d.begin;
  r["end"] = d.end;
  r["total"] = d.total();
  std::vector<double> hips;
  hips.reserve(3 * d.hips.size());
  for (const auto& h : d.hips) hips.insert(hips.end(), {h.x(), h.y(), h.z()});
  r["hips"] = owning(std::move(hips), pyb::dtype::of<double>(), {static_cast<ssize_t>(d.hips.size()), 3});
  pyb::dict results;
  for (size_t m = 0; m < d.config.methods.size(); ++m) {
    const ssize_t n = static_cast<ssize_t>(d.results[m].size());
    results[pyb::str(d.config.methods[m])] = owning(std::move(d.results[m]), hipResultDtype(), {n});
  }
  r["results"] = results;
  pyb::list series;
  for (auto& t : d.trajectories) {
    pyb::dict s;
    s["trajectory"] = t.trajectory;
    s["method"] = t.method;
    s["depth_label"] = t.depthLabel;
    s["depth"] = t.depth;
    s["step"] = t.step;
    s["half"] = t.half;
    const ssize_t points = static_cast<ssize_t>(t.contact.size());
    s["force"] = owning(std::move(t.force), pyb::dtype::of<float>(), {points, 3});
    s["contact"] = owning(std::move(t.contact), pyb::dtype("?"), {points});
    series.append(s);
  }
  r["trajectories"] = series;
  return r;
}

pyb::dict readSweep(const std::filesystem::path& path) {
  const std::string dir = path.string();
  SweepData d;
  {
    pyb::gil_scoped_release release;
    d = readSweepData(dir);
  }
  return toPython(std::move(d), dir, "");
}

/// Removes a temporary sweep directory when the sweep ends, however it ends.
struct TemporaryDirectory {
  std::string path;  ///< empty: none
  ~TemporaryDirectory() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

pyb::dict sweep(const PyCache& c, const std::string& depths, const std::vector<std::string>& methods, uint64_t samples,
                uint64_t seed, int level, double stiffness, int threads, const std::optional<fs::path>& output,
                const std::string& sampleOn) {
  SweepInputs in;
  in.cache = c.cache;
  SweepConfig& cfg = in.config;
  cfg.source = c.source;
  if (methods.empty()) throw InputError("methods: empty list");
  ForceSettings force;  // the shared reader (force_option_text.h), its messages by key
  for (const auto& m : methods) setForceOption(force, "method", m);
  cfg.methods = methods;
  // the shared readers (sweep_option_text.h, force_option_text.h), their messages by key
  setSweepOption(cfg, "samples", std::to_string(samples));
  setSweepOption(cfg, "seed", std::to_string(seed));
  setSweepOption(cfg, "level", std::to_string(level));
  setForceOption(force, "stiffness", stiffness);
  cfg.force = force.options;
  setSweepOption(cfg, "sample_on", sampleOn);
  cfg.backend = toString(c.backend);
  in.depths = parseDepthList(depths, "depths");
  requireThreads(threads, "threads");
  std::string dir;
  const bool temporary = !output;
  TemporaryDirectory cleanup;
  if (temporary) {
    dir = (fs::temp_directory_path() /
           ("smoothforce_sweep_" + hexHash(reinterpret_cast<uintptr_t>(&in)) + "_" + std::to_string(::getpid())))
              .string();
    cleanup.path = dir;
  } else {
    dir = output->string();
  }
  std::string table;
  SweepData d;
  {
    pyb::gil_scoped_release release;
    SweepControl ctl;
    ctl.threads = c.backend == Backend::Serial ? 1 : threads;
    SweepData run = runSweep(std::move(in), ctl);
    writeSweepData(run, dir);
    table = writeSweepSummary(run, dir);
    d = std::move(run);
  }
  pyb::dict r = toPython(std::move(d), temporary ? "" : dir, table);
  if (temporary) {
    r["config"] = readJson(fs::path(dir) / "sweep.json");
    r["summary"] = readJson(fs::path(dir) / "summary.json");
  }
  return r;  // a temporary directory goes with `cleanup`
}

}  // namespace

void bindSweep(pyb::module_& m) {
  using namespace pybind11::literals;
  m.def("sweep", &sweep, "cache"_a, pyb::kw_only(), "depths"_a = "2%", "methods"_a = std::vector<std::string>{"patch"},
        "samples"_a = 1000, "seed"_a = 1, "level"_a = 8, "stiffness"_a = 500.0, "threads"_a = 0,
        "output"_a = pyb::none(), "sample_on"_a = "patch",
        "An offset-surface force sweep, as `smoothforce sweep`: `samples` surface points (seeded), one probe per\n"
        "point and depth (depths: '2%,4%' of the diagonal or metres '0.002') pressed in along the normal, per\n"
        "method (patch, direct, shading), plus the default trajectory series. Runs in parallel, GIL released.\n"
        "output: a directory to keep (sweep.json, hips.bin, results_METHOD.bin, summary.json, PLYs); None: a\n"
        "temporary one. Returns a dict: config and summary (summary.json as dicts), table (str), hips (N, 3)\n"
        "float64 m, results {method: structured (N,) force (3,) N, scp (3,) m, ref_distance, face, status,\n"
        "iterations, contact, done}, trajectories (list of dicts with force (P, 3), contact (P,)), complete.");
  m.def("read_sweep", &readSweep, "directory"_a,
        "Reads a sweep directory (`smoothforce sweep -o DIR` or sweep(output=DIR); a shard or checkpoint too)\n"
        "with the engine's reader: the same dict as sweep() (summary None when summary.json is absent, table\n"
        "None). Raises ValueError naming a missing, truncated or inconsistent file.");
}

}  // namespace sf::py
