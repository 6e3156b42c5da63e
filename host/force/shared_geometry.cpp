// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/force/shared_geometry.h>

#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/force/god_object.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include "force_tracking_detail.h"

namespace sf {

/// Each part with the options it was made for (a handful per cache: a linear search).
struct SharedGeometry::Parts {
  struct Surface {
    PatchSurfaceOptions options;
    std::shared_ptr<const PatchSurface> surface;
  };
  struct Store {
    int capacity;
    std::shared_ptr<LazyPatches> patches;
  };
  /// the patch method's polygon scene (kPlanarTolerance) and the lazy surface on its facets
  std::shared_ptr<const PolygonScene> patchScene;
  std::shared_ptr<LazyPatchSurface> lazySurface;
  std::vector<Surface> surfaces;
  std::vector<Store> stores;
  /// the direct and shading methods' watertight scene (godObjectScene: in the renderers' local
  /// frame when the mesh is far from the origin)
  std::shared_ptr<const PolygonScene> godObjectScene;
};

namespace {
bool sameSurfaceOptions(const PatchSurfaceOptions& a, const PatchSurfaceOptions& b) {
  return a.level == b.level && a.targetError == b.targetError && a.triangleBudget == b.triangleBudget &&
         a.subdivision == b.subdivision && a.candidates == b.candidates;
}
}  // namespace

SharedGeometry::SharedGeometry(std::shared_ptr<const PatchCache> cache)
    : cache_(std::move(cache)), parts_(std::make_unique<Parts>()) {
  if (!cache_) throw InputError("SharedGeometry: no cache");
}

SharedGeometry::~SharedGeometry() = default;

std::unique_ptr<ForceRenderer> SharedGeometry::makeRenderer(ForceMethod method, const ForceOptions& options) {
  validateForceOptions(options);
  const bool patch = method == ForceMethod::Patch;
  if (!patch) {
    if (!parts_->godObjectScene) parts_->godObjectScene = godObjectScene(*cache_);
    return std::make_unique<GodObjectRenderer>(cache_, parts_->godObjectScene, method, options);
  }
  if (!parts_->patchScene) parts_->patchScene = std::make_shared<const PolygonScene>(*cache_, kPlanarTolerance);
  const std::shared_ptr<const PolygonScene>& scene = parts_->patchScene;
  const bool surfaceGuess = options.initialGuess == InitialGuess::Surface;
  const bool prebuilt = hasPatchData(*cache_);
  if (prebuilt && options.surfaceIndex != SurfaceIndex::Bounds) {  // auto: the tessellation, as makeForceRenderer
    std::shared_ptr<const PatchSurface> surface;
    if (surfaceGuess) {
      const PatchSurfaceOptions o = patchSurfaceOptions(options);
      for (const Parts::Surface& s : parts_->surfaces)
        if (sameSurfaceOptions(s.options, o)) surface = s.surface;
      if (!surface) {
        surface = std::make_shared<const PatchSurface>(*cache_, o);
        parts_->surfaces.push_back({o, surface});
      }
    }
    return makePatchForceRenderer(cache_, scene, options, std::move(surface));
  }
  detail::SharedLazyParts lazy;  // a prebuilt cache needs no patch store: only the boxes
  for (const Parts::Store& s : parts_->stores)
    if (!prebuilt && s.capacity == options.patchCapacity) lazy.patches = s.patches;
  if (!prebuilt && !lazy.patches) {
    lazy.patches = std::make_shared<LazyPatches>(cache_, options.patchCapacity);
    parts_->stores.push_back({options.patchCapacity, lazy.patches});
  }
  if (surfaceGuess) {
    if (!parts_->lazySurface) parts_->lazySurface = detail::makeBoundsIndex(*cache_, *scene);
    lazy.surface = parts_->lazySurface;
  }
  return detail::makeSharedPatchRenderer(cache_, scene, options, nullptr, lazy);
}

std::vector<SharedGeometry::Part> SharedGeometry::memory() const {
  std::vector<Part> parts{{"cache", cache_->bytes()}};
  if (parts_->patchScene) parts.push_back({"polygon_scene", parts_->patchScene->bytes()});
  for (const Parts::Surface& s : parts_->surfaces) parts.push_back({"patch_surface", s.surface->bytes()});
  if (parts_->lazySurface) parts.push_back({"lazy_surface", parts_->lazySurface->bytes()});
  for (const Parts::Store& s : parts_->stores) parts.push_back({"lazy_patches", s.patches->bytes()});
  if (parts_->godObjectScene) parts.push_back({"god_object_scene", parts_->godObjectScene->bytes()});
  return parts;
}

}  // namespace sf
