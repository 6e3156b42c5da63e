// SPDX-License-Identifier: Apache-2.0
// In-memory input: a polygon mesh given as arrays, checked and reported as a mesh file is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/patch/mesh_pipeline.h>

namespace sf {

/// How MeshArrays::normals is laid out. Auto: by its row count, #V rows per vertex, #C rows
/// per corner (per vertex when #V == #C).
enum class NormalLayout { Auto, PerVertex, PerCorner };
/// Parses "auto|vertex|corner"; throws InputError naming the value.
NormalLayout parseNormalLayout(const std::string& s);

/// A polygon mesh as caller-owned arrays (nothing is copied until loadMeshArrays). Row-major,
/// C order. Units: metres.
///   positions    numVertices x 3 doubles
///   faceOffsets  numFaces + 1 int32: face f owns corners faceOffsets[f] .. faceOffsets[f+1]-1;
///                faceOffsets[0] = 0, faceOffsets[numFaces] = #C
///   faceVertices #C int32 vertex indices in [0, numVertices), counter-clockwise from outside
///   normals      numNormals x 3 doubles or null: per vertex (numNormals = #V) or per corner
///                (numNormals = #C), see NormalLayout; used as a file's normals are (NormalMode)
///   creaseEdges  numCreases x 2 int32 or null: edges marked sharp, 0-based vertex ids (as a
///                file's crease tags, creases.h; read unless PatchOptions::creases.tags is off)
///   creaseSharpness numCreases doubles (OpenSubdiv's sharpness, > 0 sharp) or null: all 10
struct MeshArrays {
  const double* positions = nullptr;
  size_t numVertices = 0;
  const int32_t* faceOffsets = nullptr;
  size_t numFaces = 0;
  const int32_t* faceVertices = nullptr;
  const double* normals = nullptr;
  size_t numNormals = 0;
  NormalLayout normalLayout = NormalLayout::Auto;
  const int32_t* creaseEdges = nullptr;
  size_t numCreases = 0;
  const double* creaseSharpness = nullptr;
  std::string name = "<arrays>";     ///< names the mesh in messages, as a file's path does
  std::optional<uint64_t> meshHash;  ///< provenance hash of the cache; unset: meshArraysHash()
};

/// XXH64 of the arrays' contents (positions, offsets, indices, normals and their layout).
/// Call it on checked arrays (meshFromArrays did not throw).
uint64_t meshArraysHash(const MeshArrays& in);

/// Copies checked arrays into a PolygonMesh (sourcePath = in.name). Throws InputError
/// "NAME: <field> ...: message" naming the field and the face, corner, vertex or row for: a
/// null array with a non-zero count, no faces, counts beyond int32, faceOffsets[0] != 0,
/// decreasing offsets or a face with fewer than 3 corners, an index out of range, a
/// non-finite position or normal, a normal row count that fits neither #V nor #C (or not the
/// layout asked for) -- the checks the mesh readers make on a file.
PolygonMesh meshFromArrays(const MeshArrays& in);

/// loadMesh for arrays: meshFromArrays, then the same checks, orientation and normals as a
/// file (mesh_pipeline.h); fileHash = in.meshHash or meshArraysHash(in). A file read with
/// readMesh and its arrays given here (with meshHash = the file's hash) give byte-identical
/// caches. Throws InputError.
LoadedMesh loadMeshArrays(const MeshArrays& in, const PatchOptions& options);

}  // namespace sf
