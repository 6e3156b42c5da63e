// SPDX-License-Identifier: Apache-2.0
/* SmoothForce C API: patch caches and a servo step behind opaque handles.
 *
 * Plain C (C99 and later; C++ too). Link SmoothForce::capi (CMake) or -lsmoothforce_capi.
 * Units: metres, newtons, N/m, seconds. Arrays are row-major (C order): "n x 3" means
 * 3 n doubles x0 y0 z0 x1 y1 z1 ...
 *
 * Errors: every function that can fail returns an sf_status (SF_OK = 0). The message of a
 * handle's last failed call is sf_cache_error() / sf_haptic_error() (NULL-free: "" when
 * none); a failed create (no handle yet) leaves its message in sf_last_error(), which is per
 * thread. Messages name the file and line, the field and element, or the option, as the
 * command line's do. No C++ exception crosses this boundary.
 *
 * Threads: one handle is used by one thread at a time; different handles are independent.
 * sf_haptic_step does not allocate, lock, throw or do I/O (it is for a 1 kHz servo loop).
 */
#ifndef SMOOTHFORCE_C_H
#define SMOOTHFORCE_C_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Status codes. */
typedef enum sf_status {
  SF_OK = 0,
  SF_ERROR_INPUT = 1,    /**< bad input: a file, an array, an option value (message names it) */
  SF_ERROR_ARGUMENT = 2, /**< a NULL handle or pointer, or an index out of range */
  SF_ERROR_MEMORY = 3,   /**< out of memory */
  SF_ERROR_INTERNAL = 4  /**< a bug in SmoothForce (message says where) */
} sf_status;

/** Status bits of a patch point (sf_cache_evaluate) and of a step (sf_step_result.status): the
 *  SF_ST_* bits of the patch's construction and of the evaluated point, and the SF_TRACK_* bits
 *  that refinement and the force methods add. The values of the C++ library's sf::SF_ST_* and
 *  sf::SF_TRACK_* (smoothforce/base/status.h; the C API asserts them equal when it is built). */
enum sf_status_bits {
  SF_ST_GUARD = 0x1,                /**< a backward end tangent was replaced (guard 1) */
  SF_ST_ZERO_EDGE = 0x2,            /**< an edge of (near) zero length */
  SF_ST_EDGE_NORMAL = 0x4,          /**< edge normal or an end tangent undefined; fallback used */
  SF_ST_CROSS_TANGENT = 0x8,        /**< cross tangent undefined; fallback used */
  SF_ST_FOLD = 0x10,                /**< patch normal opposite to the edge normal near an edge */
  SF_ST_BULGE = 0x20,               /**< surface leaves the face box by > 0.5 face diameters */
  SF_ST_OUTSIDE = 0x40,             /**< evaluation point outside the domain (or a bad face index) */
  SF_ST_SINGULAR = 0x80,            /**< dG/dxi x dG/deta vanishes; the normal is a fallback */
  SF_ST_TOO_MANY_SIDES = 0x100,     /**< more than 64 or fewer than 3 sides: no patch */
  SF_ST_NONFINITE = 0x200,          /**< non-finite input */
  SF_ST_MODEL_POINT = 0x400,        /**< the SCP and normal come from the refinement's quadratic
                                         model (final_step "model"), not a patch evaluation */
  SF_ST_AFFINE = 0x800,             /**< the patch is its flat triangle's affine map plus its curved
                                         edges' deviations (every corner normal the plane's, the map
                                         proven regular; fold repair on) */
  SF_TRACK_CONVERGED = 0x10000,     /**< refinement met the tolerances */
  SF_TRACK_MAX_ITER = 0x20000,      /**< refinement hit the iteration cap */
  SF_TRACK_STALLED = 0x40000,       /**< no step could decrease the distance before the tolerance */
  SF_TRACK_BOUNDARY = 0x80000,      /**< the SCP is held on a boundary or non-manifold edge */
  SF_TRACK_DEGENERATE = 0x100000,   /**< patch not evaluable: its polygon was used instead */
  SF_TRACK_GLOBAL = 0x200000,       /**< a global query ran this step */
  SF_TRACK_ENTER = 0x400000,        /**< contact began this step */
  SF_TRACK_LEAVE = 0x800000,        /**< contact ended this step */
  SF_TRACK_NO_POLYGON = 0x1000000,  /**< the mesh has no polygon */
  SF_TRACK_BAD_HIP = 0x2000000,     /**< HIP not finite or beyond 1e15 m: not rendered, state reset */
  SF_TRACK_PROXY_LIMIT = 0x4000000, /**< god-object: more than 3 constraints or the pass limit */
  SF_TRACK_INSIDE = 0x8000000,      /**< contact started: the HIP is inside the surface */
  SF_TRACK_FOLD_EDGE =
      0x10000000 /**< the SCP is held on an edge where the surface turns back (a fold, or a crease at a valley) */
};

