// Tessellating patches into triangles for viewing (MeshLab, ParaView, Blender).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_eval.h>

namespace sf {

/// A triangle mesh with per-vertex normals: positions, normals #V by 3; triangles #T by 3;
/// face[t] = the polygon (patch) each triangle came from.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> positions, normals;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<int32_t> face;
};

/// Appends the domain points of one n-gon's level-L tessellation, in tessellatePatches' vertex
/// order: the centre, then ring r = 1..L (the domain polygon scaled by r/L, each side split in
/// r): 1 + n L (L+1) / 2 points (xi, eta).
void domainRingPoints(int n, int level, std::vector<Eigen::Vector2d>& out);

/// Samples every built patch on `level` rings (each polygon edge split `level` times):
/// 1 + n L (L+1) / 2 vertices and n L^2 triangles per n-gon, counter-clockwise seen from
/// outside. Faces that were not built (status GP_ST_TOO_MANY_SIDES/NONFINITE) are skipped.
/// `evaluate` does the batch evaluation (CPU: evaluatePatches; or an OpenCL evaluator).
/// Throws InputError when level is outside [1, 256].
TriangleMesh tessellatePatches(const PatchCache& cache, int level, const BatchEvaluator& evaluate);

/// Writes OBJ (v, vn, f v//vn) or ASCII PLY (x y z nx ny nz, vertex_indices) by extension.
/// Throws InputError for an unknown extension or a write failure.
void writeTriangleMesh(const TriangleMesh& mesh, const std::string& path);

}  // namespace sf
