// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/patch_options.h>

#include <smoothforce/base/error.h>

#include "gp_config.h"

namespace sf {

static_assert(static_cast<int>(CrossTangentMode::Corrected) == GP_CT_CORRECTED &&
                  static_cast<int>(CrossTangentMode::Paper) == GP_CT_PAPER &&
                  static_cast<int>(CrossTangentMode::Blend) == GP_CT_BLEND,
              "patch_options.h CrossTangentMode must equal gp_config.h GP_CT_*");

Precision parsePrecision(const std::string& s) {
  if (s == "float") return Precision::Float;
  if (s == "double") return Precision::Double;
  throw InputError("--precision: expected float|double, got '" + s + "'");
}
CrossTangentMode parseCrossTangent(const std::string& s) {
  if (s == "corrected") return CrossTangentMode::Corrected;
  if (s == "paper") return CrossTangentMode::Paper;
  if (s == "blend") return CrossTangentMode::Blend;
  throw InputError("--cross-tangent: expected corrected|paper|blend, got '" + s + "'");
}
Backend parseBackend(const std::string& s) {
  if (s == "serial") return Backend::Serial;
  if (s == "tbb") return Backend::Tbb;
  if (s == "opencl") return Backend::OpenCL;
  throw InputError("--backend: expected serial|tbb|opencl, got '" + s + "'");
}
const char* toString(Precision p) { return p == Precision::Float ? "float" : "double"; }
const char* toString(CrossTangentMode m) {
  switch (m) {
    case CrossTangentMode::Paper:
      return "paper";
    case CrossTangentMode::Blend:
      return "blend";
    default:
      return "corrected";
  }
}
const char* toString(Backend b) {
  switch (b) {
    case Backend::Serial:
      return "serial";
    case Backend::OpenCL:
      return "opencl";
    default:
      return "tbb";
  }
}

}  // namespace sf