/** A whole-mesh patch cache (or a mesh whose patches are built on demand). */
typedef struct sf_cache sf_cache;
/** A force renderer with the safety layer and the servo step (one object at a pose). */
typedef struct sf_haptic sf_haptic;

/** "0.5.0": the library's version. */
const char* sf_version(void);
/** Name of a status code ("SF_ERROR_INPUT"). */
const char* sf_status_name(sf_status status);
/** The calling thread's message of the last failed create function ("" when none). */
const char* sf_last_error(void);

/** How a mesh becomes patches. Strings as the command line's options; NULL: the default.
 *  Fill with sf_cache_options_init first. */
typedef struct sf_cache_options {
  const char* precision;     /**< "double" (default) or "float" */
  const char* normals;       /**< "auto" (default), "file", "angle", "area" */
  const char* cross_tangent; /**< "corrected" (default), "paper", "blend" */
  const char* orient;        /**< "outward" (default) or "keep" */
  const char* backend;       /**< construction and evaluation: "tbb" (default) or "serial" */
  int threads;               /**< oneTBB workers, 0: all cores */
  int lazy;                  /**< 1: build no patch now; a haptic built on it builds them near the
                                  contact (bounded set); evaluation needs a built cache (0, default) */
  const char* normal_layout; /**< arrays: "auto" (default; by row count), "vertex", "corner" */
  const char* name;          /**< arrays: names the mesh in messages (default "<arrays>") */
  const char* cage;          /**< "none" (default) or "catmull-clark": the mesh is a subdivision cage whose
                                  vertices move to their Catmull-Clark limit positions and limit normals
                                  (needs normals "auto"); a non-manifold cage is SF_ERROR_INPUT */
  const char* creases;       /**< which marks make crease edges: "tags,groups" (default), any
                                  comma-separated list of tags, groups, normals, or "none" */
  double crease_angle;       /**< degrees in [0, 180): also a crease where the faces' normals are
                                  further apart; 0 (default) off */
  const int32_t* crease_edges; /**< arrays: num_creases x 2 vertex ids (0-based) of edges marked
                                    sharp, or NULL; read as a file's crease tags */
  int32_t num_creases;         /**< arrays: rows of crease_edges */
  const double* crease_sharpness; /**< arrays: num_creases sharpness values (> 0 sharp), or NULL: 10 */
  const char* fold_repair;     /**< "on" (default; "split" is a synonym), "search" or "off": with on,
                                    every flat polygon with a reflex or straight corner is cut into
                                    convex pieces first; the cache's faces are then the pieces
                                    (sf_cache_face_source). search: on, then vertex normals turned (at
                                    most 60 degrees, with their mirror images on a symmetric mesh) where
                                    that removes fault area of the closed patch surface (seconds;
                                    sf_cache_normal_turn; refused with lazy). off: the design
                                    page's construction on the polygons as read */
} sf_cache_options;
void sf_cache_options_init(sf_cache_options* options);

/** A cache from a file: a patch cache file (.sfcache, checked) as it is, or a mesh (OBJ,
 *  OFF, PLY) read, checked, oriented, normals computed and every patch built. *out is NULL
 *  on failure (message: sf_last_error). options may be NULL (defaults). */
sf_status sf_cache_from_file(const char* path, const sf_cache_options* options, sf_cache** out);

/** A cache from arrays (nothing kept after the call):
 *  positions     num_vertices x 3
 *  face_offsets  num_faces + 1 (0 first; face f owns corners face_offsets[f] .. face_offsets[f+1]-1)
 *  face_vertices face_offsets[num_faces] vertex indices, counter-clockwise from outside
 *  normals       num_normals x 3 per vertex or per corner, or NULL with num_normals 0
 *  The same checks and normals rules as a file; errors name the field and element, e.g.
 *  "<arrays>: faceVertices[9] (face 2, corner 1): vertex index 8 out of range [0, 8)". */
