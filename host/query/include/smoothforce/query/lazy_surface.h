// SPDX-License-Identifier: Apache-2.0
// The patch surface of a skeleton cache (patches built lazily, lazy_patches.h) for the global
// nearest-point query: which faces can hold the patch point nearest a HIP, without building
// every patch: only patches whose bound is within the current best distance are built.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/patch/patch_bounds.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/query/polygon_facets.h>

namespace sf {

class FacePointEvaluator;

/// A face and the distance (m) from a query point to its box.
struct FaceDistance {
  int face = -1;
  double distance = 0;
};

/// Three kinds of boxes:
/// - per face, the a-priori box (patchBoxes: from the face's vertices and normals, a proof that
///   the patch lies inside; about 5-10 times the patch's own box diagonal), widened by the
///   polygon facets' tolerance so that it holds the face's facets too, and the face box: the
///   a-priori box cut down to the axis-aligned box of the face's swept boxes (below; the a-priori
///   box itself for a face without them); the face boxes in an Embree BVH, built in the
///   constructor;
/// - per corner sector (the domain triangle of the centre and domain edge k), computed in the
///   constructor: the sector box, an oriented box of the patch at 3 x 3 samples, and the swept
///   box, an oriented box of those samples and the polygon's fan triangle (sectorDistance,
///   sweptDistance);
/// - per face, its cells, computed the first time the face is asked for (cells()) and kept: each
///   sector split 2 x 2 along the ray from the centre and along the edge, each cell with an
///   oriented box (axes along the cell and its normal) of the patch at its 5 x 5 of a 9 x 9
///   sample grid per sector.
/// The sampled boxes are widened by the sector's largest sum of second differences of the
/// samples along both grid directions (times 0.5 for cells, 1 for sectors: 4 and 8 times the
/// deviation of a quadratic from its bilinear interpolant), 1e-6 of the sector's size, 1e-7 of
/// the distance from the local origin (localOrigin: (0,0,0) unless the mesh is far from it, about
/// which the boxes are stored) and 64 epsilons of that origin's distance from (0,0,0). An
/// estimate, not a proof: tests/query/test_lazy_surface.cpp
/// checks that every patch point lies in one of its face's cell, sector and swept boxes, 10 x 11
/// samples per edge of every patch of every mesh in ../shared/meshes (600 random patches of the
/// larger ones), and of the spot cage and the quad-sphere moved by 1e4 to 1e13 m.
/// Outside every a-priori box, the winding number of the patch surface around a point equals
/// that of the base polygons: the straight line from a polygon point to the patch point of the
/// same domain point stays in the face's box, and neighbouring faces agree on their shared edge,
/// so the polygons deform into the patches without crossing the point. The same holds outside
/// the swept boxes of the faces whose a-priori box holds the point (sweptDistance: the sector
/// mapped linearly onto its fan triangle), and, once every face's cells are computed
/// (computeAllCells), outside the swept boxes of its cells (sweptCellDistance), on the samples'
/// estimate. For one renderer: not
/// thread-safe (cells() caches); the cache and facets must outlive it. Memory: 180 floats per
/// corner, allocated in the constructor.
class LazyPatchSurface {
 public:
  /// The most faces facesWithin() returns.
  static constexpr size_t kMaxFaces = 256;
  /// Builds the face boxes' BVH and every face's sector and swept boxes (9 patch evaluations
  /// per corner sector, scalar: 6.5 ms for the spot cage's 180 faces, 0.36 s for the 23,062
  /// triangles of odedstein/spot.obj on this project's 2-core machine, about twice the time of
  /// loading the mesh and building every patch with its quality there). Throws std::runtime_error with Embree's
  /// message when Embree fails.
  LazyPatchSurface(const PatchCache& cache, const PolygonFacets& facets);
  ~LazyPatchSurface();
  LazyPatchSurface(const LazyPatchSurface&) = delete;
  LazyPatchSurface& operator=(const LazyPatchSurface&) = delete;

  /// Whether q (m) lies in some face's box (faceBox).
  bool inAnyBox(const Eigen::Vector3d& q) const noexcept;
  /// Whether q (m) lies farther from the box of every a-priori box than its diagonal
  /// (farBeyondBox): no contact there.
  bool farBeyond(const Eigen::Vector3d& q) const noexcept { return farBeyondBox(q, boxLo_, boxHi_); }
  /// The faces whose box (faceBox) is within `radius` (m) of q, nearest box first, at most `cap`
  /// (<= kMaxFaces; the first kept) into out; returns how many. *found, when given, receives how
  /// many qualified (more than cap: the rest were dropped). Ties in distance come as the BVH
  /// meets them where every face fits; where some were dropped, or `after` is given, the order is
  /// (distance, face) (the query runs again in that order), and after, when given, keeps only the
  /// faces after it (the next batch after a full one: its last entry). Does not allocate or throw.
  size_t facesWithin(const Eigen::Vector3d& q, double radius, FaceDistance* out, size_t cap, size_t* found = nullptr,
                     const FaceDistance* after = nullptr) const noexcept;
  /// Whether q lies in some swept box (sweptDistance) of a face whose a-priori box holds q (false
  /// when no a-priori box holds q; the face boxes decide which faces to look at: a face box holds
  /// the part of its a-priori box that its swept boxes can), and, after computeAllCells, in a swept
  /// box of one of that sector's cells (sweptCellDistance). Outside every swept box, the winding
  /// number of the patch surface around q is that of the base polygons, as outside the a-priori
  /// boxes (on the samples' estimate). True when more than kMaxFaces face boxes hold q, or one of
  /// them belongs to a face without a patch (in doubt). Does not allocate or throw.
  bool inAnySweptBox(const Eigen::Vector3d& q) const noexcept;

