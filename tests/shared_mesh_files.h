// SPDX-License-Identifier: Apache-2.0
// The list of shared meshes the whole-input tests (and bench/refine_stats.cpp) run over; no
// dependency beyond the standard library, so that benchmarks can include it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sf::test {

/// The path of a shared mesh from its path under ../shared/meshes ("keenan_crane/spot.obj").
inline std::string sharedMesh(const std::string& rel) { return std::string(SF_SHARED_MESHES) + "/" + rel; }

/// Every mesh file (.obj, .off, .ply) under ../shared/meshes (SF_SHARED_MESHES) of at most
/// maxBytes (the larger ones are the dense references, covered by the CLI runs), sorted.
inline std::vector<std::string> sharedMeshFiles(uintmax_t maxBytes = 3'000'000) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(SF_SHARED_MESHES)) {
    const std::string ext = entry.path().extension().string();
    if ((ext == ".obj" || ext == ".off" || ext == ".ply") && entry.file_size() <= maxBytes)
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace sf::test
