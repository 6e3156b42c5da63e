// SPDX-License-Identifier: Apache-2.0
#include "cli_common.h"
#include "cli_exit.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <smoothforce/base/status.h>
#include <smoothforce/force/force_option_text.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/runtime/loop_option_text.h>

namespace sf::cli {

PatchOptions PatchArgs::options() const {
  PatchOptions o;
  try {  // the values every front end accepts, with the same message (patch_option_text.h)
    o = parsePatchOptions(
        PatchOptionText{precision, normals, crossTangent, orient, cage, creases, creaseAngle, foldRepair},
        OptionSpelling::Flag);
  } catch (const InputError& e) {
    throw UsageError(e.what());  // on the command line a bad value is a usage error
  }
  // loadMesh refuses the pair too (scene files, C API); on the command line it is a usage error
  if (o.cage != CageMode::None && o.normals != NormalMode::Auto)
    throw UsageError("--cage " + cage + " uses the limit surface's normals: --normals " + normals +
                     " cannot be combined with it (leave --normals auto)");
  return o;
}

void RefineArgs::apply(ForceOptions& o) const {
  ForceSettings f;
  f.options = o;
  // the shared reader (force_option_text.h): the preset first, the options given after it
  if (!preset.empty()) setForceOption(f, "preset", preset, OptionSpelling::Flag);
  auto given = [](const CLI::Option* opt) { return opt && opt->count() > 0; };
  if (given(refineOpt)) setForceOption(f, "refine", refine, OptionSpelling::Flag);
  if (given(tolOpt)) setForceOption(f, "angle_tolerance", angleTol, OptionSpelling::Flag);
  if (given(posTolOpt)) setForceOption(f, "position_tolerance", posTol, OptionSpelling::Flag);
  if (given(iterOpt)) setForceOption(f, "max_iterations", maxIter, OptionSpelling::Flag);
  if (given(guessOpt)) setForceOption(f, "initial_guess", guess, OptionSpelling::Flag);
  if (given(levelOpt)) setForceOption(f, "guess_level", guessLevel, OptionSpelling::Flag);
  if (given(finalStepOpt)) setForceOption(f, "final_step", finalStep, OptionSpelling::Flag);
  if (given(indexOpt)) setForceOption(f, "surface_index", surfaceIndex, OptionSpelling::Flag);
  checkForceOptions(f.options, OptionSpelling::Flag);  // the pairs, by flag (--final-step model needs --refine newton)
  o = f.options;
}

Precision RefineArgs::precision(Precision given) const {
  if (preset.empty() || (precisionOpt && precisionOpt->count() > 0)) return given;
  return findForcePreset(preset).precision;
}

void addRefineArgs(CLI::App& cmd, RefineArgs& a) {
  cmd.add_option("--preset", a.preset,
                 "fast|balanced|accurate: refinement options (and the precision of patches built now) from the "
                 "trade-off study, docs/results.md 'Speed against accuracy'; explicit options override it")
      ->check(forceOptionCheck("preset"));
  a.refineOpt = cmd.add_option("--refine", a.refine, "newton|paper: SCP refinement on the patches")
                    ->check(forceOptionCheck("refine"))
                    ->capture_default_str();
  a.tolOpt =
      cmd.add_option("--angle-tol", a.angleTol, "refinement stops below this angle (rad)")
          ->check(forceOptionCheck("angle_tolerance"))
          ->capture_default_str();
  a.posTolOpt = cmd.add_option("--position-tol", a.posTol,
                               "refinement also stops only when the SCP's tangential residual |(HIP - SCP) x n| is "
                               "below this fraction of the bounding-box diagonal")
                     ->check(forceOptionCheck("position_tolerance"))
                     ->capture_default_str();
  a.iterOpt = cmd.add_option("--max-iter", a.maxIter, "refinement iteration cap")
                  ->check(forceOptionCheck("max_iterations"))
                  ->capture_default_str();
  a.guessOpt = cmd.add_option("--initial-guess", a.guess,
                              "surface|polygon: the global query out of contact (the nearest point of the patch "
                              "surface, contact when the HIP is inside it; or the paper's nearest base-polygon "
                              "point, contact when below its patch's tangent plane)")
                   ->check(forceOptionCheck("initial_guess"))
                   ->capture_default_str();
  a.levelOpt = cmd.add_option("--guess-level", a.guessLevel,
                              "tessellation level of the patch surface for the global query (0: chosen)")
                   ->check(forceOptionCheck("guess_level"))
                   ->capture_default_str();
  a.indexOpt = cmd.add_option("--surface-index", a.surfaceIndex,
                              "bounds|tessellation: the index of the patch surface for --initial-guess surface "
                              "on a prebuilt cache. bounds: boxes per face, corner sector and cell (memory grows "
                              "with the patches); tessellation: a fine tessellation with error bounds in BVHs "
                              "(0.1-0.5 MB per face on coarse cages, docs/results.md 'Runtime memory by "
                              "structure'). Both find the same nearest patch point")
                   ->check(forceOptionCheck("surface_index"))
                   ->capture_default_str();
  a.finalStepOpt = cmd.add_option("--final-step", a.finalStep,
                                   "evaluated|model: the Newton refinement's converging step ends on an evaluation of "
                                   "the patch, or on its quadratic model (one evaluation fewer per tracking step; "
                                   "docs/results.md 'Speed against accuracy')")
                       ->check(forceOptionCheck("final_step"))
                       ->capture_default_str();
  a.precisionOpt = cmd.get_option_no_throw("--precision");
}

CLI::Validator optionCheck(const char* key, std::function<void(const std::string&)> set) {
  return CLI::Validator(
      [set = std::move(set)](std::string& value) -> std::string {
        try {
          set(value);
          return {};
        } catch (const InputError& e) {
          const std::string m = e.what();
          const size_t colon = m.find(": ");
          return colon == std::string::npos ? m : m.substr(colon + 2);
        }
      },
      "", key);
}

CLI::Validator patchOptionCheck(const char* key) {
  return optionCheck(key, [key](const std::string& value) {
    PatchOptions scratch;
    setPatchOption(scratch, key, value, OptionSpelling::Flag);
  });
}

CLI::Validator loopOptionCheck(const char* key) {
  return optionCheck(key, [key](const std::string& value) { rt::checkLoopOption(key, value, OptionSpelling::Flag); });
}

CLI::Validator forceOptionCheck(const char* key) {
  return optionCheck(key, [key](const std::string& value) {
    ForceSettings scratch;
    setForceOption(scratch, key, value, OptionSpelling::Flag);
  });
}

void addSurfaceArgs(CLI::App& cmd, PatchArgs& a) {
  a.precisionOpt = cmd.add_option("--precision", a.precision, "float|double: precision of the patch records")
                       ->check(patchOptionCheck("precision"))
                       ->capture_default_str();
  a.normalsOpt = cmd.add_option("--normals", a.normals,
                                "auto|file|angle|area: vertex normals. auto: the file's wherever it gives one normal "
                                "per vertex (in vertex order, or through face references f v//vn whose corners agree "
                                "within 1e-3 rad); at vertices whose corners carry different normals, one per smoothing "
                                "sector (creases); without file normals, angle-weighted (cache build reports how many). "
                                "file: the file's, per corner as given. angle|area: angle- or area-weighted Newell "
                                "normals")
                     ->check(patchOptionCheck("normals"))
                     ->capture_default_str();
  a.crossTangentOpt = cmd.add_option("--cross-tangent", a.crossTangent,
                                     "corrected|paper|blend: cross-tangent construction (design page, Robustness)")
                          ->check(patchOptionCheck("cross_tangent"))
                          ->capture_default_str();
  a.orientOpt = cmd.add_option("--orient", a.orient,
                               "outward|keep: outward turns faces that run against their neighbours back into line, "
                               "then flips a closed mesh whose faces point inward; keep leaves both as read")
                    ->check(patchOptionCheck("orient"))
                    ->capture_default_str();
  a.cageOpt = cmd.add_option("--cage", a.cage,
                             "none|catmull-clark: catmull-clark reads the mesh as a subdivision cage and moves every "
                             "vertex to its Catmull-Clark limit position with its limit normal before building "
                             "patches (boundaries: edge-and-corner; needs --normals auto; docs/cage.md)")
                  ->check(patchOptionCheck("cage"))
                  ->capture_default_str();
  a.creasesOpt = cmd.add_option("--creases", a.creases,
                                "LIST|none: which marks make crease edges, a comma-separated list of: tags (OBJ 't "
                                "crease'/'t corner', PLY edge crease properties), groups (OBJ smoothing-group "
                                "borders), normals (split file normals under --normals auto; --normals file always "
                                "keeps them). A crease is one curve both faces share, sharp between them "
                                "(docs/guide.md 'Creases')")
                     ->check(patchOptionCheck("creases"))
                     ->capture_default_str();
  a.creaseAngleOpt = cmd.add_option("--crease-angle", a.creaseAngle,
                                    "DEG: also make a crease of every edge whose two faces' normals are more than DEG "
                                    "degrees apart (0: off)")
                         ->check(patchOptionCheck("crease_angle"))
                         ->capture_default_str();
  a.foldRepairOpt =
      cmd.add_option("--fold-repair", a.foldRepair,
                     "off|on|search: on (split is a synonym) cuts every flat polygon (its vertices on its plane, "
                     "whatever its corner normals) with a reflex or straight corner (within 1 degree) "
                     "into convex pieces on diagonals between its own vertices before building patches: "
                     "the patch of such a polygon folds, or is singular at the straight corner. The cache "
                     "holds the pieces; cache info names the faces cut and the pieces of each. A flat "
                     "triangle with its plane's corner normals is evaluated as its affine map plus its "
                     "curved edges' deviations from their chords, where a bound proves that map regular "
                     "(the same surface where its patch did not fold). search: on, "
                     "then vertex normals turned (at most 60 degrees) where that removes fault area of "
                     "the closed patch surface, with their mirror images on a symmetric mesh: the lever "
                     "for curved polygons (seconds; cache info lists the normals turned; needs the "
                     "whole surface, so not for lazy --mesh rendering). off: the "
                     "design page's construction on the polygons as read (docs/fold-levers.md)")
          ->check(patchOptionCheck("fold_repair"))
          ->capture_default_str();
}

void addBackendArgs(CLI::App& cmd, PatchArgs& a) {
  cmd.add_option("--backend", a.backend, "serial|tbb|opencl")
      ->check(CLI::IsMember({"serial", "tbb", "opencl"}))
      ->capture_default_str();
  cmd.add_option("--cl-device", a.clDevice,
                 "OpenCL device for --backend opencl: index or name substring (default: first GPU, else CPU)");
  cmd.add_option("--device", a.clDevice)  // deprecated spelling: hidden (empty group)
      ->group("")
      ->each([](const std::string&) {
        std::fprintf(stderr, "smoothforce: --device is deprecated for the OpenCL device; use --cl-device\n");
      });
  cmd.add_option("--threads", a.threads, "worker threads for tbb (0 = all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
}

void addPatchArgs(CLI::App& cmd, PatchArgs& a) {
  addSurfaceArgs(cmd, a);
  addBackendArgs(cmd, a);
}

void PatchArgs::checkCache(const PatchCache& c, const std::string& path) const {
  auto given = [](const CLI::Option* o) { return o && o->count() > 0; };
  auto differs = [&](const char* option, const std::string& built, const std::string& wanted) {
    if (built != wanted)
      throw InputError(path + ": built with " + option + " " + built + ", but " + option + " " + wanted +
                       " was given (a cache keeps its options: rebuild it, or drop the option)");
  };
  if (given(precisionOpt)) differs("--precision", toString(c.options.precision), precision);
  if (given(normalsOpt)) differs("--normals", toString(c.options.normals), normals);
  if (given(crossTangentOpt)) differs("--cross-tangent", toString(c.options.crossTangent), crossTangent);
  if (given(orientOpt)) differs("--orient", c.options.keepOrientation ? "keep" : "outward", orient);
  if (given(cageOpt)) differs("--cage", toString(c.options.cage), cage);
  if (given(creasesOpt)) {
    CreaseOptions wanted;
    parseCreaseMarks(creases, wanted);
    differs("--creases", creaseMarksText(c.options.creases), creaseMarksText(wanted));
  }
  if (given(foldRepairOpt))
    differs("--fold-repair", toString(c.options.foldRepair), toString(parseFoldRepairMode(foldRepair)));
  if (given(creaseAngleOpt) && c.options.creases.angleDeg != creaseAngle)
    differs("--crease-angle", std::to_string(c.options.creases.angleDeg), std::to_string(creaseAngle));
}

double construct(PatchCache& cache, const PatchArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  if (args.backendKind() == Backend::OpenCL) {
    OpenCLOptions o;
    o.device = args.clDevice;
    constructPatchesOpenCL(cache, o);
  } else {
    constructPatches(cache, args.backendKind(), args.threads);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

NormalSearchReport finishFoldRepair(PatchCache& cache, const PatchArgs& args) {
  return sf::finishFoldRepair(cache, args.backendKind(), args.threads);
}

std::vector<std::string> describeNormalSearch(const NormalSearchReport& r) {
  std::vector<std::string> out;
  char buf[320];
  if (!r.closed) {
    out.emplace_back("fold repair: search: the patch surface is not closed (no inside, no fault measure): no normal turned");
    return out;
  }
  const double pct = r.totalArea > 0 ? 100.0 / r.totalArea : 0;
  if (!r.applied) {
    std::snprintf(buf, sizeof buf,
                  "fold repair: search: fault area %.3g%%; no normal turned lowers it (level %d, %.1f s)",
                  r.faultBefore * pct, r.searchLevel, r.seconds);
    out.emplace_back(buf);
    return out;
  }
  double most = 0;
  for (const NormalChange& c : r.changes) most = std::max(most, c.rotationDeg);
  const std::string mirror = r.mirrorAxis < 0 ? "" : std::string(", mirror pairs across ") + "xyz"[r.mirrorAxis];
  char levels[64];
  if (r.polishLevel > 0)
    std::snprintf(levels, sizeof levels, "levels %d and %d", r.searchLevel, r.polishLevel);
  else
    std::snprintf(levels, sizeof levels, "level %d", r.searchLevel);
  std::snprintf(buf, sizeof buf,
                "fold repair: search: %zu vertex normals turned (at most %.1f degrees), %zu faces changed; fault area "
                "%.3g%% -> %.3g%% (%lld candidates at %s%s, %.1f s)",
                r.changes.size(), most, r.changedFaces.size(), r.faultBefore * pct, r.faultAfter * pct,
                static_cast<long long>(r.evaluations), levels, mirror.c_str(), r.seconds);
  out.emplace_back(buf);
  if (r.polishLevel > 0) {
    std::snprintf(buf, sizeof buf,
                  "  measured at level %d: %.3g%% after the passes at level %d, %.3g%% after the last pass",
                  r.polishLevel, r.polishFaultBefore * pct, r.searchLevel, r.polishFaultAfter * pct);
    out.emplace_back(buf);
  }
  std::string list = "  turned (vertex: degrees):";
  for (size_t i = 0; i < r.changes.size() && i < 10; ++i) {
    std::snprintf(buf, sizeof buf, " %d: %.1f", r.changes[i].vertex, r.changes[i].rotationDeg);
    list += buf;
  }
  if (r.changes.size() > 10) list += " ...";
  out.push_back(list);
  return out;
}

namespace {

/// On stderr: faces with more sides than a patch can have are holes in the patch surface (the
/// polygons' methods still render them); every command that opens a mesh or cache says so.
void noteUnbuiltFaces(const PatchCache& cache, const std::string& path) {
  int count = 0, largest = 0;
  for (int f = 0; f < cache.numFaces(); ++f)
    if (cache.faceSize(f) > SF_MAX_PATCH_SIDES) {
      ++count;
      largest = std::max(largest, cache.faceSize(f));
    }
  if (count > 0)
    std::fprintf(stderr,
                 "%s: note: %d face%s with more than %d sides (up to %d) get no patch: the patch surface has a hole "
                 "there (split such faces; direct and shading render the polygons)\n",
                 path.c_str(), count, count == 1 ? "" : "s", SF_MAX_PATCH_SIDES, largest);
}

/// On stderr: faces that repeat another face's vertices (a copy, or the same face in the opposite
/// order: a double-sided sheet, which encloses nothing) make the inside tests unreliable near
/// them; a trace 2 m from such a 1 m sheet found phantom contact of 1 kN.
void noteDuplicateFaces(const MeshReport& report, const std::string& path) {
  if (report.duplicateFaces.empty()) return;
  std::fprintf(stderr,
               "%s: note: %zu face%s repeat another face's vertices (face %d first): a double-sided or doubled "
               "surface encloses nothing there and contact near it is unreliable (remove the copies)\n",
               path.c_str(), report.duplicateFaces.size(), report.duplicateFaces.size() == 1 ? "" : "s",
               report.duplicateFaces.front());
}

}  // namespace

Source openSource(const std::string& path, const PatchArgs& args, bool lazy) {
  Source s;
  if (isPatchCacheFile(path)) {
    s.cache = readPatchCache(path);
    args.checkCache(s.cache, path);
    noteUnbuiltFaces(s.cache, path);
    return s;
  }
  const PatchOptions opt = args.options();
  s.loaded = std::make_unique<LoadedMesh>(loadMesh(path, opt));
  s.cache = preparePatchCache(s.loaded->mesh, s.loaded->cornerNormals, opt, s.loaded->fileHash, !lazy);
  noteUnbuiltFaces(s.cache, path);
  noteDuplicateFaces(s.loaded->report, path);
  if (!lazy) {
    s.buildSeconds = construct(s.cache, args);
    if (opt.foldRepair == FoldRepairMode::Search)
      for (const std::string& line : describeNormalSearch(finishFoldRepair(s.cache, args)))
        std::fprintf(stderr, "%s: %s\n", path.c_str(), line.c_str());
  }
  return s;
}

BatchEvaluator makeEvaluator(const PatchCache& cache, const PatchArgs& args) {
  const Backend b = args.backendKind();
  if (b == Backend::OpenCL) {
    OpenCLOptions o;
    o.device = args.clDevice;
    auto ev = std::make_shared<OpenCLEvaluator>(cache, o);
    return [ev](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
      ev->evaluate(f, x, y, n, out);
    };
  }
  const int threads = args.threads;
  return [&cache, b, threads](const int32_t* f, const double* x, const double* y, size_t n, PatchPoint* out) {
    evaluatePatches(cache, f, x, y, n, out, b, threads);
  };
}

std::string faceSizeText(const std::vector<int>& h) {
  std::string s;
  for (size_t n = 0; n < h.size(); ++n) {
    if (!h[n]) continue;
    if (!s.empty()) s += ", ";
    s += std::to_string(h[n]) + " " + (n == 3 ? "tri" : n == 4 ? "quad" : std::to_string(n) + "-gon");
  }
  return s.empty() ? "none" : s;
}

}  // namespace sf::cli
