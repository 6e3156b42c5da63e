// SPDX-License-Identifier: Apache-2.0
// The geometry of one cache shared by the renderers made from it: the objects of a scene that
// use one mesh.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <smoothforce/force/force_method.h>

namespace sf {

/// Makes force renderers of one cache that share what they can: the polygon scenes (Embree
/// BVHs), the patch surface of a prebuilt cache, and for a skeleton (a mesh: patches built
/// lazily) its patch store and the lazy patch surface's boxes, the costly part of setting up a
/// renderer on a mesh (about 0.4 s and 45 MB for the 23,062 triangles of odedstein/spot.obj).
/// Each renderer keeps its own contact state, and its forces are those of a renderer made alone
/// by makeForceRenderer, bit for bit. Renderers made by one SharedGeometry share the lazy parts'
/// caches (built patches, cells), so step them from one thread (as a scene's step() does), or
/// give each thread's renderers their own SharedGeometry. Parts are made on first need and kept
/// by the renderers that use them: the SharedGeometry may go first. Not thread-safe.
class SharedGeometry {
 public:
  /// Throws InputError for a null cache.
  explicit SharedGeometry(std::shared_ptr<const PatchCache> cache);
  ~SharedGeometry();
  SharedGeometry(const SharedGeometry&) = delete;
  SharedGeometry& operator=(const SharedGeometry&) = delete;

  /// A renderer as makeForceRenderer(cache, method, options) makes it, from the shared parts.
  /// Throws InputError for bad options.
  std::unique_ptr<ForceRenderer> makeRenderer(ForceMethod method, const ForceOptions& options);

  const std::shared_ptr<const PatchCache>& cache() const noexcept { return cache_; }

  /// One runtime structure and the bytes it holds on the heap (Embree's BVHs as its memory
  /// monitor counts them).
  struct Part {
    std::string name;
    size_t bytes = 0;
  };
  /// Every structure the renderers made so far hold, the cache first: "cache" (the patch records
  /// and mesh, PatchCache::bytes), "polygon_scene" (the patch method's polygons and BVH),
  /// "patch_surface" (the tessellation index of the global query, SurfaceIndex::Tessellation:
  /// tessellations and BVHs, one per option set), "lazy_surface" (the bounds index,
  /// SurfaceIndex::Bounds or a skeleton: boxes per face, sector and cell; cells grow as contact
  /// reaches new faces), "lazy_patches" (a skeleton's patch entries, up to the capacity),
  /// "god_object_scene" (the direct and shading
  /// methods' polygons and BVH). Not thread-safe, as makeRenderer.
  std::vector<Part> memory() const;

 private:
  struct Parts;
  std::shared_ptr<const PatchCache> cache_;
  std::unique_ptr<Parts> parts_;
};

}  // namespace sf
