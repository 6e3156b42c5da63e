// SPDX-License-Identifier: Apache-2.0
// From a mesh file to a patch cache: read, check, orient, normals, construct.
#pragma once

#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/seams.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// A mesh read and checked, ready for construction.
struct LoadedMesh {
  PolygonMesh mesh;
  SeamReport seams;                            ///< seams written twice, joined before the check
  OrientationRepair orientation;               ///< faces turned to agree with their neighbours (not under keep)
  MeshReport report;                           ///< topology report (after the seams and turns, before any flip)
  bool flipped = false;                        ///< faces were reversed to point outward
  uint64_t fileHash = 0;                       ///< XXH64 of the file's bytes
  std::vector<Eigen::Vector3d> cornerNormals;  ///< #C unit normals per the chosen mode
  NormalReport normalReport;                   ///< where they came from; split, crease and fallback vertices
  std::vector<int> normalFallbacks;            ///< = normalReport.fallbackVertices
  int creaseCorners = 0;                       ///< = normalReport.creaseCorners
  /// With a cage (PatchOptions::cage): the control points before they moved to their limit
  /// positions (#V, m; mesh.positions then holds the limit positions). Empty without a cage.
  std::vector<Eigen::Vector3d> cagePositions;
  int cageBoundaryVertices = 0;  ///< with a cage: referenced vertices on a boundary
  /// With fold repair On or Search: the faces that were cut into convex pieces or fanned about a
  /// new centre vertex (mesh then holds the pieces, mesh.faceSource their faces as read, and the
  /// centres after the vertices read; report and normals were made before the cut).
  PolygonSplitReport split;
};

/// Reads `path`, joins its seams written twice (stitchSeams, seams.h: boundary edges that
/// coincide end for end, as exporters write them where normals or texture coordinates split a
/// vertex; unless options.keepOrientation, also those between a face written turned and its
/// neighbour), unless options.keepOrientation turns the faces that run against their neighbours
/// (orientCoherently), checks it, flips an inward-facing closed mesh unless keepOrientation,
/// and computes corner normals per options.normals (normals.h: NormalMode, NormalReport).
/// With options.cage CatmullClark, then moves every referenced vertex to its Catmull-Clark
/// limit position and uses its limit normal at every corner (catmullClarkLimit, cage_limit.h;
/// the report stays the one of the cage as read). With options.foldRepair On or Search, last
/// cuts the flat polygons with a reflex or straight corner into convex pieces (splitBadCorners;
/// their corners keep the normals computed above), then fans the flat polygons whose patch has
/// a straight corner about a new centre vertex (splitStraightPatchCorners). Throws InputError
/// (file:line, element; with a cage also: normals other than Auto, and the topology cageProblem
/// names).
LoadedMesh loadMesh(const std::string& path, const PatchOptions& options);

/// The same for a mesh already in memory (mesh_arrays.h builds one from arrays): joins its
/// seams, orients it, checks it and computes its corner normals; fileHash = meshHash.
LoadedMesh loadMesh(PolygonMesh mesh, uint64_t meshHash, const PatchOptions& options);

/// Builds the whole-mesh patch cache from a loaded mesh on the CPU backends
/// (Backend::Serial / Backend::Tbb; threads <= 0: oneTBB default). Under FoldRepairMode::Search
/// the patches are those of On: the normal search runs next, on the built surface
/// (finishFoldRepair, query/normal_search.h), as the command line, C API and Python do.
PatchCache buildPatchCache(const LoadedMesh& loaded, const PatchOptions& options, Backend backend, int threads = 0);

/// The base mesh, corner normals and adjacency without any patch (hasPatchData false): for
/// lazy construction near the contact point (lazy_patches.h). Cheap: no patch is built.
/// Throws InputError for options a lazy surface cannot build (requireLazyOptions).
PatchCache preparePatchSkeleton(const LoadedMesh& loaded, const PatchOptions& options);

/// The cache's base mesh as a PolygonMesh (positions, faces; after any outward flip; no file
/// normals), for the checks a cache file alone allows (checkMesh's intersections).
PolygonMesh cacheBaseMesh(const PatchCache& cache);

/// Counts of construction status bits over all faces, for reports.
struct PatchStatusSummary {
  int guard = 0, zeroEdge = 0, edgeNormal = 0, crossTangent = 0, fold = 0, bulge = 0, notBuilt = 0;
  float maxBulge = 0;
  std::vector<int> foldFaces, bulgeFaces, degenerateFaces;  ///< face ids
  /// Faces with a corner inside out: its two edge curves leave the vertex in the wrong order about
  /// the vertex normal ((C_k'(0) x -C_k-1'(1)) . N_k < 0, from the built records; Eq. 8-9), so
  /// the patch meets its neighbours upside down at that corner and folds there. Empty for a
  /// cache without patch data.
  std::vector<int> insideOutFaces;
  /// Flat triangles whose patch is their affine map plus their curved edges' deviations
  /// (GP_ST_AFFINE, markAffineTriangles).
  std::vector<int> affineFaces;
};
PatchStatusSummary summarizePatchStatus(const PatchCache& cache);

/// Face ids for a report line: the first 10, each after a space, then " ..." if there are more
/// (" 3 17 40").
std::string faceIdsText(const std::vector<int>& ids);

}  // namespace sf
