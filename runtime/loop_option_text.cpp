// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/loop_option_text.h>

#include <climits>
#include <cmath>
#include <iterator>

#include <smoothforce/base/error.h>

namespace sf::rt {

const OptionSpec kLoopOptionSpecs[6] = {
    {"rate", "--rate", OptionType::Number, "a rate in [1, 10000] Hz", "servo rate, Hz"},
    {"duration", "--duration", OptionType::Number, "a finite duration > 0 s", "how long the loop runs, s"},
    {"max_force", "--max-force", OptionType::Number, "a finite force > 0 N", "force limit, N"},
    {"max_force_step", "--max-force-step", OptionType::Number, "a force step > 0 N",
     "force change limit per step, N"},
    {"ramp_time", "--ramp", OptionType::Number, "a finite time >= 0 s", "force ramp-in at start, s (0: none)"},
    {"max_missed", "--max-missed", OptionType::Integer, "an integer >= 1",
     "consecutive missed deadlines that latch a zero-force fault"},
};

namespace {

const OptionSpec& specOf(const std::string& key) { return optionSpec(kLoopOptionSpecs, key, "loop"); }

}  // namespace

void checkLoopOption(const std::string& key, double v, OptionSpelling sp) {
  const OptionSpec& s = specOf(key);
  bool ok = true;
  if (key == "rate")
    ok = v >= 1 && v <= 10000;
  else if (key == "duration" || key == "max_force")
    ok = v > 0 && std::isfinite(v);
  else if (key == "max_force_step")
    ok = v > 0;
  else if (key == "ramp_time")
    ok = v >= 0 && std::isfinite(v);
  else  // max_missed
    ok = v >= 1 && v <= INT_MAX && v == std::floor(v);
  if (!ok) throwBadOption(s, sp, optionNumberText(v));
}

void checkLoopOption(const std::string& key, const std::string& value, OptionSpelling sp) {
  checkLoopOption(key, parseOptionNumber(specOf(key), sp, value), sp);
}

void checkSafetyOptions(const SafetyOptions& o, OptionSpelling sp) {
  checkLoopOption("max_force", o.maxForce, sp);
  checkLoopOption("max_force_step", o.maxForceStep, sp);
  checkLoopOption("ramp_time", o.rampTime, sp);
  checkLoopOption("max_missed", static_cast<double>(o.maxConsecutiveMisses), sp);
}

}  // namespace sf::rt
