// C++ instantiations of the single-source patch math (kernels/gp_patch.h, gp_refine.h):
// sf::gpf (float) and sf::gpd (double). Both share the layout macros of gp_config.h.
#pragma once

#include <cmath>

#include "gp_config.h"

namespace sf::gpf {
#define GP_REAL float
#define GP_IS_DOUBLE 0
#include "gp_patch.h"
#include "gp_domain.h"
#include "gp_refine.h"
#undef GP_REAL
#undef GP_IS_DOUBLE
}  // namespace sf::gpf

namespace sf::gpd {
#define GP_REAL double
#define GP_IS_DOUBLE 1
#include "gp_patch.h"
#include "gp_domain.h"
#include "gp_refine.h"
#undef GP_REAL
#undef GP_IS_DOUBLE
}  // namespace sf::gpd