sf_status sf_cache_from_arrays(const double* positions, int32_t num_vertices, const int32_t* face_offsets,
                               int32_t num_faces, const int32_t* face_vertices, const double* normals,
                               int32_t num_normals, const sf_cache_options* options, sf_cache** out);

/** Frees the cache (NULL: nothing). Haptics made from it keep what they need. */
void sf_cache_free(sf_cache* cache);
/** The message of the cache's last failed call ("" when none). */
const char* sf_cache_error(const sf_cache* cache);
/** Counts (0 for a NULL cache). */
int32_t sf_cache_num_faces(const sf_cache* cache);
int32_t sf_cache_num_vertices(const sf_cache* cache);
/** The face of the mesh as read that face `face` of the cache comes from: itself unless the
 *  cache was built with fold_repair "split", which cuts polygons into pieces; -1 for a NULL
 *  cache or a face out of range. */
int32_t sf_cache_face_source(const sf_cache* cache, int32_t face);
/** Degrees by which fold_repair "search" turned the normal at corner `corner` (0 .. n-1) of
 *  face `face`, from the normal computed to the one the patch was built with; 0 where it turned
 *  none (and for every corner under the other modes); -1 for a NULL cache or a face or corner
 *  out of range. */
double sf_cache_normal_turn(const sf_cache* cache, int32_t face, int32_t corner);
/** Degrees (0 .. 180) by which fold_repair "on" or "search" turned an edge curve's direction
 *  where it untangled a vertex fan (docs/guide.md, --fold-repair): edge `edge` (0 .. n-1, from
 *  corner edge to corner edge + 1) of face `face`, at its start (end 0: the direction leaving
 *  corner edge) or at its end (end 1: the direction arriving at corner edge + 1), from the
 *  construction's own direction (the chord projected on the vertex's tangent plane) to the one
 *  the patch was built with (under search, from the turned normals). 0 where none turned (every
 *  edge under off, and on open or non-manifold meshes); -1 for a NULL cache or a face, edge or
 *  end out of range. The two faces of an edge report the same turns (the one's start is the
 *  other's end). Computed from the cache's positions and normals on the first call, then kept
 *  with the handle. */
double sf_cache_tangent_turn(sf_cache* cache, int32_t face, int32_t edge, int32_t end);
/** Writes the cache file atomically (a lazy cache cannot be written: SF_ERROR_INPUT). */
sf_status sf_cache_save(sf_cache* cache, const char* path);

/** Certifies every patch once (the first call; later calls reuse it): proves from interval
 *  bounds of its exact derivatives that the patch is regular and never turns over against its
 *  polygon (C++ sf::certifyPatches). margins (num_faces floats, may be NULL) receives per face
 *  a value > 0 where certified (a lower bound on the cosine between the patch normal and the
 *  face normal), < 0 where the patch is proven to turn over, 0 where undecided or without
 *  patch; *certified (may be NULL) the number certified. Costs about 0.05 s of one core per quad
 *  and 0.1-1 s per triangle or larger polygon. sf_cache_save then writes them (cache format 2);
 *  haptics created before keep the cache they were made with. SF_ERROR_INPUT for a lazy cache. */
sf_status sf_cache_certify(sf_cache* cache, float* margins, int32_t* certified);

/** Evaluates count points on the patches: face (0-based) and (xi, eta) in the face's domain,
 *  the regular n-gon with corners (cos 2 pi k/n, sin 2 pi k/n). Outputs (any may be NULL):
 *  position count x 3 (m), normal count x 3 (unit), status count SF_ST_* bits (a point
 *  outside its domain or a bad face index: SF_ST_OUTSIDE, zero vectors). In parallel (the
 *  cache's backend). SF_ERROR_INPUT for a lazy cache. */
sf_status sf_cache_evaluate(sf_cache* cache, size_t count, const int32_t* faces, const double* xi, const double* eta,
                            double* position, double* normal, uint32_t* status);

/** Polygons of the cache's mesh (any cache: it keeps its mesh) that intersect other polygons
 *  they share no vertex with (exact test on the polygons' triangles, touching included;
 *  docs/mesh-check.md): count pairs of face ids (0-based, file order), a < b, sorted by (a, b).
 *  pairs: capacity x 2 int32_t, or NULL with capacity 0 to ask for the count; *count receives
 *  the number of pairs (all of them, also when it exceeds capacity: then the first capacity are
 *  written). Reported, never refused. Computed on the first call of this function or of
 *  sf_cache_self_crossing_faces, then kept with the handle. */
