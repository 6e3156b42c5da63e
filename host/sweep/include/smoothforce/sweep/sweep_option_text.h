// SPDX-License-Identifier: Apache-2.0
// The sweep's own options as text and numbers: the one reader of them that every front end uses
// (the `sweep` command's flags, Python's sweep() keyword arguments, runSweep for C++ callers,
// and a sweep.json read back), so that each rejects a bad value with the same message,
// "NAME: expected VALUES, got 'VALUE'" (option_spec.h). The force options of a sweep are read by
// force_option_text.h.
#pragma once

#include <cstdint>
#include <string>

#include <smoothforce/base/option_spec.h>
#include <smoothforce/sweep/sweep_io.h>

namespace sf {

/// Every sweep option: samples (surface samples per depth, [1, 2^32]), seed (std::mt19937_64,
/// [0, 2^64 - 1]), level (tessellation level for sampling and projection, 1..64), approach (the
/// probe's first step at p + approach * depth * n, a factor > 0), sample_on (patch|reference),
/// knn (neighbours per HIP for the discontinuity metric, 1..64), threshold_deg (a neighbour pair
/// above this angle is flagged, (0, 180] degrees). Defaults: SweepConfig.
extern const OptionSpec kSweepOptionSpecs[7];

/// Sets one option of `config` from its text (numbers as decimal text). Throws InputError
/// "NAME: expected VALUES, got 'VALUE'", and "unknown sweep option 'KEY'".
void setSweepOption(SweepConfig& config, const std::string& key, const std::string& value,
                    OptionSpelling spelling = OptionSpelling::Key);

/// Sets one numeric option (every one but sample_on; seed exactly only up to 2^53: pass larger
/// seeds as text); the message shows the value as optionNumberText does.
void setSweepOption(SweepConfig& config, const std::string& key, double value,
                    OptionSpelling spelling = OptionSpelling::Key);

/// Checks every option of `config`; sample_on "file" (a sweep of a HIP file, which counts its
/// HIPs) leaves samples unchecked. Throws as setSweepOption does.
void checkSweepOptions(const SweepConfig& config, OptionSpelling spelling = OptionSpelling::Key);

}  // namespace sf
