// SPDX-License-Identifier: Apache-2.0
// The patch cache file: versioned header, provenance hashes, checksummed payload.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Newest format version this build writes: 4 for a cache whose fold repair turned normals
/// (format 3 plus PatchCache::computedNormals after faceSource), 3 for a fold-repaired cache
/// (PatchCache::faceSource after faceBulge and the certificates, which the header's section bits
/// name), 2 for a cache with certificates (PatchCache::faceCertificate, after faceBulge), else 1.
/// Reads 1 .. this.
inline constexpr uint32_t kCacheFormatVersion = 4;

/// The format version writePatchCache writes `cache` in: 4 with turned normals, 3 with fold
/// repair, else 2 with certificates, else 1.
uint32_t cacheFormatVersion(const PatchCache& cache);

/// XXH64 of the options that determine the patches (precision, cross tangent, normals,
/// orientation, and the cage, creases and fold repair where they are not the default: without
/// them the hash is the one of caches written before those options existed) and of the record
/// layout. The header has no
/// field of its own for the cage: readPatchCache recovers it from this hash.
uint64_t hashPatchOptions(const PatchOptions& options);

/// Writes the cache to `path` atomically: to a temporary file beside it, then renamed.
/// Layout: 128-byte little-endian header (magic "SFPATCH", version, mesh and options hashes,
/// counts, payload size and XXH64 checksum, header checksum), then the arrays in
/// PatchCache order (faceCertificate in format 2 and where format 3's sections say, faceSource in
/// formats 3 and 4, computedNormals in format 4). Throws InputError when the file cannot be written.
void writePatchCache(const PatchCache& cache, const std::string& path);

/// True when the file at `path` starts with the cache magic (false when unreadable).
bool isPatchCacheFile(const std::string& path);

/// What a loaded cache must match; unset fields are not checked.
struct CacheExpectation {
  std::optional<uint64_t> meshHash;
  std::optional<PatchOptions> options;
};

/// Reads and fully validates a cache file. Throws InputError naming the file for: a file
/// that is not a cache, truncated, corrupted (checksum), written by a newer format version,
/// inconsistent counts or indices, or not matching `expect` (different mesh or options).
/// Sizes are checked against the file size before anything is allocated.
PatchCache readPatchCache(const std::string& path, const CacheExpectation& expect = {});

}  // namespace sf
