// SPDX-License-Identifier: Apache-2.0
// Polygon meshes as read from file: n-gons kept as they are, numbered in file order.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <smoothforce/base/error.h>  // InputError, thrown by every reader

namespace sf {

/// A polygon mesh in compressed-row form.
/// positions:       #V by 3 vertex positions (file units; metres unless the scene says otherwise).
/// faceOffsets:     #F+1; face f owns corners faceOffsets[f] .. faceOffsets[f+1]-1.
/// faceVertices:    #C (total corners) vertex index per corner, counter-clockwise seen from outside.
/// fileNormals:     #V by 3 per-vertex normals from the file, or empty.
/// fileCornerNormals: #C by 3 per-corner normals from the file (OBJ `f v//vn`), or empty.
/// Faces and vertices keep the file's order; nothing is triangulated, merged or dropped.
struct PolygonMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int32_t> faceOffsets{0};
  std::vector<int32_t> faceVertices;
  std::vector<Eigen::Vector3d> fileNormals;
  std::vector<Eigen::Vector3d> fileCornerNormals;
  std::string sourcePath;  ///< file it came from, for messages

  int numVertices() const { return static_cast<int>(positions.size()); }
  int numFaces() const { return static_cast<int>(faceOffsets.size()) - 1; }
  int numCorners() const { return static_cast<int>(faceVertices.size()); }
  int faceSize(int f) const { return faceOffsets[f + 1] - faceOffsets[f]; }
  /// Vertex index of corner k (mod n) of face f.
  int faceVertex(int f, int k) const {
    const int n = faceSize(f);
    return faceVertices[faceOffsets[f] + ((k % n) + n) % n];
  }
  /// Appends a face given its vertex indices (no checks; loaders validate first).
  void addFace(const std::vector<int32_t>& verts) {
    faceVertices.insert(faceVertices.end(), verts.begin(), verts.end());
    faceOffsets.push_back(static_cast<int32_t>(faceVertices.size()));
  }
};

}  // namespace sf
