// SPDX-License-Identifier: Apache-2.0
// `smoothforce generate torus-knot|sphere|torus`: test objects with exact normals.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::cli {

void addGenerateCommand(CLI::App& app);

}  // namespace sf::cli
