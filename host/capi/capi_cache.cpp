// SPDX-License-Identifier: Apache-2.0
// C API: caches from files or arrays, saving, batch evaluation.
#include <smoothforce/base/status.h>
#include <smoothforce/base/thread_limit.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_arrays.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tangent_fans.h>
#include <smoothforce/query/normal_search.h>
#include <smoothforce/query/surface_distance.h>
#include <smoothforce/version.h>
#include "capi_detail.h"

#include <vector>

namespace sf::capi {

std::string& lastError() {
  thread_local std::string message;
  return message;
}

namespace {

struct Parsed {
  PatchOptions patch;
  Backend backend = Backend::Tbb;
  int threads = 0;
  bool lazy = false;
};

Parsed parseOptions(const sf_cache_options* o) {
  sf_cache_options d;
  sf_cache_options_init(&d);
  if (!o) o = &d;
  Parsed p;
  PatchOptionText text;
  text.precision = opt(o->precision, "double");
  text.normals = opt(o->normals, "auto");
  text.crossTangent = opt(o->cross_tangent, "corrected");
  text.orient = opt(o->orient, "outward");
  text.cage = opt(o->cage, "none");
  text.creases = opt(o->creases, "tags,groups");
  text.creaseAngle = o->crease_angle;
  text.foldRepair = opt(o->fold_repair, "on");
  p.patch = parsePatchOptions(text);
  p.backend = parseBackend(opt(o->backend, "tbb"));
  if (p.backend == Backend::OpenCL) throw InputError("backend: the C API builds on the CPU: tbb or serial");
  requireThreads(o->threads, "threads");
  p.threads = o->threads;
  if (o->normal_layout) parseNormalLayout(o->normal_layout);  // used by arrays only; checked for files too
  p.lazy = o->lazy != 0;
  return p;
}

sf_cache* finish(const LoadedMesh& lm, const Parsed& p, std::string source) {
  PatchCache c = preparePatchCache(lm.mesh, lm.cornerNormals, p.patch, lm.fileHash, !p.lazy);
  if (!p.lazy) {
    constructPatches(c, p.backend, p.threads);
    finishFoldRepair(c, p.backend, p.threads);
  }
  auto* h = new sf_cache;
  h->cache = std::make_shared<const PatchCache>(std::move(c));
  h->backend = p.backend;
  h->threads = p.threads;
  h->source = std::move(source);
  return h;
}

/// The intersection and self-crossing report of the cache's base mesh, made once per handle.
const MeshReport& polygons(sf_cache& h) {
  if (!h.polygons) h.polygons = std::make_unique<MeshReport>(checkMesh(cacheBaseMesh(*h.cache)));
  return *h.polygons;
}

}  // namespace
}  // namespace sf::capi

using namespace sf;
using namespace sf::capi;

