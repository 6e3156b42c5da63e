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
/// Crease marks as the file gives them (creases.h turns them into crease edges):
/// creaseTags:          edges tagged sharp (OBJ `t crease`, PLY edge elements with a crease property).
/// cornerTags:          vertices tagged sharp (OBJ `t corner`).
/// faceSmoothingGroups: #F smoothing group per face (OBJ `s N`; 0 for `s off` / `s 0` and for faces
///                      before the first `s`), or empty when the file has no `s` statement.

/// One edge tagged sharp: 0-based vertex ids and OpenSubdiv's sharpness (0 smooth .. 10 infinitely
/// sharp); `line` is the file line (0 when not from a file), for messages. The readers check that
/// the ids are vertices of the file, v0 != v1 and the sharpness is finite and >= 0, not that the
/// edge is in a face. OBJ: one tag per vertex pair of a `t crease` statement, `line` where the
/// statement starts; PLY: one per row of the `edge` element, `line` its header line.
struct CreaseTag {
  int32_t v0 = 0, v1 = 0;
  double sharpness = 0;
  size_t line = 0;
};

/// One vertex tagged sharp (a corner): 0-based vertex id, OpenSubdiv's sharpness, file line (OBJ:
/// one tag per vertex of a `t corner` statement, `line` where the statement starts).
struct CornerTag {
  int32_t v = 0;
  double sharpness = 0;
  size_t line = 0;
};

struct PolygonMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int32_t> faceOffsets{0};
  std::vector<int32_t> faceVertices;
  std::vector<Eigen::Vector3d> fileNormals;
  std::vector<Eigen::Vector3d> fileCornerNormals;
  std::vector<CreaseTag> creaseTags;
  std::vector<CornerTag> cornerTags;
  std::vector<int64_t> faceSmoothingGroups;
  /// #F: the face of the mesh as read that each face comes from, where faces were split
  /// (polygon_split.h); empty when every face is the one read.
  std::vector<int32_t> faceSource;
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
