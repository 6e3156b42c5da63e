// SPDX-License-Identifier: Apache-2.0
// What the fold repair changed in a cache, per face, read from the cache alone.
#pragma once

#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// What the fold repair (PatchOptions::foldRepair) changed, per face, from the cache's own
/// record of it: PatchCache::faceSource (the split's pieces), PatchCache::computedNormals (the
/// normals the search turned) and the untangled vertex fans (tangent_fans.h, derived from the
/// cache's positions and normals). Angles in degrees.
struct FoldRepairRecord {
  /// A face as read that the fold repair cut (into convex pieces, or into a fan): its pieces, the
  /// cache's faces (ascending). A flat cap merged from several triangles before its fan is listed
  /// under its first triangle; its other triangles have no faces of their own.
  struct Cut {
    int faceAsRead = -1;
    std::vector<int> faces;
  };
  /// A corner whose normal was turned: corner k of the face (its vertex) and by how much.
  struct Turn {
    int corner = -1;
    int vertex = -1;
    double degrees = 0;
  };
  /// A face whose patch the turned normals or untangled fans changed. An edge curve (edge k:
  /// V_k -> V_{k+1}) is built from its two ends' normals, and on a face with a crease edge from
  /// the normals of the faces across it too; an edge is listed where one of those turned or where
  /// an untangled fan gives one of its end tangents.
  struct FaceChange {
    int face = -1;
    std::vector<Turn> turns;  ///< the face's own corners that turned (may be empty across a crease)
    std::vector<int> edges;   ///< edges k whose curve changed, ascending
  };
  std::vector<Cut> cuts;             ///< ascending by faceAsRead
  std::vector<FaceChange> changed;   ///< ascending by face
  int turnedNormals = 0;   ///< vertex normals turned (the corners of a vertex that share one count once)
  int turnedCorners = 0;   ///< corners whose normal turned
  int edgeCurves = 0;      ///< mesh edges whose curve changed (an edge shared by two faces counts once)
  double maxDegrees = 0;   ///< largest turn of a corner normal
  double meanDegrees = 0;  ///< mean over the turned vertex normals
  int untangledVertices = 0;     ///< vertices whose fan of edge tangents was untangled
  double maxTangentTurnDeg = 0;  ///< largest turn of an edge tangent there
};

/// The record of `cache` (empty lists where the fold repair was off or changed nothing).
FoldRepairRecord foldRepairRecord(const PatchCache& cache);

}  // namespace sf
