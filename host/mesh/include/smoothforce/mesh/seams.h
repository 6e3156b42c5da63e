// SPDX-License-Identifier: Apache-2.0
// Seams written twice: boundary edges that coincide with another boundary edge, end for end,
// joined into one interior edge (an exporter's vertices split where normals or texture
// coordinates differ, a triangle soup).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// What stitchSeams joined, or why it joined nothing.
struct SeamReport {
  int seamEdges = 0;  ///< pairs of boundary edges joined into one interior edge each
  /// of them, pairs whose two edges ran the same way (acrossTurnedFaces): one face of each is
  /// turned against the other until the orientation repair turns it back
  int turnedSeams = 0;
  /// (vertex, the vertex it was merged into), by vertex id: the merged vertex keeps its id and
  /// position but no face refers to it any more; its class's smallest id stands for it.
  std::vector<std::array<int, 2>> mergedVertices;
  bool cornerNormals = false;  ///< per-vertex file normals that differed across a seam went to the corners
  int pairsFound = 0;          ///< boundary edge pairs found: seamEdges joined, openEdges left open
  int openEdges = 0;           ///< pairs left open, where joining them made one of the defects in leftOpen
  /// What joining the open pairs would have made ("edges used by more than two faces", "faces
  /// on the vertices of others", ...); empty when every pair found was joined.
  std::string leftOpen;

  /// Lines for `cache build` (empty when there was no seam).
  std::vector<std::string> describe(int maxIds = 10) const;
};

/// Joins the seams of `mesh` that were written twice: every boundary edge (used by one face)
/// a -> b whose end positions are, bit for bit, those of exactly one other boundary edge c -> d
/// in the opposite direction (P[c] = P[b], P[d] = P[a]), with no third boundary edge at the same
/// positions, becomes an interior edge of the two faces: d is merged into a and c into b (each
/// class of merged vertices into its smallest id). Nothing else moves: faces keep their ids and
/// corner order, vertices their ids and positions (a merged vertex stays in `positions`, no
/// longer referenced), and crease and corner tags are moved to the vertex that stands for
/// theirs. Where per-vertex file normals differ across a seam, every corner takes its own
/// vertex's file normal (fileCornerNormals, as OBJ `f v//vn` gives them; fileNormals is then
/// cleared), so the normal modes treat the seam as OBJ split normals. Coincident vertices that
/// no such edge pair joins stay apart (two parts touching at a point or along an edge written
/// four times). Where joining makes a defect at merged vertices (an edge of more than two faces,
/// a vertex of two fans, a face with a repeated vertex or on another face's vertices, an edge
/// used twice in one direction), the pairs at those vertices stay open (openEdges, leftOpen says
/// which defects) and the rest join; nothing joins if that does not clear them in four rounds.
/// Meshes without such pairs are left as they are (pairsFound 0). #F + #C log #C time.
///
/// acrossTurnedFaces: also join a boundary edge a -> b whose end positions are those of exactly
/// one other boundary edge running the same way (P[c] = P[a], P[d] = P[b]) and of none running
/// the other way: a face written turned against its neighbour, as a soup with a flipped face
/// writes it (c merged with a, d with b). The joined edge is used twice in one direction, which
/// is then not a defect that keeps pairs open: the caller turns the faces back in line
/// (orientCoherently, mesh_check.h), as loadMesh does under OrientPolicy::Outward.
SeamReport stitchSeams(PolygonMesh& mesh, bool acrossTurnedFaces = false);

}  // namespace sf
