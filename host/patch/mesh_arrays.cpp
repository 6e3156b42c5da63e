// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/mesh_arrays.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/error.h>
#include <smoothforce/base/hash.h>

namespace sf {
namespace {

constexpr size_t kMaxCount = static_cast<size_t>(std::numeric_limits<int32_t>::max());

[[noreturn]] void fail(const MeshArrays& in, const std::string& what) { throw InputError(in.name + ": " + what); }

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// Checks rows x 3 doubles for finiteness (and, positions, the coordinate range of
/// coordinate_range.h); names the field, row and column of the first bad one.
void checkFinite(const MeshArrays& in, const double* a, size_t rows, const char* field, const char* row,
                 bool position = false) {
  for (size_t i = 0; i < rows * 3; ++i)
    if (!std::isfinite(a[i]) || (position && !(std::fabs(a[i]) <= kMaxCoordinate)))
      fail(in, std::string(field) + "[" + std::to_string(i / 3) + "][" + std::to_string(i % 3) + "] (" + row + " " +
                   std::to_string(i / 3) + "): " + (std::isfinite(a[i]) ? "value " : "non-finite value ") + num(a[i]) +
                   (std::isfinite(a[i]) ? " m beyond the coordinate range +-1e15 m" : ""));
}

}  // namespace

NormalLayout parseNormalLayout(const std::string& s) {
  if (s == "auto") return NormalLayout::Auto;
  if (s == "vertex") return NormalLayout::PerVertex;
  if (s == "corner") return NormalLayout::PerCorner;
  throw InputError("normal layout: expected auto, vertex or corner, got '" + s + "'");
}

PolygonMesh meshFromArrays(const MeshArrays& in) {
  if (in.numVertices > kMaxCount)
    fail(in, "positions: " + std::to_string(in.numVertices) + " vertices (at most 2^31-1)");
  if (in.numFaces > kMaxCount - 1) fail(in, "faceOffsets: " + std::to_string(in.numFaces) + " faces (at most 2^31-2)");
  if (in.numFaces == 0) fail(in, "no faces");
  if (in.numVertices > 0 && !in.positions)
    fail(in, "positions: null with " + std::to_string(in.numVertices) + " vertices");
  if (!in.faceOffsets) fail(in, "faceOffsets: null with " + std::to_string(in.numFaces) + " faces");
  if (in.faceOffsets[0] != 0) fail(in, "faceOffsets[0]: " + std::to_string(in.faceOffsets[0]) + " (must be 0)");
  for (size_t f = 0; f < in.numFaces; ++f) {
    const int64_t n = int64_t{in.faceOffsets[f + 1]} - in.faceOffsets[f];
    if (n < 3)
      fail(in, "faceOffsets[" + std::to_string(f + 1) + "] (face " + std::to_string(f) + "): " + std::to_string(n) +
                   " corners (" + std::to_string(in.faceOffsets[f]) + " to " + std::to_string(in.faceOffsets[f + 1]) +
                   "); a face needs at least 3");
  }
  const size_t corners = static_cast<size_t>(in.faceOffsets[in.numFaces]);
  if (!in.faceVertices) fail(in, "faceVertices: null with " + std::to_string(corners) + " corners");
  checkFinite(in, in.positions, in.numVertices, "positions", "vertex", true);
  for (size_t f = 0; f < in.numFaces; ++f)
    for (int32_t c = in.faceOffsets[f]; c < in.faceOffsets[f + 1]; ++c) {
      const int32_t v = in.faceVertices[c];
      if (v < 0 || static_cast<size_t>(v) >= in.numVertices)
        fail(in, "faceVertices[" + std::to_string(c) + "] (face " + std::to_string(f) + ", corner " +
                     std::to_string(c - in.faceOffsets[f]) + "): vertex index " + std::to_string(v) +
                     " out of range [0, " + std::to_string(in.numVertices) + ")");
    }

  PolygonMesh m;
  m.sourcePath = in.name;
  m.positions.resize(in.numVertices);
  for (size_t v = 0; v < in.numVertices; ++v)
    m.positions[v] = Eigen::Vector3d(in.positions[3 * v], in.positions[3 * v + 1], in.positions[3 * v + 2]);
  m.faceOffsets.assign(in.faceOffsets, in.faceOffsets + in.numFaces + 1);
  m.faceVertices.assign(in.faceVertices, in.faceVertices + corners);

  if (in.numNormals > 0 || in.normals) {
    if (!in.normals) fail(in, "normals: null with " + std::to_string(in.numNormals) + " rows");
    const bool vertexRows = in.numNormals == in.numVertices, cornerRows = in.numNormals == corners;
    bool perVertex = false;
    switch (in.normalLayout) {
      case NormalLayout::Auto:
        if (!vertexRows && !cornerRows)
          fail(in, "normals: " + std::to_string(in.numNormals) + " rows, expected " + std::to_string(in.numVertices) +
                       " (one per vertex) or " + std::to_string(corners) + " (one per corner)");
        perVertex = vertexRows;
        break;
      case NormalLayout::PerVertex:
        if (!vertexRows)
          fail(in, "normals: " + std::to_string(in.numNormals) + " rows, expected " + std::to_string(in.numVertices) +
                       " (one per vertex)");
        perVertex = true;
        break;
      case NormalLayout::PerCorner:
        if (!cornerRows)
          fail(in, "normals: " + std::to_string(in.numNormals) + " rows, expected " + std::to_string(corners) +
                       " (one per corner)");
        break;
    }
    checkFinite(in, in.normals, in.numNormals, "normals", perVertex ? "vertex" : "corner");
    auto& dst = perVertex ? m.fileNormals : m.fileCornerNormals;
    dst.resize(in.numNormals);
    for (size_t i = 0; i < in.numNormals; ++i)
      dst[i] = Eigen::Vector3d(in.normals[3 * i], in.normals[3 * i + 1], in.normals[3 * i + 2]);
  }
  if (in.numCreases > 0 && !in.creaseEdges) fail(in, "creaseEdges: null with " + std::to_string(in.numCreases) + " rows");
  for (size_t i = 0; i < in.numCreases; ++i) {
    const int32_t a = in.creaseEdges[2 * i], b = in.creaseEdges[2 * i + 1];
    const double s = in.creaseSharpness ? in.creaseSharpness[i] : kInfiniteSharpness;
    const std::string row = "creaseEdges[" + std::to_string(i) + "]: ";
    for (int32_t v : {a, b})
      if (v < 0 || static_cast<size_t>(v) >= in.numVertices)
        fail(in, row + "vertex index " + std::to_string(v) + " out of range [0, " + std::to_string(in.numVertices) + ")");
    if (a == b) fail(in, row + "both ends are vertex " + std::to_string(a));
    if (!(s >= 0) || !std::isfinite(s))
      fail(in, "creaseSharpness[" + std::to_string(i) + "]: " + std::to_string(s) + " (expected a finite value >= 0)");
    m.creaseTags.push_back({a, b, s, 0});
  }
  return m;
}

uint64_t meshArraysHash(const MeshArrays& in) {
  const size_t corners = in.numFaces ? static_cast<size_t>(in.faceOffsets[in.numFaces]) : 0;
  const uint64_t counts[5] = {in.numVertices, in.numFaces, corners, in.numNormals,
                              static_cast<uint64_t>(in.normalLayout)};
  uint64_t h = hashBytes(counts, sizeof counts, 0x5346415252415953ull);  // "SFARRAYS"
  h = hashBytes(in.positions, in.numVertices * 3 * sizeof(double), h);
  h = hashBytes(in.faceOffsets, (in.numFaces + 1) * sizeof(int32_t), h);
  h = hashBytes(in.faceVertices, corners * sizeof(int32_t), h);
  if (in.normals) h = hashBytes(in.normals, in.numNormals * 3 * sizeof(double), h);
  if (in.numCreases) {  // only then: the hash of arrays without creases stays as it was
    h = hashBytes(in.creaseEdges, in.numCreases * 2 * sizeof(int32_t), h);
    if (in.creaseSharpness) h = hashBytes(in.creaseSharpness, in.numCreases * sizeof(double), h);
  }
  return h;
}

LoadedMesh loadMeshArrays(const MeshArrays& in, const PatchOptions& options) {
  PolygonMesh mesh = meshFromArrays(in);
  const uint64_t hash = in.meshHash ? *in.meshHash : meshArraysHash(in);
  return loadMesh(std::move(mesh), hash, options);
}

}  // namespace sf
