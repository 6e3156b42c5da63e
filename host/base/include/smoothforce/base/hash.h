// SPDX-License-Identifier: Apache-2.0
// Content hashes (xxHash XXH64) for cache provenance and checksums.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace sf {

/// XXH64 of a byte range.
uint64_t hashBytes(const void* data, size_t size, uint64_t seed = 0);
/// XXH64 of a whole file's bytes; throws InputError when it cannot be read.
uint64_t hashFile(const std::string& path);
/// 16 lower-case hex digits.
std::string hexHash(uint64_t h);

}  // namespace sf
