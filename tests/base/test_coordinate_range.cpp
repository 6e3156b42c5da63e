// SPDX-License-Identifier: Apache-2.0
// Positions beyond the coordinate range (coordinate_range.h: 1e15 m) never reach Embree (whose
// Debian build aborts on a point beyond 1.8e18 m): every renderer reports such a HIP as
// SF_TRACK_BAD_HIP with no force and its state reset, every query finds nothing there, and the
// mesh and CSV readers refuse such coordinates naming the file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/csv_reader.h>
#include <smoothforce/base/error.h>
#include <smoothforce/base/status.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include <smoothforce/query/patch_surface.h>
#include "patch_test_support.h"
#include "surface_tessellation.h"

namespace sf {
namespace {

/// HIPs beyond the range on every axis, both signs, just beyond it up to the largest double,
/// and one not finite: 6 x 5 + 1.
std::vector<Eigen::Vector3d> outOfRange() {
  std::vector<Eigen::Vector3d> out;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0})
      for (double v : {1.01e15, 1e17, 1.9e18, 1e30, 1.7e308}) {
        Eigen::Vector3d p(0.01, 0.02, 0.03);
        p[axis] = sign * v;
        out.push_back(p);
      }
  out.emplace_back(NAN, 0, 0);
  return out;
}

/// The message of the InputError f() throws, or "" when it throws none.
template <class F>
std::string message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CoordinateRange, Predicate) {
  EXPECT_TRUE(inCoordinateRange(Eigen::Vector3d(1e15, -1e15, 0)));
  EXPECT_FALSE(inCoordinateRange(Eigen::Vector3d(0, 1.0000001e15, 0)));
  EXPECT_FALSE(inCoordinateRange(Eigen::Vector3d(0, 0, INFINITY)));
  EXPECT_FALSE(inCoordinateRange(Eigen::Vector3d(0, 0, NAN)));
}

/// A mesh's renderers of every kind (patch on a prebuilt cache, patch on lazy patches, each also
/// with model final steps, direct, shading) and a HIP 2% of the diagonal below the patch point at the centre of face 0
/// (below its polygon too): in contact for each.
struct EveryRenderer {
  explicit EveryRenderer(const std::string& rel) {
    const std::string path = test::sharedMesh(rel);
    auto cache = std::make_shared<const PatchCache>(test::cacheFromFile(path));
    auto skeleton = std::make_shared<const PatchCache>(test::skeletonFromFile(path));
    PatchPoint pp;
    const int32_t f0 = 0;
    const double x0 = 0, y0 = 0;
    evaluatePatches(*cache, &f0, &x0, &y0, 1, &pp, Backend::Serial);
    diag = boundingDiagonal(*cache);
    inside = pp.pos - 2e-2 * diag * pp.normal;
    renderers.push_back(makeForceRenderer(cache, ForceMethod::Patch, ForceOptions{}));
    renderers.push_back(makeForceRenderer(skeleton, ForceMethod::Patch, ForceOptions{}));
    ForceOptions model;
    model.finalStep = FinalStep::Model;
    renderers.push_back(makeForceRenderer(cache, ForceMethod::Patch, model));
    renderers.push_back(makeForceRenderer(skeleton, ForceMethod::Patch, model));
    renderers.push_back(makeForceRenderer(cache, ForceMethod::Direct, ForceOptions{}));
    renderers.push_back(makeForceRenderer(cache, ForceMethod::Shading, ForceOptions{}));
  }
  double diag = 0;
  Eigen::Vector3d inside;
  std::vector<std::unique_ptr<ForceRenderer>> renderers;
};