sf_status sf_cache_intersecting_pairs(sf_cache* cache, int32_t* pairs, size_t capacity, size_t* count);

/** Faces of the cache's mesh whose outline, projected on the face's best-fit (Newell) plane,
 *  crosses itself (a bow-tie quad): face ids sorted, the same conventions as
 *  sf_cache_intersecting_pairs (faces: capacity int32_t). */
sf_status sf_cache_self_crossing_faces(sf_cache* cache, int32_t* faces, size_t capacity, size_t* count);

/** One direction of sf_cache_distance: from every sample of one surface to the nearest point
 *  of the other. */
typedef struct sf_distance_direction {
  double max;            /**< fraction of the diagonal */
  double mean;           /**< fraction of the diagonal */
  size_t points;         /**< samples measured */
  int32_t worst_face;    /**< face (of the sampled surface) of the farthest sample */
  double worst_point[3]; /**< m: that sample */
} sf_distance_direction;

/** What sf_cache_distance measured. */
typedef struct sf_surface_distance {
  double diagonal;                      /**< m: the cache's bounding-box diagonal, the unit of max and mean */
  int32_t level_cache, level_other;     /**< the levels each surface was sampled at (lowered where the
                                             asked level would give more than about 4 million samples) */
  sf_distance_direction cache_to_other; /**< from the cache's patch surface to other */
  sf_distance_direction other_to_cache; /**< from other to the cache's patch surface */
  double hausdorff;                     /**< the larger max: the two-sided Hausdorff distance of the samples */
} sf_surface_distance;

/** How far the cache's patch surface lies from `other`, both ways (the command line's `cache
 *  distance`, C++ sf::measureSurfaceDistance): to "patches" (or NULL) compares with other's patch
 *  surface (the same mesh under other options), "polygons" with other's polygons as read (a
 *  dense mesh: a lazy cache will do). Each surface is sampled on its level-`level` rings
 *  (1..64; the command line's default is 8) and each sample's nearest point found on the other
 *  surface, exactly to the refinement's tolerances. In parallel (the cache's threads).
 *  SF_ERROR_INPUT (message: the cache's) for a level outside 1..64, a `to` other than those
 *  two, or a lazy cache whose patches are asked for; SF_ERROR_ARGUMENT for a NULL handle or out. */
sf_status sf_cache_distance(sf_cache* cache, const sf_cache* other, const char* to, int32_t level,
                            sf_surface_distance* out);

/** Force rendering and safety options. Fill with sf_haptic_options_init first. */
typedef struct sf_haptic_options {
  const char* method;    /**< "patch" (default), "direct", "shading" */
  const char* preset;    /**< refinement preset "fast", "balanced", "accurate", or NULL */
  double stiffness;      /**< k in F = k (SCP - HIP), N/m (default 500) */
  int patch_capacity;    /**< lazy caches: patches held at once (default 256; <= 0: all) */
  double max_force;      /**< safety clamp, N (default 3.3) */
  double max_force_step; /**< largest change per step, N (default 0.5; INFINITY disables) */
  double ramp_time;      /**< force ramp-in from the first step, s (default 0.5; 0 disables) */
  double rate;           /**< nominal servo rate, Hz (default 1000): deadlines of sf_haptic_step */
  const char* final_step; /**< patch method: "evaluated" (default, NULL) or "model": the Newton
                               refinement's converging step ends on its quadratic model, one patch
                               evaluation fewer per tracking step (docs/design.md "The model final step";
                               since 0.2.0) */
  const char* surface_index; /**< patch method on a prebuilt cache, the index of the global query:
                                  "auto" (default, NULL: "bounds" for sf_haptic, "tessellation" for
                                  sf_cache_trace), "bounds" (boxes per sector and cell, about 3 kB per
                                  face) or "tessellation" (0.1-0.5 MB per face, contact starts about 3x
                                  faster); docs/guide.md "--surface-index" (since 0.5.0) */
} sf_haptic_options;
void sf_haptic_options_init(sf_haptic_options* options);

