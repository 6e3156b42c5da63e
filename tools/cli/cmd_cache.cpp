// SPDX-License-Identifier: Apache-2.0
// `smoothforce cache build|info|distance`
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <system_error>

#include <smoothforce/base/hash.h>
#include <smoothforce/mesh/creases.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/fold_repair_record.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/force/shared_geometry.h>
#include <smoothforce/query/surface_distance.h>
#include <smoothforce/query/surface_faults.h>
#include "cli_common.h"
#include "cli_exit.h"
#include "cli_output.h"

namespace sf::cli {
namespace {

void printPatchSummary(const PatchCache& c) {
  const PatchStatusSummary s = summarizePatchStatus(c);
  std::printf("patches: %d built (precision %s, cross tangent %s)\n", c.numFaces() - s.notBuilt,
              toString(c.options.precision), toString(c.options.crossTangent));
  std::printf(
      "patch status: guard used %d, folds %d, bulges > 0.5 %d (max bulge %.3f), "
      "degenerate %d, not built %d\n",
      s.guard, s.fold, s.bulge, s.maxBulge, static_cast<int>(s.degenerateFaces.size()), s.notBuilt);
  auto list = [](const char* what, const std::vector<int>& ids) {
    if (!ids.empty()) std::printf("  %s faces:%s\n", what, faceIdsText(ids).c_str());
  };
  list("fold", s.foldFaces);
  list("bulge", s.bulgeFaces);
  list("degenerate", s.degenerateFaces);
  if (!s.affineFaces.empty())
    std::printf(
        "  flat triangles with their plane's normals, each patch its affine map with its edge curves (the "
        "same boundary, proven regular), %zu faces:%s\n",
        s.affineFaces.size(), faceIdsText(s.affineFaces).c_str());
  if (!s.insideOutFaces.empty())
    std::printf("  corners inside out (the two edge curves leave the vertex in the wrong order about its normal: the "
                "patch folds there), %zu faces:%s\n",
                s.insideOutFaces.size(), faceIdsText(s.insideOutFaces).c_str());
}

void printCertificates(const PatchCache& c) {
  const CertificateSummary s = summarizeCertificates(c);
  if (!s.present) {
    std::printf("certificate: not computed (cache build --certify)\n");
    return;
  }
  std::printf(
      "certificate: %d of %d patches certified fold-free (smallest margin %.3g), %d undecided, %d proven to fold\n",
      s.certified, c.numFaces() - s.notBuilt, s.minMargin, s.undecided, s.folded);
  if (!s.uncertifiedFaces.empty()) std::printf("  uncertified faces:%s\n", faceIdsText(s.uncertifiedFaces).c_str());
  if (!s.foldedFaces.empty()) std::printf("  proven folded faces:%s\n", faceIdsText(s.foldedFaces).c_str());
}

/// The crease edges and vertices of a built surface (summarizeCreases), as `cache build` and
/// `cache info` print them.
CreaseSummary creasesOf(const PatchCache& c) {
  return summarizeCreases(cacheBaseMesh(c), c.slotTwin, c.cornerNormals.data());
}

void printCreases(const PatchCache& c) {
  const CreaseSummary s = creasesOf(c);
  if (s.edges.empty()) {
    std::printf("creases: none\n");
    return;
  }
  for (const std::string& line : s.describe()) std::printf("%s\n", line.c_str());
}

nlohmann::ordered_json creasesJson(const PatchCache& c) {
  const CreaseSummary s = creasesOf(c);
  return {{"edges", s.edges}, {"crease_vertices", s.creaseVertices}, {"corners", s.corners}, {"darts", s.darts}};
}

void printFoldRepair(const PatchCache& c) {
  if (c.options.foldRepair == FoldRepairMode::Off) return;
  const FoldRepairRecord r = foldRepairRecord(c);
  if (r.cuts.empty()) {
    std::printf("fold repair: %s: no flat polygon with a reflex or straight corner; the faces are those read\n",
                toString(c.options.foldRepair));
  } else {
    size_t pieces = 0;
    for (const FoldRepairRecord::Cut& cut : r.cuts) pieces += cut.faces.size();
    std::printf(
        "fold repair: %s: %zu %s as read replaced by %zu pieces (convex pieces cut on diagonals, fan triangles; a "
        "flat cap merged from its triangles is listed under its first); the cache's faces are the pieces\n",
        toString(c.options.foldRepair), r.cuts.size(), r.cuts.size() == 1 ? "face" : "faces", pieces);
    for (size_t i = 0; i < r.cuts.size() && i < 10; ++i) {
      std::string ids;  // every piece (faceIdsText would stop at 10)
      for (const int f : r.cuts[i].faces) (ids += ' ') += std::to_string(f);
      std::printf("  face %d as read: faces%s\n", r.cuts[i].faceAsRead, ids.c_str());
    }
    if (r.cuts.size() > 10) std::printf("  ... (cache info --json: every one)\n");
  }
  if (r.untangledVertices > 0)
    std::printf(
        "fold repair: %s: %d vertex fans untangled (edge tangents turned in their tangent planes by at most %.3g "
        "degrees)\n",
        toString(c.options.foldRepair), r.untangledVertices, r.maxTangentTurnDeg);
  if (c.options.foldRepair != FoldRepairMode::Search) {
    if (!r.changed.empty())
      std::printf("  %zu patches and %d edge curves changed:", r.changed.size(), r.edgeCurves);
    for (size_t i = 0; i < r.changed.size() && i < 10; ++i) std::printf(" %d", r.changed[i].face);
    if (!r.changed.empty()) std::printf(r.changed.size() > 10 ? " ... (cache info --json: every one)\n" : "\n");
    return;
  }
  if (r.turnedCorners == 0) {
    std::printf("fold repair: search: no normal turned; every patch is the one of fold repair on\n");
    return;
  }
  std::printf(
      "fold repair: search: %d vertex normals turned (%d corners) by %.3g degrees on average, at most %.3g; %zu "
      "patches and %d edge curves changed\n",
      r.turnedNormals, r.turnedCorners, r.meanDegrees, r.maxDegrees, r.changed.size(), r.edgeCurves);
  for (size_t i = 0; i < r.changed.size() && i < 10; ++i) {
    const FoldRepairRecord::FaceChange& fc = r.changed[i];
    std::string turns, edges;
    for (const FoldRepairRecord::Turn& t : fc.turns) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%d (vertex %d) %.3g deg", turns.empty() ? "" : ", ", t.corner, t.vertex,
                    t.degrees);
      turns += buf;
    }
    std::printf("  face %d: corners turned: %s; edge curves changed:%s\n", fc.face,
                turns.empty() ? "none (across a crease)" : turns.c_str(), faceIdsText(fc.edges).c_str());
  }
  if (r.changed.size() > 10) std::printf("  ... (cache info --json: every one)\n");
}