// Every renderer (EveryRenderer) on two meshes: in contact, then each out-of-range HIP: BAD_HIP, no contact, zero force; the next
// valid HIP is a contact start again (the state was reset), the same as after reset().
TEST(CoordinateRange, EveryRendererReportsABadHip) {
  const auto bad = outOfRange();
  ASSERT_EQ(bad.size(), 31u);
  int checked = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    EveryRenderer e(rel);
    for (size_t k = 0; k < e.renderers.size(); ++k) {
      ForceRenderer& r = *e.renderers[k];
      r.reset();
      const ForceSample fresh = r.step(e.inside);
      ASSERT_TRUE(fresh.contact) << rel << " " << k;
      for (const Eigen::Vector3d& hip : bad) {
        r.step(e.inside);  // in contact
        const ForceSample s = r.step(hip);
        EXPECT_TRUE(s.status & SF_TRACK_BAD_HIP) << rel << " " << hip.transpose();
        EXPECT_FALSE(s.contact);
        EXPECT_EQ(s.force.norm(), 0.0);
        const ForceSample again = r.step(e.inside);
        EXPECT_TRUE(again.contact);
        EXPECT_TRUE(again.status & SF_TRACK_ENTER) << "state reset";
        EXPECT_EQ(again.scp, fresh.scp) << "as after reset()";
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2 * 6 * 31);
}

// A HIP that jumps from a contact to farther from the object's box than the box's diagonal
// (farBeyondBox; within the coordinate range) leaves the contact with no force, for every
// method: from 1e14 m the patch method's tracking stalled and kept a contact of 5e16 N, the
// god-object one of 5e14 N at 1e12 m. Nearer, a HIP pushed through keeps its contact
// (ForceThinPlate.NoPopThroughForAnyMethod). 6 directions x 4 distances x 6 kinds x 2 meshes.
TEST(CoordinateRange, AJumpFarOutsideLeavesTheContact) {
  int checked = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    EveryRenderer e(rel);
    for (size_t k = 0; k < e.renderers.size(); ++k) {
      ForceRenderer& r = *e.renderers[k];
      for (int axis = 0; axis < 3; ++axis)
        for (const double sign : {1.0, -1.0})
          for (const double d : {10 * e.diag, 1e6, 1e12, 1e14}) {
            r.reset();
            ASSERT_TRUE(r.step(e.inside).contact) << rel;
            Eigen::Vector3d far = e.inside;
            far[axis] += sign * d;
            const ForceSample s = r.step(far);
            EXPECT_FALSE(s.contact) << rel << " " << k << " " << far.transpose();
            EXPECT_EQ(s.force.norm(), 0.0);
            ++checked;
          }
    }
  }
  EXPECT_EQ(checked, 2 * 6 * 6 * 4);
}

// The queries themselves, called directly: nothing found, no abort.
TEST(CoordinateRange, QueriesFindNothingBeyond) {
  const auto cache = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const PatchSurface surface(cache);
  const PolygonScene scene(cache);
  const LazyPatchSurface lazy(cache, scene.facets());
  CandidateBuffer<> c;
  int checked = 0;
  for (const Eigen::Vector3d& q : outOfRange()) {
    EXPECT_EQ(surface.candidates(q, c.data(), c.size()), 0u);
    EXPECT_FALSE(surface.inErrorBand(q));
    EXPECT_EQ(surface.winding(q), 0);
    EXPECT_LT(scene.nearest(q).facet, 0);
    EXPECT_FALSE(scene.contains(q, Eigen::Vector3d(0, 0, 1)));
    EXPECT_LT(scene.firstCrossing(q, Eigen::Vector3d::Zero()).facet, 0);
    FaceDistance fd[4];
    EXPECT_EQ(lazy.facesWithin(q, 1.0, fd, 4), 0u);
    ++checked;
  }
  EXPECT_EQ(checked, 31);
}

