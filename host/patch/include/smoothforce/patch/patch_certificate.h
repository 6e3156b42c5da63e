// SPDX-License-Identifier: Apache-2.0
// A per-patch certificate: a proof, from interval bounds of the exact derivatives, that a
// Gregory patch is regular and never turns over against its polygon.
#pragma once

#include <cstdint>
#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// What the certificate of one patch found.
enum class CertificateVerdict : int {
  Certified = 0,  ///< dot(dG/dxi x dG/deta, d) > 0 proven on the whole domain for a fixed direction d
  Undecided = 1,  ///< neither proven nor disproven within the cell budget
  Folded = 2,     ///< the patch proven to meet an edge's midpoint or a corner upside down (its normal
                  ///< against the edge normal n_c or the vertex normal there, which its neighbours
                  ///< share: it folds against them), or J < 0 along n_face proven on a part of the
                  ///< domain and no proof along the other directions: it turns over against its polygon
  NotBuilt = 3,   ///< no patch (too many sides, non-finite input) or a zero-area polygon
  Regular = 4,    ///< no fixed direction proves it, but dG/dxi x dG/deta != 0 is proven on the whole
                  ///< domain (each cell along its own centre's normal) and the patch meets each edge
                  ///< along the edge normal: it does not fold, though it is no height field
};

/// Budget of the adaptive subdivision: the domain's bounding box is cut into a grid of
/// 2^startDepth x 2^startDepth cells (quads: 2^quadStartDepth), and a cell that is neither
/// proven nor disproven is split into quadrants, down to maxDepth levels (cells 2^-maxDepth of
/// the box wide); at most maxCells evaluations per patch. On the second-order models most of a
/// quad's domain is proven on cells 2^-5 of the box; the other polygons' outer bands (near their
/// domain's boundary, where the blending's denominators are small) need 2^-6 and finer, where a
/// coarser start only adds the cells that fail (docs/certificate.md, "Quads start coarser").
/// Triangles get their own, deeper budget: their blending's gradients are steeper (the edge
/// parameters' denominators vanish at their domain's corners), and the bounds of a nearly flat
/// triangle of a sphere (odedstein sphere.obj) prove J > 0 only on cells of 2^-10 to 2^-11 of the
/// box; three triangles of the spot cage's Catmull-Clark limit need cells of 2^-13 to 2^-14 near a
/// corner (384,000-406,000 cells), hence depth 14 and 500,000 cells.
/// maxDepth 11: most patches the Newell normal leaves undecided at depth 9 are decided two
/// levels deeper at little cost, since only the cells near J = 0 go deeper (docs/certificate.md,
/// "Budget and direction").
struct CertificateOptions {
  int startDepth = 6;
  int quadStartDepth = 5;
  int maxDepth = 11;
  int maxCells = 400000;
  int triangleMaxDepth = 14;
  int triangleMaxCells = 500000;
  /// Where the Newell normal does not certify a patch, try again along the mean of its unit
  /// corner normals (a patch may be a regular height field over another plane than its polygon's).
  bool cornerNormalDirection = true;
  /// Where neither certifies it, try once more along the centre of the patch's normal cone: the
  /// direction with the largest smallest cosine to its unit normals sampled on a
  /// (coneSamples + 1)^2 grid of the domain's box (minimaxDirection), unless those samples
  /// already spread past a half-space.
  bool normalConeDirection = true;
  int coneSamples = 24;  ///< clamped to 2..256
  /// Where no fixed direction certifies it, prove the patch regular: every cell bounded along
  /// the unit normal at its own centre (CertificateVerdict::Regular).
  bool regularity = true;
};

/// The certificate of one patch.
struct PatchCertificate {
  CertificateVerdict verdict = CertificateVerdict::NotBuilt;
  /// Certified: a lower bound > 0 on cos(angle between the patch normal and `direction`) over
  /// the whole domain. Regular: a lower bound > 0 on the cosine between the patch normal and
  /// the normal at the centre of each cell, over every cell. Folded: an upper bound < 0 of the
  /// cosine to the normal it was proven against (n_c, N_k or n_face) on a proven part. Else 0.
  double margin = 0;
  /// Unit direction the verdict is about: the polygon's Newell normal n_face, or, for a patch
  /// certified only along another direction, the mean of its unit corner normals or the centre
  /// of its sampled normal cone. Zero when not built, and for a regular patch (no one direction).
  double direction[3] = {0, 0, 0};
  int cells = 0;  ///< interval evaluations spent (every direction tried)
};