extern "C" {

const char* sf_version(void) { return SF_VERSION_STRING; }

const char* sf_status_name(sf_status s) {
  switch (s) {
    case SF_OK:
      return "SF_OK";
    case SF_ERROR_INPUT:
      return "SF_ERROR_INPUT";
    case SF_ERROR_ARGUMENT:
      return "SF_ERROR_ARGUMENT";
    case SF_ERROR_MEMORY:
      return "SF_ERROR_MEMORY";
    case SF_ERROR_INTERNAL:
      return "SF_ERROR_INTERNAL";
  }
  return "SF_UNKNOWN_STATUS";
}

const char* sf_last_error(void) { return lastError().c_str(); }

void sf_cache_options_init(sf_cache_options* o) {
  if (o)
    *o = sf_cache_options{nullptr, nullptr, nullptr, nullptr, nullptr, 0, 0,   nullptr,
                          nullptr, nullptr, nullptr, 0.0,     nullptr, 0, nullptr, nullptr};
}

sf_status sf_cache_from_file(const char* path, const sf_cache_options* options, sf_cache** out) {
  return create(out, [&]() -> sf_cache* {
    if (!path) throw std::invalid_argument("path: NULL");
    const Parsed p = parseOptions(options);
    if (isPatchCacheFile(path)) {
      CacheExpectation expect;
      auto* h = new sf_cache;
      std::unique_ptr<sf_cache> keep(h);
      h->cache = std::make_shared<const PatchCache>(readPatchCache(path, expect));
      h->backend = p.backend;
      h->threads = p.threads;
      h->source = path;
      return keep.release();
    }
    return finish(loadMesh(path, p.patch), p, path);
  });
}

sf_status sf_cache_from_arrays(const double* positions, int32_t num_vertices, const int32_t* face_offsets,
                               int32_t num_faces, const int32_t* face_vertices, const double* normals,
                               int32_t num_normals, const sf_cache_options* options, sf_cache** out) {
  return create(out, [&]() -> sf_cache* {
    const Parsed p = parseOptions(options);
    MeshArrays a;
    if (options && options->name) a.name = options->name;
    if (options && options->normal_layout) a.normalLayout = parseNormalLayout(options->normal_layout);
    if (num_vertices < 0) throw InputError(a.name + ": num_vertices: " + std::to_string(num_vertices) + " (< 0)");
    if (num_faces < 0) throw InputError(a.name + ": num_faces: " + std::to_string(num_faces) + " (< 0)");
    if (num_normals < 0) throw InputError(a.name + ": num_normals: " + std::to_string(num_normals) + " (< 0)");
    a.positions = positions;
    a.numVertices = static_cast<size_t>(num_vertices);
    a.faceOffsets = face_offsets;
    a.numFaces = static_cast<size_t>(num_faces);
    a.faceVertices = face_vertices;
    a.normals = normals;
    a.numNormals = static_cast<size_t>(num_normals);
    if (options) {
      if (options->num_creases < 0)
        throw InputError(a.name + ": num_creases: " + std::to_string(options->num_creases) + " (< 0)");
      a.creaseEdges = options->crease_edges;
      a.numCreases = static_cast<size_t>(options->num_creases);
      a.creaseSharpness = options->crease_sharpness;
    }
    return finish(loadMeshArrays(a, p.patch), p, a.name);
  });
}

void sf_cache_free(sf_cache* cache) { delete cache; }

const char* sf_cache_error(const sf_cache* cache) { return cache ? cache->error.c_str() : "cache: NULL"; }

int32_t sf_cache_num_faces(const sf_cache* cache) { return cache ? cache->cache->numFaces() : 0; }
int32_t sf_cache_num_vertices(const sf_cache* cache) { return cache ? cache->cache->numVertices() : 0; }
int32_t sf_cache_face_source(const sf_cache* cache, int32_t face) {
  if (!cache || face < 0 || face >= cache->cache->numFaces()) return -1;
  return cache->cache->sourceFace(face);
}

double sf_cache_normal_turn(const sf_cache* cache, int32_t face, int32_t corner) {
  if (!cache || face < 0 || face >= cache->cache->numFaces() || corner < 0 || corner >= cache->cache->faceSize(face))
    return -1;
  return cache->cache->normalTurnDeg(cache->cache->faceOffsets[face] + corner);
}

double sf_cache_tangent_turn(sf_cache* cache, int32_t face, int32_t edge, int32_t end) {
  if (!cache || face < 0 || face >= cache->cache->numFaces() || edge < 0 || edge >= cache->cache->faceSize(face) ||
      end < 0 || end > 1)
    return -1;
  try {
    if (!cache->tangentTurns)
      cache->tangentTurns = std::make_unique<std::vector<double>>(untangleTangentFans(*cache->cache).turnDeg);
  } catch (const std::exception& e) {  // out of memory: no turn can be reported
    cache->error = e.what();
    return -1;
  }
  const std::vector<double>& t = *cache->tangentTurns;
  return t.empty() ? 0.0 : t[2 * size_t(cache->cache->faceOffsets[face] + edge) + size_t(end)];
}

sf_status sf_cache_save(sf_cache* cache, const char* path) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (!path) throw std::invalid_argument("path: NULL");
    if (!hasPatchData(*cache->cache))
      throw InputError(cache->source + ": a lazy cache (no patch built) cannot be saved: create it with lazy = 0");
    writePatchCache(*cache->cache, path);
  });
}

