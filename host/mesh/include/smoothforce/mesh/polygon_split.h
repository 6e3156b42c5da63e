// SPDX-License-Identifier: Apache-2.0
// The fold repair's split: polygons with a reflex or straight corner cut into convex pieces on
// diagonals between their own vertices.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// How construction repairs patches that fold (`--fold-repair`, key `fold_repair`).
/// Off: the design page's construction on the polygons as read. On (the default; "split" is
/// read as a synonym): every flat polygon (its vertices within kFlatHeight of its Newell plane,
/// whatever its corner normals) with a corner of at least 180 - kStraightCornerDeg degrees is cut
/// into convex pieces first (splitBadCorners). The edge curves of a flat polygon leave each
/// vertex along the chord's projection on that vertex's tangent plane, so the patch over the
/// plane is close to the map of the regular n-gon domain onto the polygon, and that map folds at a
/// reflex corner (no normal or tangent length changes that: docs/fold-levers.md); at a straight
/// corner the patch's Jacobian vanishes. This holds for the caps of extruded parts whose corner
/// normals are averaged with the sides' as much as for planar sheets (docs/fold-levers.md,
/// "Extruded parts"). Curved polygons are left whole: on the spot cage, cutting its quads with a
/// reflex corner on their plane (4 of them within 0.5% of planar) raised the fault area from
/// 1.577% to 1.630%. Search: On, and then, once every patch is built, vertex normals turned
/// within a bound where that removes fault area of the closed patch surface
/// (searchNormalsAgainstFaults, query/normal_search.h: the lever for curved polygons, whose folds
/// come from the corner normals). It needs the whole surface, so lazy construction refuses it.
enum class FoldRepairMode { Off = 0, On = 1, Search = 2 };
/// "off", "on", "split" (the name of On in version 0.5) or "search"; throws InputError for
/// anything else.
FoldRepairMode parseFoldRepairMode(const std::string& s);
/// "off", "on" or "search".
const char* toString(FoldRepairMode m);

/// A corner whose interior angle on the polygon's Newell plane is at least 180 degrees minus
/// this (degrees) is a bad corner: reflex, or straight within it.
inline constexpr double kStraightCornerDeg = 1.0;
/// A polygon that is cut is cut until no piece has a corner of at least 180 minus this (degrees)
/// where diagonals allow: a convex piece with a nearly straight corner (175 degrees, between two
/// 36-degree tips of a star-shaped cap) still folds near it. Measured on extruded parts
/// (docs/fold-levers.md, "Extruded parts"): 1 left a fault on the star, 10 and 20 none, 30 made
/// thin pieces that fault on a notched disc.
inline constexpr double kPieceStraightCornerDeg = 10.0;
/// Of the cuts that leave most pieces without a bad corner, the shortest whose four new corner
/// angles are all at least this (degrees) is taken; where none is, the one whose smallest angle
/// is largest. Shorter cuts dome less where the corner normals lean off the plane (a cut's edge
/// curve leaves each end in that end's tangent plane). Measured on the extruded parts
/// (docs/fold-levers.md, "Which diagonal"): 25 to 40 give the same pieces, 10 and 20 a fault
/// on a notched disc.
inline constexpr double kCutMinAngleDeg = 30.0;
/// A flat polygon: no vertex farther from its Newell plane than this fraction of its diameter.
inline constexpr double kFlatHeight = 1e-4;
/// Faces with more corners are left whole (no patch is built for them either: GP_MAX_N), which
/// bounds the search for diagonals (cubic in the corners, per cut).
inline constexpr int kMaxSplitCorners = 64;

