# SPDX-License-Identifier: Apache-2.0
# Type stubs of the compiled module (python/py_*.cpp); python/tests checks that they name exactly
# what the module defines. Regenerate with pybind11-stubgen after changing the module.
"""
SmoothForce: smooth haptic force on coarse polygon meshes through G1 Gregory patches
(Wu et al., 'Smooth Force Rendering on Coarse Polygonal Meshes').

Units: metres, newtons, N/m, seconds. Bad input (files, arrays, options) raises ValueError
with a message naming the file and line, or the field and element. Status words carry the
bits SF_ST_* (patch and point), SF_TRACK_* (step) and SF_PROBE_* (sweep probe), module constants.
"""
from __future__ import annotations
import numpy
import os
import typing
__all__: list[str] = ['Cache', 'Haptic', 'SF_PROBE_INSIDE', 'SF_PROBE_ON_FAULT', 'SF_PROBE_UNDECIDED', 'SF_ST_AFFINE', 'SF_ST_BULGE', 'SF_ST_CROSS_TANGENT', 'SF_ST_EDGE_NORMAL', 'SF_ST_FOLD', 'SF_ST_GUARD', 'SF_ST_MODEL_POINT', 'SF_ST_NONFINITE', 'SF_ST_OUTSIDE', 'SF_ST_SINGULAR', 'SF_ST_TOO_MANY_SIDES', 'SF_ST_ZERO_EDGE', 'SF_TRACK_BAD_HIP', 'SF_TRACK_BOUNDARY', 'SF_TRACK_CONVERGED', 'SF_TRACK_DEGENERATE', 'SF_TRACK_ENTER', 'SF_TRACK_FOLD_EDGE', 'SF_TRACK_GLOBAL', 'SF_TRACK_INSIDE', 'SF_TRACK_LEAVE', 'SF_TRACK_MAX_ITER', 'SF_TRACK_NO_POLYGON', 'SF_TRACK_PROXY_LIMIT', 'SF_TRACK_STALLED', 'Surface', 'read_sweep', 'sweep', 'trace']
class Cache:
    """
    A whole mesh's Gregory patches (or, lazy, the mesh whose patches a renderer builds near the contact).
    """
    @staticmethod
    def from_arrays(positions: typing.Any, face_offsets: typing.Any, face_vertices: typing.Any, normals: typing.Any = None, *, normal_layout: str = 'auto', name: str = '<arrays>', precision: str = 'double', normals_mode: str = 'auto', cross_tangent: str = 'corrected', orient: str = 'outward', backend: str = 'tbb', threads: int = 0, lazy: bool = False, cage: str = 'none', creases: str = 'tags,groups', crease_angle: float = 0.0, crease_edges: typing.Any = None, crease_sharpness: typing.Any = None, fold_repair: str = 'on') -> Cache:
        """
        A cache from arrays, with the checks and reports of a file:
          positions     (V, 3) float, m
          face_offsets  (F + 1,) int: face f owns corners face_offsets[f] .. face_offsets[f+1]-1
          face_vertices (C,) int vertex indices, counter-clockwise seen from outside
          normals       (V, 3) per vertex or (C, 3) per corner, or None (normal_layout: auto, vertex,
                        corner); used as a file's normals are (normals_mode: auto, file, angle, area)
          crease_edges  (K, 2) int vertex ids (0-based) of edges marked sharp, or None; crease_sharpness
                        (K,) float (> 0 sharp) or None (10): read as a file's crease tags
        Raises ValueError naming the field and element ('<arrays>: faceVertices[9] (face 2, corner 1):
        vertex index 8 out of range [0, 8)'). The GIL is released while the patches are built.
        """
    @staticmethod
    def from_file(path: os.PathLike, *, precision: str = 'double', normals: str = 'auto', cross_tangent: str = 'corrected', orient: str = 'outward', backend: str = 'tbb', threads: int = 0, lazy: bool = False, cage: str = 'none', creases: str = 'tags,groups', crease_angle: float = 0.0, fold_repair: str = 'on') -> Cache:
        """
        A cache from a patch cache file (checked, kept as it is) or a mesh file (OBJ, OFF, PLY: read,
        checked, oriented, normals computed, every patch built unless lazy). Options as `smoothforce
        cache build`'s (cage: none or catmull-clark, the limit positions and normals of a subdivision
        cage; creases: which marks make crease edges, a list of tags, groups, normals, or none;
        crease_angle: degrees, 0 off; fold_repair: on (default; split a synonym), flat polygons with a
        reflex or straight corner cut into convex pieces; search, on and then vertex normals turned where
        that removes fault area of the closed surface, with their mirror images on a symmetric mesh
        (computed_normals keeps the normals before; not with lazy); or off). Raises ValueError naming the file and line. The GIL is released.
        """
    def certify(self) -> numpy.ndarray:
        """
        Certifies every patch once (later calls reuse it), GIL released: proves from interval bounds of
        its exact derivatives that the patch is regular and never turns over against a fixed direction
        (its polygon's normal or, where that does not prove it, the mean of its corner normals). Returns
        the (F,) float32 margins (read-only view): > 0 certified (a lower bound on the cosine between
        patch normal and that direction), < 0 proven to turn over against its polygon, 0 undecided or no
        patch. About 0.05 s of one core per quad, 0.1-1 s per triangle or larger polygon; save() then
        writes them.
        """
    def distance_to(self, other: Cache, *, to: str = 'patches', level: int = 8) -> dict:
        """
        How far this cache's patch surface lies from `other`, both ways, as `smoothforce cache distance`:
        to='patches' compares with other's patch surface (the same mesh under other options), to='polygons'
        with other's polygons as read (a dense mesh: Cache.from_file(path, lazy=True) will do). Each
        surface is sampled on its level-`level` rings (1..64), each sample's nearest point found on the
        other (a surface that would give more than about 4 million samples at a lower level). Returns a
        dict: diagonal_m (this mesh's), levels_used, cache_to_other and other_to_cache (max, mean:
        fractions of the diagonal; points; worst_face; worst_point (m)), hausdorff. GIL released.
        Raises ValueError for a bad level or `to`, or a lazy cache asked for its patches.
        """
    def evaluate(self, faces: typing.Any, xi: typing.Any, eta: typing.Any) -> numpy.ndarray:
        """
        Evaluates N points (faces (N,) int, xi and eta (N,) float in the face's domain, the regular n-gon
        with corners (cos 2 pi k/n, sin 2 pi k/n)) in parallel, GIL released. Returns a structured array
        (N,) with fields position (3,) m, dxi (3,), deta (3,) (derivatives), normal (3,) (unit), status
        (GP_ST_* bits; a point outside its domain or a bad face: GP_ST_OUTSIDE = 1, zero vectors).
        """
    def polygons(self) -> dict:
        """
        Polygons of the mesh (any cache: it keeps its mesh) that intersect others they share no vertex
        with, and polygons whose outline crosses itself (docs/mesh-check.md). A dict:
          intersecting_pairs       (K, 2) int32 face ids (0-based, file order), a < b, sorted
          intersecting_pair_areas  (K, 2) float64 the two faces' areas, m^2
          intersecting_faces       (M,) int32 the distinct faces of the pairs, sorted
          intersecting_area        float, m^2: their total area
          area                     float, m^2: all faces'
          self_crossing_faces      (S,) int32 sorted face ids
        Reported, never refused. The GIL is released while it runs.
        """
    def save(self, path: os.PathLike) -> None:
        """
        Writes the patch cache file atomically (temporary file, then rename).
        """
    @property
    def cage(self) -> str:
        """
        "none" or "catmull-clark" (positions are then the cage's limit positions)
        """
    @property
    def certificates(self) -> typing.Any:
        """
        (F,) float32 certificate margins (see certify()), or None when not computed
        """
    @property
    def face_source(self) -> typing.Any:
        """
        (F,) int32: with fold_repair on, the face of the mesh as read that each face (piece) comes
        from; None with fold_repair off (every face is the one read)
        """
    @property
    def corner_normals(self) -> numpy.ndarray:
        """
        (C, 3) float64 unit normals the patches were built with (read-only view)
        """
    @property
    def computed_normals(self) -> typing.Any:
        """
        (C, 3) float64 unit normals as computed, before fold_repair search turned some of them
        (corner_normals holds the turned ones; the rows that differ are the corners it changed),
        or None where no normal was turned (read-only view)
        """
    @property
    def tangent_turns(self) -> typing.Any:
        """
        (C, 2) float64 degrees (0..180) by which fold_repair on or search turned the edge curves' directions where
        it untangled a vertex fan: row s = corner k of its face, column 0 the edge k -> k+1 at its start
        (leaving corner k), column 1 the same edge at its end (arriving at corner k+1), from the
        construction's own direction; 0 where none turned. None where no fan was untangled (off,
        open or non-manifold meshes, meshes without a tangled fan). Computed on each access (a new array)
        """
    @property
    def face_offsets(self) -> numpy.ndarray:
        """
        (F + 1,) int32 (read-only view)
        """
    @property
    def face_status(self) -> numpy.ndarray:
        """
        (F,) uint32 GP_ST_* construction bits (read-only view)
        """
    @property
    def face_vertices(self) -> numpy.ndarray:
        """
        (C,) int32 (read-only view; after any outward flip)
        """
    @property
    def lazy(self) -> bool:
        ...
    @property
    def mesh_hash(self) -> str:
        """
        XXH64 of the mesh file's bytes (arrays: of the arrays), 16 hex digits
        """
    @property
    def num_corners(self) -> int:
        ...
    @property
    def num_faces(self) -> int:
        ...
    @property
    def num_vertices(self) -> int:
        ...
    @property
    def positions(self) -> numpy.ndarray:
        """
        (V, 3) float64 vertex positions, m (read-only view)
        """
    @property
    def precision(self) -> str:
        ...
    @property
    def report(self) -> dict:
        """
        What the checks found (lists of lines, as `cache build` prints; empty for a cache file)
        """
    @property
    def source(self) -> str:
        ...
