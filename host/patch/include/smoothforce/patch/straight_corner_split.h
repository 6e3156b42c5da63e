// SPDX-License-Identifier: Apache-2.0
// The fold repair's fan split: flat polygons whose patch has a straight corner (a crease running
// smoothly through the vertex) cut into triangles about a new centre vertex, or on diagonals into
// pieces fanned about their own centres where one centre does not see every edge.
#pragma once

#include <Eigen/Core>
#include <vector>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/polygon_split.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// The fold repair's second cut (FoldRepairMode On and Search; loadMesh runs it after
/// splitBadCorners). A flat polygon (its vertices within kFlatHeight of its Newell plane) can have
/// a patch corner that is straight although its own corner is not: where a crease runs smoothly
/// through the vertex along both of the polygon's edges there (the rim of a turned part's flat
/// cap), both edge curves leave the vertex along the crease, in opposite directions
/// (gp_crease_edge_tangents), so the patch's Jacobian vanishes at that corner and no certificate
/// can prove it regular there (rounding turns some a hair past straight: a corner inside out). No
/// cut on the polygon's own diagonals helps: every such cut leaves a piece (an ear) holding both
/// edges of some corner. So each flat polygon with a corner between two of its crease edges whose
/// edge curves' end tangents are within kStraightCornerDeg degrees of straight (either way) in the
/// vertex's tangent plane is replaced by the fan of triangles (V_k, V_k+1, centre) about one new
/// vertex: the polygon's own patch (the design page's construction) evaluated at its domain's
/// centre, with that patch's normal there, or, where every corner of the polygon has the same
/// normal, with that normal. The edges of the polygon keep their edge curves (built from the same
/// two vertices and normals), so the neighbours' patches are unchanged and the surface stays G1
/// across every edge; a flat polygon with one normal keeps its plane. Each triangle's corner at V_k
/// sits between the crease and the spoke to the centre, no longer straight. A flat polygon of more
/// than 12 corners whose corner normals are all its plane's (within 1e-6 radians; a gear's face once
/// splitBadCorners has cut its teeth off) is fanned the same way with or without such a corner: its
/// patch is the flat polygon, which the fan's affine triangles keep, while the certificate's bounds
/// of a patch of that many corners seldom decide it (a 24-gon undecided after minutes).
///
/// A cap triangulated from its rim alone (a CAD export: triangles joined across edges that are not
/// creases, a disc whose every vertex is on its rim) has such corners in its ears (both rim edges
/// of a vertex in one triangle), and a fan about one ear's own centre is thin (on an octagonal
/// cylinder 4 of its 12 triangles were proven to fold where the ears alone were only undecided). So
/// where such a cap is flat (its rim within kFlatHeight of one plane, every corner normal within
/// 1e-6 radians of that plane's normal) and one of its triangles has a straight patch corner, its
/// triangles are merged into the polygon of its rim first, and that polygon is fanned as above; the
/// cap keeps its plane and its rim curves. Its fan triangles map to its first triangle as read
/// (mesh.faceSource stays ascending, pieces after their face as read); its other triangles have no
/// face left, and report.fannedFaces lists them all. A cap whose fan fails keeps its triangles.
/// A cap of more corners than a patch takes (GP_MAX_N: a finely divided cylinder's) has no patch
/// of its own: it is fanned about its area centroid, with its corners' one normal; so is a flat
/// polygon read with more than GP_MAX_N corners whose corner normals are all its plane's (such a
/// cap as one face), where every fan triangle turns the polygon's way (else it is left as read,
/// without a patch).
/// A flat region of such triangles that is not a disc of its rim (the annulus of a stepped shaft
/// between its two rims, triangulated from them: each triangle with an edge on the inner rim, a
/// valley, then folds beside that edge) is cut into convex pieces of its triangles instead (a
/// greedy merge across the longest shared edges while the piece stays convex), and each piece
/// with a straight patch corner is fanned as above; the other pieces keep their triangles.
///
/// A fan stands only where its centre sees every edge curve of the polygon (as the construction
/// builds it) turn one way about it, at 1 degree or more, and sees each edge's chord at
/// kFanTangledGapDeg plus 1 degree or more (and 180 minus that or less): a centre outside the
/// curved outline's kernel folds the fan's triangles, and spokes closer than kFanTangledGapDeg
/// would be untangled apart (tangent_fans.h), bending them across thin triangles. A polygon with one corner normal
/// whose centre fails (a long slot's cap sees its far arcs at under a degree; a thin skewed quad its short edges) is
/// cut on diagonals between its own vertices, greedily (the cut whose worse side stands best), at most 6 cuts deep,
/// into pieces that either stand whole (every corner between kFanTangledGapDeg and 180 - kPieceStraightCornerDeg
/// degrees between its edge tangents, no cut crossing an edge curve) or fan about their own area centroid under the
/// same tests (each with the same 1-degree margin); report.fanPieces counts the pieces that stand whole. Faces no plan
/// keeps, and faces with more than kMaxSplitCorners corners, are left whole and listed in report.unfannedFaces (a cap:
/// all its triangles). Updates mesh (positions: the centres appended; faces, fileCornerNormals, faceSmoothingGroups,
/// fileNormals where one per vertex, faceSource) and cornerNormals (#C, one per corner) in place; report.fannedFaces
/// (faces as read, mesh.faceSource), report.fanTriangles and report.addedVertices say what was cut. options give the
/// cross-tangent mode of the patch the centre is taken from.
void splitStraightPatchCorners(PolygonMesh& mesh, std::vector<Eigen::Vector3d>& cornerNormals,
                               const PatchOptions& options, PolygonSplitReport& report);

}  // namespace sf
