// SPDX-License-Identifier: Apache-2.0
// The servo loop's options as numbers: the one check of them that every front end uses (the
// command line's `loop` flags, the C API's sf_haptic_options fields, Python's Haptic keyword
// arguments), so that each rejects a bad value with the same message,
// "NAME: expected VALUES, got 'VALUE'" (option_spec.h).
#pragma once

#include <string>

#include <smoothforce/base/option_spec.h>
#include <smoothforce/runtime/safety.h>

namespace sf::rt {

/// Every loop option: rate (servo rate, Hz, [1, 10000]), duration (s, > 0), max_force (N, > 0),
/// max_force_step (N per step, > 0; +inf disables), ramp_time (s, >= 0), max_missed (deadlines
/// missed in a row that latch a fault, >= 1). Defaults: StepOptions, LoopOptions, SafetyOptions.
extern const OptionSpec kLoopOptionSpecs[6];

/// Checks one loop option's value; throws InputError "NAME: expected VALUES, got 'VALUE'" (the
/// value as optionNumberText shows it), and for an unknown key.
void checkLoopOption(const std::string& key, double value, OptionSpelling spelling = OptionSpelling::Key);

/// The same for the value as decimal text (the command line); a text that is no number gets the
/// same message.
void checkLoopOption(const std::string& key, const std::string& value, OptionSpelling spelling = OptionSpelling::Key);

/// Checks max_force, max_force_step, ramp_time and max_missed of `options` (validate(SafetyOptions)
/// by flag).
void checkSafetyOptions(const SafetyOptions& options, OptionSpelling spelling = OptionSpelling::Key);

}  // namespace sf::rt