  /// Whether face f has its sector and swept boxes (sectorDistance, sweptDistance: computed for
  /// every face in the constructor, 3 x 3 samples per corner sector); false for a face without a
  /// patch.
  bool sectors(int f) const noexcept { return sectorState_[f] > 0; }
  /// Distance (m) from q to the box of corner sector k of face f (sectors(f) true): an
  /// oriented box of the sector's 3 x 3 samples widened by their second differences (twice the
  /// cells' factor); a lower bound of the distance to the sector's patch, cheaper and looser
  /// than its cells'.
  double sectorDistance(int f, int k, const Eigen::Vector3d& q) const noexcept;

  /// Cells per corner sector.
  static constexpr int kCellsPerSector = 4;
  /// Face f's cells: computes them on first use; returns how many (4 n; 0 for a face without a
  /// patch). With an evaluator (a refiner's, lent: PatchRefiner::pointEvaluator) the samples go
  /// 16 at a time on its SIMD lanes, else one at a time; the same boxes, bit for bit. Does not
  /// allocate or throw.
  int cells(int f, FacePointEvaluator* evaluator = nullptr) noexcept;
  /// Computes every face's cells now, in parallel (oneTBB): 81 patch evaluations per corner
  /// sector, 288 bytes per corner held. For a prebuilt cache in a servo loop, so that no step pays
  /// for them (the first contact on the spot cage took up to 0.46 ms computing them). Not
  /// thread-safe with other calls.
  void computeAllCells() noexcept;
  /// Distance (m) from q to the box of cell i of face f (0 inside; cells(f) called before): a
  /// lower bound of the distance from q to the part of the patch over the cell.
  double cellDistance(int f, int i, const Eigen::Vector3d& q) const noexcept;
  /// Distance (m) from q to the swept box of corner sector k of face f (sectors(f) true):
  /// an oriented box, in the frame of the polygon's fan triangle (centroid, V_k, V_k+1),
  /// of the sector's 3 x 3 samples and that triangle, widened by the sector's margin and the facets'
  /// tolerance. It holds the straight segments from the fan triangle's points to the patch
  /// points of the same domain point (the sector mapped linearly onto the triangle), so that
  /// the base polygons deform into the patches inside the swept boxes.
  double sweptDistance(int f, int k, const Eigen::Vector3d& q) const noexcept;
  /// Distance (m) from q to the swept box of cell i of face f (cells(f) called before): as
  /// sweptDistance, for the cell's 5 x 5 samples and its part of the fan triangle (the sector
  /// mapped linearly onto the triangle), widened by the cell's margin and the facets' tolerance.
  /// inAnySweptBox asks them inside a sector's swept box once computeAllCells ran.
  double sweptCellDistance(int f, int i, const Eigen::Vector3d& q) const noexcept;
  /// A domain point of cell i of face f to start refining towards q from: q's position along
  /// the cell box's two tangent axes, as fractions of their ranges (clamped to 0.05..0.95), taken
  /// as fractions of the cell's ray and edge ranges (cells(f) called before).
  Eigen::Vector2d cellStart(int f, int i, const Eigen::Vector3d& q) const noexcept;

  const PatchBox& aprioriBox(int f) const noexcept { return apriori_[f]; }
  /// The box of face f that facesWithin and inAnyBox use: its a-priori box cut down to the box of
  /// its swept boxes (a lower bound of the distance to the patch and its polygon on the samples'
  /// estimate, as the sector and cell boxes).
  const PatchBox& faceBox(int f) const noexcept { return faceBoxes_[f]; }
  /// Bytes the surface holds: the boxes computed so far (cells and sectors are computed as
  /// contact reaches their faces) and the BVH of the face boxes (Embree's own count).
  size_t bytes() const noexcept;
  /// Every edge has a twin: the patch surface is closed where every face has a patch.
  bool closed() const noexcept { return closed_; }
  /// Faces whose cells have been computed.
  int sampledFaces() const noexcept { return sampledCount_; }

  struct Impl;  ///< Embree device and scene (opaque)

 private:
  /// Fills face f's sector and swept boxes and sectorState_[f].
  bool computeSectors(int f) noexcept;
  /// Fills face f's cell boxes and cellCount_[f] (once); returns the count.
  int computeCells(int f) noexcept;

  const PatchCache& cache_;
  const PolygonFacets& facets_;
  bool closed_ = false;
  Eigen::Vector3d boxLo_{0, 0, 0}, boxHi_{0, 0, 0};  ///< m: farBeyond's box
  std::vector<PatchBox> apriori_;
  std::vector<PatchBox> faceBoxes_;     ///< #F: the BVH's boxes (faceBox)
  std::vector<float> cellBoxes_;        ///< #C x 4 oriented boxes of 18 floats (lazy_surface.cpp makeObb), by face slot
  std::vector<float> sectorBoxes_;      ///< #C oriented boxes, one per corner sector (sectorDistance), by face slot
  std::vector<int8_t> sectorState_;     ///< #F: 0 no patch, 1 sector and swept boxes computed
  std::vector<float> sweptBoxes_;       ///< #C oriented boxes, one per corner sector (sweptDistance), by face slot
  std::vector<float> sweptCellBoxes_;   ///< #C x 4 oriented boxes (sweptCellDistance), by face slot
  std::vector<double> facetTolerance_;  ///< #F: widening for the polygon facets, m
  std::vector<int16_t> cellCount_;      ///< #F: -1 not computed yet
  int sampledCount_ = 0;
  bool allCells_ = false;  ///< computeAllCells ran: inAnySweptBox asks the cells' swept boxes
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf
