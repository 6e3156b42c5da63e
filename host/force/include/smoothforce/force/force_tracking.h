// SPDX-License-Identifier: Apache-2.0
// Contact tracking on the Gregory patches (paper Algorithm 1). The SF_TRACK_* status bits
// that every force method adds to ForceSample::status are in base/status.h (included here).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>

#include <smoothforce/base/status.h>  // SF_TRACK_* bits
#include <smoothforce/force/force_method.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_surface.h>

namespace sf {

class PolygonScene;

/// Checks options: every value in its range and final_step model only with refine newton
/// (checkForceOptions, force_option_text.h: the message every front end gives, by key; it
/// covers validateRefineOptions' checks); throws InputError naming the bad value.
void validateForceOptions(const ForceOptions& options);

/// The patch method (Algorithm 1) over a shared scene of the same cache.
///
/// Out of contact (InitialGuess::Surface, the default, with prebuilt patches and the tessellation
/// index, SurfaceIndex::Tessellation or Auto) each step runs the
/// global nearest-point query on the patch surface: PatchSurface gives every face whose patch
/// can hold the nearest point (its tessellation's distance minus its error bound is below the
/// best upper bound) with the nearest tessellation point as the start; the refinement runs from
/// each, in order, until the next candidate's lower bound exceeds the best distance found; the
/// nearest refined point is the SCP candidate. Contact starts when the HIP is inside the patch
/// surface (insidePatchSurface). On a skeleton cache (patches built lazily, LazyPatches), and on a
/// prebuilt cache with SurfaceIndex::Bounds (its cells computed here), the
/// same query runs over boxes instead of a tessellation of every patch (LazyPatchSurface: the
/// faces whose box (the a-priori box from vertices and normals, cut down to the face's swept
/// boxes) is within the polygon start's refined distance, then the cells of those patches, in
/// order of lower bound; outside every swept box of a closed mesh the base polygons' inside test
/// decides, with no patch work): only the patches that can hold the nearest point are built. With
/// InitialGuess::Polygon (the paper's Section 4.1) the global query is the nearest base-polygon
/// point mapped into its patch's domain by mean value coordinates, refined once, and contact
/// starts when (HIP - SCP) . n < 0.
/// In contact only the local refinement from the previous SCP runs (Algorithm 1), and contact
/// ends when (HIP - SCP) . n >= 0. F = stiffness (SCP - HIP).
/// surface: shared by several renderers; when null and needed it is built here (from the cache).
/// Given, it is used whatever options.surfaceIndex says.
std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options,
                                                      std::shared_ptr<const PatchSurface> surface = nullptr);

/// A HIP that moves farther than this fraction of the mesh's bounding-box diagonal in one step
/// while in contact has jumped (a device glitch, a re-grab, a scene reset, an object's pose
/// jump). Local tracking from the held SCP (Algorithm 1 keeps a contact while the HIP is below
/// the SCP's tangent plane) then held contact for HIPs far outside the surface, so such a step
/// also asks the global query whether the HIP is inside: the contact holds (at the tracked SCP,
/// so that a jump into a thin part does not pop through) only where it is, and ends elsewhere.
/// 0.03 diagonals per step is 3 m/s at a 1 kHz servo loop on a 10 cm object, beyond a hand's
/// speed; a step that trips it needlessly only pays for the query.
inline constexpr double kJumpDiagonals = 0.03;

/// Contact state of the patch method between steps (Algorithm 1).
struct PatchContactState {
  bool inContact = false;
  int face = -1;            ///< face of the last SCP in contact
  Eigen::Vector2d X{0, 0};  ///< its domain point
  int edge = -1;            ///< its held boundary edge (RefineResult::edge)
  Eigen::Vector3d hip{0, 0, 0};  ///< m, the HIP of the last step in contact
  /// the HIP of this step jumped (markJump): the contact holds only where the HIP is inside
  bool verify = false;
};

/// Marks a contact whose HIP jumped (moved farther than kJumpDiagonals x the diagonal of
/// `scene`'s box since the last step in contact): state.verify, so that finishPatchStep (or the
/// renderer) keeps the tracked contact only where the global query finds the HIP inside.
/// Returns state.verify. Never throws.
bool markJump(const PolygonScene& scene, const Eigen::Vector3d& hip, PatchContactState& state) noexcept;

/// Where one patch step's refinement starts: in contact the previous SCP; out of contact the
/// global query's first candidate (surface), or the nearest polygon point mapped into the face's
/// domain by mean value coordinates (polygon, Section 4.1).
struct PatchStepStart {
  bool global = false;  ///< the global query ran
  int face = -1, facet = -1, edge = -1;
  Eigen::Vector2d X{0, 0};
  Eigen::Vector3d polygonPoint{0, 0, 0};  ///< m, nearest polygon point (polygon start only)
  SurfaceCandidate candidate;             ///< surface start: the first candidate, (face, X); face -1 otherwise
  int windingVerdict = -2;                ///< surface start: insideByWinding (-2: not computed)
  /// m, surface start: an upper bound of the HIP's distance to the patch surface found on the way
  /// (insideByWinding's error band, or the hint's point; infinite: none), for
  /// PatchSurface::candidates, and the face of the patch point it is measured to (-1: unknown)
  double reach = std::numeric_limits<double>::infinity();
  int reachFace = -1;
  bool seeded = false;  ///< surface start: (face, X) is the hint's seed, not the first candidate
};

