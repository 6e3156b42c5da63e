// SPDX-License-Identifier: Apache-2.0
// The force options as text and numbers: the one reader and writer of them that every front end
// uses (the command line's flags, scene files' keys, the C API's sf_haptic_options fields,
// Python's keyword arguments, the sweep's configuration JSON), so that each accepts the same
// values and rejects a bad one with the same message, "NAME: expected VALUES, got 'VALUE'"
// (option_spec.h).
#pragma once

#include <string>

#include <smoothforce/base/option_spec.h>
#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_presets.h>

namespace sf {

/// A force renderer as the front ends choose it: the method and its options.
struct ForceSettings {
  ForceMethod method = ForceMethod::Patch;
  ForceOptions options;
  std::string preset;  ///< the preset last applied ("" none): fast|balanced|accurate
};

/// Every force option, in the order front ends apply them (a preset first, explicit options
/// after it): method, preset, stiffness (N/m), refine, angle_tolerance (rad), position_tolerance
/// (fraction of the bounding-box diagonal), max_iterations, initial_guess, guess_level,
/// final_step, patch_capacity, surface_index.
extern const OptionSpec kForceOptionSpecs[12];

/// Sets one option from its text (numbers as decimal text). `preset` applies the preset's
/// refinement options (force_presets.h) over those set before it. Throws InputError
/// "NAME: expected VALUES, got 'VALUE'" for a bad value, and "unknown force option 'KEY'".
void setForceOption(ForceSettings& settings, const std::string& key, const std::string& value,
                    OptionSpelling spelling = OptionSpelling::Key);

/// Sets one numeric option (stiffness, angle_tolerance, position_tolerance, max_iterations,
/// guess_level, patch_capacity; the integer ones take integral values only); the message for a
/// bad value shows it as optionNumberText does, as the text form does for the same number.
/// Throws InputError as above, and for a key that is not numeric.
void setForceOption(ForceSettings& settings, const std::string& key, double value,
                    OptionSpelling spelling = OptionSpelling::Key);

/// The text of one option of `settings` (setForceOption of it gives it back; preset: "" when none).
std::string forceOptionValue(const ForceSettings& settings, const std::string& key);

/// The settings a C or Python haptic takes, through the reader above in the front ends' order:
/// method (null: patch), preset (null: none), stiffness (N/m), patch_capacity, final_step (null:
/// the preset's or the default), surface_index (null: auto), then checkForceOptions. Throws
/// InputError by key.
ForceSettings readHapticForceSettings(const char* method, const char* preset, double stiffness, int patchCapacity,
                                      const char* finalStep, const char* surfaceIndex = nullptr);

/// Checks every option's value and the pair the values must agree on (final_step model needs
/// refine newton); throws InputError with the message setForceOption gives (by key or flag).
void checkForceOptions(const ForceOptions& options, OptionSpelling spelling = OptionSpelling::Key);

/// The named preset; throws InputError "preset: expected fast|balanced|accurate, got 'NAME'"
/// (by key or flag).
const ForcePreset& findForcePreset(const std::string& name, OptionSpelling spelling);

}  // namespace sf
