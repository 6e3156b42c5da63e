// SPDX-License-Identifier: Apache-2.0
// C++ instantiations of the single-source patch math (kernels/gp_patch.h, gp_refine.h):
// sf::gpf (float) and sf::gpd (double). Both share the layout macros of gp_config.h.
// The domain tables (kernels/gp_tables.h) are filled once, on first use (gp_tables.cpp).
#pragma once

#include <cmath>

#include "gp_config.h"

// const: the table's address never changes (its one-time fill is idempotent), so the compiler may
// hoist the call out of the domain loops instead of calling across the library for every edge
#define GP_DOMAIN_TABLE_DECLARE __attribute__((const)) const gp_domain* gp_domain_table()
#define GP_DOMAIN_TABLE(n) (gp_domain_table() + (n))

namespace sf::gpf {
#define GP_REAL float
#define GP_IS_DOUBLE 0
// order matters: each part uses the ones before it
// clang-format off
#include "gp_patch.h"
#include "gp_bound.h"
#include "gp_domain.h"
#include "gp_refine.h"
// clang-format on
#undef GP_REAL
#undef GP_IS_DOUBLE
}  // namespace sf::gpf

namespace sf::gpd {
#define GP_REAL double
#define GP_IS_DOUBLE 1
// order matters: each part uses the ones before it
// clang-format off
#include "gp_patch.h"
#include "gp_bound.h"
#include "gp_domain.h"
#include "gp_refine.h"
// clang-format on
#undef GP_REAL
#undef GP_IS_DOUBLE
}  // namespace sf::gpd

// the table hooks are expanded inside the functions above; nothing else needs them
#undef GP_DOMAIN_TABLE_DECLARE
#undef GP_DOMAIN_TABLE
