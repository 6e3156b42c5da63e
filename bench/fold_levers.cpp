// SPDX-License-Identifier: Apache-2.0
// Two normal levers against the folds and overlaps of the design page's construction, measured
// on a mesh: the fault area (surface_faults.h) and the faces whose sampled patch normal turns
// against the polygon's (24 x 24 domain grid), for the construction as built, after replacing
// every vertex normal by the minimax normal of its faces (the direction that maximises the
// smallest cosine to the incident face normals), and after pulling the normals of such faces'
// corners towards the face normals (12 rounds of 25%, at most 60 degrees from the original).
// Both keep G1 (every edge curve is still built from its own vertices' normals).
// With --search, the normals that searchNormalsAgainstFaults finds instead (normal_search.h).
//   fold_levers MESH [--cage] [--search [--level L] [--passes P] [--polish-level L] [--bound DEG] [--no-symmetry]
//                         [-o CACHE] [--crease-angle DEG]]
//   (docs/fold-levers.md; --no-symmetry: NormalSearchOptions::keepSymmetry false; --polish-level:
//   NormalSearchOptions::polishLevel, -1 for no last pass)
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/normal_search.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/surface_faults.h>
#include "bench_common.h"

using namespace sf;

namespace {

/// The polygons' unit Newell normals and the face of every slot (the positions never move here).
struct Faces {
  std::vector<Eigen::Vector3d> normal;  // #F
  std::vector<int> ofSlot;              // #C
  explicit Faces(const PatchCache& c) : ofSlot(c.numSlots()) {
    const PolygonMesh base = cacheBaseMesh(c);
    for (int f = 0; f < c.numFaces(); ++f) {
      normal.push_back(newellNormal(base, f).normalized());
      for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) ofSlot[s] = f;
    }
  }
};

/// The smallest cosine between the patch normal and the face normal over a g x g grid of the
/// domain's box (points at least 1e-9 inside the domain).
double minCos(const PatchCache& c, const Faces& faces, int f, int g) {
  const int n = c.faceSize(f);
  double worst = 2;
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j) {
      const double x = -1 + 2.0 * i / g, y = -1 + 2.0 * j / g;
      if (!insideDomain(n, x, y, -1e-9)) continue;
      const PatchPoint p = evaluatePatch(c, f, x, y);
      const Eigen::Vector3d N = p.dxi.cross(p.deta);
      worst = std::min(worst, N.norm() > 0 ? N.dot(faces.normal[f]) / N.norm() : -1.0);
    }
  return worst;
}
void report(const char* tag, const PatchCache& c, const Faces& faces) {
  int bad = 0;
  std::string ids;
  for (int f = 0; f < c.numFaces(); ++f)
    if (minCos(c, faces, f, 24) <= 0) {
      ++bad;
      if (bad <= 12) {
        ids += ' ';
        ids += std::to_string(f);
      }
    }
  PatchSurface s(c);
  const SurfaceFaults sf = measureSurfaceFaults(s);
  std::string top;
  if (sf.closed) {
    const std::vector<int> ff = sf.faultFaces();
    for (size_t i = 0; i < ff.size() && i < 6; ++i) {
      char b[48];
      std::snprintf(b, sizeof b, " %d (%.2f%%)", ff[i], 100 * sf.faceFault[ff[i]] / sf.totalArea);
      top += b;
    }
  }
  char area[64] = "- (not closed)";
  if (sf.closed) std::snprintf(area, sizeof area, "%.3f%%, largest:", 100 * sf.faultArea() / sf.totalArea);
  std::printf("%-24s turned-over faces %3d [%s%s ]  fault area %s%s\n", tag, bad, ids.c_str(), bad > 12 ? " ..." : "",
              area, top.c_str());
}

