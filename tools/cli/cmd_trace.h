// `smoothforce trace`: stateful force rendering over a recorded HIP sequence.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::cli {

/// Registers `trace (--cache C | --mesh M) --method patch|direct|shading --hips IN.csv -o OUT.csv
/// [--stiffness K] [--refine newton|paper] [--angle-tol RAD] [--max-iter N]` and the patch options.
/// IN: header x,y,z, one HIP (m) per servo step. OUT: header
/// x,y,z,contact,face,xi,eta,scp_x,scp_y,scp_z,fx,fy,fz,iterations,status (%.17g), one row per
/// input row; face -1 and zero force out of contact. Summary on stderr.
void addTraceCommand(CLI::App& app);

}  // namespace sf::cli
