/* SmoothForce C API: patch caches and a servo step behind opaque handles (issue 12 part 5).
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

/** A whole-mesh patch cache (or a mesh whose patches are built on demand). */
typedef struct sf_cache sf_cache;
/** A force renderer with the safety layer and the servo step (one object at a pose). */
typedef struct sf_haptic sf_haptic;

/** "0.1.0": the library's version. */
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
/** Writes the cache file atomically (a lazy cache cannot be written: SF_ERROR_INPUT). */
sf_status sf_cache_save(sf_cache* cache, const char* path);

/** Evaluates count points on the patches: face (0-based) and (xi, eta) in the face's domain,
 *  the regular n-gon with corners (cos 2 pi k/n, sin 2 pi k/n). Outputs (any may be NULL):
 *  position count x 3 (m), normal count x 3 (unit), status count GP_ST_* bits (a point
 *  outside its domain or a bad face index: GP_ST_OUTSIDE, zero vectors). In parallel (the
 *  cache's backend). SF_ERROR_INPUT for a lazy cache. */
sf_status sf_cache_evaluate(sf_cache* cache, size_t count, const int32_t* faces, const double* xi, const double* eta,
                            double* position, double* normal, uint32_t* status);

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

#ifdef __cplusplus
}
#endif

#endif /* SMOOTHFORCE_C_H */
