// SPDX-License-Identifier: Apache-2.0
// The status bits have one definition per language: status.h for C++ users, gp_config.h for
// the shared patch math (C++ and OpenCL C). They must agree bit for bit.
#include <smoothforce/base/status.h>

#include "gp_config.h"

namespace sf {

static_assert(SF_ST_GUARD == GP_ST_GUARD && SF_ST_ZERO_EDGE == GP_ST_ZERO_EDGE &&
                  SF_ST_EDGE_NORMAL == GP_ST_EDGE_NORMAL && SF_ST_CROSS_TANGENT == GP_ST_CROSS_TANGENT &&
                  SF_ST_FOLD == GP_ST_FOLD && SF_ST_BULGE == GP_ST_BULGE && SF_ST_OUTSIDE == GP_ST_OUTSIDE &&
                  SF_ST_SINGULAR == GP_ST_SINGULAR && SF_ST_TOO_MANY_SIDES == GP_ST_TOO_MANY_SIDES &&
                  SF_ST_NONFINITE == GP_ST_NONFINITE && SF_ST_MODEL_POINT == GP_ST_MODEL_POINT &&
                  SF_ST_AFFINE == GP_ST_AFFINE && SF_ST_DEGENERATE_MASK == GP_ST_DEGENERATE_MASK,
              "status.h SF_ST_* must equal gp_config.h GP_ST_*");
static_assert(SF_TRACK_CONVERGED == GP_TRACK_CONVERGED && SF_TRACK_MAX_ITER == GP_TRACK_MAX_ITER &&
                  SF_TRACK_STALLED == GP_TRACK_STALLED && SF_TRACK_BOUNDARY == GP_TRACK_BOUNDARY &&
                  SF_TRACK_DEGENERATE == GP_TRACK_DEGENERATE && SF_TRACK_FOLD_EDGE == GP_TRACK_FOLD_EDGE,
              "status.h SF_TRACK_* must equal gp_config.h GP_TRACK_*");
static_assert(GP_MAX_N == 64 && SF_MAX_PATCH_SIDES == GP_MAX_N, "status.h: SF_ST_TOO_MANY_SIDES documents n > 64");
static_assert((SF_TRACK_MASK & 0xFFFFu) == 0 && (SF_TRACK_MASK & (GP_ST_AFFINE * 2 - 1)) == 0,
              "SF_TRACK_* bits lie above the GP_ST_* bits");
static_assert((SF_PROBE_MASK & SF_TRACK_MASK) == 0 && SF_PROBE_MASK > SF_TRACK_MASK,
              "the sweep's SF_PROBE_* bits lie above the SF_TRACK_* bits (one status word)");

}  // namespace sf
