// SPDX-License-Identifier: Apache-2.0
// Subdivision cages: a polygon mesh read as a Catmull-Clark control cage, its vertices moved to
// their limit positions with limit normals, and its limit surface sampled for measurements.
// Computed with OpenSubdiv 3.5 (Far::TopologyRefiner, Far::PrimvarRefiner::Limit, Bfr::Surface).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/mesh_check.h>

namespace sf {

/// What the mesh is before patches are built: None, the polygons themselves; CatmullClark, the
/// control cage of a Catmull-Clark surface (Sdc::SCHEME_CATMARK, Catmark weights on triangles,
/// no creases) whose vertices move to their limit positions and take their limit normals.
/// Boundaries: Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER (boundary edges are infinitely sharp
/// B-spline curves and boundary vertices with one face stay where they are: the rule of USD's
/// default `interpolateBoundary = edgeAndCorner` and of Blender's "keep corners").
enum class CageMode { None = 0, CatmullClark = 1 };

/// Parses "none|catmull-clark"; throws InputError ("--cage: expected ...") otherwise.
CageMode parseCageMode(const std::string& s);
/// "none" or "catmull-clark".
const char* toString(CageMode m);

/// Empty when OpenSubdiv can refine `mesh` as a Catmull-Clark cage; else what is wrong, naming
/// the first offending element: a non-manifold edge or vertex, an interior edge used twice in
/// one direction (inconsistent orientation), a face repeating a vertex or another face's
/// vertices, or a mesh without faces. `report` is checkMesh(mesh).
std::string cageProblem(const PolygonMesh& mesh, const MeshReport& report);

/// The Catmull-Clark limit of every vertex of a cage.
struct CageLimit {
  std::vector<Eigen::Vector3d> positions;  ///< #V by 3, m: limit positions (unreferenced vertices unmoved)
  std::vector<Eigen::Vector3d> normals;    ///< #V by 3, unit limit normals (zero at unreferenced vertices)
  std::vector<int> fallbackVertices;       ///< vertices whose limit tangents are parallel: the angle-weighted
                                           ///< Newell normal of the moved mesh was used instead
  int boundaryVertices = 0;                ///< referenced vertices on a boundary
};

/// Moves each referenced vertex of `mesh` to its Catmull-Clark limit position: one uniform
/// refinement (Far::TopologyRefiner::RefineUniform, level 1, full topology kept, so that every
/// face is a quad, which the Catmark limit masks assume), Far::PrimvarRefiner::Interpolate to that
/// level, then Far::PrimvarRefiner::Limit with the two limit tangents at the level-0 vertices'
/// children (which have the level-0 vertices' limits). The normal is the unit cross product
/// tangent1 x tangent2, turned to agree with the area-weighted Newell normal of the vertex's
/// faces (the faces' counter-clockwise orientation). `report` is checkMesh(mesh). Throws
/// InputError (prefixed with mesh.sourcePath) when cageProblem is not empty, or for non-finite
/// results.
CageLimit catmullClarkLimit(const PolygonMesh& mesh, const MeshReport& report);

/// The limit surface of a Catmull-Clark cage, tessellated face by face with Bfr: positions and
/// unit normals (Du x Dv normalised; zero where it vanishes) #P by 3, triangles #T by 3 in Bfr's
/// parametric order (counter-clockwise in the face's (u, v)), face[t] the cage face each
/// triangle lies on. faceFirstPoint (#F+1): face f's points are faceFirstPoint[f] ..
/// faceFirstPoint[f+1]-1, in Bfr::Tessellation::GetCoords order (boundary points first,
/// starting at the face's corner 0, then interior points); empty for a face without limit surface.
struct LimitTessellation {
  std::vector<Eigen::Vector3d> positions, normals;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<int32_t> face;
  std::vector<int32_t> faceFirstPoint;
};

/// Samples every face's limit surface on a uniform Bfr::Tessellation of `rate` segments per
/// edge (1..256), evaluated by Bfr::Surface built from a Bfr::RefinerSurfaceFactory with
/// irregular regions approximated at `approxLevel` (1..10; each level halves the error of the
/// Gregory end caps, about 0.25% of the diagonal at 1). Same Sdc options as catmullClarkLimit.
/// Throws InputError as catmullClarkLimit does, and for rate or approxLevel out of range.
LimitTessellation tessellateLimitSurface(const PolygonMesh& mesh, const MeshReport& report, int rate,
                                         int approxLevel = 8);

}  // namespace sf
