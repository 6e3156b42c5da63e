// SPDX-License-Identifier: Apache-2.0
// Tessellating patches into triangles for viewing (MeshLab, ParaView, Blender).
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_eval.h>

namespace sf {

/// A triangle mesh with per-vertex normals: positions, normals #V by 3; triangles #T by 3;
/// face[t] = the polygon (patch) each triangle came from. Per vertex (#V): status = the
/// evaluation's SF_ST_* bits (OR over the patches that share a welded vertex), fold = 1 where a
/// patch holding the vertex is flagged SF_ST_FOLD, bulge = the largest bulge / face diameter of
/// those patches. firstVertex (#F): index of face f's centre vertex before welding, -1 for a
/// face that was not built.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> positions, normals;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<int32_t> face;
  std::vector<uint32_t> status;
  std::vector<uint8_t> fold;
  std::vector<float> bulge;
  std::vector<int32_t> firstVertex;
};

/// Appends the domain points of one n-gon's level-L tessellation, in tessellatePatches' vertex
/// order: the centre, then ring r = 1..L (the domain polygon scaled by r/L, each side split in
/// r): 1 + n L (L+1) / 2 points (xi, eta).
void domainRingPoints(int n, int level, std::vector<Eigen::Vector2d>& out);

/// Appends the triangles of one n-gon's level-L ring tessellation (n L^2, counter-clockwise seen
/// from outside, tessellatePatches' order), as indices of domainRingPoints(n, L) plus `base`.
void ringTriangles(int n, int level, int32_t base, std::vector<std::array<int32_t, 3>>& out);

/// The faces of `cache` whose patches are built (status without GP_ST_NOT_BUILT), in order.
std::vector<int32_t> builtFaces(const PatchCache& cache);

/// Evaluates the level-L domainRingPoints of faces[0..count) a bounded batch at a time (at most
/// about 2^18 points each: memory stays bounded on meshes of millions of faces) and calls
/// visit(i, X, points, m) for each face faces[i] in order, with its m ring points' domain
/// coordinates X and evaluations. The values are those of one batch of every point (evaluations
/// are bit-identical whatever the batch). Throws InputError when level is outside [1, 256].
void visitRingPoints(
    const PatchCache& cache, int level, const int32_t* faces, size_t count, const BatchEvaluator& evaluate,
    const std::function<void(size_t i, const Eigen::Vector2d* X, const PatchPoint* points, size_t m)>& visit);

/// Samples every built patch on `level` rings (each polygon edge split `level` times):
/// 1 + n L (L+1) / 2 vertices and n L^2 triangles per n-gon, counter-clockwise seen from
/// outside. Faces that were not built (status GP_ST_TOO_MANY_SIDES/NONFINITE) are skipped.
/// `evaluate` does the batch evaluation (CPU: evaluatePatches; or an OpenCL evaluator).
/// Throws InputError when level is outside [1, 256].
TriangleMesh tessellatePatches(const PatchCache& cache, int level, const BatchEvaluator& evaluate);

/// What weldPatchSeams did: boundary points merged, and shared edges whose two patches do not
/// meet (their boundary curves differ by more than the tolerance somewhere: a crease of
/// `--normals file`), left open there.
struct WeldReport {
  size_t merged = 0;       ///< vertices removed
  size_t openEdges = 0;    ///< shared edges with at least one point left unwelded
  size_t edgesWelded = 0;  ///< shared edges (slot pairs) visited
};

/// Welds the tessellation of tessellatePatches(cache, level, ...) along the patches' shared
/// edges, by topology (cache.slotTwin: the same edge in the neighbouring face, run the other
/// way): boundary point j of edge k of face f is point L - j of the twin's edge, corners are the
/// mesh vertices. A pair is merged only where the two positions agree within `tolerance`
/// (metres; <= 0: 1e-9 of the bounding diagonal for double caches, 1e-5 for float), so a closed
/// manifold mesh becomes one closed surface with V + E (L - 1) + sum_f (1 + n_f L (L - 1) / 2)
/// vertices. The merged vertex keeps the first position, the normalised sum of the normals, the
/// OR of the status bits and fold flags and the largest bulge. Indices are renumbered in order of
/// first appearance. Throws InputError when `mesh` does not match the cache and level.
WeldReport weldPatchSeams(const PatchCache& cache, int level, TriangleMesh& mesh, double tolerance = 0);

/// How writeTriangleMesh writes.
struct TriangleMeshFormat {
  bool binary = true;  ///< PLY: binary little-endian (false: ASCII)
};

/// Writes by extension. OBJ: `v`, `vn`, then per patch a group `g patch_F` with its triangles
/// (`f v//vn`). PLY (binary little-endian, or ASCII): vertex x y z (double, m), nx ny nz (float),
/// status (uint), fold (uchar), bulge (float); face vertex_indices (list uchar int), patch (int).
/// Throws InputError naming the file for an unknown extension or a write failure.
void writeTriangleMesh(const TriangleMesh& mesh, const std::string& path, const TriangleMeshFormat& format = {});

}  // namespace sf
