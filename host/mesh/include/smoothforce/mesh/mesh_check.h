// Topology and sanity report for a polygon mesh (non-manifold edges, duplicates, ...).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// What checkMesh found. Every list holds element ids (0-based, file order).
struct MeshReport {
  int numVertices = 0, numFaces = 0, numEdges = 0;
  std::vector<int> faceSizeHistogram;                ///< [n] = faces with n corners
  std::vector<std::array<int, 2>> nonManifoldEdges;  ///< vertex pairs used by > 2 faces
  std::vector<int> nonManifoldVertices;              ///< vertices with more than one face fan
  std::vector<int> duplicateFaces;                   ///< faces repeating an earlier face's vertex set
  std::vector<int> degenerateFaces;                  ///< repeated vertex, zero-length edge or zero area
  std::vector<int> unreferencedVertices;
  std::vector<std::vector<int>> boundaryLoops;        ///< each a vertex loop
  std::vector<std::array<int, 2>> inconsistentEdges;  ///< interior edges used twice in one direction
  int numComponents = 0;
  double signedVolume = 0;  ///< meaningful for closed meshes (no boundary edges)
  bool closed() const { return boundaryLoops.empty(); }
  bool clean() const;  ///< no problem lists non-empty
  /// Human-readable lines: counts plus the first few ids of each problem.
  std::vector<std::string> describe(int maxIds = 10) const;
};

/// Computes the report. Never throws on bad topology; that is what it reports.
MeshReport checkMesh(const PolygonMesh& mesh);

/// Reverses every face's corner order (and corner normals) in place.
void flipFaces(PolygonMesh& mesh);

/// Orientation policy: `Outward` flips a closed mesh whose signed volume is negative (faces
/// pointing inward, e.g. polygon_laplacian/sphere2.off), when at most 10% of its edges are
/// inconsistently oriented (then the majority's faces point outward after the flip; the
/// report keeps the inconsistent edges); `Keep` leaves it. Returns true when the mesh was flipped.
enum class OrientPolicy { Outward, Keep };
bool applyOrientation(PolygonMesh& mesh, const MeshReport& report, OrientPolicy policy);

}  // namespace sf
