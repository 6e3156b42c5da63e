// Contact tracking on the Gregory patches (paper Algorithm 1). The SF_TRACK_* status bits
// that every force method adds to ForceSample::status are in base/status.h (included here).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include <smoothforce/base/status.h>  // SF_TRACK_* bits
#include <smoothforce/force/force_method.h>
#include <smoothforce/query/patch_refine.h>

namespace sf {

class PolygonScene;
class PatchSeeds;

/// Checks options (stiffness > 0 and finite, then validateRefineOptions);
/// throws InputError naming the bad value.
void validateForceOptions(const ForceOptions& options);

/// The patch method (Algorithm 1) over a shared scene of the same cache. Out of contact each
/// step runs the global nearest-polygon query, maps the point to its domain by mean value
/// coordinates and refines it on the patches; contact starts when (HIP - SCP) . n < 0 (n the
/// outward patch normal). With InitialGuess::Tessellation the global query is instead the
/// nearest vertex of a level-L tessellation of the patches (PatchSeeds, built in the
/// constructor), refined from that vertex's (face, xi, eta). In contact only the local refinement from the previous SCP
/// runs, and contact ends when (HIP - SCP) . n >= 0. F = stiffness (SCP - HIP).
std::unique_ptr<ForceRenderer> makePatchForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                      std::shared_ptr<const PolygonScene> scene,
                                                      const ForceOptions& options);

/// Contact state of the patch method between steps (Algorithm 1).
struct PatchContactState {
  bool inContact = false;
  int face = -1;             ///< face of the last SCP in contact
  Eigen::Vector2d X{0, 0};   ///< its domain point
  int edge = -1;             ///< its held boundary edge (RefineResult::edge)
};

/// Where one patch step's refinement starts: out of contact the global query (Embree nearest
/// polygon point, mapped into the face's domain by mean value coordinates, Section 4.1); in
/// contact the previous SCP.
struct PatchStepStart {
  bool global = false;  ///< the global query ran
  int face = -1, facet = -1, edge = -1;
  Eigen::Vector2d X{0, 0};
  Eigen::Vector3d polygonPoint{0, 0, 0};  ///< m, nearest polygon point (global only)
};

/// First half of a patch-method step at `hip` (m). Returns false when the step ends without a
/// refinement (non-finite HIP, mesh without polygons): s is then the step's sample and state is
/// updated. Otherwise fills start, and s with the status bits so far. lambda: scratch for the
/// largest face's size. seeds: when given (InitialGuess::Tessellation), the global query is the
/// nearest tessellation vertex instead of the nearest polygon point (start.facet stays -1).
/// Never throws or allocates; the scene must belong to the cache.
bool beginPatchStep(const PolygonScene& scene, const PatchCache& cache, const Eigen::Vector3d& hip,
                    PatchContactState& state, double* lambda, PatchStepStart& start, ForceSample& s,
                    const PatchSeeds* seeds = nullptr) noexcept;

/// Second half: r = the refinement from `start` (PatchRefiner::refine or OpenCLRefiner). A
/// degenerate global start falls back to the polygon point; contact when (HIP - SCP) . n < 0;
/// F = stiffness (SCP - HIP) (N/m, m). Updates state and s. Never throws or allocates.
void finishPatchStep(const PolygonScene& scene, const Eigen::Vector3d& hip, const PatchStepStart& start,
                     RefineResult r, double stiffness, PatchContactState& state, ForceSample& s) noexcept;

/// makeForceRenderer with a scene built once and shared by several renderers (the scene must
/// belong to `cache`).
std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                 std::shared_ptr<const PolygonScene> scene, ForceMethod method,
                                                 const ForceOptions& options);

}  // namespace sf