sf_status sf_cache_certify(sf_cache* cache, float* margins, int32_t* certified) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (!hasPatchData(*cache->cache))
      throw InputError(cache->source + ": a lazy cache (no patch built) cannot be certified: create it with lazy = 0");
    if (static_cast<int>(cache->cache->faceCertificate.size()) != cache->cache->numFaces()) {
      auto copy = std::make_shared<PatchCache>(*cache->cache);
      certifyPatches(*copy, cache->threads);
      cache->cache = std::move(copy);
    }
    const std::vector<float>& m = cache->cache->faceCertificate;
    if (margins) std::copy(m.begin(), m.end(), margins);
    if (certified) *certified = summarizeCertificates(*cache->cache).certified;
  });
}

sf_status sf_cache_distance(sf_cache* cache, const sf_cache* other, const char* to, int32_t level,
                            sf_surface_distance* out) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (!other || !out) throw std::invalid_argument("distance: other and out must not be NULL");
    const DistanceSurface as = parseDistanceSurface(to ? to : "patches");
    const SurfaceDistance d =
        measureSurfaceDistance(*cache->cache, DistanceSurface::Patches, *other->cache, as, level, cache->threads);
    auto side = [](const DistanceDirection& s, sf_distance_direction& o) {
      o.max = s.max;
      o.mean = s.mean;
      o.points = s.points;
      o.worst_face = s.worstFace;
      for (int k = 0; k < 3; ++k) o.worst_point[k] = s.worstPoint[k];
    };
    out->diagonal = d.diagonal;
    out->level_cache = d.levelA;
    out->level_other = d.levelB;
    side(d.aToB, out->cache_to_other);
    side(d.bToA, out->other_to_cache);
    out->hausdorff = std::max(d.aToB.max, d.bToA.max);
  });
}

sf_status sf_cache_evaluate(sf_cache* cache, size_t count, const int32_t* faces, const double* xi, const double* eta,
                            double* position, double* normal, uint32_t* status) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (count && (!faces || !xi || !eta)) throw std::invalid_argument("evaluate: faces, xi and eta must not be NULL");
    if (count > (size_t(1) << 40))  // a negative number cast to size_t, or more than memory holds
      throw std::invalid_argument("evaluate: count " + std::to_string(count) + " is more than 2^40 points");
    if (!hasPatchData(*cache->cache))
      throw InputError(cache->source + ": a lazy cache (no patch built) cannot be evaluated: create it with lazy = 0");
    std::vector<PatchPoint> pts(count);
    evaluatePatches(*cache->cache, faces, xi, eta, count, pts.data(), cache->backend, cache->threads);
    for (size_t i = 0; i < count; ++i) {
      for (int k = 0; k < 3; ++k) {
        if (position) position[3 * i + k] = pts[i].pos[k];
        if (normal) normal[3 * i + k] = pts[i].normal[k];
      }
      if (status) status[i] = pts[i].status;
    }
  });
}

sf_status sf_cache_intersecting_pairs(sf_cache* cache, int32_t* pairs, size_t capacity, size_t* count) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (!count) throw std::invalid_argument("intersecting pairs: count is NULL");
    if (capacity && !pairs) throw std::invalid_argument("intersecting pairs: pairs is NULL with a capacity");
    const std::vector<IntersectingPair>& found = polygons(*cache).intersectingPairs;
    for (size_t i = 0; i < found.size() && i < capacity; ++i) {
      pairs[2 * i] = found[i].a;
      pairs[2 * i + 1] = found[i].b;
    }
    *count = found.size();
  });
}

sf_status sf_cache_self_crossing_faces(sf_cache* cache, int32_t* faces, size_t capacity, size_t* count) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (!count) throw std::invalid_argument("self-crossing faces: count is NULL");
    if (capacity && !faces) throw std::invalid_argument("self-crossing faces: faces is NULL with a capacity");
    const std::vector<int>& found = polygons(*cache).selfCrossingFaces;
    for (size_t i = 0; i < found.size() && i < capacity; ++i) faces[i] = found[i];
    *count = found.size();
  });
}

}  // extern "C"
