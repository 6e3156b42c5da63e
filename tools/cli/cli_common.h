// SPDX-License-Identifier: Apache-2.0
// Shared pieces of the `smoothforce` subcommands: patch options, loading MESH|CACHE, backends.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

#include <smoothforce/force/force_method.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/normal_search.h>

namespace sf::cli {

/// Options every command that builds patches takes: the patch surface (--precision,
/// --normals, --cross-tangent, --orient, --cage, --creases, --crease-angle, --fold-repair) and where the work runs
/// (--backend, --cl-device, --threads).
struct PatchArgs {
  std::string precision = "double", normals = "auto", crossTangent = "corrected", orient = "outward", cage = "none",
              creases = "tags,groups";
  double creaseAngle = 0;
  std::string foldRepair = "on";
  std::string backend = "tbb", clDevice;
  int threads = 0;
  /// The surface options as registered (null when the command lacks them); count() > 0 when given.
  CLI::Option *precisionOpt = nullptr, *normalsOpt = nullptr, *crossTangentOpt = nullptr, *orientOpt = nullptr,
              *cageOpt = nullptr, *creasesOpt = nullptr, *creaseAngleOpt = nullptr, *foldRepairOpt = nullptr;
  PatchOptions options() const;
  Backend backendKind() const { return parseBackend(backend); }
  /// A cache file keeps the options it was built with: throws InputError `PATH: built with
  /// --normals angle, but --normals file was given` when an option given explicitly differs.
  void checkCache(const PatchCache& cache, const std::string& path) const;
};

/// Registers --precision, --normals, --cross-tangent, --orient, --cage, --creases, --crease-angle,
/// --fold-repair (the patch surface).
void addSurfaceArgs(CLI::App& cmd, PatchArgs& args);
/// Registers --backend, --cl-device (the OpenCL device; --device is a hidden, deprecated
/// alias outside `loop`) and --threads.
void addBackendArgs(CLI::App& cmd, PatchArgs& args);
/// Both of the above.
void addPatchArgs(CLI::App& cmd, PatchArgs& args);

/// The patch method's refinement options of every command that computes forces (trace, loop,
/// sweep): --preset, --refine, --angle-tol, --position-tol, --max-iter, --initial-guess, --guess-level,
/// --final-step.
/// Order: defaults, then the preset (force_presets.h), then the options given explicitly.
struct RefineArgs {
  std::string preset, refine = "newton", guess = "surface", finalStep = "evaluated",
                     surfaceIndex = toString(ForceOptions{}.surfaceIndex);
  double angleTol = ForceOptions{}.angleTolerance, posTol = ForceOptions{}.positionTolerance;
  int maxIter = ForceOptions{}.maxIterations, guessLevel = ForceOptions{}.tessellationLevel;
  CLI::Option *refineOpt = nullptr, *tolOpt = nullptr, *posTolOpt = nullptr, *iterOpt = nullptr, *guessOpt = nullptr,
              *levelOpt = nullptr, *finalStepOpt = nullptr, *indexOpt = nullptr;
  CLI::Option* precisionOpt = nullptr;  ///< --precision of addPatchArgs, when the command has it
  /// Fills o's refinement fields (stiffness untouched) through the shared reader
  /// (force_option_text.h, by flag). Throws InputError for an unknown
  /// preset, refinement or initial guess.
  void apply(ForceOptions& o) const;
  /// The preset's precision advice for patches built now, unless --precision was given;
  /// `given` is the precision otherwise used.
  Precision precision(Precision given) const;
};

/// The check of an option's value on the command line: `set` is the shared reader's setter
/// (option_spec.h), so that the command line rejects a bad value with the message every front
/// end gives ("--orient: expected outward|keep, got 'inward'"; CLI11 puts the flag first).
CLI::Validator optionCheck(const char* key, std::function<void(const std::string&)> set);
/// optionCheck of a patch option (patch_option_text.h), a force option (force_option_text.h) and
/// a loop option (loop_option_text.h), by key.
CLI::Validator patchOptionCheck(const char* key);
CLI::Validator forceOptionCheck(const char* key);
CLI::Validator loopOptionCheck(const char* key);

/// Registers the RefineArgs options; call after addPatchArgs (to see --precision).
void addRefineArgs(CLI::App& cmd, RefineArgs& args);

/// A patch cache obtained from a mesh (built now) or a cache file (loaded), with the
/// mesh-side information when there was a mesh.
struct Source {
  PatchCache cache;
  std::unique_ptr<LoadedMesh> loaded;  ///< null when read from a cache file
  double buildSeconds = 0;
};

/// Loads a cache file (detected by its magic; PatchArgs::checkCache) or reads the mesh and
/// builds its patches with the chosen backend; lazy: a mesh gives a skeleton (no patch built;
/// the force renderer builds them on demand, lazy_patches.h).
Source openSource(const std::string& path, const PatchArgs& args, bool lazy = false);

/// Builds patches for an already loaded mesh with the chosen backend; returns seconds.
double construct(PatchCache& cache, const PatchArgs& args);

/// Under --fold-repair search, the normal search on a built cache (sf::finishFoldRepair with the
/// arguments' backend and threads); nothing otherwise.
NormalSearchReport finishFoldRepair(PatchCache& cache, const PatchArgs& args);

/// The normal search's report as lines for the user (cache build, stderr of the other commands).
std::vector<std::string> describeNormalSearch(const NormalSearchReport& r);

/// A batch evaluator for the chosen backend (CPU or OpenCL).
BatchEvaluator makeEvaluator(const PatchCache& cache, const PatchArgs& args);

/// "4 tri, 160 quad, 16 5-gon"
std::string faceSizeText(const std::vector<int>& histogram);

void addCacheCommands(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addExportCommand(CLI::App& app);

}  // namespace sf::cli
