// SPDX-License-Identifier: Apache-2.0
// A fold repair for curved polygons: vertex normals turned, within a bound, where that removes
// fault area of the closed patch surface (docs/fold-levers.md, "Normals found by search").
#pragma once

#include <cstdint>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// Options of searchNormalsAgainstFaults.
struct NormalSearchOptions {
  /// No vertex normal ends farther than this from the one it was built with, degrees in (0, 90].
  double maxRotationDeg = 60;
  int passes = 2;  ///< rounds over the vertices of faulted faces, 1..16
  /// Where the mesh is mirror-symmetric (an axis-aligned plane through its box's centre maps
  /// vertices, faces and vertex normals onto each other, within 1e-9 of the diagonal), turn each
  /// normal together with its mirror image, and those on the plane only within it, so that the
  /// surface keeps the symmetry; false: every normal on its own.
  bool keepSymmetry = true;
  /// Uniform tessellation level (PatchSurfaceOptions::level) of the fault measure that compares
  /// the candidates, 1..64; 0: the level whose tessellation has about searchTriangles triangles
  /// (the rays of every candidate of a vertex cross all of it), or the surface's own level
  /// (PatchSurface's choice, the one the result is judged at) where that is finer: a dense mesh's
  /// folds are thinner than a coarser level's triangles, which would see none. On the spot cage a search
  /// at its own level (12) left 0.16-0.18% of the area faulted when measured at levels 24 and 32
  /// (folds thinner than its triangles); at 14 and 16, 0.025% at every level.
  int searchLevel = 0;
  int64_t searchTriangles = 150'000;  ///< with searchLevel 0, >= 1000
  /// Level of one last pass over the vertices of the faces faulted at that level, after the
  /// passes at the search level: folds and overlaps thinner than the search level's triangles,
  /// which its measure cannot see (on the spot cage two patches crossing the face between them,
  /// 0.013% of the area measured at level 32). It keeps only moves that remove at least half the
  /// fault area on the faces they change. 0: 1.5 x the search level, rounded, lowered to stay
  /// within polishTriangles, and no last pass where that is not finer than the search level (dense
  /// meshes); -1: no last pass; else 1..64.
  int polishLevel = 0;
  int64_t polishTriangles = 400'000;  ///< with polishLevel 0, >= 1000
  Backend backend = Backend::Tbb;  ///< construction of the candidate patches (Serial or Tbb)
  int threads = 0;                 ///< > 0: at most this many oneTBB threads (Tbb), 0: oneTBB's default
};

/// One vertex normal the search turned: every corner of `vertex` that shared the normal
/// (corners split by a crease keep theirs apart, each its own group).
struct NormalChange {
  int vertex = -1;
  double rotationDeg = 0;        ///< angle between the normal built with and the one kept
  std::vector<int> corners;      ///< corner slots (PatchCache::faceVertices order) that changed
};

/// What the search did. Fault areas from measureSurfaceFaults at the surface's default level.
struct NormalSearchReport {
  bool closed = false;          ///< false: an open surface has no inside; nothing searched
  bool applied = false;         ///< false: no change lowered the fault area; the cache is as given
  double faultBefore = 0;       ///< m^2
  double faultAfter = 0;        ///< m^2 (= faultBefore unless applied)
  double totalArea = 0;         ///< m^2 of the probed surface (before)
  std::vector<NormalChange> changes;  ///< the normals turned, in search order
  std::vector<int> changedFaces;      ///< faces whose patch the search changed (any bit of its records), ascending
  int searchLevel = 0;                ///< the level the candidates were compared at
  int polishLevel = 0;                ///< the level of the last pass, 0: none
  double polishFaultBefore = 0;       ///< m^2 at polishLevel, before the last pass (after the others)
  double polishFaultAfter = 0;        ///< m^2 at polishLevel, after it
  int64_t evaluations = 0;            ///< candidate surfaces measured
  int mirrorAxis = -1;                ///< the symmetry kept (0 x, 1 y, 2 z), -1 none
  double seconds = 0;
};

/// Turns vertex normals of `cache` where that removes fault area (surface_faults.h) of its
/// closed patch surface, in `passes` passes at the search level and one at the polish level:
/// for every normal at a corner of a face with fault area at that level, the candidates
/// are its slerps (halfway and all the way, clamped to maxRotationDeg from the original) towards
/// each of its corners' polygon normals (the corner's two edges' cross product) and towards the
/// direction that maximises the smallest cosine to them (a normal with every corner sector of
/// its fan positively oriented in its tangent plane, where one exists); the candidate that
/// lowers the fault area most is kept. A candidate's area is compared only over the triangles it
/// can change: those of the faces at the vertex, of the faces whose untangled fan tangents it
/// changes (tangent_fans.h: a normal turns its edges' own directions at the neighbouring
/// vertices too, and so their fans), and every triangle in the box of their old and new
/// tessellations (the winding number changes nowhere else). Every edge curve is still built
/// from its own vertices' positions and normals (and the shared fan directions at its ends), so
/// G1 holds as before; faces with no turned corner and the same end tangents keep their patches
/// bit for bit, but for a face with a crease edge at a turned vertex (built with the normals
/// across it; foldRepairRecord lists it). At the end the fault area is measured at the surface's
/// own level; unless it fell, every normal is put back (applied false).
///
/// On a mirror-symmetric mesh (keepSymmetry) a normal and its mirror image are one move: the
/// candidates of the first, reflected for the second, compared over the triangles either changes.
///
/// The cache must have its patches built (constructPatches); its corner normals and patches are
/// replaced where applied, and cache.computedNormals then keeps the normals it was given (the
/// record of what turned, which the cache file stores). The sampled fault measure is the
/// objective, not a proof: certify the result (certifyPatches) where a proof per patch is needed.
/// Throws std::invalid_argument for options out of range or a cache without patches,
/// std::runtime_error when Embree fails.
/// Cost: about 10 measured candidates per normal visited. The rays of the surface off the
/// vertex's faces are built once per normal, and each candidate tessellates and traces only those
/// faces (the crossings add up to the whole surface's, so the choices are those of whole-surface
/// rays): on the spot cage, 962 candidates at levels 14 and 21 in 29-30 s on 2 Zen 3 vCPUs,
/// peak RSS 130-136 MB (the faces whose fans a candidate changes cost a third more time than the
/// vertex's own faces alone).
NormalSearchReport searchNormalsAgainstFaults(PatchCache& cache, const NormalSearchOptions& options = {});

/// The last step of construction for a cache built with FoldRepairMode::Search (every patch
/// built): searchNormalsAgainstFaults with the default options on `backend`'s CPU side (Serial
/// stays serial, otherwise oneTBB with `threads`), the cache's patches replaced with the result.
/// Nothing for the other modes (a report with closed false). The entry points that build a
/// whole cache (command line, C API, Python) call it after construction.
NormalSearchReport finishFoldRepair(PatchCache& cache, Backend backend = Backend::Tbb, int threads = 0);

}  // namespace sf