class Surface:
    """
    The stateless surface query on a prebuilt cache (C++ SurfaceQuery): for many points, the
    signed distance to the patch surface and its nearest point, as the patch method's global query
    finds them at a contact start. Building it tessellates the patches and builds a BVH once.
    """
    def __init__(self, cache: Cache, *, preset: typing.Any = None) -> None:
        """
        preset: the refinement tolerances (fast, balanced, accurate) or None. Raises ValueError for a lazy
        cache (no patches built) or a bad preset.
        """
    def query(self, points: typing.Any, *, threads: int = 0) -> numpy.ndarray:
        """
        points (N, 3), m -> structured array (N,): signed_distance m (negative inside; NaN for a point not
        finite or beyond 1e15 m), point (3,) m and normal (3,) of the nearest patch point, face (-1: none),
        xi, eta (its domain point), status (SF_TRACK_*/SF_ST_* bits; SF_TRACK_INSIDE inside). Stateless: the
        answers do not depend on the order or the thread count (threads <= 0: all cores). GIL released.
        """
class Haptic:
    """
    The servo step for a loop the caller owns (a device SDK's 1 kHz callback): a renderer on the
    cache, the safety layer (force clamp, rate limit, ramp-in, non-finite fault) and deadline
    accounting. step() does not allocate in the engine (the returned dict is Python's).
    """
    def __init__(self, cache: Cache, *, method: str = 'patch', stiffness: float = 500.0, preset: typing.Any = None, patch_capacity: int = 256, max_force: float = 3.3, max_force_step: float = 0.5, ramp_time: float = 0.5, rate: float = 1000.0, final_step: str = 'evaluated', surface_index: str = 'auto') -> None:
        """
        Units: N/m, N, N per step, s, Hz; final_step evaluated or model (as --final-step); surface_index
        auto, bounds or tessellation (as --surface-index: auto is bounds here, about 3 kB per face of a
        prebuilt cache instead of 0.1-0.5 MB). Raises ValueError for an option out of range.
        """
    def reset(self) -> None:
        """
        Forgets the contact; clears the fault latch and the safety counters.
        """
    def set_pose(self, translation: typing.Sequence[float], quaternion: typing.Sequence[float], scale: float = 1.0) -> None:
        """
        Moves the object (translation m, quaternion w x y z, uniform scale); applied by the next step.
        """
    def step(self, hip: typing.Sequence[float], time: float) -> dict:
        """
        One step at HIP (3,) m and time s (caller's clock). Returns a dict: force (after safety, N; command
        this), rendered (before safety), scp, normal, contact, face, status, flags (bit 0 clamped, 1 rate
        limited, 2 ramping, 3 faulted, 4 missed deadline), faulted, iterations.
        """
    @property
    def patches_built(self) -> int:
        ...