// A mesh far from the origin renders as it does at the origin (the float BVHs are built about
// the mesh, localOrigin; the signed volume that orients it is taken about it, checkMesh): the
// spot cage and the quad-sphere moved by 1e4 and 1e7 m, probes at 2 points per face (a step 1%
// of the diagonal out, then one 1% in): the same contact verdict at every step, forces within
// 1e-6 of the stiffness times the diagonal (the HIPs' own rounding at 1e7 m is 2e-9 m) or, at a
// tie (two patch points as near, at most 0.1% of the steps), the same distance; except
// where a step's SCP is held on a fold edge of the spot cage (SF_TRACK_FOLD_EDGE: two sides by
// itself; the verdict or the SCP may differ), at most 1% of the steps. At 1e7 m the moved spot cage was oriented inside
// out and the patch method found no contact at all before. The god-object (direct, shading) works about the mesh
// (GodObjectRenderer's local frame): before, at 1e7 m its proxy, rounded in world coordinates, left its facet's plane
// by 1e-9 m and fell through (a sweep of the moved spot cage missed 306 of 1,838 contacts).
TEST(CoordinateRange, AMeshFarFromTheOriginRendersAsAtTheOrigin) {
  int steps = 0, foldEdge = 0, ties = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    PatchOptions po;
    const LoadedMesh base = loadMesh(test::sharedMesh(rel), po);
    auto at = [&](const Eigen::Vector3d& shift) {
      PolygonMesh m = base.mesh;
      for (auto& p : m.positions) p += shift;
      return std::make_shared<const PatchCache>(buildPatchCache(loadMesh(std::move(m), 1, po), po, Backend::Tbb));
    };
    const auto home = at(Eigen::Vector3d::Zero());
    const double diag = boundingDiagonal(*home);
    // per face, the patch points at its centre and half-way to corner 0: 1% in, 1% out
    std::vector<Eigen::Vector3d> walk;
    for (int f = 0; f < home->numFaces(); ++f)
      for (const double x : {0.0, 0.5}) {
        PatchPoint pp;
        const double y = 0;
        evaluatePatches(*home, &f, &x, &y, 1, &pp, Backend::Serial);
        walk.push_back(pp.pos - 0.01 * diag * pp.normal);
        walk.push_back(pp.pos + 0.01 * diag * pp.normal);
      }
    for (const double d : {1e4, 1e7}) {
      const Eigen::Vector3d shift = d * Eigen::Vector3d(0.48, -0.6, 0.64);
      const auto moved = at(shift);
      for (const ForceMethod method : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading}) {
        auto a = makeForceRenderer(home, method, ForceOptions{}), b = makeForceRenderer(moved, method, ForceOptions{});
        for (size_t i = 0; i < walk.size(); i += 2) {  // a probe: from just outside to the HIP
          a->reset();
          b->reset();
          for (const Eigen::Vector3d& hip : {walk[i + 1], walk[i]}) {
            const ForceSample sa = a->step(hip), sb = b->step(hip + shift);
            ++steps;
            if ((sa.status | sb.status) & SF_TRACK_FOLD_EDGE) {
              // the verdict, or the SCP (one tracked contact held on the fold edge, the other
              // left it and was handed over by the global query), may differ
              const bool differ = sa.contact != sb.contact || (sa.force - sb.force).norm() >= 1e-6 * 500 * diag;
              foldEdge += differ;
              if (differ) continue;
            }
            EXPECT_EQ(sa.contact, sb.contact) << rel << " " << d << " " << int(method) << " " << hip.transpose();
            if ((sa.force - sb.force).norm() < 1e-6 * 500 * diag) continue;
            // the same verdict, another SCP: only a tie (two points as near; the quad-sphere's
            // symmetry), each rounding choosing one
            const double da = (sa.scp - hip).norm(), db = (sb.scp - (hip + shift)).norm();
            EXPECT_LT(std::abs(da - db), 1e-6 * diag) << rel << " " << d << " " << int(method);
            ++ties;
          }
        }
      }
    }
  }
  EXPECT_EQ(steps, 2 * 3 * 4 * (180 + 512));  // 2 shifts x 3 methods x 2 probes of 2 steps per face
  EXPECT_LE(foldEdge, steps / 100);
  EXPECT_LE(ties, steps / 1000);
}

// The patch surface of a mesh far from the origin aims no finer than its evaluation noise
// (evaluationNoise: the rounding of its coordinates): the spot cage moved by 1e7 m has the
// same tessellation level and adaptive triangle count as at home within 0.1% (the noise is far
// below the target there; the moved vertices round), and moved by 1e11 and 1e13 m at most as many. Before, at 1e13 m (where a
// coordinate rounds to 2 mm, 1e-3 of the cage's diagonal) every triangle was subdivided to the
// depth limit and a sweep ran out of memory.
TEST(CoordinateRange, PatchSurfaceFarFromTheOriginStaysTheSize) {
  PatchOptions po;
  const LoadedMesh base = loadMesh(test::sharedMesh("keenan_crane/spot_control_mesh.obj"), po);
  auto surfaceAt = [&](double d, size_t& adaptive) {
    PolygonMesh m = base.mesh;
    for (auto& p : m.positions) p += d * Eigen::Vector3d(0.48, -0.6, 0.64);
    const PatchCache cache = buildPatchCache(loadMesh(std::move(m), 1, po), po, Backend::Tbb);
    const PatchSurface surface(cache);
    adaptive = surface.numPointTriangles();
    return surface.level();
  };
  size_t home = 0, far = 0;
  const int homeLevel = surfaceAt(0, home);
  ASSERT_GT(home, 0u);
  EXPECT_EQ(surfaceAt(1e7, far), homeLevel);
  EXPECT_NEAR(double(far), double(home), 1e-3 * double(home));  // the moved vertices' rounding
  for (const double d : {1e11, 1e13}) {
    EXPECT_LE(surfaceAt(d, far), homeLevel) << d;
    EXPECT_LE(far, home) << d;
  }
}

