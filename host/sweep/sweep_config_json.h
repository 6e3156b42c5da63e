// SPDX-License-Identifier: Apache-2.0
// Private to the sweep module: a sweep's configuration as JSON, as config.json and summary.json
// both write it (one writer and one reader, sweep_io.cpp describeConfig).
#pragma once

#include <nlohmann/json.hpp>

#include <smoothforce/sweep/sweep_io.h>

namespace sf {

/// Every setting of `config` that decides the results, under the keys config.json uses.
nlohmann::ordered_json sweepConfigJson(const SweepConfig& config);

}  // namespace sf
