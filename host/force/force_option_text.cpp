// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/force/force_option_text.h>

#include <climits>
#include <cmath>
#include <iterator>

#include <smoothforce/base/error.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/force/force_tracking.h>

namespace sf {

const OptionSpec kForceOptionSpecs[12] = {
    {"method", "--method", OptionType::Text, "patch|direct|shading", "force method: Gregory patches, god-object or force shading"},
    {"preset", "--preset", OptionType::Text, "fast|balanced|accurate", "refinement options from the trade-off study"},
    {"stiffness", "--stiffness", OptionType::Number, "a stiffness in (0, 1e12] N/m", "k in F = k (SCP - HIP), N/m"},
    {"refine", "--refine", OptionType::Text, "newton|paper", "SCP refinement on the patches"},
    {"angle_tolerance", "--angle-tol", OptionType::Number, "a finite angle > 0 rad", "refinement stops below this angle (rad)"},
    {"position_tolerance", "--position-tol", OptionType::Number, "a finite fraction of the bounding-box diagonal > 0",
     "refinement also stops only when the SCP's tangential residual is below this fraction of the diagonal"},
    {"max_iterations", "--max-iter", OptionType::Integer, "an integer >= 1", "refinement iteration cap"},
    {"initial_guess", "--initial-guess", OptionType::Text, "surface|polygon", "the patch method's global query out of contact"},
    {"guess_level", "--guess-level", OptionType::Integer, "an integer in 0..64 (0: chosen)",
     "tessellation level of the patch surface for the global query"},
    {"final_step", "--final-step", OptionType::Text, "evaluated|model",
     "the Newton refinement's converging step ends on an evaluation of the patch or on its model"},
    {"patch_capacity", "--patch-capacity", OptionType::Integer, "an integer (<= 0: every touched face stays built)",
     "lazy patches: faces whose patches are held at once"},
    {"surface_index", "--surface-index", OptionType::Text, "auto|bounds|tessellation",
     "the patch surface's index for the global query on a prebuilt cache: boxes per sector and cell (bounds), a "
     "tessellation with error bounds (tessellation), or bounds for the servo loop and tessellation for batches (auto)"},
};

namespace {

const OptionSpec& specOf(const std::string& key) { return optionSpec(kForceOptionSpecs, key, "force"); }

bool numeric(const std::string& key) { return specOf(key).type != OptionType::Text; }

/// Checks `v` for the numeric option `s` and stores it; throws with v as optionNumberText shows it.
void setNumber(ForceOptions& o, const OptionSpec& s, OptionSpelling sp, double v) {
  const std::string key = s.key;
  auto integer = [&](long long lo, long long hi) {
    if (!(v == std::floor(v)) || v < double(lo) || v > double(hi)) throwBadOption(s, sp, optionNumberText(v));
    return static_cast<int>(v);
  };
  if (key == "stiffness") {
    if (!(v > 0 && v <= kMaxStiffness)) throwBadOption(s, sp, optionNumberText(v));
    o.stiffness = v;
  } else if (key == "angle_tolerance") {
    if (!(v > 0) || !std::isfinite(v)) throwBadOption(s, sp, optionNumberText(v));
    o.angleTolerance = v;
  } else if (key == "position_tolerance") {
    if (!(v > 0) || !std::isfinite(v)) throwBadOption(s, sp, optionNumberText(v));
    o.positionTolerance = v;
  } else if (key == "max_iterations") {
    o.maxIterations = integer(1, INT_MAX);
  } else if (key == "guess_level") {
    o.tessellationLevel = integer(0, 64);
  } else {  // patch_capacity
    o.patchCapacity = integer(INT_MIN, INT_MAX);
  }
}

}  // namespace

const ForcePreset& findForcePreset(const std::string& name, OptionSpelling spelling) {
  for (const ForcePreset& p : forcePresets())
    if (p.name == name) return p;
  throwBadOption(specOf("preset"), spelling, name);
}

void setForceOption(ForceSettings& f, const std::string& key, const std::string& value, OptionSpelling sp) {
  const OptionSpec& s = specOf(key);
  if (numeric(key)) {
    const double v = parseOptionNumber(s, sp, value);
    setNumber(f.options, s, sp, v);
    return;
  }
  try {
    if (key == "method") {
      f.method = parseForceMethod(value);
    } else if (key == "preset") {
      applyForcePreset(findForcePreset(value, sp), f.options);
      f.preset = value;
    } else if (key == "refine") {
      f.options.refine = parseRefineMethod(value);
    } else if (key == "initial_guess") {
      f.options.initialGuess = parseInitialGuess(value);
    } else if (key == "surface_index") {
      f.options.surfaceIndex = parseSurfaceIndex(value);
    } else {  // final_step
      f.options.finalStep = parseFinalStep(value);
    }
  } catch (const InputError&) {
    throwBadOption(s, sp, value);  // one message, whoever parsed it
  }
}

void setForceOption(ForceSettings& f, const std::string& key, double value, OptionSpelling sp) {
  const OptionSpec& s = specOf(key);
  if (!numeric(key)) throwBadOption(s, sp, optionNumberText(value));
  setNumber(f.options, s, sp, value);
}

std::string forceOptionValue(const ForceSettings& f, const std::string& key) {
  specOf(key);  // an unknown key throws
  const ForceOptions& o = f.options;
  if (key == "method") return toString(f.method);
  if (key == "preset") return f.preset;
  if (key == "stiffness") return optionNumberText(o.stiffness);
  if (key == "refine") return toString(o.refine);
  if (key == "angle_tolerance") return optionNumberText(o.angleTolerance);
  if (key == "position_tolerance") return optionNumberText(o.positionTolerance);
  if (key == "max_iterations") return std::to_string(o.maxIterations);
  if (key == "initial_guess") return toString(o.initialGuess);
  if (key == "guess_level") return std::to_string(o.tessellationLevel);
  if (key == "final_step") return toString(o.finalStep);
  if (key == "surface_index") return toString(o.surfaceIndex);
  return std::to_string(o.patchCapacity);
}

void checkForceOptions(const ForceOptions& o, OptionSpelling sp) {
  ForceOptions scratch;
  setNumber(scratch, specOf("stiffness"), sp, o.stiffness);
  setNumber(scratch, specOf("angle_tolerance"), sp, o.angleTolerance);
  setNumber(scratch, specOf("position_tolerance"), sp, o.positionTolerance);
  setNumber(scratch, specOf("max_iterations"), sp, o.maxIterations);
  setNumber(scratch, specOf("guess_level"), sp, o.tessellationLevel);
  if (o.refine != RefineMethod::Newton && o.refine != RefineMethod::PaperDescent)
    throwBadOption(specOf("refine"), sp, std::to_string(static_cast<int>(o.refine)));
  if (o.initialGuess != InitialGuess::Surface && o.initialGuess != InitialGuess::Polygon)
    throwBadOption(specOf("initial_guess"), sp, std::to_string(static_cast<int>(o.initialGuess)));
  if (o.surfaceIndex != SurfaceIndex::Auto && o.surfaceIndex != SurfaceIndex::Bounds &&
      o.surfaceIndex != SurfaceIndex::Tessellation)
    throwBadOption(specOf("surface_index"), sp, std::to_string(static_cast<int>(o.surfaceIndex)));
  if (o.finalStep != FinalStep::Evaluated && o.finalStep != FinalStep::Model)
    throwBadOption(specOf("final_step"), sp, std::to_string(static_cast<int>(o.finalStep)));
  if (o.finalStep == FinalStep::Model && o.refine != RefineMethod::Newton)
    throw InputError(std::string(optionName(specOf("final_step"), sp)) + ": 'model' ends a Newton step on its model: it needs " +
                     optionName(specOf("refine"), sp) + " newton, got " + optionName(specOf("refine"), sp) + " " +
                     toString(o.refine));
}

ForceSettings readHapticForceSettings(const char* method, const char* preset, double stiffness, int patchCapacity,
                                      const char* finalStep, const char* surfaceIndex) {
  ForceSettings f;
  if (method) setForceOption(f, "method", method);
  if (preset) setForceOption(f, "preset", preset);
  setForceOption(f, "stiffness", stiffness);
  setForceOption(f, "patch_capacity", static_cast<double>(patchCapacity));
  if (finalStep) setForceOption(f, "final_step", finalStep);
  if (surfaceIndex) setForceOption(f, "surface_index", surfaceIndex);
  checkForceOptions(f.options);
  return f;
}

// checkForceOptions covers every check of validateRefineOptions (the refinement options' ranges
// and the final-step pair), with the message every front end gives
void validateForceOptions(const ForceOptions& o) { checkForceOptions(o); }

}  // namespace sf
