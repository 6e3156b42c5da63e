// SPDX-License-Identifier: Apache-2.0
// `smoothforce loop`: the real-time servo loop (runtime/) on a scene, a patch cache or a mesh.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::cli {

/// Registers the `loop` subcommand: --scene S | --cache C | --mesh M, --method, --device,
/// --rate, --duration, --stiffness, --speed, --depth, --record, safety limits, --paced and
/// --watchdog-ms (udp devices).
void addLoopCommand(CLI::App& app);

}  // namespace sf::cli
