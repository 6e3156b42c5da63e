// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/loop_report.h>

#include <cstdio>

namespace sf::rt {

std::string loopReport(const LoopStats& s, double rate, const SafetyCounters& c, int patchesBuilt, int totalFaces,
                       long long recordsWritten) {
  std::string out;
  char buf[256];
  out += "step compute: " + s.compute.summaryUs() + "\n";
  out += "wake-up lateness: " + s.lateness.summaryUs() + "\n";
  if (s.paced)
    std::snprintf(buf, sizeof buf, "steps: %lld device-paced (one per sample, mean %.1f Hz) in %.3f s%s\n",
                  static_cast<long long>(s.steps), s.elapsed > 0 ? static_cast<double>(s.steps) / s.elapsed : 0.0,
                  s.elapsed, s.stopped ? ", stopped early" : "");
  else
    std::snprintf(buf, sizeof buf, "steps: %lld of %lld ticks at %g Hz in %.3f s%s\n", static_cast<long long>(s.steps),
                  static_cast<long long>(s.ticks), rate, s.elapsed, s.stopped ? ", stopped early" : "");
  out += buf;
  std::snprintf(buf, sizeof buf, "missed deadlines: %lld (max consecutive %d, skipped ticks %lld)\n",
                static_cast<long long>(s.missedDeadlines), c.maxConsecutiveMisses,
                static_cast<long long>(s.skippedTicks));
  out += buf;
  std::snprintf(buf, sizeof buf, "contacts: %lld steps in contact, %lld onsets\n",
                static_cast<long long>(s.contactSteps), static_cast<long long>(s.contactOnsets));
  out += buf;
  std::snprintf(buf, sizeof buf,
                "patch constructions: %d for %d faces (a face evicted and needed again is built again)\n", patchesBuilt,
                totalFaces);
  out += buf;
  std::snprintf(buf, sizeof buf,
                "safety: %lld clamps, %lld rate limits, %lld non-finite, fault: ", static_cast<long long>(c.clamps),
                static_cast<long long>(c.rateLimits), static_cast<long long>(c.nonFinite));
  out += buf;
  if (c.fault == Fault::None) {
    out += "none\n";
  } else {
    std::snprintf(buf, sizeof buf, "%s at %.3f s (force zero from then on)\n", toString(c.fault), c.faultTime);
    out += buf;
  }
  if (recordsWritten >= 0) {
    std::snprintf(buf, sizeof buf, "records: %lld written, %lld dropped\n", recordsWritten,
                  static_cast<long long>(s.recordsDropped));
    out += buf;
  }
  return out;
}

}  // namespace sf::rt
