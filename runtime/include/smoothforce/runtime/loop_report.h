// SPDX-License-Identifier: Apache-2.0
// The end-of-run report of the servo loop.
#pragma once

#include <string>

#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/servo_loop.h>

namespace sf::rt {

/// Lines (each ending in '\n'):
///   step compute: p50 A us, p99 B us, p99.9 C us, max D us
///   wake-up lateness: p50 A us, p99 B us, p99.9 C us, max D us
///   steps: N of T ticks at R Hz in E s[, stopped early]
///     (device-paced: steps: N device-paced (one per sample, mean R Hz) in E s[, stopped early])
///   missed deadlines: M (max consecutive C, skipped ticks S)
///   contacts: X steps in contact, Y onsets
///   patch constructions: P for F faces (a face evicted and needed again is built again)
///   safety: C clamps, R rate limits, N non-finite, fault: none | REASON at T s
///   records: W written, D dropped        (only when recording)
/// Percentiles are nearest-rank over all steps (LatencyHistogram). P counts constructions
/// (ForceRenderer::patchesBuilt, each shared store once): with a small --patch-capacity a face
/// evicted and needed again counts again, so P may exceed the F faces of the scene's meshes.
std::string loopReport(const LoopStats& stats, double rate, const SafetyCounters& safety, int patchesBuilt,
                       int totalFaces, long long recordsWritten = -1);

}  // namespace sf::rt
