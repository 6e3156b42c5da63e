// SPDX-License-Identifier: Apache-2.0
// `smoothforce sweep` and `smoothforce sweep-merge`: offset-surface force sweeps.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::cli {

void addSweepCommands(CLI::App& app);

}  // namespace sf::cli
