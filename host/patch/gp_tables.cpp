// SPDX-License-Identifier: Apache-2.0
// The domain tables of the patch math (kernels/gp_tables.h): one gp_domain per n = 3..GP_MAX_N
// and precision, filled by the kernels' own formulas once, before main (and at first use,
// should another static initialiser evaluate a patch first).
#include <array>

#include <smoothforce/patch/detail/gp_math.h>

namespace {

template <class Domain, class Init>
const Domain* fill(Init init) {
  static const std::array<Domain, GP_MAX_N + 1> table = [&] {
    std::array<Domain, GP_MAX_N + 1> t{};
    for (int n = 3; n <= GP_MAX_N; ++n) init(n, &t[n], 1);
    return t;
  }();
  return table.data();
}

}  // namespace

namespace sf::gpf {
const gp_domain* gp_domain_table() { return fill<gp_domain>(gp_domain_init); }
}  // namespace sf::gpf
namespace sf::gpd {
const gp_domain* gp_domain_table() { return fill<gp_domain>(gp_domain_init); }
}  // namespace sf::gpd

namespace {
// fills both tables before main: the servo loop's first evaluation then takes no lock
[[maybe_unused]] const bool kFilled = sf::gpf::gp_domain_table() && sf::gpd::gp_domain_table();
}  // namespace