def read_sweep(directory: os.PathLike) -> dict:
    """
    Reads a sweep directory (`smoothforce sweep -o DIR` or sweep(output=DIR); a shard or checkpoint too)
    with the engine's reader: the same dict as sweep() (summary None when summary.json is absent, table
    None). Raises ValueError naming a missing, truncated or inconsistent file.
    """
def sweep(cache: Cache, *, depths: str = '2%', methods: typing.Sequence[str] = ('patch',), samples: int = 1000, seed: int = 1, level: int = 8, stiffness: float = 500.0, threads: int = 0, output: os.PathLike | None = None, sample_on: str = 'patch') -> dict:
    """
    An offset-surface force sweep, as `smoothforce sweep`: `samples` surface points (seeded), one probe per
    point and depth (depths: '2%,4%' of the diagonal or metres '0.002') pressed in along the normal, per
    method (patch, direct, shading), plus the default trajectory series. Runs in parallel, GIL released.
    output: a directory to keep (sweep.json, hips.bin, results_METHOD.bin, summary.json, PLYs); None: a
    temporary one. Returns a dict: config and summary (summary.json as dicts), table (str), hips (N, 3)
    float64 m, results {method: structured (N,) force (3,) N, scp (3,) m, ref_distance, face, status,
    iterations, contact, done}, trajectories (list of dicts with force (P, 3), contact (P,)), complete.
    """
