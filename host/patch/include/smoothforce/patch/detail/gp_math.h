// SPDX-License-Identifier: Apache-2.0
// C++ instantiations of the single-source patch math (kernels/gp_patch.h, gp_refine.h):
// sf::gpf (float) and sf::gpd (double). Both share the layout macros of gp_config.h.
// The domain tables (kernels/gp_tables.h) are filled once, on first use (gp_tables.cpp).
#pragma once

#include <cmath>

#include "gp_config.h"

namespace sf::gpf {
#define GP_REAL float
#define GP_IS_DOUBLE 0
#define GP_INST_FULL 1
#define GP_INST_TABLE 1
#include "gp_instantiate.h"
}  // namespace sf::gpf

namespace sf::gpd {
#define GP_REAL double
#define GP_IS_DOUBLE 1
#define GP_INST_FULL 1
#define GP_INST_TABLE 1
#include "gp_instantiate.h"
}  // namespace sf::gpd