nlohmann::ordered_json foldRepairJson(const PatchCache& c) {
  if (c.options.foldRepair == FoldRepairMode::Off) return nullptr;
  const FoldRepairRecord r = foldRepairRecord(c);
  nlohmann::ordered_json cut = nlohmann::ordered_json::array(), changed = nlohmann::ordered_json::array();
  for (const FoldRepairRecord::Cut& k : r.cuts) cut.push_back({{"face_as_read", k.faceAsRead}, {"faces", k.faces}});
  for (const FoldRepairRecord::FaceChange& fc : r.changed) {
    nlohmann::ordered_json turns = nlohmann::ordered_json::array();
    for (const FoldRepairRecord::Turn& t : fc.turns)
      turns.push_back({{"corner", t.corner}, {"vertex", t.vertex}, {"degrees", t.degrees}});
    changed.push_back({{"face", fc.face}, {"turned", turns}, {"edges", fc.edges}});
  }
  return {{"mode", toString(c.options.foldRepair)},
          {"cut", cut},
          {"turned_normals", r.turnedNormals},
          {"turned_corners", r.turnedCorners},
          {"mean_degrees", r.meanDegrees},
          {"max_degrees", r.maxDegrees},
          {"untangled_vertices", r.untangledVertices},
          {"max_tangent_turn_degrees", r.maxTangentTurnDeg},
          {"edge_curves", r.edgeCurves},
          {"changed", changed}};
}