/// Corners at one vertex with one normal (a crease splits them): the unit a normal lever moves
/// (vertexNormalGroups), and each corner's group.
struct NormalGroups {
  std::vector<std::vector<int>> slots;
  std::vector<int> of;  // #C
  explicit NormalGroups(const PatchCache& c) : slots(vertexNormalGroups(c)), of(c.numSlots()) {
    for (size_t g = 0; g < slots.size(); ++g)
      for (const int s : slots[g]) of[s] = static_cast<int>(g);
  }
};

Eigen::Vector3d normalAt(const PatchCache& c, int s) {
  return {c.cornerNormals[3 * s], c.cornerNormals[3 * s + 1], c.cornerNormals[3 * s + 2]};
}
void setNormal(PatchCache& c, const std::vector<int>& slots, const Eigen::Vector3d& n) {
  for (int s : slots)
    for (int i = 0; i < 3; ++i) c.cornerNormals[3 * s + i] = n[i];
}

/// Every group's normal replaced by the minimax normal of its faces (projected subgradient
/// ascent on the sphere from the original), where that raises the smallest cosine.
void minimaxNormals(PatchCache& c, const Faces& faces) {
  const NormalGroups g(c);
  double worstBefore = 1, worstAfter = 1;
  int changed = 0;
  for (const std::vector<int>& slots : g.slots) {
    std::vector<Eigen::Vector3d> fn;
    for (int s : slots) fn.push_back(faces.normal[faces.ofSlot[s]]);
    auto minDot = [&](const Eigen::Vector3d& m) {
      double w = 2;
      for (const auto& a : fn) w = std::min(w, m.dot(a));
      return w;
    };
    const Eigen::Vector3d n0 = normalAt(c, slots[0]);
    const Eigen::Vector3d m = minimaxDirection(fn, n0, 2000);
    worstBefore = std::min(worstBefore, minDot(n0));
    worstAfter = std::min(worstAfter, minDot(m));
    if (minDot(m) > minDot(n0) + 1e-3) {
      setNormal(c, slots, m);
      ++changed;
    }
  }
  std::printf("  minimax: %d of %zu normals moved; smallest cosine to an incident face normal %.3f -> %.3f\n", changed,
              g.slots.size(), worstBefore, worstAfter);
}

/// Rounds of: every face whose sampled normal turns against its polygon (smallest cosine <= 0.05)
/// pulls its corners' normals 25% of the way towards its face normal, at most 60 degrees from the
/// original in all.
void pullNormals(PatchCache& c, const Faces& faces) {
  const NormalGroups g(c);
  const std::vector<double> orig = c.cornerNormals;
  const double cap = std::cos(60 * std::numbers::pi / 180);
  for (int round = 0; round < 12; ++round) {
    std::vector<Eigen::Vector3d> pull(g.slots.size(), Eigen::Vector3d::Zero());
    int bad = 0;
    for (int f = 0; f < c.numFaces(); ++f) {
      if (minCos(c, faces, f, 16) > 0.05) continue;
      ++bad;
      for (int s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) pull[g.of[s]] += faces.normal[f];
    }
    if (!bad) break;
    for (size_t i = 0; i < g.slots.size(); ++i) {
      if (pull[i].squaredNorm() == 0) continue;
      const int s0 = g.slots[i][0];
      const Eigen::Vector3d n0(orig[3 * s0], orig[3 * s0 + 1], orig[3 * s0 + 2]);
      Eigen::Vector3d m = (0.75 * normalAt(c, s0) + 0.25 * pull[i].normalized()).normalized();
      if (m.dot(n0) < cap) m = cap * n0 + std::sqrt(1 - cap * cap) * (m - m.dot(n0) * n0).normalized();
      setNormal(c, g.slots[i], m);
    }
    constructPatches(c, Backend::Tbb, 0);
  }
}

