// SPDX-License-Identifier: Apache-2.0
// The fold repair's untangled vertex fans (tangent_fans.h), over every shared mesh: read from the
// built records alone, on a closed manifold mesh every fan of one normal leaves its vertex in the faces' order with
// consecutive edge tangents 1 to 179 degrees apart, no corner is inside out there, every given
// tangent lies in its vertex's tangent plane, and the faces at no tangled fan keep the records of
// the construction as read (fold repair off) bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/tangent_fans.h>

#include "patch_test_support.h"
#include "shared_mesh_files.h"
#include "tilted_cube_support.h"

namespace sf {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Vector3d positionOf(const PatchCache& c, int v) {
  return {c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]};
}

/// The records' end tangent directions at every corner's vertex, by the mesh's directed edges
/// (independent of the cache's adjacency): out[(v, w)] = C'(0) of the edge v -> w of the face that
/// runs it so, and the normal of each corner.
struct Fans {
  std::map<std::pair<int, int>, Eigen::Vector3d> out;     // unit direction leaving v toward w
  std::map<std::pair<int, int>, int> faceOf;              // the face running v -> w
  std::map<int, std::vector<Eigen::Vector3d>> normals;    // corner normals at v
  std::map<int, std::vector<std::pair<int, int>>> edges;  // (next, prev) of each corner at v
};

Fans fansOf(const PatchCache& c) {
  Fans r;
  const size_t ns = c.numSlots();
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f), first = c.faceOffsets[f];
    for (int k = 0; k < n; ++k) {
      const size_t s = first + k;
      const int v = c.faceVertices[s], w = c.faceVertices[first + (k + 1) % n],
                p = c.faceVertices[first + (k + n - 1) % n];
      const Eigen::Vector3d m0(c.edgeDataD[GP_E_M0 * ns + s], c.edgeDataD[(GP_E_M0 + 1) * ns + s],
                               c.edgeDataD[(GP_E_M0 + 2) * ns + s]);
      r.out[{v, w}] = m0.normalized();
      r.faceOf[{v, w}] = f;
      r.normals[v].emplace_back(c.cornerNormals[3 * s], c.cornerNormals[3 * s + 1], c.cornerNormals[3 * s + 2]);
      r.edges[v].push_back({w, p});
    }
  }
  return r;
}

/// Vertex v's fan as the faces order it (walking corner to corner: the edge v -> prev of one face
/// is the edge v -> next of the next), or empty where it does not close (boundary, non-manifold)
/// or the normals at v differ.
std::vector<int> orderedFan(const Fans& fans, int v) {
  const auto& corners = fans.edges.at(v);
  for (const Eigen::Vector3d& n : fans.normals.at(v))
    if (n != fans.normals.at(v)[0]) return {};
  std::map<int, int> nextOf;  // next -> prev of the same corner
  for (const auto& [w, p] : corners)
    if (!nextOf.emplace(w, p).second) return {};
  std::vector<int> order;  // the far ends of the edges, in order
  int w = corners[0].first;
  for (size_t i = 0; i < corners.size(); ++i) {
    order.push_back(w);
    const auto it = nextOf.find(w);
    if (it == nextOf.end()) return {};
    w = it->second;
  }
  return w == corners[0].first ? order : std::vector<int>{};
}

