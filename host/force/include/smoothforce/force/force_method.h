// Force rendering methods and the stateful contact tracker interface (paper Section 4).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// patch: SCP tracked on the Gregory patches (Wu et al., Algorithm 1).
/// direct: god-object on the base polygons (Zilles & Salisbury 1995).
/// shading: god-object position and depth, force direction from the normal interpolated
///          from vertex normals at the contact point (Morgenbesser & Srinivasan 1996).
enum class ForceMethod { Patch, Direct, Shading };
/// Refinement of the SCP on a patch (paper 4.2): the paper's descent with numerical
/// differences and the Fig. 8 adaptive step, or Newton / Gauss-Newton on exact derivatives.
enum class RefineMethod { PaperDescent, Newton };
/// Where the patch method's global query starts refinement (out of contact): polygon = the
/// nearest point of the base polygons (Embree) mapped to the domain by mean value coordinates
/// (paper 4.1); tessellation = the nearest vertex of a level-L tessellation of the patches
/// (k-d tree), which carries its (face, xi, eta). Used by ForceMethod::Patch only.
enum class InitialGuess { Polygon, Tessellation };

/// Parsers throw InputError naming the value.
ForceMethod parseForceMethod(const std::string& s);
RefineMethod parseRefineMethod(const std::string& s);
InitialGuess parseInitialGuess(const std::string& s);
const char* toString(ForceMethod m);
const char* toString(RefineMethod m);
const char* toString(InitialGuess g);

/// Force rendering options. Units: metres, newtons, N/m, radians.
struct ForceOptions {
  double stiffness = 500.0;  ///< k in F = k (SCP - HIP), N/m; > 0
  RefineMethod refine = RefineMethod::Newton;
  double angleTolerance = 1e-5;  ///< stop when angle(G - HIP, normal) below this, rad
  int maxIterations = 50;        ///< per refinement
  InitialGuess initialGuess = InitialGuess::Polygon;
  int tessellationLevel = 2;  ///< for InitialGuess::Tessellation: each polygon edge split in L, 1..64
  /// Lazy construction (the cache is a skeleton, preparePatchSkeleton): faces whose patches
  /// are held at once (LRU); <= 0: every face that is touched stays built.
  int patchCapacity = 256;
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
  uint32_t status = 0;  ///< GP_ST_* and SF_TRACK_* bits (force_tracking.h)
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
  /// Patch constructions so far with lazy construction (a face evicted and needed again counts
  /// again); the cache's face count when prebuilt; 0 for methods that need no patch.
  virtual int patchesBuilt() const noexcept = 0;
};

/// A tracker over a prebuilt cache (shared, read-only), or over a skeleton (hasPatchData false)
/// whose patches the patch method then builds lazily near the contact point (lazy_patches.h,
/// at most options.patchCapacity held). Throws InputError for bad options.
std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache, ForceMethod method,
                                                 const ForceOptions& options);

}  // namespace sf
