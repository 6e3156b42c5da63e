// SPDX-License-Identifier: Apache-2.0
// Force rendering methods and the stateful contact tracker interface (paper Section 4).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/query/refine_options.h>

namespace sf {

/// patch: SCP tracked on the Gregory patches (Wu et al., Algorithm 1).
/// direct: god-object on the base polygons (Zilles & Salisbury 1995).
/// shading: god-object position and depth, force direction from the normal interpolated
///          from vertex normals at the contact point (Morgenbesser & Srinivasan 1996).
enum class ForceMethod { Patch, Direct, Shading };
/// Parser throws InputError naming the value. (RefineMethod, InitialGuess: refine_options.h.)
ForceMethod parseForceMethod(const std::string& s);
const char* toString(ForceMethod m);

/// The index of the patch surface behind the patch method's global query (InitialGuess::Surface)
/// on a prebuilt cache. Both find the same nearest patch point (every candidate whose lower bound
/// is below the best distance found is refined); they differ in what they hold and how fast a
/// step out of contact is (docs/results.md "The surface index: memory against speed").
/// - bounds: boxes per face, per corner sector and per cell of the patches (LazyPatchSurface:
///   about 3 kB per face, every cell computed when the renderer is made); contact where the HIP lies
///   below the nearest patch point, the base polygons' inside test outside every swept box (of
///   the sectors and of their cells).
///   Memory grows with the number of patches, not with a tessellation.
/// - tessellation: a fine tessellation of every patch with error bounds in Embree BVHs
///   (PatchSurface: 0.1-0.5 MB per face on coarse cages); contact where the HIP is inside by the
///   tessellation's winding number. Contact starts about 3 times faster.
/// - auto (default): bounds for the servo loop (the runtime's scenes: `loop`, C sf_haptic, Python
///   Haptic), where memory counts and a step has a millisecond; tessellation for batches
///   (makeForceRenderer, `trace`, sweeps), where contact starts dominate.
/// A skeleton cache (patches built lazily) always uses bounds.
enum class SurfaceIndex { Auto, Bounds, Tessellation };
/// Parser throws InputError naming the value ("auto"|"bounds"|"tessellation").
SurfaceIndex parseSurfaceIndex(const std::string& s);
const char* toString(SurfaceIndex i);

/// The largest stiffness an option may give, N/m: 1e12, far beyond any haptic device (a few
/// thousand N/m) or rigid-contact simulation.
inline constexpr double kMaxStiffness = 1e12;

/// Force rendering options: the refinement options (refine, angleTolerance, positionTolerance, finalStep,
/// maxIterations, initialGuess, tessellationLevel; refine_options.h) plus these. Units: metres,
/// newtons, N/m, radians.
struct ForceOptions : RefineOptions {
  /// k in F = k (SCP - HIP), N/m; in (0, kMaxStiffness]: with positions within 1e15 m
  /// (coordinate_range.h) every force is then finite (1e308 N/m overflowed to inf forces)
  double stiffness = 500.0;
  /// Lazy construction (the cache is a skeleton, preparePatchSkeleton): faces whose patches
  /// are held at once (LRU); <= 0: every face that is touched stays built.
  int patchCapacity = 256;
  /// InitialGuess::Surface on a prebuilt cache: the index of the patch surface (SurfaceIndex).
  SurfaceIndex surfaceIndex = SurfaceIndex::Auto;
};

/// One servo step's result. For direct/shading, scp is the god-object (proxy) and face,
/// xi, eta locate it on the polygon holding it (domain coordinates, design page).
struct ForceSample {
  Eigen::Vector3d force{0, 0, 0};   ///< N
  Eigen::Vector3d scp{0, 0, 0};     ///< m
  Eigen::Vector3d normal{0, 0, 0};  ///< unit surface normal at the SCP
  bool contact = false;
  int face = -1;
  double xi = 0, eta = 0;
  int iterations = 0, transitions = 0;
  uint32_t status = 0;  ///< SF_ST_* (= GP_ST_*) and SF_TRACK_* bits (base/status.h)
};

/// A stateful contact tracker for one object (Algorithm 1): out of contact a global query
/// decides penetration; in contact only local tracking from the previous SCP, so thin parts
/// never pop through. step() is real-time safe: it does not allocate, lock, throw or log.
class ForceRenderer {
 public:
  virtual ~ForceRenderer() = default;
  /// One servo step at haptic interface point `hip` (m).
  virtual ForceSample step(const Eigen::Vector3d& hip) noexcept = 0;
  /// Forget the contact state (next step starts out of contact).
  virtual void reset() noexcept = 0;
  /// reset(), with a hint for the next global query: patch point (face, xi, eta) of the cache
  /// (domain coordinates, Eq. 3) lies near the next HIP's nearest surface point (a sweep's
  /// surface sample, whose HIP is pressed in along its normal). The patch method refines from
  /// there first, which bounds the candidates it must refine; the nearest point found is the
  /// same up to the refinement's tolerance. Other methods ignore the hint. An out-of-range face
  /// is ignored.
  virtual void resetNear(int face, double xi, double eta) noexcept {
    (void)face, (void)xi, (void)eta;
    reset();
  }
  /// Patch constructions so far with lazy construction (a face evicted and needed again counts
  /// again); the cache's face count when prebuilt; 0 for methods that need no patch.
  virtual int patchesBuilt() const noexcept = 0;
  /// What patchesBuilt() counts: the lazy patch store (which renderers made by one
  /// SharedGeometry share: shared_geometry.h) or the prebuilt cache; null when it counts
  /// nothing. Counts over several renderers take each store once.
  virtual const void* patchStore() const noexcept { return nullptr; }
};

/// A tracker over a prebuilt cache (shared, read-only), or over a skeleton (hasPatchData false)
/// whose patches the patch method then builds lazily near the contact point (lazy_patches.h,
/// at most options.patchCapacity held). Throws InputError for bad options.
std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache, ForceMethod method,
                                                 const ForceOptions& options);

}  // namespace sf
