// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_option_text.h>

#include <charconv>
#include <cmath>
#include <iterator>

#include <smoothforce/base/error.h>

namespace sf {

const OptionSpec kSweepOptionSpecs[7] = {
    {"samples", "--samples", OptionType::Integer, "an integer in [1, 4294967296]", "surface samples per depth"},
    {"seed", "--seed", OptionType::Integer, "an integer in [0, 18446744073709551615]",
     "sampling seed (std::mt19937_64)"},
    {"level", "--level", OptionType::Integer, "an integer in 1..64", "tessellation level for sampling and projection"},
    {"approach", "--approach", OptionType::Number, "a finite factor > 0",
     "probes first step at p + APPROACH * depth * n (outside), then at the HIP"},
    {"sample_on", "--sample-on", OptionType::Text, "patch|reference", "where surface samples are drawn"},
    {"knn", "--knn", OptionType::Integer, "an integer in 1..64", "neighbours per HIP for the discontinuity metric"},
    {"threshold_deg", "--threshold-deg", OptionType::Number, "an angle in (0, 180] degrees",
     "flag neighbour pairs above this angle"},
};

namespace {

const OptionSpec& specOf(const std::string& key) { return optionSpec(kSweepOptionSpecs, key, "sweep"); }

}  // namespace

void setSweepOption(SweepConfig& c, const std::string& key, double v, OptionSpelling sp) {
  const OptionSpec& s = specOf(key);
  auto bad = [&] { throwBadOption(s, sp, optionNumberText(v)); };
  auto integer = [&](double lo, double hi) {
    if (!(v >= lo && v <= hi && v == std::floor(v))) bad();
    return v;
  };
  if (key == "samples") {
    c.samples = static_cast<uint64_t>(integer(1, 4294967296.0));
  } else if (key == "seed") {
    c.seed = static_cast<uint64_t>(integer(0, 9007199254740992.0));  // 2^53: beyond, doubles skip integers
  } else if (key == "level") {
    c.level = static_cast<int>(integer(1, 64));
  } else if (key == "approach") {
    if (!(v > 0) || !std::isfinite(v)) bad();
    c.approach = v;
  } else if (key == "knn") {
    c.knn = static_cast<int>(integer(1, 64));
  } else if (key == "threshold_deg") {
    if (!(v > 0 && v <= 180)) bad();
    c.thresholdDeg = v;
  } else {  // sample_on
    bad();
  }
}

void setSweepOption(SweepConfig& c, const std::string& key, const std::string& value, OptionSpelling sp) {
  const OptionSpec& s = specOf(key);
  if (key == "sample_on") {
    if (value != "patch" && value != "reference") throwBadOption(s, sp, value);
    c.sampleOn = value;
  } else if (key == "seed") {  // all 64 bits, which a double does not carry
    uint64_t seed = 0;
    const auto r = std::from_chars(value.data(), value.data() + value.size(), seed);
    if (value.empty() || r.ec != std::errc() || r.ptr != value.data() + value.size()) throwBadOption(s, sp, value);
    c.seed = seed;
  } else {
    setSweepOption(c, key, parseOptionNumber(s, sp, value), sp);
  }
}

void checkSweepOptions(const SweepConfig& c, OptionSpelling sp) {
  SweepConfig scratch;
  if (c.sampleOn != "file") {  // a sweep of a HIP file counts its HIPs
    setSweepOption(scratch, "samples", static_cast<double>(c.samples), sp);
    setSweepOption(scratch, "sample_on", c.sampleOn, sp);
  }
  setSweepOption(scratch, "level", c.level, sp);
  setSweepOption(scratch, "approach", c.approach, sp);
  setSweepOption(scratch, "knn", c.knn, sp);
  setSweepOption(scratch, "threshold_deg", c.thresholdDeg, sp);
}

}  // namespace sf