def trace(cache: Cache, hips: typing.Any, *, method: str = 'patch', stiffness: float = 500.0, preset: typing.Any = None, patch_capacity: int = 256, final_step: str = 'evaluated', surface_index: str = 'auto') -> numpy.ndarray:
    """
    A force trace: one stateful renderer (method patch, direct or shading; stiffness N/m; preset fast,
    balanced or accurate; final_step evaluated or model, as --final-step; surface_index auto, bounds or
    tessellation, as --surface-index: auto is tessellation here) stepped over hips (T, 3), m,
    in order, as `smoothforce trace` does (no safety layer). Returns a structured array (T,): hip (3,),
    scp (3,) m, force (3,) N, normal (3,), xi, eta,
    face (-1 out of contact), iterations, status (SF_ST_*/SF_TRACK_* bits), contact. GIL released.
    """
SF_PROBE_INSIDE: int = 536870912
SF_PROBE_ON_FAULT: int = 2147483648
SF_PROBE_UNDECIDED: int = 1073741824
SF_ST_AFFINE: int = 2048
SF_ST_BULGE: int = 32
SF_ST_CROSS_TANGENT: int = 8
SF_ST_EDGE_NORMAL: int = 4
SF_ST_FOLD: int = 16
SF_ST_GUARD: int = 1
SF_ST_MODEL_POINT: int = 1024
SF_ST_NONFINITE: int = 512
SF_ST_OUTSIDE: int = 64
SF_ST_SINGULAR: int = 128
SF_ST_TOO_MANY_SIDES: int = 256
SF_ST_ZERO_EDGE: int = 2
SF_TRACK_BAD_HIP: int = 33554432
SF_TRACK_BOUNDARY: int = 524288
SF_TRACK_CONVERGED: int = 65536
SF_TRACK_DEGENERATE: int = 1048576
SF_TRACK_ENTER: int = 4194304
SF_TRACK_FOLD_EDGE: int = 268435456
SF_TRACK_GLOBAL: int = 2097152
SF_TRACK_INSIDE: int = 134217728
SF_TRACK_LEAVE: int = 8388608
SF_TRACK_MAX_ITER: int = 131072
SF_TRACK_NO_POLYGON: int = 16777216
SF_TRACK_PROXY_LIMIT: int = 67108864
SF_TRACK_STALLED: int = 262144
__version__: str = '0.4.0'
