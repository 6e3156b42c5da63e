// SPDX-License-Identifier: Apache-2.0
// `smoothforce trace`: stateful force rendering over a recorded HIP sequence.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::cli {

/// Registers `trace (--cache C | --mesh M) --method patch|direct|shading --hips IN.csv -o OUT.csv
/// [--stiffness K] [--refine newton|paper] [--angle-tol RAD] [--max-iter N]` and the patch options.
/// IN: header x,y,z, one HIP (m) per servo step. OUT: header
/// x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status (%.17g), one row per
/// input row; out of contact: contact 0, face -1, xi = eta = 0, scp = the HIP, zero force
/// (iterations and status still say what the step did). Summary on stderr: steps, steps in
/// contact, contacts started, largest |F_i - F_{i-1}| and the mean / max compute time per step.
void addTraceCommand(CLI::App& app);

}  // namespace sf::cli
