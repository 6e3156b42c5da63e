// SPDX-License-Identifier: Apache-2.0
// The mesh harnesses (fuzz_obj, fuzz_off, fuzz_ply): readMesh on the input, then the
// guarantees of a PolygonMesh that readMesh returned (host/mesh_io.h, host/mesh.h).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>

#include <smoothforce/mesh/mesh_io.h>
#include "fuzz_common.h"

namespace sf::fuzz {

inline void checkMesh(const PolygonMesh& m) {
  if (m.numFaces() < 1) crash("mesh without faces accepted");
  if (m.faceOffsets.front() != 0 || m.faceOffsets.back() != m.numCorners()) crash("face offsets inconsistent");
  for (int f = 0; f < m.numFaces(); ++f)
    if (m.faceSize(f) < 3) crash("face " + std::to_string(f) + " has fewer than 3 corners");
  for (int c = 0; c < m.numCorners(); ++c)
    if (m.faceVertices[c] < 0 || m.faceVertices[c] >= m.numVertices())
      crash("corner " + std::to_string(c) + " refers to vertex " + std::to_string(m.faceVertices[c]) + " of " +
            std::to_string(m.numVertices()));
  for (const auto& p : m.positions)
    if (!p.allFinite()) crash("non-finite position accepted");
  if (!m.fileNormals.empty() && m.fileNormals.size() != m.positions.size()) crash("per-vertex normals miscounted");
  if (!m.fileCornerNormals.empty() && static_cast<int>(m.fileCornerNormals.size()) != m.numCorners())
    crash("per-corner normals miscounted");
  for (const auto& n : m.fileNormals)
    if (!n.allFinite()) crash("non-finite normal accepted");
  for (const auto& n : m.fileCornerNormals)
    if (!n.allFinite()) crash("non-finite corner normal accepted");
}

/// With SF_FUZZ_SKIP_KNOWN=1 (tools/fuzz), inputs that would only hit a bug already reported
/// are skipped, so that fuzzing goes on past it (see fuzz/known_issues.supp). Delete an entry
/// once its bug is fixed.
inline bool knownIssue(const uint8_t* data, size_t size, const char* ext) {
  static const bool skip = std::getenv("SF_FUZZ_SKIP_KNOWN") && std::string(std::getenv("SF_FUZZ_SKIP_KNOWN")) == "1";
  if (!skip) return false;
  if (std::string_view(ext) != ".obj") return false;
  // OBJ relative index INT64_MIN: host/mesh_io_obj.cpp:26 negates it, then accepts index == count.
  // Any token (split at whitespace and '/') that reads as INT64_MIN, however spelt.
  const char* p = reinterpret_cast<const char*>(data);
  const char* end = p + size;
  while (p < end) {
    const char* q = p;
    while (q < end && *q != '/' && *q != ' ' && *q != '\t' && *q != '\n' && *q != '\r' && *q != '\v' && *q != '\f') ++q;
    int64_t v = 0;
    const auto r = std::from_chars(p, q, v);
    if (r.ec == std::errc() && r.ptr == q && v == INT64_MIN) return true;
    p = q + 1;
  }
  return false;
}

inline int fuzzMesh(const uint8_t* data, size_t size, const char* ext) {
  if (knownIssue(data, size, ext)) return 0;
  const std::string& path = writeInput(data, size, ext);
  PolygonMesh m;
  if (accepted(path, [&] { m = readMesh(path); })) checkMesh(m);
  return 0;
}

}  // namespace sf::fuzz
