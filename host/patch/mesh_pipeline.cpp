// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/mesh_pipeline.h>

#include <array>

#include <Eigen/Geometry>

#include <smoothforce/base/error.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/straight_corner_split.h>
#include "gp_config.h"  // GP_* status bits and record layout

namespace sf {

LoadedMesh loadMesh(const std::string& path, const PatchOptions& options) {
  PolygonMesh mesh = readMesh(path);
  Eigen::Vector3d lo, hi;
  referencedBox(mesh, lo, hi);
  if (const std::string why = floatReachProblem(lo, hi, options.precision); !why.empty())
    throw InputError(path + ": " + why);
  const uint64_t hash = hashFile(path);
  return loadMesh(std::move(mesh), hash, options);
}

LoadedMesh loadMesh(PolygonMesh mesh, uint64_t meshHash, const PatchOptions& options) {
  LoadedMesh out;
  out.mesh = std::move(mesh);
  out.fileHash = meshHash;
  // under outward orientation, faces written turned against their neighbours join them too:
  // orientCoherently turns them back
  out.seams = stitchSeams(out.mesh, !options.keepOrientation);
  if (!options.keepOrientation) out.orientation = orientCoherently(out.mesh);
  out.report = checkMesh(out.mesh);
  out.flipped =
      applyOrientation(out.mesh, out.report, options.keepOrientation ? OrientPolicy::Keep : OrientPolicy::Outward);
  if (options.cage == CageMode::None) {
    out.cornerNormals = cornerNormals(out.mesh, options.normals, out.normalReport, options.creases);
  } else {
    // the cage's limit normals are the surface's own: file or polygon normals would describe the cage
    if (options.normals != NormalMode::Auto)
      throw InputError((out.mesh.sourcePath.empty() ? std::string("mesh") : out.mesh.sourcePath) + ": --cage " +
                       toString(options.cage) + " uses the limit surface's normals: --normals " +
                       toString(options.normals) + " cannot be combined with it (leave --normals auto)");
    CageLimit limit = catmullClarkLimit(out.mesh, out.report);
    out.cagePositions = std::move(out.mesh.positions);
    out.mesh.positions = std::move(limit.positions);
    out.cageBoundaryVertices = limit.boundaryVertices;
    out.cornerNormals.resize(out.mesh.faceVertices.size());
    for (size_t c = 0; c < out.mesh.faceVertices.size(); ++c)
      out.cornerNormals[c] = limit.normals[out.mesh.faceVertices[c]];
    out.normalReport = NormalReport{};
    out.normalReport.mode = options.normals;
    out.normalReport.source = NormalSource::CageLimit;
    out.normalReport.fallbackVertices = std::move(limit.fallbackVertices);
    out.normalReport.fileHasNormals = !out.mesh.fileNormals.empty() || !out.mesh.fileCornerNormals.empty();
  }
  if (options.foldRepair != FoldRepairMode::Off) {
    out.split = splitBadCorners(out.mesh, &out.cornerNormals);
    splitStraightPatchCorners(out.mesh, out.cornerNormals, options, out.split);
  }
  out.normalFallbacks = out.normalReport.fallbackVertices;
  out.creaseCorners = out.normalReport.creaseCorners;
  return out;
}

PatchCache buildPatchCache(const LoadedMesh& loaded, const PatchOptions& options, Backend backend, int threads) {
  PatchCache cache = preparePatchCache(loaded.mesh, loaded.cornerNormals, options, loaded.fileHash);
  constructPatches(cache, backend, threads);
  return cache;
}

PatchCache preparePatchSkeleton(const LoadedMesh& loaded, const PatchOptions& options) {
  return preparePatchCache(loaded.mesh, loaded.cornerNormals, options, loaded.fileHash, false);
}

PolygonMesh cacheBaseMesh(const PatchCache& cache) {
  PolygonMesh m;
  m.positions.resize(cache.numVertices());
  for (int v = 0; v < cache.numVertices(); ++v)
    m.positions[v] = {cache.positions[3 * v], cache.positions[3 * v + 1], cache.positions[3 * v + 2]};
  m.faceOffsets = cache.faceOffsets;
  m.faceVertices = cache.faceVertices;
  m.faceSource = cache.faceSource;
  return m;
}

PatchStatusSummary summarizePatchStatus(const PatchCache& cache) {
  PatchStatusSummary s;
  for (int f = 0; f < cache.numFaces(); ++f) {
    const uint32_t st = cache.faceStatus[f];
    s.guard += (st & GP_ST_GUARD) != 0;
    s.zeroEdge += (st & GP_ST_ZERO_EDGE) != 0;
    s.edgeNormal += (st & GP_ST_EDGE_NORMAL) != 0;
    s.crossTangent += (st & GP_ST_CROSS_TANGENT) != 0;
    s.notBuilt += (st & GP_ST_NOT_BUILT) != 0;
    if (st & GP_ST_FOLD) {
      ++s.fold;
      s.foldFaces.push_back(f);
    }
    if (st & GP_ST_BULGE) {
      ++s.bulge;
      s.bulgeFaces.push_back(f);
    }
    if (st & GP_ST_DEGENERATE_MASK) s.degenerateFaces.push_back(f);
    if (st & GP_ST_AFFINE) s.affineFaces.push_back(f);
    s.maxBulge = std::max(s.maxBulge, cache.faceBulge[f]);
  }
  if (!hasPatchData(cache)) return s;
  std::array<double, GP_MAX_N * GP_E_NFIELDS> d;
  std::array<float, GP_MAX_N * GP_E_NFIELDS> fl;
  for (int f = 0; f < cache.numFaces(); ++f) {
    const int n = cache.faceSize(f);
    if (n < 3 || n > GP_MAX_N || (cache.faceStatus[f] & GP_ST_NOT_BUILT)) continue;
    if (cache.options.precision == Precision::Double) {
      gatherRecords(cache, f, d.data());
    } else {
      gatherRecords(cache, f, fl.data());
      std::copy_n(fl.begin(), size_t(n) * GP_E_NFIELDS, d.begin());
    }
    bool insideOut = false;
    for (int k = 0; k < n && !insideOut; ++k) {
      const double* a = &d[size_t(k) * GP_E_NFIELDS + GP_E_M0];  // C_k'(0)
      const double* b = &d[size_t((k + n - 1) % n) * GP_E_NFIELDS + GP_E_M1];  // C_k-1'(1)
      const double* m = &d[size_t(k) * GP_E_NFIELDS + GP_E_N0];
      const Eigen::Vector3d out(a[0], a[1], a[2]), in(-b[0], -b[1], -b[2]), normal(m[0], m[1], m[2]);
      insideOut = out.cross(in).dot(normal) < 0;
    }
    if (insideOut) s.insideOutFaces.push_back(f);
  }
  return s;
}

std::string faceIdsText(const std::vector<int>& ids) {
  std::string s;
  for (size_t i = 0; i < ids.size() && i < 10; ++i) (s += ' ') += std::to_string(ids[i]);
  if (ids.size() > 10) s += " ...";
  return s;
}

}  // namespace sf