/// What a caller knows before a patch-method step out of contact (beginPatchStep): a patch
/// point near the HIP's nearest surface point, typically the point the last step ended at
/// (finishPatchStep's `next`) or a sweep's surface sample the HIP was pressed in from. The
/// global query refines from (face, X) first (a seed), and that refinement stands in for a
/// candidate's where refineCandidates allows it: the candidates refined, and so the nearest
/// point, are the same up to the refinement's tolerance. point, when finite: that patch point's
/// position (m), whose distance from the HIP bounds the candidate search before any refinement.
struct PatchStepHint {
  int face = -1;            ///< -1: no hint
  Eigen::Vector2d X{0, 0};  ///< domain point of `face`
  Eigen::Vector3d point{Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())};
  /// false: the point only bounds the search, no seed
  bool seed = true;
};

/// A global surface step's candidates, kept from beginPatchStep for finishPatchStep so that one
/// PatchSurface::candidates search serves both (the OpenCL sweep): c[0, capacity) is the
/// caller's storage; count = the candidates found, at most capacity. The list is the whole
/// search's when count < capacity; a full one is searched again in finishPatchStep.
struct CandidateList {
  SurfaceCandidate* c = nullptr;
  int capacity = 0;
  int count = 0;
};

/// First half of a patch-method step at `hip` (m), for callers that run the refinement elsewhere
/// (the OpenCL sweep): returns false when the step ends without a refinement (non-finite HIP,
/// no polygon or no candidate, or out of contact on the surface with insideByWinding 0: outside
/// the closed surface beyond every error band, where no patch work is needed): s is then the
/// step's sample and state is updated. Otherwise
/// fills start, and s with the status bits so far. surface: the global query on the patches
/// (null: the polygon start). lambda: scratch for the largest face's size. firstCandidate: a
/// surface step looks up its first candidate (start.candidate); false leaves the whole global
/// query to the caller (nearestOnPatches: one candidate search per step, not two). hint: what
/// the caller knows from its last step (PatchStepHint); with firstCandidate and a hint face in
/// range, a surface step starts at the hint (start.seeded) instead of the first candidate and
/// searches no candidates: finishPatchStep does, bounded by the seed's refinement (the hint's
/// point bounds start.reach). list (with firstCandidate, capacity >= 2): an unseeded step's
/// candidates are collected there (its first is the start) for finishPatchStep; a seeded step
/// leaves it empty. In contact it marks a HIP that jumped (markJump).
/// Never throws or allocates; the scene and surface must belong to the cache.
bool beginPatchStep(const PolygonScene& scene, const PatchSurface* surface, const PatchCache& cache,
                    const Eigen::Vector3d& hip, PatchContactState& state, double* lambda, PatchStepStart& start,
                    ForceSample& s, bool firstCandidate = true, const PatchStepHint& hint = {},
                    CandidateList* list = nullptr) noexcept;

/// Second half: r = the refinement from `start` (PatchRefiner::refine or OpenCLRefiner). A
/// global surface step runs the rest of the global query with `refiner` (nearestOnPatches, r as
/// its first refinement, from the first candidate or the hint's seed: the candidates are
/// deterministic), then decides contact by insidePatchSurface; a polygon step uses the polygon
/// itself where the patch is degenerate and decides by (HIP - SCP) . n < 0; a tracking step
/// continues contact while (HIP - SCP) . n < 0, and on a surface, where that fails, ends it only
/// where the global query would not start one (insideByWinding, then nearestOnPatches from r and
/// insidePatchSurface: inside a surface fault the refinement can reach a nearer sheet the HIP is
/// above; the contact then holds at the query's SCP, with SF_TRACK_GLOBAL set and no
/// SF_TRACK_LEAVE); where the HIP jumped (state.verify) and stays below, the contact holds only
/// where the global query finds the HIP inside (insideByWinding, else nearestOnPatches from r and
/// insidePatchSurface; SF_TRACK_GLOBAL), and ends elsewhere (without a surface the renderer
/// decides). F = stiffness (SCP - HIP) (N/m, m). Updates
/// state and s. Never throws or allocates.
/// next, when given: set to the patch point the step ended at (a global step: its query's
/// nearest point; else the refinement's: face, X and position), where that point is usable
/// (finite, not degenerate), the next step's hint; untouched otherwise. list: beginPatchStep's,
/// when it collected the candidates (a whole list is refined without searching again; the same
/// result).
void finishPatchStep(const PolygonScene& scene, const PatchSurface* surface, PatchRefiner& refiner,
                     const Eigen::Vector3d& hip, const PatchStepStart& start, RefineResult r,
                     const ForceOptions& options, PatchContactState& state, ForceSample& s,
                     PatchStepHint* next = nullptr, const CandidateList* list = nullptr) noexcept;

/// makeForceRenderer with a scene (and, for the patch method, a patch surface) built once and
/// shared by several renderers (they must belong to `cache`; surface may be null).
std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                 std::shared_ptr<const PolygonScene> scene, ForceMethod method,
                                                 const ForceOptions& options,
                                                 std::shared_ptr<const PatchSurface> surface = nullptr);

}  // namespace sf