nlohmann::ordered_json certificateJson(const PatchCache& c) {
  const CertificateSummary s = summarizeCertificates(c);
  if (!s.present) return nullptr;
  return {{"certified", s.certified},
          {"undecided", s.undecided},
          {"folded", s.folded},
          {"min_margin", s.minMargin},
          {"uncertified_faces", s.uncertifiedFaces},
          {"folded_faces", s.foldedFaces}};
}

std::vector<int> histogram(const PatchCache& c) {
  std::vector<int> h;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    if (static_cast<int>(h.size()) <= n) h.resize(n + 1, 0);
    ++h[n];
  }
  return h;
}

void build(const std::string& mesh, std::string out, const PatchArgs& args, bool certify) {
  if (isPatchCacheFile(mesh)) throw InputError(mesh + ": is already a patch cache; give a mesh file");
  const PatchOptions opt = args.options();
  LoadedMesh lm = loadMesh(mesh, opt);
  const MeshReport& r = lm.report;
  std::printf("mesh: %s (%d vertices, %d faces: %s)\n", mesh.c_str(), r.numVertices, r.numFaces,
              faceSizeText(r.faceSizeHistogram).c_str());
  for (const std::string& line : lm.seams.describe()) std::printf("  %s\n", line.c_str());
  for (const std::string& line : r.describe()) std::printf("  %s\n", line.c_str());
  for (const std::string& line : lm.orientation.describe()) std::printf("%s\n", line.c_str());
  if (lm.flipped)
    std::printf(
        "orientation: closed mesh faced inward (signed volume %.6g): flipped to outward "
        "(--orient keep to keep)\n",
        r.signedVolume);
  if (opt.cage != CageMode::None)
    std::printf("cage: %s: %d vertices moved to their limit positions (%d on a boundary; boundaries edge-and-corner)\n",
                toString(opt.cage), r.numVertices - static_cast<int>(r.unreferencedVertices.size()),
                lm.cageBoundaryVertices);
  std::printf("normals: %s\n", toString(opt.normals));
  for (const std::string& line : lm.normalReport.describe()) std::printf("  %s\n", line.c_str());
  if (opt.foldRepair != FoldRepairMode::Off && (!lm.split.splitFaces.empty() || !lm.split.unsplitFaces.empty())) {
    std::printf(
        "fold repair: %s: %zu flat %s with a reflex or straight corner cut into %d convex pieces (faces as read:%s)\n",
        toString(opt.foldRepair), lm.split.splitFaces.size(), lm.split.splitFaces.size() == 1 ? "polygon" : "polygons",
        lm.split.pieces, faceIdsText(lm.split.splitFaces).c_str());
    if (!lm.split.unsplitFaces.empty())
      std::printf("  left whole (outline not simple, or no diagonal cuts them):%s\n",
                  faceIdsText(lm.split.unsplitFaces).c_str());
  }
  if (opt.foldRepair != FoldRepairMode::Off && (!lm.split.fannedFaces.empty() || !lm.split.unfannedFaces.empty())) {
    std::printf(
        "fold repair: %s: %zu %s as read (flat polygons with a straight corner between creases, more than 12 "
        "corners on their plane's one normal or more than 64 corners; a flat cap's "
        "triangles merged first, a flat annulus's into convex pieces) fanned into %d triangles about %d new centre "
        "%s and %d pieces cut off on diagonals (faces:%s)\n",
        toString(opt.foldRepair), lm.split.fannedFaces.size(), lm.split.fannedFaces.size() == 1 ? "face" : "faces",
        lm.split.fanTriangles, lm.split.addedVertices, lm.split.addedVertices == 1 ? "vertex" : "vertices",
        lm.split.fanPieces, faceIdsText(lm.split.fannedFaces).c_str());
    if (!lm.split.unfannedFaces.empty())
      std::printf("  left whole (no centre of theirs or of pieces cut on their diagonals sees every edge curve):%s\n",
                  faceIdsText(lm.split.unfannedFaces).c_str());
  }
  throwIfInterrupted("cache build");
  PatchCache cache = preparePatchCache(lm.mesh, lm.cornerNormals, opt, lm.fileHash);
  const double secs = construct(cache, args);
  throwIfInterrupted("cache build");
  if (opt.foldRepair == FoldRepairMode::Search) {
    for (const std::string& line : describeNormalSearch(finishFoldRepair(cache, args)))
      std::printf("%s\n", line.c_str());
    throwIfInterrupted("cache build");
  }
  printPatchSummary(cache);
  printCreases(cache);
  std::printf("build: %.3f ms on %s: %.0f patches/s\n", secs * 1e3, args.backend.c_str(),
              cache.numFaces() / std::max(secs, 1e-9));
  if (certify) {
    const auto t0 = std::chrono::steady_clock::now();
    const CertificateSummary run = certifyPatches(cache, args.threads);
    throwIfInterrupted("cache build");
    printCertificates(cache);
    if (run.regular > 0)
      std::printf("  of the certified, regular cell by cell (no one direction is a height-field direction):%s\n",
                  faceIdsText(run.regularFaces).c_str());
    std::printf("certificate: %.3f s on the CPU (oneTBB)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  if (out.empty()) out = std::filesystem::path(mesh).filename().replace_extension(".sfcache").string();
  writePatchCache(cache, out);
  std::error_code ec;  // (a device such as /dev/null, written in place, has no size)
  const uintmax_t bytes = std::filesystem::file_size(out, ec);
  const std::string size = ec ? "written in place (not a regular file)" : std::to_string(bytes) + " bytes";
  std::printf("cache: %s, %s (mesh hash %s)\n", out.c_str(), size.c_str(), hexHash(cache.meshHash).c_str());
}

nlohmann::ordered_json patchSummaryJson(const PatchCache& c) {
  const PatchStatusSummary s = summarizePatchStatus(c);
  return {{"built", c.numFaces() - s.notBuilt},
          {"not_built", s.notBuilt},
          {"guard_used", s.guard},
          {"folds", s.fold},
          {"bulges", s.bulge},
          {"max_bulge", s.maxBulge},
          {"degenerate", s.degenerateFaces.size()},
          {"fold_faces", s.foldFaces},
          {"bulge_faces", s.bulgeFaces},
          {"degenerate_faces", s.degenerateFaces},
          {"inside_out_faces", s.insideOutFaces}};
}

/// The surface faults of c's patch surface (measureSurfaceFaults on the uniform tessellation the
/// patch method's global query uses, or at `level` when it is not 0), as `cache info --faults`
/// reports them.
SurfaceFaults cacheSurfaceFaults(const PatchCache& c, int level) {
  if (!hasPatchData(c)) throw InputError("--faults: the cache holds no built patches");
  PatchSurfaceOptions o;
  o.windingOnly = true;  // only the uniform tessellation's rays are probed
  o.level = level;
  const PatchSurface surface(c, o);
  return measureSurfaceFaults(surface);
}

/// Intersecting and self-crossing polygons of the cache's base mesh (checkMesh on it: a cache
/// keeps its mesh), every pair and face listed.
nlohmann::ordered_json polygonsJson(const MeshReport& r) {
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array(), areas = nlohmann::ordered_json::array();
  for (const IntersectingPair& p : r.intersectingPairs) {
    pairs.push_back({p.a, p.b});
    areas.push_back({p.areaA, p.areaB});
  }
  return {{"area_m2", r.surfaceArea},
          {"intersecting_pairs", pairs},
          {"intersecting_pair_areas_m2", areas},
          {"intersecting_faces", r.intersectingFaces()},
          {"intersecting_area_m2", r.intersectingArea()},
          {"self_crossing_faces", r.selfCrossingFaces}};
}

void printPolygons(const MeshReport& r) {
  std::printf("polygons: %zu intersecting pairs, %zu self-crossing\n", r.intersectingPairs.size(),
              r.selfCrossingFaces.size());
  for (const std::string& line : r.describeInput()) std::printf("  %s\n", line.c_str());
}

nlohmann::ordered_json faultsJson(const SurfaceFaults& f, const FaultAttribution& a) {
  if (!f.closed) return {{"closed", false}};
  auto part = [&](SurfaceVerdict v) {
    const auto i = static_cast<size_t>(v);
    return nlohmann::ordered_json{{"triangles", f.count[i]}, {"area_m2", f.area[i]}};
  };
  return {{"closed", true},
          {"level", f.level},
          {"offset_m", f.offset},
          {"triangles", f.triangles},
          {"degenerate_triangles", f.count[static_cast<size_t>(SurfaceVerdict::Degenerate)]},
          {"area_m2", f.totalArea},
          {"fault_area_m2", f.faultArea()},
          {"fault_fraction", f.totalArea > 0 ? f.faultArea() / f.totalArea : 0.0},
          {"folded", part(SurfaceVerdict::Folded)},
          {"overlapping", part(SurfaceVerdict::Overlapping)},
          {"thin", part(SurfaceVerdict::Thin)},
          {"fault_faces", f.faultFaces()},
          {"input_fault_area_m2", a.inputArea},
          {"input_fault_faces", a.inputFaces},
          {"construction_fault_area_m2", a.constructionArea},
          {"construction_fault_faces", a.constructionFaces}};
}

void printFaults(const SurfaceFaults& f, const FaultAttribution& a) {
  if (!f.closed) {
    std::printf(
        "surface faults: not measured (the patch surface is not closed: a boundary edge, or a face without "
        "patch; no inside)\n");
    return;
  }
  auto at = [&](SurfaceVerdict v) { return f.area[static_cast<size_t>(v)]; };
  const std::vector<int> faces = f.faultFaces();
  std::printf(
      "surface faults (uniform tessellation level %d, %lld triangles probed %.3g m either side): fault area %.6g "
      "m^2 of %.6g (%.4f%%): folded %.6g, overlapping %.6g, thin %.6g; %zu faces\n",
      f.level, static_cast<long long>(f.triangles), f.offset, f.faultArea(), f.totalArea,
      f.totalArea > 0 ? 100.0 * f.faultArea() / f.totalArea : 0.0, at(SurfaceVerdict::Folded),
      at(SurfaceVerdict::Overlapping), at(SurfaceVerdict::Thin), faces.size());
  if (faces.empty()) return;
  std::printf("  fault faces (largest area first):%s\n", faceIdsText(faces).c_str());
  const auto share = [&](double area) { return f.totalArea > 0 ? 100.0 * area / f.totalArea : 0.0; };
  std::printf("  the input's (within reach of intersecting polygons): %.6g m^2 (%.4f%%), %zu faces%s%s\n", a.inputArea,
              share(a.inputArea), a.inputFaces.size(), a.inputFaces.empty() ? "" : ":",
              faceIdsText(a.inputFaces).c_str());
  std::printf("  the construction's: %.6g m^2 (%.4f%%), %zu faces%s%s\n", a.constructionArea, share(a.constructionArea),
              a.constructionFaces.size(), a.constructionFaces.empty() ? "" : ":",
              faceIdsText(a.constructionFaces).c_str());
}

/// The runtime structures the renderers of every method build from the cache (default options;
/// SharedGeometry; the patch method with each surface index: patch_surface for tessellation,
/// lazy_surface for bounds, which the servo loop holds), each with the bytes it holds: `cache info
/// --memory`.
std::vector<SharedGeometry::Part> runtimeMemory(const PatchCache& c) {
  SharedGeometry g(std::make_shared<const PatchCache>(c));
  ForceOptions o;
  for (SurfaceIndex index : {SurfaceIndex::Tessellation, SurfaceIndex::Bounds}) {
    o.surfaceIndex = index;
    g.makeRenderer(ForceMethod::Patch, o);
  }
  g.makeRenderer(ForceMethod::Direct, ForceOptions{});
  return g.memory();
}

nlohmann::ordered_json memoryJson(const std::vector<SharedGeometry::Part>& parts, int faces) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  size_t total = 0;
  for (const SharedGeometry::Part& p : parts) {
    list.push_back({{"name", p.name}, {"bytes", p.bytes}, {"bytes_per_face", double(p.bytes) / std::max(faces, 1)}});
    total += p.bytes;
  }
  return {{"parts", list}, {"total_bytes", total}};
}

void printMemory(const std::vector<SharedGeometry::Part>& parts, int faces) {
  std::printf("runtime memory (bytes held, per face of %d):", faces);
  for (const SharedGeometry::Part& p : parts)
    std::printf(" %s %zu (%.0f)", p.name.c_str(), p.bytes, double(p.bytes) / std::max(faces, 1));
  std::printf("\n");
}

void info(const std::string& path, bool json, bool faults, int faultsLevel, bool memory) {
  const PatchCache c = readPatchCache(path);
  std::vector<SharedGeometry::Part> parts;
  if (memory) parts = runtimeMemory(c);
  const auto bytes = static_cast<unsigned long long>(std::filesystem::file_size(path));
  int boundary = 0, nonManifold = 0;
  for (int32_t t : c.slotTwin) boundary += t == -1, nonManifold += t == -2;
  const std::vector<int> h = histogram(c);
  const unsigned format = cacheFormatVersion(c);  // what writePatchCache wrote
  const PolygonMesh base = cacheBaseMesh(c);
  const MeshReport polygons = checkMesh(base);
  std::optional<SurfaceFaults> sf;
  FaultAttribution split;
  if (faults) {
    sf = cacheSurfaceFaults(c, faultsLevel);
    split = attributeFaults(*sf, facesNearIntersections(base, polygons.intersectingPairs));
  }
  if (json) {
    nlohmann::ordered_json sizes = nlohmann::ordered_json::object();
    for (size_t n = 0; n < h.size(); ++n)
      if (h[n]) sizes[std::to_string(n)] = h[n];
    printJson(stdout, {{"cache", path},
                       {"format", format},
                       {"bytes", bytes},
                       {"mesh_hash", hexHash(c.meshHash)},
                       {"options_hash", hexHash(hashPatchOptions(c.options))},
                       {"vertices", c.numVertices()},
                       {"faces", c.numFaces()},
                       {"face_sizes", sizes},
                       {"edge_slots", c.numSlots()},
                       {"boundary_slots", boundary},
                       {"non_manifold_slots", nonManifold},
                       {"options",
                        {{"precision", toString(c.options.precision)},
                         {"cross_tangent", toString(c.options.crossTangent)},
                         {"normals", toString(c.options.normals)},
                         {"orient", c.options.keepOrientation ? "keep" : "outward"},
                         {"cage", toString(c.options.cage)},
                         {"creases", creaseMarksText(c.options.creases)},
                         {"crease_angle", c.options.creases.angleDeg},
                         {"fold_repair", toString(c.options.foldRepair)}}},
                       {"fold_repair", foldRepairJson(c)},
                       {"creases", creasesJson(c)},
                       {"polygons", polygonsJson(polygons)},
                       {"patches", patchSummaryJson(c)},
                       {"certificate", certificateJson(c)},
                       {"surface_faults", sf ? faultsJson(*sf, split) : nlohmann::ordered_json(nullptr)},
                       {"memory", memory ? memoryJson(parts, c.numFaces()) : nlohmann::ordered_json(nullptr)}});
    return;
  }
  std::printf("cache: %s, format %u, %llu bytes\n", path.c_str(), format, bytes);
  std::printf("mesh hash: %s, options hash: %s\n", hexHash(c.meshHash).c_str(),
              hexHash(hashPatchOptions(c.options)).c_str());
  std::printf("mesh: %d vertices, %d faces (%s), %d edge slots\n", c.numVertices(), c.numFaces(),
              faceSizeText(h).c_str(), c.numSlots());
  std::printf("edges: %d boundary slots, %d non-manifold or inconsistently oriented slots\n", boundary, nonManifold);
  std::printf(
      "options: precision %s, cross tangent %s, normals %s, orient %s, cage %s, creases %s, crease angle %g, fold "
      "repair %s\n",
      toString(c.options.precision), toString(c.options.crossTangent), toString(c.options.normals),
      c.options.keepOrientation ? "keep" : "outward", toString(c.options.cage),
      creaseMarksText(c.options.creases).c_str(), c.options.creases.angleDeg, toString(c.options.foldRepair));
  printFoldRepair(c);
  printCreases(c);
  printPolygons(polygons);
  printPatchSummary(c);
  printCertificates(c);
  if (sf) printFaults(*sf, split);
  if (memory) printMemory(parts, c.numFaces());
}

nlohmann::ordered_json directionJson(const DistanceDirection& d) {
  return {{"max", d.max},
          {"mean", d.mean},
          {"points", d.points},
          {"worst_face", d.worstFace},
          {"worst_point", {d.worstPoint.x(), d.worstPoint.y(), d.worstPoint.z()}}};
}

void distance(const std::string& path, const std::string& to, int level, bool json, int threads) {
  const PatchCache a = readPatchCache(path);
  PatchCache b;
  DistanceSurface bAs = DistanceSurface::Patches;
  if (isPatchCacheFile(to)) {
    b = readPatchCache(to);
  } else {  // a mesh: its polygons as read (oriented, nothing cut)
    PatchOptions o;
    o.foldRepair = FoldRepairMode::Off;
    b = preparePatchSkeleton(loadMesh(to, o), o);
    bAs = DistanceSurface::Polygons;
  }
  const SurfaceDistance d = measureSurfaceDistance(a, DistanceSurface::Patches, b, bAs, level, threads);
  const char* what = bAs == DistanceSurface::Patches ? "patches" : "polygons";
  if (json) {
    printJson(stdout, {{"cache", path},
                       {"to", to},
                       {"to_surface", what},
                       {"level", level},
                       {"levels_used", {d.levelA, d.levelB}},
                       {"diagonal_m", d.diagonal},
                       {"cache_to_other", directionJson(d.aToB)},
                       {"other_to_cache", directionJson(d.bToA)},
                       {"hausdorff", std::max(d.aToB.max, d.bToA.max)}});
    return;
  }
  std::printf("distance, fractions of the diagonal %.6g m (samples at level %d and %d):\n", d.diagonal, d.levelA,
              d.levelB);
  std::printf("  %s patches -> %s %s: max %.4e (face %d), mean %.4e, %zu points\n", path.c_str(), to.c_str(), what,
              d.aToB.max, d.aToB.worstFace, d.aToB.mean, d.aToB.points);
  std::printf("  %s %s -> %s patches: max %.4e (face %d), mean %.4e, %zu points\n", to.c_str(), what, path.c_str(),
              d.bToA.max, d.bToA.worstFace, d.bToA.mean, d.bToA.points);
  std::printf("  two-sided (Hausdorff of the samples): %.4e\n", std::max(d.aToB.max, d.bToA.max));
}

}  // namespace

