// SPDX-License-Identifier: Apache-2.0
// Worker-thread limits given by users (options of the C API, Python, the command line).
#pragma once

#include <algorithm>
#include <string>

#include <smoothforce/base/error.h>

namespace sf {

/// The most oneTBB worker threads an option may ask for: 4096 (oneTBB crashed making a
/// task_arena of 2^30; the command line's --threads has the same bound).
inline constexpr int kMaxThreads = 4096;

/// Throws InputError "FIELD: expected 0 (all cores) to 4096 threads, got N" unless
/// 0 <= threads <= kMaxThreads.
inline void requireThreads(int threads, const std::string& field) {
  if (threads < 0 || threads > kMaxThreads)
    throw InputError(field + ": expected 0 (all cores) to " + std::to_string(kMaxThreads) + " threads, got " +
                     std::to_string(threads));
}

/// The arena size for a worker limit `threads` (<= 0: none, oneTBB's default), at most kMaxThreads.
inline int arenaThreads(int threads) noexcept { return std::min(threads, kMaxThreads); }

}  // namespace sf
