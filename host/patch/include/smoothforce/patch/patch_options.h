// SPDX-License-Identifier: Apache-2.0
// Options shared by patch construction, evaluation and the command line.
#pragma once

#include <string>

namespace sf {

/// Floating-point type of the patch records and of evaluation.
enum class Precision { Float, Double };
/// Cross-tangent construction (design page "Robustness"): Corrected (default: guard +
/// corner-compatibility correction, G1), Paper (Eq. 11-14 as printed), Blend (cheaper:
/// q = (1-t) d0 + t d1). Values equal the GP_CT_* codes of the shared math (asserted in
/// patch_options.cpp).
enum class CrossTangentMode : int { Corrected = 0, Paper = 1, Blend = 2 };
/// Where construction and evaluation run.
enum class Backend { Serial, Tbb, OpenCL };

/// Parsers throw InputError naming the option value; toString gives the option spelling.
Precision parsePrecision(const std::string& s);
CrossTangentMode parseCrossTangent(const std::string& s);
Backend parseBackend(const std::string& s);
const char* toString(Precision p);
const char* toString(CrossTangentMode m);
const char* toString(Backend b);

}  // namespace sf