/// What splitBadCorners did.
struct PolygonSplitReport {
  std::vector<int> splitFaces;  ///< faces as read that were cut (ascending)
  int pieces = 0;               ///< faces they became
  /// Flat faces with a bad corner left whole: their outline on their plane is not simple (a
  /// bow-tie) or has no area, they have more than kMaxSplitCorners corners, or no diagonal cuts
  /// them (ascending).
  std::vector<int> unsplitFaces;
  /// Flat faces with a straight patch corner cut into a fan about a new centre vertex (or, where
  /// that centre does not see every edge, into pieces on diagonals, fanned about their own
  /// centres or whole), and the triangles of flat caps merged into one polygon first
  /// (splitStraightPatchCorners, patch/straight_corner_split.h): as read, ascending.
  std::vector<int> fannedFaces;
  int fanTriangles = 0;   ///< fan triangles they became
  int fanPieces = 0;      ///< pieces cut off them on diagonals that stand unfanned
  int addedVertices = 0;  ///< centre vertices appended to the mesh (one per fanned face)
  /// Flat faces with a straight patch corner left whole: no fan about their centre, nor pieces
  /// cut on their diagonals, sees every edge curve, or they have more than kMaxSplitCorners
  /// corners (ascending).
  std::vector<int> unfannedFaces;
};

/// Flat faces (kFlatHeight) of `mesh` with a bad corner
/// (kStraightCornerDeg) are replaced, in place and in order,
/// by convex pieces: each cut is a diagonal between two of the polygon's own vertices, inside
/// it on its Newell plane (exact orientation tests), chosen at a bad corner so that most
/// pieces have no bad corner, then the shortest that makes no angle below kCutMinAngleDeg (else
/// the one whose smallest angle is largest); pieces with a bad corner are cut again. No vertex is added or moved, so every piece's edge curves
/// are built from the same vertex data and the surface stays G1 across the cuts.
/// Per-corner and per-face arrays follow their corners and faces: mesh.fileCornerNormals,
/// mesh.faceSmoothingGroups, *cornerNormals (#C) when given; mesh.faceSource maps each face to
/// the face as read (filled whenever this runs, identity where nothing was cut).
/// Faces checkMesh would call degenerate or self-crossing, and faces of more than
/// kMaxSplitCorners corners, are left whole (reported).
PolygonSplitReport splitBadCorners(PolygonMesh& mesh, std::vector<Eigen::Vector3d>* cornerNormals = nullptr);

/// Collects the faces that replace every face of a mesh (the fold repair's cuts), in order,
/// carrying per-corner data (mesh.fileCornerNormals where there is one per corner, corner normals
/// when given) and per-face data (mesh.faceSmoothingGroups where there is one per face,
/// mesh.faceSource: each new face maps to the face as read) along; commit() installs them.
class FaceRewrite {
 public:
  /// `cornerNormals`: one per corner of `mesh` (#C), or null. Both must outlive this object.
  FaceRewrite(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>* cornerNormals);
  /// Appends corner `slot` of the mesh (an index into mesh.faceVertices) to the face under way.
  void copyCorner(int slot);
  /// Appends a corner at `vertex` with `normal` (its corner normal and file corner normal).
  void addCorner(int vertex, const Eigen::Vector3d& normal);
  /// Closes the face under way as a piece of the mesh's face f (its group and source).
  void closeFace(int f);
  /// Replaces the mesh's faces, per-face and per-corner arrays (and *cornerNormals, when the
  /// constructor was given them) with those collected.
  void commit(PolygonMesh& mesh, std::vector<Eigen::Vector3d>* cornerNormals);

 private:
  const PolygonMesh& mesh_;
  const std::vector<Eigen::Vector3d>* normalsIn_;
  bool fileCorner_, groups_, sourced_;
  PolygonMesh out_;
  std::vector<Eigen::Vector3d> normals_;
};

/// Face f lies within kFlatHeight of its Newell plane (false for a face without a plane).
bool isFlatFace(const PolygonMesh& mesh, int f);

/// The interior angles (radians) of face f's corners on its Newell plane, in corner order
/// (empty for a face without area).
std::vector<double> planarCornerAngles(const PolygonMesh& mesh, int f);

}  // namespace sf
