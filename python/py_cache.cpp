// SPDX-License-Identifier: Apache-2.0
// smoothforce.Cache: from files or NumPy arrays, saved, evaluated in batches.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cstddef>
#include <limits>

#include <smoothforce/base/hash.h>
#include <smoothforce/base/thread_limit.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_arrays.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/normal_search.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/tangent_fans.h>
#include <smoothforce/query/surface_distance.h>
#include "py_common.h"

namespace sf::py {
namespace {

struct Options {
  PatchOptions patch;
  Backend backend = Backend::Tbb;
  int threads = 0;
  bool lazy = false;
};

Options options(const std::string& precision, const std::string& normals, const std::string& crossTangent,
                const std::string& orient, const std::string& backend, int threads, bool lazy,
                const std::string& cage, const std::string& creases = "tags,groups", double creaseAngle = 0,
                const std::string& foldRepair = "on") {
  Options o;
  o.patch = parsePatchOptions(
      PatchOptionText{precision, normals, crossTangent, orient, cage, creases, creaseAngle, foldRepair});
  o.backend = parseBackend(backend);
  if (o.backend == Backend::OpenCL) throw InputError("backend: the Python module builds on the CPU: tbb or serial");
  requireThreads(threads, "threads");
  o.threads = threads;
  o.lazy = lazy;
  return o;
}

PyCache fromLoaded(const LoadedMesh& lm, const Options& o, std::string source) {
  PyCache c;
  PatchCache pc = preparePatchCache(lm.mesh, lm.cornerNormals, o.patch, lm.fileHash, !o.lazy);
  if (!o.lazy) {
    constructPatches(pc, o.backend, o.threads);
    finishFoldRepair(pc, o.backend, o.threads);
  }
  c.cache = std::make_shared<const PatchCache>(std::move(pc));
  c.source = std::move(source);
  c.backend = o.backend;
  c.threads = o.threads;
  c.fromMesh = true;
  c.meshReport = lm.seams.describe();
  for (std::string& line : lm.report.describe()) c.meshReport.push_back(std::move(line));
  for (std::string& line : lm.orientation.describe()) c.meshReport.push_back(std::move(line));
  c.normalReport = lm.normalReport.describe();
  c.flipped = lm.flipped;
  return c;
}

/// An integer array as int32, rows x cols (cols 0: 1-D); ValueError naming the field.
std::vector<int32_t> int32Array(const pyb::handle& h, const char* field, int cols = 0) {
  const pyb::array a = pyb::array::ensure(h);
  if (!a) throw InputError(std::string(field) + ": not convertible to an array");
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u' && !(a.size() == 0 && kind == 'f'))  // [] is float64 to NumPy
    throw InputError(std::string(field) + ": expected an integer array, got dtype " + std::string(pyb::str(a.dtype())));
  if (a.ndim() != 1)
    throw InputError(std::string(field) + ": expected a 1-D array, got " + std::to_string(a.ndim()) + "-D");
  (void)cols;
  auto wide = pyb::array_t<int64_t, pyb::array::c_style | pyb::array::forcecast>::ensure(a);
  std::vector<int32_t> out(static_cast<size_t>(wide.size()));
  const int64_t* p = wide.data();
  for (size_t i = 0; i < out.size(); ++i) {
    if (p[i] < std::numeric_limits<int32_t>::min() || p[i] > std::numeric_limits<int32_t>::max())
      throw InputError(std::string(field) + "[" + std::to_string(i) + "]: " + std::to_string(p[i]) +
                       " does not fit in int32");
    out[i] = static_cast<int32_t>(p[i]);
  }
  return out;
}

/// rows x 3 doubles (NumPy may convert; no copy when already float64 C-contiguous).
Doubles rows3(const pyb::handle& h, const char* field) {
  Doubles d = numericArray(h, field);
  if (d.ndim() != 2 || d.shape(1) != 3)
    throw InputError(std::string(field) + ": expected shape (n, 3), got " + std::string(pyb::str(d.attr("shape"))));
  return d;
}

PyCache fromArrays(const pyb::handle& positions, const pyb::handle& faceOffsets, const pyb::handle& faceVertices,
                   const pyb::object& normals, const std::string& normalLayout, const std::string& name,
                   const std::string& precision, const std::string& normalMode, const std::string& crossTangent,
                   const std::string& orient, const std::string& backend, int threads, bool lazy,
                   const std::string& cage, const std::string& creases, double creaseAngle,
                   const pyb::object& creaseEdges, const pyb::object& creaseSharpness, const std::string& foldRepair) {
  const Options o = options(precision, normalMode, crossTangent, orient, backend, threads, lazy, cage, creases,
                            creaseAngle, foldRepair);
  const Doubles pos = rows3(positions, "positions");
  const std::vector<int32_t> offsets = int32Array(faceOffsets, "face_offsets");
  const std::vector<int32_t> verts = int32Array(faceVertices, "face_vertices");
  if (offsets.empty()) throw InputError(name + ": face_offsets: empty (expected #F + 1 entries, 0 first)");
  if (offsets.back() < 0 || static_cast<size_t>(offsets.back()) != verts.size())
    throw InputError(name + ": face_offsets[-1] = " + std::to_string(offsets.back()) + " but face_vertices has " +
                     std::to_string(verts.size()) + " entries");
  Doubles nrm;
  MeshArrays a;
  a.name = name;
  a.normalLayout = parseNormalLayout(normalLayout);
  if (!normals.is_none()) {
    nrm = rows3(normals, "normals");
    a.normals = nrm.data();
    a.numNormals = static_cast<size_t>(nrm.shape(0));
  }
  a.positions = pos.data();
  a.numVertices = static_cast<size_t>(pos.shape(0));
  a.faceOffsets = offsets.data();
  a.numFaces = offsets.size() - 1;
  a.faceVertices = verts.data();
  std::vector<int32_t> creaseIds;
  std::vector<double> sharpness;
  if (!creaseEdges.is_none()) {
    const pyb::array k = pyb::array::ensure(creaseEdges);
    if (!k || k.ndim() != 2 || k.shape(1) != 2)
      throw InputError(name + ": crease_edges: expected a (K, 2) array of vertex ids");
    creaseIds = int32Array(k.attr("reshape")(-1), "crease_edges");
    a.creaseEdges = creaseIds.data();
    a.numCreases = creaseIds.size() / 2;
    if (!creaseSharpness.is_none()) {
      sharpness = creaseSharpness.cast<std::vector<double>>();
      if (sharpness.size() != a.numCreases)
        throw InputError(name + ": crease_sharpness: " + std::to_string(sharpness.size()) + " values for " +
                         std::to_string(a.numCreases) + " crease edges");
      a.creaseSharpness = sharpness.data();
    }
  }
  pyb::gil_scoped_release release;
  return fromLoaded(loadMeshArrays(a, o.patch), o, name);
}

PyCache fromFile(const std::filesystem::path& fsPath, const std::string& precision, const std::string& normals,
                 const std::string& crossTangent, const std::string& orient, const std::string& backend, int threads,
                 bool lazy, const std::string& cage, const std::string& creases, double creaseAngle,
                 const std::string& foldRepair) {
  const Options o =
      options(precision, normals, crossTangent, orient, backend, threads, lazy, cage, creases, creaseAngle, foldRepair);
  const std::string path = fsPath.string();
  pyb::gil_scoped_release release;
  if (isPatchCacheFile(path)) {
    PyCache c;
    c.cache = std::make_shared<const PatchCache>(readPatchCache(path));
    c.source = path;
    c.backend = o.backend;
    c.threads = o.threads;
    return c;
  }
  return fromLoaded(loadMesh(path, o.patch), o, path);
}

/// PatchPoint as a NumPy structured dtype (the array is written in place by evaluatePatches).
pyb::dtype patchPointDtype() {
  return structDtype({{"position", "(3,)f8", offsetof(PatchPoint, pos)},
                      {"dxi", "(3,)f8", offsetof(PatchPoint, dxi)},
                      {"deta", "(3,)f8", offsetof(PatchPoint, deta)},
                      {"normal", "(3,)f8", offsetof(PatchPoint, normal)},
                      {"status", "u4", offsetof(PatchPoint, status)}},
                     sizeof(PatchPoint));
}

pyb::array evaluate(const PyCache& c, const pyb::handle& faces, const pyb::handle& xi, const pyb::handle& eta) {
  if (!hasPatchData(*c.cache))
    throw InputError(c.source + ": a lazy cache (no patch built) cannot be evaluated: build it with lazy=False");
  const std::vector<int32_t> f = int32Array(faces, "faces");
  const Doubles x = numericArray(xi, "xi"), y = numericArray(eta, "eta");
  if (x.ndim() != 1 || y.ndim() != 1 || static_cast<size_t>(x.size()) != f.size() ||
      static_cast<size_t>(y.size()) != f.size())
    throw InputError("evaluate: faces, xi and eta must be 1-D arrays of one length (" + std::to_string(f.size()) + ")");
  static_assert(std::is_standard_layout_v<PatchPoint>);
  pyb::array out(patchPointDtype(), std::vector<ssize_t>{static_cast<ssize_t>(f.size())});
  auto* pts = static_cast<PatchPoint*>(out.mutable_data());
  for (size_t i = 0; i < f.size(); ++i) new (&pts[i]) PatchPoint();
  {
    pyb::gil_scoped_release release;
    evaluatePatches(*c.cache, f.data(), x.data(), y.data(), f.size(), pts, c.backend, c.threads);
  }
  return out;
}

/// Intersecting and self-crossing polygons of the cache's base mesh (checkMesh on it), as arrays.
pyb::dict polygons(const PyCache& c) {
  MeshReport r;
  {
    pyb::gil_scoped_release release;
    r = checkMesh(cacheBaseMesh(*c.cache));
  }
  const auto k = static_cast<ssize_t>(r.intersectingPairs.size());
  pyb::array_t<int32_t> pairs({k, ssize_t(2)});
  pyb::array_t<double> areas({k, ssize_t(2)});
  auto pw = pairs.mutable_unchecked<2>();
  auto aw = areas.mutable_unchecked<2>();
  for (ssize_t i = 0; i < k; ++i) {
    const IntersectingPair& p = r.intersectingPairs[static_cast<size_t>(i)];
    pw(i, 0) = p.a;
    pw(i, 1) = p.b;
    aw(i, 0) = p.areaA;
    aw(i, 1) = p.areaB;
  }
  const auto ids = [](const std::vector<int>& v) {
    pyb::array_t<int32_t> a(static_cast<ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
  };
  pyb::dict d;
  d["intersecting_pairs"] = pairs;
  d["intersecting_pair_areas"] = areas;
  d["intersecting_faces"] = ids(r.intersectingFaces());
  d["intersecting_area"] = r.intersectingArea();
  d["area"] = r.surfaceArea;
  d["self_crossing_faces"] = ids(r.selfCrossingFaces);
  return d;
}

/// A read-only (F,) view of one of the cache's per-face arrays, kept alive by `self`; None where
/// the cache has no such array (its length is not the face count).
template <class T>
pyb::object perFaceView(pyb::object self, const std::vector<T> PatchCache::*member) {
  const PatchCache& c = *self.cast<const PyCache&>().cache;
  const std::vector<T>& v = c.*member;
  if (static_cast<int>(v.size()) != c.numFaces()) return pyb::none();
  return view(v.data(), v.size(), 1, self);
}

}  // namespace

void bindCache(pyb::module_& m) {
  using namespace pybind11::literals;
  pyb::class_<PyCache, std::shared_ptr<PyCache>>(m, "Cache",
                                                 "A whole mesh's Gregory patches (or, lazy, the mesh whose patches a "
                                                 "renderer builds near the contact).")
      .def_static("from_file", &fromFile, "path"_a, pyb::kw_only(), "precision"_a = "double", "normals"_a = "auto",
                  "cross_tangent"_a = "corrected", "orient"_a = "outward", "backend"_a = "tbb", "threads"_a = 0,
                  "lazy"_a = false, "cage"_a = "none", "creases"_a = "tags,groups", "crease_angle"_a = 0.0,
                  "fold_repair"_a = "on",
                  "A cache from a patch cache file (checked, kept as it is) or a mesh file (OBJ, OFF, PLY: read,\n"
                  "checked, oriented, normals computed, every patch built unless lazy). Options as `smoothforce\n"
                  "cache build`'s (cage: none or catmull-clark, the limit positions and normals of a subdivision\n"
                  "cage; creases: which marks make crease edges, a list of tags, groups, normals, or none;\n"
                  "crease_angle: degrees, 0 off; fold_repair: on (default; split a synonym), flat polygons with a\n"
                  "reflex or straight corner cut into convex pieces; search, on and then vertex normals turned where\n"
                  "that removes fault area of the closed surface, with their mirror images on a symmetric mesh\n"
                  "(computed_normals keeps the normals before; not with lazy); or off). Raises ValueError naming the file and line. The GIL is released.")
      .def_static("from_arrays", &fromArrays, "positions"_a, "face_offsets"_a, "face_vertices"_a,
                  "normals"_a = pyb::none(), pyb::kw_only(), "normal_layout"_a = "auto", "name"_a = "<arrays>",
                  "precision"_a = "double", "normals_mode"_a = "auto", "cross_tangent"_a = "corrected",
                  "orient"_a = "outward", "backend"_a = "tbb", "threads"_a = 0, "lazy"_a = false, "cage"_a = "none",
                  "creases"_a = "tags,groups", "crease_angle"_a = 0.0, "crease_edges"_a = pyb::none(),
                  "crease_sharpness"_a = pyb::none(), "fold_repair"_a = "on",
                  "A cache from arrays, with the checks and reports of a file:\n"
                  "  positions     (V, 3) float, m\n"
                  "  face_offsets  (F + 1,) int: face f owns corners face_offsets[f] .. face_offsets[f+1]-1\n"
                  "  face_vertices (C,) int vertex indices, counter-clockwise seen from outside\n"
                  "  normals       (V, 3) per vertex or (C, 3) per corner, or None (normal_layout: auto, vertex,\n"
                  "                corner); used as a file's normals are (normals_mode: auto, file, angle, area)\n"
                  "  crease_edges  (K, 2) int vertex ids (0-based) of edges marked sharp, or None; crease_sharpness\n"
                  "                (K,) float (> 0 sharp) or None (10): read as a file's crease tags\n"
                  "Raises ValueError naming the field and element ('<arrays>: faceVertices[9] (face 2, corner 1):\n"
                  "vertex index 8 out of range [0, 8)'). The GIL is released while the patches are built.")
      .def(
          "save",
          [](const PyCache& c, const std::filesystem::path& path) {
            if (!hasPatchData(*c.cache)) throw InputError(c.source + ": a lazy cache cannot be saved");
            pyb::gil_scoped_release release;
            writePatchCache(*c.cache, path.string());
          },
          "path"_a, "Writes the patch cache file atomically (temporary file, then rename).")
      .def("evaluate", &evaluate, "faces"_a, "xi"_a, "eta"_a,
           "Evaluates N points (faces (N,) int, xi and eta (N,) float in the face's domain, the regular n-gon\n"
           "with corners (cos 2 pi k/n, sin 2 pi k/n)) in parallel, GIL released. Returns a structured array\n"
           "(N,) with fields position (3,) m, dxi (3,), deta (3,) (derivatives), normal (3,) (unit), status\n"
           "(GP_ST_* bits; a point outside its domain or a bad face: GP_ST_OUTSIDE = 1, zero vectors).")
      .def(
          "certify",
          [](pyb::object self) {
            PyCache& c = self.cast<PyCache&>();
            if (!hasPatchData(*c.cache))
              throw InputError(c.source +
                               ": a lazy cache (no patch built) cannot be certified: create it with lazy=False");
            if (static_cast<int>(c.cache->faceCertificate.size()) != c.cache->numFaces()) {
              auto copy = std::make_shared<PatchCache>(*c.cache);
              {
                pyb::gil_scoped_release release;
                certifyPatches(*copy, c.threads);
              }
              c.cache = std::move(copy);
            }
            const auto& m = c.cache->faceCertificate;
            return view(m.data(), m.size(), 1, self);
          },
          "Certifies every patch once (later calls reuse it), GIL released: proves from interval bounds of\n"
          "its exact derivatives that the patch is regular and never turns over against a fixed direction\n"
          "(its polygon's normal or, where that does not prove it, the mean of its corner normals). Returns\n"
          "the (F,) float32 margins (read-only view): > 0 certified (a lower bound on the cosine between\n"
          "patch normal and that direction), < 0 proven to turn over against its polygon, 0 undecided or no\n"
          "patch. About 0.05 s of one core per quad, 0.1-1 s per triangle or larger polygon; save() then\n"
          "writes them.")
      .def(
          "distance_to",
          [](const PyCache& self, const PyCache& other, const std::string& to, int level) {
            const DistanceSurface as = parseDistanceSurface(to);
            SurfaceDistance d;
            {
              pyb::gil_scoped_release release;
              d = measureSurfaceDistance(*self.cache, DistanceSurface::Patches, *other.cache, as, level, self.threads);
            }
            auto side = [](const DistanceDirection& s) {
              pyb::dict r;
              r["max"] = s.max;
              r["mean"] = s.mean;
              r["points"] = s.points;
              r["worst_face"] = s.worstFace;
              r["worst_point"] = pyb::make_tuple(s.worstPoint.x(), s.worstPoint.y(), s.worstPoint.z());
              return r;
            };
            pyb::dict r;
            r["diagonal_m"] = d.diagonal;
            r["levels_used"] = pyb::make_tuple(d.levelA, d.levelB);
            r["cache_to_other"] = side(d.aToB);
            r["other_to_cache"] = side(d.bToA);
            r["hausdorff"] = std::max(d.aToB.max, d.bToA.max);
            return r;
          },
          "other"_a, pyb::kw_only(), "to"_a = "patches", "level"_a = 8,
          "How far this cache's patch surface lies from `other`, both ways, as `smoothforce cache distance`:\n"
          "to='patches' compares with other's patch surface (the same mesh under other options), to='polygons'\n"
          "with other's polygons as read (a dense mesh: Cache.from_file(path, lazy=True) will do). Each\n"
          "surface is sampled on its level-`level` rings (1..64), each sample's nearest point found on the\n"
          "other (a surface that would give more than about 4 million samples at a lower level). Returns a\n"
          "dict: diagonal_m (this mesh's), levels_used, cache_to_other and other_to_cache (max, mean:\n"
          "fractions of the diagonal; points; worst_face; worst_point (m)), hausdorff. GIL released.\n"
          "Raises ValueError for a bad level or `to`, or a lazy cache asked for its patches.")
      .def_property_readonly(
          "certificates", [](pyb::object self) { return perFaceView(self, &PatchCache::faceCertificate); },
          "(F,) float32 certificate margins (see certify()), or None when not computed")
      .def_property_readonly(
          "face_source", [](pyb::object self) { return perFaceView(self, &PatchCache::faceSource); },
          "(F,) int32: with fold_repair on, the face of the mesh as read that each face (piece) comes\n"
          "from; None with fold_repair off (every face is the one read)")
      .def_property_readonly("num_faces", [](const PyCache& c) { return c.cache->numFaces(); })
      .def_property_readonly("num_vertices", [](const PyCache& c) { return c.cache->numVertices(); })
      .def_property_readonly("num_corners", [](const PyCache& c) { return c.cache->numSlots(); })
      .def_property_readonly("lazy", [](const PyCache& c) { return !hasPatchData(*c.cache); })
      .def_property_readonly("precision", [](const PyCache& c) { return toString(c.cache->options.precision); })
      .def_property_readonly(
          "cage", [](const PyCache& c) { return toString(c.cache->options.cage); },
          "\"none\" or \"catmull-clark\" (positions are then the cage's limit positions)")
      .def_property_readonly(
          "mesh_hash", [](const PyCache& c) { return hexHash(c.cache->meshHash); },
          "XXH64 of the mesh file's bytes (arrays: of the arrays), 16 hex digits")
      .def_property_readonly("source",  // as os.fsdecode would (a file name that is not UTF-8 round-trips)
                             [](const PyCache& c) {
                               return pyb::reinterpret_steal<pyb::str>(PyUnicode_DecodeFSDefaultAndSize(
                                   c.source.data(), static_cast<Py_ssize_t>(c.source.size())));
                             })
      .def_property_readonly(
          "positions",
          [](pyb::object self) {
            const auto& c = *self.cast<const PyCache&>().cache;
            return view(c.positions.data(), c.numVertices(), 3, self);
          },
          "(V, 3) float64 vertex positions, m (read-only view)")
      .def_property_readonly(
          "face_offsets",
          [](pyb::object self) {
            const auto& c = *self.cast<const PyCache&>().cache;
            return view(c.faceOffsets.data(), c.faceOffsets.size(), 1, self);
          },
          "(F + 1,) int32 (read-only view)")
      .def_property_readonly(
          "face_vertices",
          [](pyb::object self) {
            const auto& c = *self.cast<const PyCache&>().cache;
            return view(c.faceVertices.data(), c.faceVertices.size(), 1, self);
          },
          "(C,) int32 (read-only view; after any outward flip)")
      .def_property_readonly(
          "corner_normals",
          [](pyb::object self) {
            const auto& c = *self.cast<const PyCache&>().cache;
            return view(c.cornerNormals.data(), c.numSlots(), 3, self);
          },
          "(C, 3) float64 unit normals the patches were built with (read-only view)")
      .def_property_readonly(
          "computed_normals",
          [](pyb::object self) -> pyb::object {
            const auto& c = *self.cast<const PyCache&>().cache;
            if (c.computedNormals.size() != c.cornerNormals.size()) return pyb::none();
            return view(c.computedNormals.data(), c.numSlots(), 3, self);
          },
          "(C, 3) float64 unit normals as computed, before fold_repair search turned some of them\n"
          "(corner_normals holds the turned ones; the rows that differ are the corners it changed),\n"
          "or None where no normal was turned (read-only view)")
      .def_property_readonly(
          "tangent_turns",
          [](const PyCache& c) -> pyb::object {
            std::vector<double> turns;
            {
              pyb::gil_scoped_release release;
              turns = untangleTangentFans(*c.cache).turnDeg;
            }
            if (turns.empty()) return pyb::none();
            pyb::array_t<double> out({static_cast<pyb::ssize_t>(turns.size() / 2), pyb::ssize_t{2}});
            std::copy(turns.begin(), turns.end(), out.mutable_data());
            return out;
          },
          "(C, 2) float64 degrees (0..180) by which fold_repair on or search turned the edge curves' directions where\n"
          "it untangled a vertex fan: row s = corner k of its face, column 0 the edge k -> k+1 at its start\n"
          "(leaving corner k), column 1 the same edge at its end (arriving at corner k+1), from the\n"
          "construction's own direction; 0 where none turned. None where no fan was untangled (off,\n"
          "open or non-manifold meshes, meshes without a tangled fan). Computed on each access (a new array)")
      .def_property_readonly(
          "face_status",
          [](pyb::object self) {
            const auto& c = *self.cast<const PyCache&>().cache;
            return view(c.faceStatus.data(), c.faceStatus.size(), 1, self);
          },
          "(F,) uint32 GP_ST_* construction bits (read-only view)")
      .def_property_readonly(
          "report",
          [](const PyCache& c) {
            pyb::dict d;
            d["mesh"] = c.meshReport;
            d["normals"] = c.normalReport;
            d["flipped"] = c.flipped;
            return d;
          },
          "What the checks found (lists of lines, as `cache build` prints; empty for a cache file)")
      .def("polygons", &polygons,
           "Polygons of the mesh (any cache: it keeps its mesh) that intersect others they share no vertex\n"
           "with, and polygons whose outline crosses itself (docs/mesh-check.md). A dict:\n"
           "  intersecting_pairs       (K, 2) int32 face ids (0-based, file order), a < b, sorted\n"
           "  intersecting_pair_areas  (K, 2) float64 the two faces' areas, m^2\n"
           "  intersecting_faces       (M,) int32 the distinct faces of the pairs, sorted\n"
           "  intersecting_area        float, m^2: their total area\n"
           "  area                     float, m^2: all faces'\n"
           "  self_crossing_faces      (S,) int32 sorted face ids\n"
           "Reported, never refused. The GIL is released while it runs.");
}

}  // namespace sf::py
