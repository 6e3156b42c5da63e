// SPDX-License-Identifier: Apache-2.0
// The patch cache: a whole mesh's Gregory patches as struct-of-arrays, ready to evaluate.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/mesh/cage_limit.h>
#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/polygon_split.h>
#include <smoothforce/patch/patch_options.h>

namespace sf {

/// Options that determine the patches (hashed into the cache file).
struct PatchOptions {
  Precision precision = Precision::Double;
  CrossTangentMode crossTangent = CrossTangentMode::Corrected;
  NormalMode normals = NormalMode::Auto;
  bool keepOrientation =
      false;  ///< `--orient keep`: keep faces against their neighbours and inward-facing closed meshes
  /// `--cage catmull-clark`: the mesh is a Catmull-Clark control cage; its vertices move to their
  /// limit positions and take their limit normals before construction (cage_limit.h), and the
  /// cache holds the moved mesh. Needs normals Auto (loadMesh refuses another mode).
  CageMode cage = CageMode::None;
  /// Which marks make creases (`--creases`, `--crease-angle`; creases.h). A crease edge is one
  /// curve both faces share, with each face's own tangent plane along it.
  CreaseOptions creases;
  /// `--fold-repair` (polygon_split.h): On (the default) cuts flat polygons with a reflex or
  /// straight corner into convex pieces before construction; the cache then holds the pieces
  /// (faceSource maps them to the faces as read). Off builds the design page's construction.
  FoldRepairMode foldRepair = FoldRepairMode::On;
};

/// All patches of a mesh. Counts: #V vertices, #F faces, #C corners = slots (one slot per
/// face edge: slot faceOffsets[f] + k is edge k of face f, from V_k to V_{k+1}).
/// The base mesh is kept too, so that force methods and the device loop need only the cache.
struct PatchCache {
  PatchOptions options;
  uint64_t meshHash = 0;                ///< xxh64 of the source mesh file's bytes
  std::vector<double> positions;        ///< #V*3, metres (file units)
  std::vector<int32_t> faceOffsets{0};  ///< #F+1
  std::vector<int32_t> faceVertices;    ///< #C
  std::vector<double> cornerNormals;    ///< #C*3 unit normals used for construction
  std::vector<int32_t> slotTwin;        ///< #C: see topology.h
  std::vector<uint32_t> faceStatus;     ///< #F: GP_ST_* bits of construction and quality
  std::vector<float> faceBulge;         ///< #F: bulge / face diameter (design page)
  /// #F certificate margins (patch_certificate.h): > 0 certified fold-free (a lower bound on the
  /// cosine between patch and face normal), < 0 proven to turn over, 0 undecided or no patch.
  /// Empty until certifyPatches runs (and in caches written before certificates were stored).
  std::vector<float> faceCertificate;
  /// #F with fold repair Split: the face of the mesh as read that each face (piece) comes from;
  /// empty otherwise (every face is the one read).
  std::vector<int32_t> faceSource;
  /// #C*3 unit normals as the normals option computed them, where the fold repair's normal search
  /// (FoldRepairMode::Search, query/normal_search.h) turned some: cornerNormals then holds the
  /// turned normals, and corners whose two normals differ are the ones it changed. Empty otherwise.
  std::vector<double> computedNormals;
  /// #C*6 or empty: the edge-curve end tangents the fold repair gives at vertices whose fan of
  /// edge tangents is tangled (tangent_fans.h, TangentFans::tangents); construction uses them
  /// where nonzero. Derived from positions and normals (refreshEdgeTangents) by constructPatches,
  /// the OpenCL constructor and, for a skeleton, preparePatchCache; not stored in the cache file;
  /// empty for FoldRepairMode::Off.
  std::vector<double> edgeTangents;
  /// GP_E_NFIELDS * #C per-edge records, field-major: value of field i of slot s at
  /// [i * #C + s]. Exactly one of the two is filled, per options.precision.
  std::vector<double> edgeDataD;
  std::vector<float> edgeDataF;