/// The normals found by searchNormalsAgainstFaults (normal_search.h).
void searchNormals(PatchCache& c, const NormalSearchOptions& so) {
  const NormalSearchReport r = searchNormalsAgainstFaults(c, so);
  double maxRot = 0;
  for (const NormalChange& ch : r.changes) maxRot = std::max(maxRot, ch.rotationDeg);
  std::printf("  search (level %d, %d %s, last pass at level %d, bound %.0f deg): %s; %zu normals turned (at most "
              "%.1f deg), %zu faces changed; fault %.4f%% -> %.4f%%; %lld candidates, %.1f s\n",
              r.searchLevel, so.passes, r.mirrorAxis >= 0 ? "passes, mirror pairs" : "passes", r.polishLevel,
              so.maxRotationDeg,
              r.applied ? "applied" : "not applied", r.changes.size(),
              maxRot, r.changedFaces.size(), 100 * r.faultBefore / r.totalArea, 100 * r.faultAfter / r.totalArea,
              static_cast<long long>(r.evaluations), r.seconds);
}

int run(std::vector<std::string> args) {
  NormalSearchOptions so;
  bool search = false, cage = false;
  std::string out;  // the searched cache, written there
  double creaseAngle = 0;
  std::vector<std::string> rest;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--cage") cage = true;
    else if (args[i] == "--search") search = true;
    else if (args[i] == "--level" && i + 1 < args.size()) so.searchLevel = std::stoi(args[++i]);
    else if (args[i] == "--passes" && i + 1 < args.size()) so.passes = std::stoi(args[++i]);
    else if (args[i] == "--polish-level" && i + 1 < args.size()) so.polishLevel = std::stoi(args[++i]);
    else if (args[i] == "--bound" && i + 1 < args.size()) so.maxRotationDeg = std::stod(args[++i]);
    else if (args[i] == "--no-symmetry") so.keepSymmetry = false;
    else if (args[i] == "--crease-angle" && i + 1 < args.size()) creaseAngle = std::stod(args[++i]);
    else if (args[i] == "-o" && i + 1 < args.size()) out = args[++i];
    else rest.push_back(args[i]);
  }
  if (rest.size() != 1) {
    std::fprintf(stderr,
                 "usage: fold_levers MESH [--cage] [--search [--level L] [--passes P] [--polish-level L] [--bound DEG] "
                 "[--no-symmetry] [-o CACHE] [--crease-angle DEG]]\n");
    return 2;
  }
  args = rest;
  PatchOptions o;
  if (cage) o.cage = CageMode::CatmullClark;
  o.creases.angleDeg = creaseAngle;
  o.foldRepair = FoldRepairMode::Search;  // the split of `on`, the construction's own fans: what the normals act on
  const PatchCache built = buildPatchCache(loadMesh(args[0], o), o, Backend::Tbb);
  const Faces faces(built);
  std::printf("%s%s: %d faces\n", std::filesystem::path(args[0]).filename().string().c_str(),
              o.cage == CageMode::None ? "" : " (Catmull-Clark limit)", built.numFaces());
  report("design page", built, faces);
  if (search) {
    PatchCache s = built;
    searchNormals(s, so);
    report("normals found by search", s, faces);
    std::printf("  fault area at fixed levels, design page -> search:");
    for (const int level : {16, 24, 32}) {  // folds thinner than the search level's triangles show here
      PatchSurfaceOptions po;
      po.windingOnly = true;
      po.level = level;
      const SurfaceFaults a = measureSurfaceFaults(PatchSurface(built, po)), b = measureSurfaceFaults(PatchSurface(s, po));
      if (a.closed) std::printf("  %d: %.4f%% -> %.4f%%", level, 100 * a.faultArea() / a.totalArea, 100 * b.faultArea() / b.totalArea);
    }
    std::printf("\n");
    if (!out.empty()) {
      writePatchCache(s, out);
    }
    return 0;
  }
  PatchCache a = built;
  minimaxNormals(a, faces);
  constructPatches(a, Backend::Tbb, 0);
  report("minimax normals", a, faces);
  PatchCache b = built;
  pullNormals(b, faces);
  report("normals pulled to faces", b, faces);
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return bench::guardedMain("fold_levers", [&] { return run(std::vector<std::string>(argv + 1, argv + argc)); });
}
