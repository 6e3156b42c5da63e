// SPDX-License-Identifier: Apache-2.0
// The enclosure behind the patch certificate, for tests: bounds of a patch's position and
// exact first derivatives over a box of its domain (patch_certificate.cpp).
#pragma once

#include <smoothforce/patch/detail/gp_interval.h>
#include <smoothforce/patch/patch_options.h>

namespace sf::detail {

/// Bounds of G, dG/dxi and dG/deta (each 3 coordinates) over the box [x0, x1] x [y0, y1] of the
/// domain of the patch with records recs (n * GP_E_NFIELDS, record-major, double), for every
/// point of the box that lies in the domain (the regular n-gon): the patch math of kernels/
/// evaluated on second-order Taylor models (gp_interval.h).
struct PatchEnclosure {
  interval::Interval pos[3], dxi[3], deta[3];
  interval::Interval J;  ///< dot(dG/dxi x dG/deta, nFace)
};
PatchEnclosure enclosePatch(int n, const double* recs, CrossTangentMode mode, const double nFace[3], double x0,
                            double x1, double y0, double y1);

}  // namespace sf::detail