/** One step's result (world frame = the cache's frame). */
typedef struct sf_step_result {
  double force[3];    /**< N: sf_haptic_step: after safety (command this); sf_cache_trace: the renderer's */
  double scp[3];      /**< m, surface contact point (god-object for direct/shading) */
  double normal[3];   /**< unit surface normal at the SCP */
  int32_t contact;    /**< 1 in contact */
  int32_t face;       /**< face holding the SCP (-1 out of contact) */
  double xi, eta;     /**< the SCP in the face's domain */
  int32_t iterations; /**< refinement iterations of this step */
  uint32_t status;    /**< SF_ST_* and SF_TRACK_* bits of the renderer */
  uint32_t flags;     /**< sf_haptic_step: safety and step flags (bit 0 clamped, 1 rate-limited,
                           2 ramping, 3 faulted, 4 missed deadline, 9 stale); trace: 0 */
  int32_t faulted;    /**< sf_haptic_step: 1 when a fault is latched (force zero) */
} sf_step_result;

/** A haptic on a cache (a prebuilt cache, or a lazy one whose patches it builds itself). */
sf_status sf_haptic_create(sf_cache* cache, const sf_haptic_options* options, sf_haptic** out);
void sf_haptic_free(sf_haptic* haptic);
const char* sf_haptic_error(const sf_haptic* haptic);

/** One servo step from the caller's own loop (a device SDK's 1 kHz callback): HIP (m, 3
 *  doubles) in, result out. time: the caller's clock, s (any origin; increasing): drives the
 *  ramp-in and the deadline check. Safety: 3.3 N clamp, rate limit, ramp-in, a non-finite
 *  HIP, force or time latches a fault (zero force until sf_haptic_reset); a HIP beyond 1e15 m
 *  is not rendered (status SF_TRACK_BAD_HIP, zero force). Never allocates, locks
 *  or throws. SF_ERROR_ARGUMENT for NULL pointers (without a message). */
sf_status sf_haptic_step(sf_haptic* haptic, const double hip[3], double time, sf_step_result* out);
/** Moves the object: translation (m, 3), rotation quaternion (w, x, y, z; normalised, non-zero),
 *  uniform scale > 0; applied by the next step (real-time safe). SF_ERROR_INPUT when not finite. */
sf_status sf_haptic_set_pose(sf_haptic* haptic, const double translation[3], const double quaternion[4], double scale);
/** Forgets the contact and clears the fault latch and the safety counters. */
void sf_haptic_reset(sf_haptic* haptic);

/** A force trace: the renderer alone (no safety) over count HIPs (count x 3, m) in order,
 *  stateful (contact tracked from one HIP to the next), as `smoothforce trace` does. out: count
 *  results. options as for sf_haptic_create (the safety fields are not used). */
sf_status sf_cache_trace(sf_cache* cache, const sf_haptic_options* options, size_t count, const double* hips,
                         sf_step_result* out);

/** The stateless surface query on a prebuilt cache (C++ sf::SurfaceQuery): for many points,
 *  the signed distance to the patch surface and its nearest point, as the patch method's
 *  global query finds them at a contact start. Built once (tessellation and BVH), then thread-safe. */
typedef struct sf_surface sf_surface;

/** One point's answer. */
typedef struct sf_surface_point {
  double signed_distance; /**< m, to the nearest patch point, negative inside the surface; NaN for a
                               point not finite or beyond 1e15 m (status SF_TRACK_BAD_HIP) */
  double point[3];        /**< m, the nearest patch point */
  double normal[3];       /**< its unit outward patch normal */
  int32_t face;           /**< its face (-1: none) */
  double xi, eta;         /**< its domain point */
  uint32_t status;        /**< SF_TRACK_* bits of its refinement, SF_TRACK_INSIDE inside; SF_ST_* bits */
} sf_surface_point;

/** A surface query on a prebuilt cache (a lazy cache: SF_ERROR_INPUT). options: only `preset`
 *  (the refinement tolerances) is used; NULL for the defaults. The cache must outlive it. */
sf_status sf_surface_create(sf_cache* cache, const sf_haptic_options* options, sf_surface** out);
void sf_surface_free(sf_surface* surface);
const char* sf_surface_error(const sf_surface* surface);
/** Answers count points (count x 3, m) into out (count results), on `threads` threads (<= 0: all
 *  cores; 1: the calling thread). The answers do not depend on the order, the batch or the thread
 *  count. Safe to call from several threads at once on one sf_surface. */
sf_status sf_surface_query(sf_surface* surface, size_t count, const double* points, int threads,
                           sf_surface_point* out);

#ifdef __cplusplus
}
#endif

#endif /* SMOOTHFORCE_C_H */