TEST(TangentFans, EveryFanRunsInTheFacesOrderAndOnlyTangledFansChangeTheirFaces) {
  int insideOutOn = 0, insideOutOff = 0;
  int meshes = 0, fans = 0, tangled = 0, untangled = 0, changedFaces = 0, keptFaces = 0, given = 0, turnedEnds = 0;
  std::map<std::string, int> perMesh;
  // every shared mesh, and cubes whose file normal at one corner is turned 90, 120 and 150
  // degrees (inputs built to fold: that corner's fan tangles)
  std::vector<std::pair<std::string, NormalMode>> inputs;
  for (const std::string& path : test::sharedMeshFiles()) inputs.emplace_back(path, NormalMode::Auto);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("sf_tangent_fans_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const double tilt : {90.0, 120.0, 150.0}) inputs.emplace_back(test::writeTiltedCube(dir, tilt), NormalMode::File);
  for (const auto& [path, normals] : inputs) {
    SCOPED_TRACE(path);
    PatchOptions on, off;
    on.normals = off.normals = normals;
    off.foldRepair = FoldRepairMode::Off;
    const LoadedMesh mesh = loadMesh(path, on);
    if (!mesh.split.splitFaces.empty()) continue;  // a cut changes the faces: fold_repair_split tests those
    const PatchCache a = buildPatchCache(mesh, on, Backend::Tbb);
    const PatchCache b = buildPatchCache(mesh, off, Backend::Tbb);
    ASSERT_EQ(a.faceVertices, b.faceVertices);
    ++meshes;
    const Fans built = fansOf(a), read = fansOf(b);
    // closed and manifold: every directed edge once, and its reverse there (the repair's domain)
    bool closed = built.out.size() == a.faceVertices.size();
    for (const auto& [e, d] : built.out) closed = closed && built.out.count({e.second, e.first});
    std::set<int> tangledHere;
    const double lo = kFanTangledGapDeg * kPi / 180;
    for (const auto& [v, corners] : built.edges) {
      const std::vector<int> order = orderedFan(built, v);
      if (order.size() < 3) continue;
      const Eigen::Vector3d N = built.normals.at(v)[0];
      const Eigen::Vector3d u = (std::fabs(N.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
                                    .cross(N)
                                    .normalized(),
                            w = N.cross(u);
      auto gaps = [&](const Fans& f, double* winding) {
        std::vector<double> g;
        *winding = 0;
        for (size_t i = 0; i < order.size(); ++i) {
          const Eigen::Vector3d d0 = f.out.at({v, order[i]}), d1 = f.out.at({v, order[(i + 1) % order.size()]});
          double x = std::atan2(d1.dot(w), d1.dot(u)) - std::atan2(d0.dot(w), d0.dot(u));
          x = std::fmod(x + 4 * kPi, 2 * kPi);
          g.push_back(x);
          *winding += x;
        }
        return g;
      };
      ++fans;
      double wRead = 0, wBuilt = 0;
      bool bad = false;  // tangled as the construction builds it
      for (const double x : gaps(read, &wRead)) bad = bad || x < lo || x > kPi - lo;
      bad = bad || std::fabs(wRead - 2 * kPi) > 1e-9;
      bad = bad && closed;  // elsewhere the construction's fans stay
      if (bad) tangledHere.insert(v);
      // on a closed mesh the built fan is in order, every gap within [1, 179] degrees, and where
      // it was tangled within [g, 180 - g], g = min(10, 180 / valence) degrees (up to rounding)
      const double g = bad ? std::min(kFanGapDeg * kPi / 180, kPi / order.size()) : lo;
      const std::vector<double> builtGaps = gaps(built, &wBuilt);
      if (!closed) continue;
      for (const double x : builtGaps) {
        EXPECT_GE(x, g - 1e-9) << "vertex " << v;
        EXPECT_LE(x, kPi - g + 1e-9) << "vertex " << v;
      }
      EXPECT_NEAR(wBuilt, 2 * kPi, 1e-9) << "vertex " << v;
      // every tangent at v in the tangent plane of N
      for (const int t : order) EXPECT_LT(std::fabs(built.out.at({v, t}).dot(N)), 1e-12) << "vertex " << v;
      // every tangent runs forward along its edge, within kFanMaxChordTurnDeg of its chord there
      for (const int t : order) {
        const Eigen::Vector3d e = positionOf(a, t) - positionOf(a, v), et = e - e.dot(N) * N;
        const double cosine = built.out.at({v, t}).dot(et.normalized());
        EXPECT_GT(built.out.at({v, t}).dot(e), 0) << "vertex " << v;
        if (bad) {
          EXPECT_GE(cosine, std::cos(kFanMaxChordTurnDeg * kPi / 180) - 1e-9) << "vertex " << v;
        }
      }
    }
    const TangentFans tf = untangleTangentFans(a);
    EXPECT_EQ(std::set<int>(tf.vertices.begin(), tf.vertices.end()), tangledHere);
    // the turns it reports: at every end of every edge, the angle between the records' end
    // tangents built and as read (the construction's own); turned only at the tangled vertices
    if (tf.vertices.empty()) {
      EXPECT_TRUE(tf.turnDeg.empty());
    } else {
      const size_t ns = a.numSlots();
      ASSERT_EQ(tf.turnDeg.size(), 2 * ns);
      double largest = 0;
      for (int f = 0; f < a.numFaces(); ++f)
        for (int k = 0; k < a.faceSize(f); ++k)
          for (int end = 0; end < 2; ++end) {
            const size_t s = a.faceOffsets[f] + k;
            const size_t field = end ? GP_E_M1 : GP_E_M0;
            const Eigen::Vector3d x(a.edgeDataD[field * ns + s], a.edgeDataD[(field + 1) * ns + s],
                                    a.edgeDataD[(field + 2) * ns + s]),
                y(b.edgeDataD[field * ns + s], b.edgeDataD[(field + 1) * ns + s], b.edgeDataD[(field + 2) * ns + s]);
            const double deg = std::atan2(x.cross(y).norm(), x.dot(y)) * 180 / kPi;
            const double turn = tf.turnDeg[2 * s + end];
            EXPECT_NEAR(turn, deg, 1e-9) << "face " << f << " edge " << k << " end " << end;
            const int v = a.faceVertices[a.faceOffsets[f] + (k + end) % a.faceSize(f)];
            if (turn > 1e-9) {
              EXPECT_TRUE(tangledHere.count(v)) << "face " << f << " edge " << k << " end " << end;
              ++turnedEnds;
            }
            largest = std::max(largest, turn);
          }
      EXPECT_EQ(largest, tf.maxTurnDeg);
    }
    tangled += static_cast<int>(tangledHere.size());
    untangled += static_cast<int>(tf.vertices.size());
    perMesh[std::filesystem::path(path).filename().string()] = static_cast<int>(tangledHere.size());
    // faces with no corner at a tangled fan: bit for bit the construction as read
    for (int f = 0; f < a.numFaces(); ++f) {
      bool touches = false;
      for (int k = 0; k < a.faceSize(f); ++k) {
        const int v = a.faceVertices[a.faceOffsets[f] + k];
        touches = touches || tangledHere.count(v) || tangledHere.count(a.faceVertices[a.faceOffsets[f] + (k + 1) % a.faceSize(f)]);
      }
      given += faceHasEdgeTangents(a, f);
      if (touches) {
        ++changedFaces;
        continue;
      }
      ++keptFaces;
      EXPECT_FALSE(faceHasEdgeTangents(a, f)) << "face " << f;
      EXPECT_TRUE(test::sameStatusAsDesign(a.faceStatus[f], b.faceStatus[f]))
          << "face " << f << ": " << a.faceStatus[f] << " against " << b.faceStatus[f];
      const size_t ns = a.numSlots();
      for (int k = 0; k < a.faceSize(f); ++k)
        for (size_t i = 0; i < GP_E_NFIELDS; ++i)
          ASSERT_EQ(a.edgeDataD[i * ns + a.faceOffsets[f] + k], b.edgeDataD[i * ns + b.faceOffsets[f] + k])
              << "face " << f << " corner " << k << " field " << i;
    }
    const int insideOut = static_cast<int>(summarizePatchStatus(a).insideOutFaces.size());
    if (path.ends_with("spot_control_mesh.obj")) {
      EXPECT_EQ(insideOut, 0);  // 20 as read
    }
    insideOutOn += insideOut;
    insideOutOff += static_cast<int>(summarizePatchStatus(b).insideOutFaces.size());
  }
  std::printf("untangled fans over %d meshes: %d closed fans of one normal, %d tangled (untangled %d); %d faces "
              "changed, %d kept bit for bit, %d given tangents, %d edge ends turned; faces with a corner inside out %d (off: "
              "%d)\n",
              meshes, fans, tangled, untangled, changedFaces, keptFaces, given, turnedEnds, insideOutOn, insideOutOff);
  for (const auto& [name, count] : perMesh)
    if (count) std::printf("  %s: %d\n", name.c_str(), count);
  EXPECT_EQ(untangled, tangled);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(perMesh["spot_control_mesh.obj"], 22);
  EXPECT_GT(meshes, 20);
  EXPECT_EQ(changedFaces, given);
  EXPECT_EQ(turnedEnds, 106);  // 92 on the spot cage (each edge end counted in both its faces)
  // the corners still inside out are on the meshes this leaves alone: the Stanford bunnies, open
  // and non-manifold (the spot cage had 20, each tilted cube 2)
  EXPECT_EQ(insideOutOff, 290);
  EXPECT_EQ(insideOutOn, 264);
  for (const char* cube : {"cube_90.obj", "cube_120.obj", "cube_150.obj"}) EXPECT_EQ(perMesh[cube], 1) << cube;
}

}  // namespace
}  // namespace sf
