// SPDX-License-Identifier: Apache-2.0
// Parsing and naming of the force methods, and the renderer factory.
#include <string>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/force/god_object.h>
#include <smoothforce/query/embree_scene.h>

namespace sf {

ForceMethod parseForceMethod(const std::string& s) {
  if (s == "patch") return ForceMethod::Patch;
  if (s == "direct") return ForceMethod::Direct;
  if (s == "shading") return ForceMethod::Shading;
  throw InputError("force method: expected patch|direct|shading, got '" + s + "'");
}

const char* toString(ForceMethod m) {
  switch (m) {
    case ForceMethod::Patch:
      return "patch";
    case ForceMethod::Direct:
      return "direct";
    case ForceMethod::Shading:
      return "shading";
  }
  return "?";
}

SurfaceIndex parseSurfaceIndex(const std::string& s) {
  if (s == "auto") return SurfaceIndex::Auto;
  if (s == "bounds") return SurfaceIndex::Bounds;
  if (s == "tessellation") return SurfaceIndex::Tessellation;
  throw InputError("surface index: expected auto|bounds|tessellation, got '" + s + "'");
}

const char* toString(SurfaceIndex i) {
  switch (i) {
    case SurfaceIndex::Auto:
      return "auto";
    case SurfaceIndex::Bounds:
      return "bounds";
    case SurfaceIndex::Tessellation:
      return "tessellation";
  }
  return "?";
}

std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache,
                                                 std::shared_ptr<const PolygonScene> scene, ForceMethod method,
                                                 const ForceOptions& options,
                                                 std::shared_ptr<const PatchSurface> surface) {
  validateForceOptions(options);
  if (!cache || !scene || &scene->cache() != cache.get())
    throw InputError("makeForceRenderer: the scene must be built from the same cache");
  if (method == ForceMethod::Patch)
    return makePatchForceRenderer(std::move(cache), std::move(scene), options, std::move(surface));
  return std::make_unique<GodObjectRenderer>(std::move(cache), std::move(scene), method, options);
}

std::unique_ptr<ForceRenderer> makeForceRenderer(std::shared_ptr<const PatchCache> cache, ForceMethod method,
                                                 const ForceOptions& options) {
  validateForceOptions(options);
  if (!cache) throw InputError("makeForceRenderer: no cache");
  auto scene = std::make_shared<const PolygonScene>(
      *cache, method == ForceMethod::Patch ? kPlanarTolerance : kWatertightPlanarTolerance);
  return makeForceRenderer(std::move(cache), std::move(scene), method, options);
}

}  // namespace sf