void addCacheCommands(CLI::App& app) {
  CLI::App* cache = app.add_subcommand("cache", "Build or inspect a whole-mesh patch cache");
  cache->require_subcommand(1);

  auto* b = cache->add_subcommand("build", "Build every patch of MESH and write the cache file");
  auto mesh = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto args = std::make_shared<PatchArgs>();
  b->add_option("MESH", *mesh, "mesh file (.obj, .off, .ply)")->required();
  b->add_option("-o,--output", *out, "cache file to write (default: MESH's name with .sfcache)");
  addPatchArgs(*b, *args);
  auto certify = std::make_shared<bool>(false);
  b->add_flag("--certify", *certify,
              "also certify every patch: prove from interval bounds of its exact derivatives that it is regular and "
              "never turns back against its polygon or its neighbours (stored in the cache, format 2; seconds per "
              "patch)");
  b->callback([=] { build(*mesh, *out, *args, *certify); });

  auto* i = cache->add_subcommand("info", "Validate a cache file and describe it");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  i->add_option("CACHE", *path, "cache file")->required();
  i->add_flag("--json", *json,
              "print one JSON object instead of text: cache, format, bytes, mesh_hash, options_hash, vertices, "
              "faces, face_sizes, edge_slots, boundary_slots, non_manifold_slots, options, fold_repair (null when off; "
              "else the faces as read that were cut, each with its pieces, and under search the normals turned: "
              "counts, mean and max degrees, and per changed face its turned corners and changed edge curves), polygons (intersecting "
              "and self-crossing polygons of the mesh), patches, certificate (null when not computed), "
              "surface_faults, memory");
  auto faults = std::make_shared<bool>(false);
  CLI::Option* faultsOpt = i->add_flag("--faults", *faults,
              "also measure where the closed patch surface is at fault: the area of folded and overlapping patch "
              "surface (each triangle of the global query's tessellation probed on both sides by the winding "
              "number; the faces it lies on), split into the input's (on faces within reach of intersecting "
              "polygons: one of a pair or sharing a vertex with one) and the construction's; null in --json "
              "without it");
  auto faultsLevel = std::make_shared<int>(0);
  i->add_option("--faults-level", *faultsLevel,
                "with --faults, the uniform tessellation level probed (each polygon edge split in L), 1..64; 0: "
                "the global query's own. Folds and overlaps thinner than a triangle show only at finer levels")
      ->check(CLI::Range(0, 64))
      ->needs(faultsOpt)
      ->capture_default_str();
  auto memory = std::make_shared<bool>(false);
  i->add_flag("--memory", *memory,
              "also build what the renderers build from the cache (the patch method's polygon scene and, for a "
              "prebuilt cache, both indexes of its global query: patch_surface (--surface-index tessellation) and "
              "lazy_surface (bounds, what the servo loop holds), or a skeleton's lazy parts; the god-object's "
              "polygon scene) and report the bytes each holds, in all and per face (Embree's BVHs as its memory "
              "monitor counts them); null in --json without it");
  i->callback([=] { info(*path, *json, *faults, *faultsLevel, *memory); });

  auto* d = cache->add_subcommand(
      "distance", "How far the patch surface of CACHE lies from another surface, both ways: TO's patch surface (a "
                  "cache file: the same mesh under other options, --fold-repair off say) or TO's polygons (a mesh "
                  "file: a dense mesh of the same shape)");
  auto dPath = std::make_shared<std::string>();
  auto dTo = std::make_shared<std::string>();
  auto dLevel = std::make_shared<int>(8);
  auto dJson = std::make_shared<bool>(false);
  auto dThreads = std::make_shared<int>(0);
  d->add_option("CACHE", *dPath, "cache file (prebuilt)")->required();
  d->add_option("--to", *dTo, "cache file (its patch surface) or mesh file (.obj, .off, .ply: its polygons, flat)")
      ->required();
  d->add_option("--level", *dLevel,
                "samples: each patch on the rings of its level-L tessellation (1 + n L (L+1) / 2 points per "
                "n-gon), each polygon on the same rings over its fan triangles; a surface that would give more "
                "than about 4 million samples is sampled at the highest level that does not")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  d->add_option("--threads", *dThreads, "worker threads (0 = all cores)")->check(CLI::Range(0, 4096))
      ->capture_default_str();
  d->add_flag("--json", *dJson,
              "print one JSON object: cache, to, to_surface (patches|polygons), level, levels_used (the cache's, "
              "the other's), diagonal_m, cache_to_other "
              "and other_to_cache (max, mean: fractions of the diagonal; points, worst_face, worst_point: m), "
              "hausdorff");
  d->callback([=] { distance(*dPath, *dTo, *dLevel, *dJson, *dThreads); });
}

}  // namespace sf::cli