  int numVertices() const { return static_cast<int>(positions.size() / 3); }
  int numFaces() const { return static_cast<int>(faceOffsets.size()) - 1; }
  int numSlots() const { return static_cast<int>(faceVertices.size()); }
  int faceSize(int f) const { return faceOffsets[f + 1] - faceOffsets[f]; }
  /// The face of the mesh as read that face f comes from (f itself without a split).
  int sourceFace(int f) const { return faceSource.empty() ? f : faceSource[f]; }
  /// Degrees between corner s's normal as computed and the one its patch was built with
  /// (computedNormals); 0 where the fold repair turned no normal.
  double normalTurnDeg(int s) const;
  /// Bytes held by the arrays.
  size_t bytes() const;
};

/// Copies the base mesh, its corner normals (#C, unit) and adjacency into a new cache and
/// sizes the patch arrays; constructPatches then fills them. allocatePatches false leaves the
/// patch arrays empty (a skeleton: patches built on demand, lazy_patches.h; faceStatus and
/// faceBulge then stay 0 until a face is built there); it throws InputError for options a lazy
/// surface cannot build (requireLazyOptions).
PatchCache preparePatchCache(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>& cornerNormals,
                             const PatchOptions& options, uint64_t meshHash, bool allocatePatches = true);

/// Throws InputError where patches built lazily, near the contact point, cannot honour
/// `options`: FoldRepairMode::Search, whose normal search needs the whole surface first.
void requireLazyOptions(const PatchOptions& options);

/// A float cache holds its patch records (control points in world coordinates) in float: it
/// must lie within this many bounding-box diagonals of the origin, where float rounds a
/// coordinate by at most 1.2e-5 of the diagonal. Farther, double precision is needed.
inline constexpr double kFloatReachDiagonals = 100;

/// Empty when a mesh whose referenced vertices span the box (lo, hi) (m) suits `precision`;
/// else why not (a float mesh of nonzero size farther from the origin than kFloatReachDiagonals
/// diagonals: its coordinate, diagonal and float rounding). preparePatchCache, loadMesh and the
/// cache reader refuse such a mesh with this message.
std::string floatReachProblem(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Precision precision);

/// Builds every patch (Eq. 6-14 with the design page's conventions) and its quality, on the
/// CPU: Backend::Serial or Backend::Tbb (threads <= 0: oneTBB's default). The OpenCL backend
/// fills the same arrays (opencl_backend.h). Never throws on degenerate faces: their status
/// says what happened.
void constructPatches(PatchCache& cache, Backend backend, int threads = 0);

/// Builds face f's patch alone (Eq. 6-14 and its quality, as constructPatches does) from the
/// base mesh, corner normals and options of `skeleton` (its patch arrays may be empty) into
/// recs (n * GP_E_NFIELDS, record-major, n <= GP_MAX_N). Returns the GP_ST_* status
/// (GP_ST_TOO_MANY_SIDES, recs untouched, when n is outside 3..GP_MAX_N); *bulge, when given,
/// receives the bulge / face diameter. Allocation-free; used for lazy construction.
uint32_t buildPatchRecords(const PatchCache& skeleton, int f, double* recs, float* bulge = nullptr) noexcept;
uint32_t buildPatchRecords(const PatchCache& skeleton, int f, float* recs, float* bulge = nullptr) noexcept;
/// Face f's edge records as buildPatchRecords builds them, in double, without the quality
/// sampling (status: the construction's bits only, no GP_ST_FOLD or bulge). Allocation-free.
uint32_t buildPatchEdges(const PatchCache& skeleton, int f, double* recs) noexcept;

/// For edge k of face f (V_k -> V_{k+1}): the corner indices (into faceVertices and
/// cornerNormals) of the face across the edge at V_k (atStart) and at V_{k+1} (atEnd); face f's
/// own corners there when the edge has no single neighbour (boundary, non-manifold).
void acrossCorners(const PatchCache& cache, int f, int k, int32_t& atStart, int32_t& atEnd);

/// True when corners a and b carry different normals (any component, exactly).
bool cornerNormalsDiffer(const PatchCache& cache, int32_t a, int32_t b);

/// True when edge k of face f is a crease: it has one neighbour face, and the two faces' corner
/// normals differ at one of its ends (creases.h: every way a crease is marked ends as split
/// corner normals). Such an edge is built from what both faces share (gp_build_patch_creased):
/// one curve, two tangent planes along it.
bool isCreaseEdge(const PatchCache& cache, int f, int k);

/// True when some edge of face f is a crease (isCreaseEdge).
bool faceHasCrease(const PatchCache& cache, int f);

/// #V flags: 1 where the corners of a vertex carry more than one normal (the vertex a crease
/// touches: its faces form two or more smoothing sectors there), else 0.
std::vector<uint8_t> creaseVertexFlags(const PatchCache& cache);

/// The box (lo, hi, m) of the base mesh's referenced vertices (topology.h referencedBox);
/// false, lo = hi = 0, without faces.
bool referencedBox(const PatchCache& cache, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

/// Bounding-box diagonal of the cache's base mesh (its referenced vertices), m (0 without faces).
double boundingDiagonal(const PatchCache& cache);

/// True when the cache holds constructed patches (its edge data are filled), false for a
/// skeleton (preparePatchSkeleton) whose patches are built on demand (lazy_patches.h).
inline bool hasPatchData(const PatchCache& c) {
  return c.options.precision == Precision::Double ? !c.edgeDataD.empty() : !c.edgeDataF.empty();
}

/// Copies face f's edge records from the cache into recs (n * GP_E_NFIELDS, record-major).
void gatherRecords(const PatchCache& cache, int f, double* recs);
void gatherRecords(const PatchCache& cache, int f, float* recs);

}  // namespace sf
