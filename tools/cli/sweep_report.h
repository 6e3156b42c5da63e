// SPDX-License-Identifier: Apache-2.0
// Sweep outputs for people: the table on stdout, matplotlib plots (tools/sweep_plots.py) and
// OUTDIR/index.html.
#pragma once

#include <string>

#include <smoothforce/sweep/sweep_io.h>

namespace sf::cli {

/// Writes summary.json and the PLYs (writeSweepSummary), prints the table, runs the plot
/// script when python3 with matplotlib is found (unless !plots) and writes index.html.
void finishSweepOutputs(const SweepData& data, const std::string& dir, bool plots);

}  // namespace sf::cli