// Float precision holds a mesh within kFloatReachDiagonals (100) diagonals of the origin; a mesh
// farther out (at 1e7 m float rounds the spot cage's coordinates by 1 m; a sweep of it ran at 75
// probes/s on noise) is refused with a message that names the file and asks for double: from a
// mesh file, from arrays (preparePatchCache) and from a float cache file written elsewhere. At 90
// diagonals it is built; double precision builds it at any distance in range.
TEST(CoordinateRange, FloatPrecisionRefusesAMeshFarFromTheOrigin) {
  const auto dir = std::filesystem::temp_directory_path() / ("sf_float_reach_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  PatchOptions fo;
  fo.precision = Precision::Float;
  const PolygonMesh cage = readMesh(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const LoadedMesh home = loadMesh(cage, 1, fo);
  const double diag = boundingDiagonal(buildPatchCache(home, fo, Backend::Serial));
  int refused = 0, built = 0;
  for (const double reach : {90.0, 110.0, 1e4, 1e7 / diag}) {  // the far corner's distance, in diagonals
    PolygonMesh m = cage;
    Eigen::Vector3d hi = m.positions[0];
    for (const auto& p : m.positions) hi = hi.cwiseMax(p);
    const double shift = reach * diag - hi.x();  // the largest coordinate at reach diagonals
    for (auto& p : m.positions) p.x() += shift;
    const std::string obj = (dir / ("far_" + std::to_string(int(reach)) + ".obj")).string();
    {
      std::ofstream out(obj);
      out.precision(17);
      for (const auto& p : m.positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      for (int f = 0; f < m.numFaces(); ++f) {
        out << 'f';
        for (int s = m.faceOffsets[f]; s < m.faceOffsets[f + 1]; ++s) out << ' ' << m.faceVertices[s] + 1;
        out << '\n';
      }
    }
    const LoadedMesh far = loadMesh(std::move(m), 1, PatchOptions{});
    if (reach < kFloatReachDiagonals) {
      EXPECT_EQ(message([&] { buildPatchCache(loadMesh(obj, fo), fo, Backend::Serial); }), "") << reach;
      ++built;
      continue;
    }
    std::string e = message([&] { loadMesh(obj, fo); });
    EXPECT_NE(e.find(obj + ": float precision: the mesh's coordinates reach"), std::string::npos) << e;
    EXPECT_NE(e.find("use double precision"), std::string::npos) << e;
    e = message([&] { preparePatchCache(far.mesh, far.cornerNormals, fo, 1); });
    EXPECT_NE(e.find("float precision"), std::string::npos) << e;
    EXPECT_NO_THROW(buildPatchCache(loadMesh(obj, PatchOptions{}), PatchOptions{}, Backend::Serial)) << reach;
    // a float cache file of such a mesh (written by another build): the home cache moved
    PatchCache moved = buildPatchCache(home, fo, Backend::Serial);
    for (size_t i = 0; i < moved.positions.size(); i += 3) moved.positions[i] += shift;
    const std::string file = (dir / "far.sfcache").string();
    writePatchCache(moved, file);
    e = message([&] { readPatchCache(file); });
    EXPECT_NE(e.find("far.sfcache"), std::string::npos) << e;
    EXPECT_NE(e.find("float precision"), std::string::npos) << e;
    ++refused;
  }
  EXPECT_EQ(built, 1);
  EXPECT_EQ(refused, 3);
  std::filesystem::remove_all(dir);
}

// A vertex no face references (which readers keep) sets no size: the spot cage with one at 1e14
// m renders as without it, every method, bit for bit (its diagonal, the polygons' box and the
// signed volume's frame are of the referenced vertices). Before, the diagonal was 1e14 m, every
// size-relative tolerance with it, and a sweep's 1% depth 1e12 m.
TEST(CoordinateRange, AStrayVertexSetsNoSize) {
  PatchOptions po;
  const LoadedMesh base = loadMesh(test::sharedMesh("keenan_crane/spot_control_mesh.obj"), po);
  PolygonMesh strayMesh = base.mesh;
  strayMesh.positions.emplace_back(1e14, 0, 0);
  const auto home = std::make_shared<const PatchCache>(buildPatchCache(base, po, Backend::Tbb));
  const auto stray =
      std::make_shared<const PatchCache>(buildPatchCache(loadMesh(std::move(strayMesh), 1, po), po, Backend::Tbb));
  ASSERT_EQ(stray->numVertices(), home->numVertices() + 1);
  EXPECT_EQ(boundingDiagonal(*stray), boundingDiagonal(*home));
  EXPECT_EQ(stray->edgeDataD, home->edgeDataD);
  const double diag = boundingDiagonal(*home);
  int steps = 0;
  for (const ForceMethod method : {ForceMethod::Patch, ForceMethod::Direct, ForceMethod::Shading}) {
    auto a = makeForceRenderer(home, method, ForceOptions{}), b = makeForceRenderer(stray, method, ForceOptions{});
    for (int f = 0; f < home->numFaces(); ++f) {  // a probe per face: 1% out, then 1% in
      PatchPoint pp;
      const double x = 0, y = 0;
      evaluatePatches(*home, &f, &x, &y, 1, &pp, Backend::Serial);
      a->reset();
      b->reset();
      for (const Eigen::Vector3d& hip : {Eigen::Vector3d(pp.pos + 0.01 * diag * pp.normal),
                                         Eigen::Vector3d(pp.pos - 0.01 * diag * pp.normal)}) {
        const ForceSample sa = a->step(hip), sb = b->step(hip);
        EXPECT_EQ(sa.contact, sb.contact) << int(method) << " " << f;
        EXPECT_EQ(sa.force, sb.force) << int(method) << " " << f;
        ++steps;
      }
    }
  }
  EXPECT_EQ(steps, 3 * 2 * 180);
}

// The readers: OBJ, OFF, PLY vertices and CSV positions beyond the range are refused with
// file:line (PLY: the vertex), values at the range's edge are read.
TEST(CoordinateRange, ReadersRefuseFarCoordinates) {
  const auto dir = std::filesystem::temp_directory_path() / ("sf_range_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    const std::string p = (dir / name).string();
    std::ofstream(p) << text;
    return p;
  };
  const std::string tri = "f 1 2 3\n";
  const std::string ok = write("ok.obj", "v 0 0 0\nv 1e15 0 0\nv 0 -1e15 0\n" + tri);
  EXPECT_EQ(readMesh(ok).positions.size(), 3u);
  std::string e = message([&] { readMesh(write("far.obj", "v 0 0 0\nv 2e15 0 0\nv 0 1 0\n" + tri)); });
  EXPECT_NE(e.find("far.obj:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("beyond the coordinate range"), std::string::npos) << e;
  e = message([&] { readMesh(write("far.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 0 -1e300\n3 0 1 2\n")); });
  EXPECT_NE(e.find("far.off:5:"), std::string::npos) << e;
  e = message([&] {
    readMesh(write("far.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double "
                   "z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1e20 0\n3 0 "
                   "1 2\n"));
  });
  EXPECT_NE(e.find("far.ply"), std::string::npos) << e;
  EXPECT_NE(e.find("vertex 2"), std::string::npos) << e;
  const std::string csv = write("far.csv", "x,y,z\n0,0,0\n# a comment\n0,-3e15,0\n");
  const NumericCsv t = readNumericCsv(csv, {"x", "y", "z"});
  e = message([&] { requirePositions(t, csv); });
  EXPECT_NE(e.find("far.csv:4: y = -3e+15 m is beyond"), std::string::npos) << e;
  // a value too small for a double is its rounding (0), not an error; a directory is named so
  const NumericCsv tiny = readNumericCsv(write("tiny.csv", "x,y,z\n1e-400,-2e-330,5e-324\n"), {"x", "y", "z"});
  EXPECT_EQ(tiny.at(0, 0), 0.0);
  EXPECT_EQ(tiny.at(0, 1), -0.0);
  EXPECT_GT(tiny.at(0, 2), 0.0);
  e = message([&] { readNumericCsv(dir.string(), {"x", "y", "z"}); });
  EXPECT_NE(e.find(": is a directory, not a CSV file"), std::string::npos) << e;
  const std::string replay = write("far_t.csv", "t,x,y,z\n0,0,0,0\n1,1e16,0,0\n");
  e = message([&] { requirePositions(readNumericCsv(replay, {"t", "x", "y", "z"}), replay, 1); });
  EXPECT_NE(e.find("far_t.csv:3: x = 1e+16 m"), std::string::npos) << e;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sf