/// Certifies the patch with edge records recs (n * GP_E_NFIELDS, record-major, 3 <= n <= 64)
/// built with cross-tangent mode `mode`. First, on a box of width 2e-9 just inside each edge's
/// midpoint and each corner, the patch normal against the edge normal n_c (t = 1/2) and the vertex
/// normal N_k, which its neighbours share and the G1 construction makes it parallel to there: a
/// patch proven upside down at one of them is folded, and one not proven right side up at every
/// edge's midpoint is certified by no direction. Then it bounds J = dot(dG/dxi x dG/deta, n_face) over boxes of
/// the domain by evaluating the patch math (Eq. 2-14, kernels/gp_eval.h) in outward-rounded
/// interval arithmetic, and splits a box in four until J > 0 is proven on it (certified), J < 0
/// is proven on a box that meets the domain (folded), or the budget runs out (undecided).
/// n_face is the polygon's unit Newell normal; where it does not certify the patch and
/// options.cornerNormalDirection is set, the same runs along the mean of the unit corner normals,
/// then (normalConeDirection) along the centre of its sampled normal cone, and a patch proven
/// along either is certified (PatchCertificate::direction says along which). Where none does
/// (options.regularity; not for CrossTangentMode::Paper), every cell is bounded along the unit
/// normal at its own centre, which proves dG/dxi x dG/deta != 0 there (Regular).
/// Conservative: a certified patch has no point where its normal is perpendicular to or against
/// that direction (so it is regular, and a height field over the plane normal to it wherever its
/// boundary projects to a simple curve there), a regular one no point where its normal vanishes;
/// both lie on n_c's side at every edge's midpoint, so with the construction's G1 (the patch
/// normal parallel to n_c along an edge) and a normal that vanishes nowhere, along the whole edge:
/// the patch meets its neighbours without turning back. faceStatus: the face's construction status
/// (GP_ST_AFFINE: the patch is its triangle's affine map plus its curved edges' deviations,
/// markAffineTriangles; certified from affineTriangleMargin's bound on its Jacobian, with that
/// margin and the plane's normal as direction, where the bound proves it). Never throws;
/// thread-safe.
PatchCertificate certifyPatch(int n, const double* recs, CrossTangentMode mode, const CertificateOptions& options = {},
                              uint32_t faceStatus = 0);
PatchCertificate certifyPatch(int n, const float* recs, CrossTangentMode mode, const CertificateOptions& options = {},
                              uint32_t faceStatus = 0);

/// Counts of a cache's certificates, and the faces that are not certified (ids, ascending).
struct CertificateSummary {
  int certified = 0, undecided = 0, folded = 0, notBuilt = 0;
  /// Of the certified, those proven regular cell by cell (CertificateVerdict::Regular), and
  /// their ids; -1 and empty where unknown: the cache keeps one margin per face, not its kind.
  int regular = -1;
  std::vector<int> regularFaces;
  double minMargin = 0;  ///< smallest margin of the certified patches (0 when none)
  std::vector<int> uncertifiedFaces, foldedFaces;
  bool present = false;  ///< false for caches written before certificates were stored
};

/// Certifies every built patch of the cache (oneTBB; threads <= 0: oneTBB's default) into
/// cache.faceCertificate (#F, PatchCertificate::margin as float: > 0 certified, height field or
/// regular; < 0 folded; 0 undecided or not built). Returns their summary with the regular ones
/// counted. Throws std::invalid_argument for a cache without patch data.
CertificateSummary certifyPatches(PatchCache& cache, int threads = 0, const CertificateOptions& options = {});

/// The summary of the certificates a cache holds (CertificateSummary::regular unknown: -1).
CertificateSummary summarizeCertificates(const PatchCache& cache);

}  // namespace sf
