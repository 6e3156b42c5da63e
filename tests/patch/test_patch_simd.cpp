// SPDX-License-Identifier: Apache-2.0
// The SIMD paths (patch_simd.h): for every dispatch target this CPU runs,
// construction and batch evaluation give the same bits as the scalar path over whole meshes
// (every face, both precisions, every cross-tangent mode), and the batch evaluator agrees with
// the independent reference (tests/reference/) within the bounds PatchVsReference states.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>

#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_simd.h>

#include "gregory_reference.h"
#include "reference_patch_support.h"
#include "patch_test_support.h"

namespace sf {
namespace {

const CrossTangentMode kModes[] = {CrossTangentMode::Corrected, CrossTangentMode::Paper, CrossTangentMode::Blend};

// Quads, triangles, pentagons to 12-gons, non-convex planar n-gons, a boundary.
const char* const kMeshes[] = {"keenan_crane/spot_control_mesh.obj",
                               "polygon_laplacian/hexaSphere.off",
                               "geomview/snub_dodecahedron.off",
                               "polygon_laplacian/tetris.obj",
                               "pmp/hole_capsule.off",
                               "polygon_laplacian/L-plane.obj"};

struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
  void add(int f, double x, double y) {
    face.push_back(f);
    xi.push_back(x);
    eta.push_back(y);
  }
};

std::vector<SimdTarget> simdTargets() {
  std::vector<SimdTarget> v = supportedSimdTargets();
  v.pop_back();  // Scalar: the comparison's other side
  return v;
}

PatchCache skeleton(const std::string& rel, CrossTangentMode mode, Precision p) {
  PatchOptions o;
  o.crossTangent = mode;
  o.precision = p;
  const LoadedMesh lm = loadMesh(test::sharedMesh(rel), o);
  return preparePatchCache(lm.mesh, lm.cornerNormals, o, 0);
}

PatchCache built(PatchCache c, SimdTarget t, Backend b) {
  BuildOptions o;
  o.simd = t;
  o.backend = b;
  constructPatches(c, o);
  return c;
}

bool sameBits(const PatchPoint& a, const PatchPoint& b) {
  return a.status == b.status && std::memcmp(a.pos.data(), b.pos.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.dxi.data(), b.dxi.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.deta.data(), b.deta.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.normal.data(), b.normal.data(), 3 * sizeof(double)) == 0;
}

/// Per face: its centre, corners, points on and just outside each edge, and `random` uniform
/// points of the bounding square (those outside the domain included), plus queries on faces
/// that do not exist; shuffled. Seeded.
Queries faceQueries(const PatchCache& c, int random, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Queries q;
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f);
    q.add(f, 0, 0);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d a = domainCorner(n, k), b = domainCorner(n, (k + 1) % n);
      q.add(f, a.x(), a.y());
      const Eigen::Vector2d m = 0.5 * (a + b);
      q.add(f, m.x(), m.y());
      q.add(f, 1.01 * m.x(), 1.01 * m.y());  // just outside
    }
    for (int i = 0; i < random; ++i) q.add(f, u(rng), u(rng));
  }
  for (int f : {-1, c.numFaces(), c.numFaces() + 7}) q.add(f, 0.1, 0.1);
  std::vector<size_t> perm(q.face.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), rng);
  Queries s;
  for (size_t i : perm) s.add(q.face[i], q.xi[i], q.eta[i]);
  return s;
}

TEST(SimdTargets, NamesAndSupport) {
  for (SimdTarget t : {SimdTarget::Auto, SimdTarget::Scalar, SimdTarget::SSE4, SimdTarget::AVX2, SimdTarget::AVX512})
    EXPECT_EQ(parseSimdTarget(toString(t)), t);
  try {
    parseSimdTarget("avx1024");
    ADD_FAILURE() << "no error for avx1024";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("avx1024"), std::string::npos) << e.what();
  }
  const std::vector<SimdTarget> v = supportedSimdTargets();
  ASSERT_FALSE(v.empty());
  EXPECT_EQ(v.back(), SimdTarget::Scalar);
  EXPECT_EQ(resolveSimdTarget(SimdTarget::Auto), v.front());
  std::printf("SIMD targets on this CPU:");
  for (SimdTarget t : v)
    std::printf(" %s (%d double / %d float lanes)", toString(t), simdLanes(t, Precision::Double),
                simdLanes(t, Precision::Float));
  std::printf("\n");
  for (SimdTarget t : {SimdTarget::SSE4, SimdTarget::AVX2, SimdTarget::AVX512}) {
    if (std::find(v.begin(), v.end(), t) != v.end()) {
      EXPECT_GE(simdLanes(t, Precision::Double), 2) << toString(t);
      EXPECT_EQ(simdLanes(t, Precision::Float), 2 * simdLanes(t, Precision::Double)) << toString(t);
    } else {
      EXPECT_THROW(resolveSimdTarget(t), std::invalid_argument) << toString(t);
    }
  }
}

// Records, statuses and bulges of every face: bit-identical to the scalar serial build, for
// every target, serial and TBB.
TEST(SimdConstruction, EveryTargetBitIdenticalToScalar) {
  const std::vector<SimdTarget> targets = simdTargets();
  if (targets.empty()) GTEST_SKIP() << "this CPU runs no SIMD target";
  long faces = 0;
  for (const char* rel : kMeshes)
    for (Precision p : {Precision::Double, Precision::Float})
      for (CrossTangentMode mode : kModes) {
        const PatchCache s = skeleton(rel, mode, p);
        const PatchCache ref = built(s, SimdTarget::Scalar, Backend::Serial);
        for (SimdTarget t : targets)
          for (Backend b : {Backend::Serial, Backend::Tbb}) {
            const PatchCache c = built(s, t, b);
            const std::string what = std::string(rel) + " " + toString(p) + " " + toString(mode) + " " + toString(t);
            EXPECT_EQ(c.faceStatus, ref.faceStatus) << what;
            ASSERT_EQ(c.faceBulge.size(), ref.faceBulge.size()) << what;
            EXPECT_EQ(0, std::memcmp(c.faceBulge.data(), ref.faceBulge.data(), c.faceBulge.size() * sizeof(float)))
                << what;
            if (p == Precision::Double)
              EXPECT_EQ(0, std::memcmp(c.edgeDataD.data(), ref.edgeDataD.data(), c.edgeDataD.size() * sizeof(double)))
                  << what;
            else
              EXPECT_EQ(0, std::memcmp(c.edgeDataF.data(), ref.edgeDataF.data(), c.edgeDataF.size() * sizeof(float)))
                  << what;
            faces += c.numFaces();
          }
      }
  // 6 meshes x 2 precisions x 3 modes x 2 backends per target
  EXPECT_GT(faces, 72L * static_cast<long>(targets.size()) * 100);
}

// Faces of every size 3..GP_MAX_N in one cache, and sizes the patch math refuses (a 2-gon is
// not a polygon; GP_MAX_N + 1): the same status and zeros on every path.
TEST(SimdConstruction, EveryFaceSizeAndTooMany) {
  PolygonMesh m;
  std::vector<Eigen::Vector3d> normals;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<int> sizes;
  for (int n = 3; n <= GP_MAX_N + 1; ++n)
    for (int copies = 0; copies < (n <= 12 ? 9 : 1); ++copies) sizes.push_back(n);
  for (int n : sizes) {
    std::vector<int32_t> f;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n;
      f.push_back(m.numVertices());
      m.positions.emplace_back(std::cos(a), std::sin(a), 0.1 * u(rng));
      normals.push_back(Eigen::Vector3d(0.25 * u(rng), 0.25 * u(rng), 1).normalized());
    }
    m.addFace(f);
  }
  const std::vector<SimdTarget> targets = simdTargets();
  if (targets.empty()) GTEST_SKIP() << "this CPU runs no SIMD target";
  for (Precision p : {Precision::Double, Precision::Float}) {
    PatchOptions o;
    o.precision = p;
    const PatchCache s = preparePatchCache(m, normals, o, 0);
    const PatchCache ref = built(s, SimdTarget::Scalar, Backend::Serial);
    EXPECT_EQ(ref.faceStatus.back() & GP_ST_TOO_MANY_SIDES, GP_ST_TOO_MANY_SIDES);
    for (SimdTarget t : targets) {
      const PatchCache c = built(s, t, Backend::Tbb);
      EXPECT_EQ(c.faceStatus, ref.faceStatus) << toString(t);
      EXPECT_EQ(c.faceBulge, ref.faceBulge) << toString(t);
      EXPECT_EQ(c.edgeDataD, ref.edgeDataD) << toString(t);
      EXPECT_EQ(c.edgeDataF, ref.edgeDataF) << toString(t);
      const Queries q = faceQueries(c, 8, 4);
      std::vector<PatchPoint> out(q.face.size());
      EvalOptions eo;
      eo.simd = t;
      PatchEvaluator(c, eo).evaluate(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), out.data());
      size_t same = 0;
      for (size_t i = 0; i < out.size(); ++i) {
        const bool valid = q.face[i] >= 0 && q.face[i] < c.numFaces();
        PatchPoint e{};
        if (valid && c.faceSize(q.face[i]) <= GP_MAX_N) e = evaluatePatch(c, q.face[i], q.xi[i], q.eta[i]);
        if (valid && c.faceSize(q.face[i]) > GP_MAX_N) e.status = GP_ST_TOO_MANY_SIDES;
        if (!valid) e.status = GP_ST_OUTSIDE;
        same += sameBits(out[i], e);
      }
      EXPECT_EQ(same, out.size()) << toString(p) << " " << toString(t);
    }
  }
}

// Every query (whole meshes, points inside, on and outside each domain, bad face indices,
// shuffled): the batch result of every target, serial and TBB, is evaluatePatch's, bit for bit.
TEST(SimdEvaluation, EveryTargetBitIdenticalToScalar) {
  std::vector<SimdTarget> targets = supportedSimdTargets();  // Scalar batch too
  long points = 0;
  for (const char* rel : kMeshes)
    for (Precision p : {Precision::Double, Precision::Float})
      for (CrossTangentMode mode : kModes) {
        const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), mode, p);
        const Queries q = faceQueries(c, 24, 11);
        std::vector<PatchPoint> expect(q.face.size()), out(q.face.size());
        for (size_t i = 0; i < q.face.size(); ++i) {
          if (q.face[i] < 0 || q.face[i] >= c.numFaces()) {
            expect[i].status = GP_ST_OUTSIDE;
            continue;
          }
          expect[i] = evaluatePatch(c, q.face[i], q.xi[i], q.eta[i]);
        }
        for (SimdTarget t : targets)
          for (Backend b : {Backend::Serial, Backend::Tbb}) {
            EvalOptions o;
            o.simd = t;
            o.backend = b;
            PatchEvaluator ev(c, o);
            ASSERT_EQ(ev.target(), t);
            for (int pass = 0; pass < 2; ++pass) {  // the evaluator reuses its buffers
              std::fill(out.begin(), out.end(), PatchPoint{{9, 9, 9}, {9, 9, 9}, {9, 9, 9}, {9, 9, 9}, 77});
              ev.evaluate(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), out.data());
              size_t same = 0;
              for (size_t i = 0; i < out.size(); ++i) same += sameBits(out[i], expect[i]);
              EXPECT_EQ(same, out.size())
                  << rel << " " << toString(p) << " " << toString(mode) << " " << toString(t) << " pass " << pass;
            }
            points += static_cast<long>(out.size());
          }
      }
  EXPECT_GT(points, 100000L);
}

// A batch of a few points on many faces (the sorted path) equals one of many points.
TEST(SimdEvaluation, FewQueriesOnManyFaces) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("polygon_laplacian/hexaSphere.off"));
  const Queries q = faceQueries(c, 4, 2);
  for (SimdTarget t : supportedSimdTargets()) {
    EvalOptions o;
    o.simd = t;
    PatchEvaluator ev(c, o);
    size_t same = 0, count = 0;
    for (size_t b = 0; b < q.face.size(); b += 5) {
      const size_t m = std::min<size_t>(5, q.face.size() - b);
      PatchPoint out[5];
      ev.evaluate(q.face.data() + b, q.xi.data() + b, q.eta.data() + b, m, out);
      for (size_t i = 0; i < m; ++i, ++count) {
        const int f = q.face[b + i];
        PatchPoint e{};
        if (f >= 0 && f < c.numFaces())
          e = evaluatePatch(c, f, q.xi[b + i], q.eta[b + i]);
        else
          e.status = GP_ST_OUTSIDE;
        same += sameBits(out[i], e);
      }
    }
    EXPECT_EQ(same, count) << toString(t);
  }
}

// FacePointEvaluator (a few points of one face side by side: the refinement's finite
// differences) gives evaluatePatch's bits for every count 1..16, on every face of every mesh,
// both precisions, every cross-tangent mode; its points include corners and points outside.
// evaluateRecords (the face's double records given field-major, as the lazy refinement does)
// gives the same bits.
TEST(SimdEvaluation, FacePointsBitIdenticalToScalar) {
  long points = 0, faces = 0, givenPoints = 0;
  for (const char* rel : kMeshes)
    for (Precision p : {Precision::Double, Precision::Float})
      for (CrossTangentMode mode : kModes) {
        const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), mode, p);
        FacePointEvaluator few(c), recordsGiven;
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-1, 1);
        for (int f = 0; f < c.numFaces(); ++f) {
          if (c.faceSize(f) > GP_MAX_N) continue;
          const int n = c.faceSize(f);
          for (int count = 1; count <= 16; ++count) {
            double xi[16], eta[16];
            for (int i = 0; i < count; ++i) {
              const Eigen::Vector2d a = domainCorner(n, i);
              xi[i] = i % 3 == 0 ? a.x() : u(rng);  // corners and random points (some outside)
              eta[i] = i % 3 == 0 ? a.y() : u(rng);
            }
            PatchPoint out[16], given[16];
            few.evaluate(f, xi, eta, count, out);
            if (p == Precision::Double) {  // the same face's records given by the caller (a lazy store's)
              std::vector<double> fieldMajor(size_t(n) * GP_E_NFIELDS);
              for (int i = 0; i < GP_E_NFIELDS; ++i)
                for (int k = 0; k < n; ++k)
                  fieldMajor[size_t(i) * n + k] = c.edgeDataD[size_t(i) * c.numSlots() + c.faceOffsets[f] + k];
              recordsGiven.evaluateRecords(n, static_cast<int>(mode), c.faceStatus[f], fieldMajor.data(), xi, eta,
                                           count, given);
            }
            for (int i = 0; i < count; ++i, ++points) {
              const PatchPoint scalar = evaluatePatch(c, f, xi[i], eta[i]);
              ASSERT_TRUE(sameBits(out[i], scalar))
                  << rel << " " << toString(p) << " " << toString(mode) << " face " << f << " count " << count << " point " << i;
              if (p == Precision::Double) {
                ASSERT_TRUE(sameBits(given[i], scalar)) << rel << " evaluateRecords, face " << f << " point " << i;
                ++givenPoints;
              }
            }
          }
          ++faces;
        }
      }
  EXPECT_GT(faces, 3000L);
  EXPECT_EQ(points, faces * 136);
  EXPECT_EQ(givenPoints, points / 2);  // every double face, with its records given (evaluateRecords)
}

// FacePointEvaluator keeps the last face's records as vectors: over a random sequence of
// (face, count) calls, where the same face comes back after other faces, after other counts
// (other targets: SSE4, AVX2, AVX-512, scalar) and after records given by the caller
// (evaluateRecords on the same evaluator), every point has evaluatePatch's bits.
TEST(SimdEvaluation, FacePointsKeptRecordsFollowFaceAndTarget) {
  long points = 0, calls = 0, repeats = 0;
  for (const char* rel : kMeshes)
    for (Precision p : {Precision::Double, Precision::Float}) {
      const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, p);
      FacePointEvaluator few(c);
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> u(-0.8, 0.8);
      std::uniform_int_distribution<int> pickFace(0, std::min(c.numFaces(), 6) - 1), pickCount(1, 16), pick(0, 9);
      int last = -1;
      for (int call = 0; call < 4000; ++call, ++calls) {
        const int f = pickFace(rng), count = pickCount(rng);  // a few faces: each comes back often
        if (c.faceSize(f) > GP_MAX_N) continue;
        repeats += f == last;
        last = f;
        double xi[16], eta[16];
        for (int i = 0; i < count; ++i) xi[i] = u(rng), eta[i] = u(rng);
        PatchPoint out[16];
        if (p == Precision::Double && pick(rng) == 0) {  // now and then another face's records, given
          const int g = (f + 1) % c.numFaces(), n = c.faceSize(g);
          std::vector<double> fieldMajor(size_t(n) * GP_E_NFIELDS);
          for (int i = 0; i < GP_E_NFIELDS; ++i)
            for (int k = 0; k < n; ++k)
              fieldMajor[size_t(i) * n + k] = c.edgeDataD[size_t(i) * c.numSlots() + c.faceOffsets[g] + k];
          few.evaluateRecords(n, static_cast<int>(c.options.crossTangent), c.faceStatus[g], fieldMajor.data(), xi, eta,
                              count, out);
          for (int i = 0; i < count; ++i, ++points)
            ASSERT_TRUE(sameBits(out[i], evaluatePatch(c, g, xi[i], eta[i]))) << rel << " records of face " << g;
          last = -1;
          continue;
        }
        few.evaluate(f, xi, eta, count, out);
        for (int i = 0; i < count; ++i, ++points)
          ASSERT_TRUE(sameBits(out[i], evaluatePatch(c, f, xi[i], eta[i])))
              << rel << " " << toString(p) << " call " << call << " face " << f << " count " << count << " point " << i;
      }
    }
  EXPECT_EQ(calls, 4000L * 2 * long(std::size(kMeshes)));
  EXPECT_GT(points, calls * 7);   // about 8.5 points per call
  EXPECT_GT(repeats, calls / 8);  // the same face again, right after itself
}

ref::CrossTangent refMode(CrossTangentMode m) {
  return m == CrossTangentMode::Paper   ? ref::CrossTangent::Paper
         : m == CrossTangentMode::Blend ? ref::CrossTangent::Blend
                                        : ref::CrossTangent::Corrected;
}

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// The batch evaluator of every target against the independent reference on whole real cages,
// with PatchVsReference's bounds (double: 1e-12 position, 1e-10 derivatives of the face size,
// 1e-8 rad normal; float: 2e-5 and 1e-4). Points with a singular or degenerate status are
// counted, not compared (as there).
TEST(SimdEvaluation, AgreesWithReference) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/hexaSphere.off",
                          "geomview/snub_dodecahedron.off", "pmp/hole_capsule.off"})
    for (Precision p : {Precision::Double, Precision::Float})
      for (CrossTangentMode mode : kModes) {
        if (p == Precision::Float && mode != CrossTangentMode::Corrected) continue;
        const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), mode, p);
        std::mt19937 rng(8);
        std::uniform_real_distribution<double> u(-1, 1);
        Queries q;
        for (int f = 0; f < c.numFaces(); ++f)
          for (int i = 0; i < 12;) {
            const double x = u(rng), y = u(rng);
            if (insideDomain(c.faceSize(f), x, y)) q.add(f, x, y), ++i;
          }
        for (SimdTarget t : supportedSimdTargets()) {
          EvalOptions o;
          o.simd = t;
          std::vector<PatchPoint> out(q.face.size());
          PatchEvaluator(c, o).evaluate(q.face.data(), q.xi.data(), q.eta.data(), q.face.size(), out.data());
          double dpos = 0, dder = 0, dnor = 0;
          size_t compared = 0, flagged = 0;
          int lastFace = -1;
          std::unique_ptr<ref::RefPatchEvaluator> ev;
          double size = 0;
          for (size_t i = 0; i < out.size(); ++i) {
            const int f = q.face[i], n = c.faceSize(f);
            if (f != lastFace) {
              const ref::RefPatch rp = test::referencePatchOf(c, f, refMode(mode));
              size = 0;
              for (int k = 0; k < n; ++k) size = std::max(size, (rp.V[k] - rp.V[(k + 1) % n]).norm());
              ev = std::make_unique<ref::RefPatchEvaluator>(rp);
              lastFace = f;
            }
            const PatchPoint& r = out[i];
            if (r.status & (GP_ST_DEGENERATE_MASK | GP_ST_SINGULAR)) {
              ++flagged;
              continue;
            }
            ++compared;
            const ref::RefEval e = ev->evaluate(q.xi[i], q.eta[i]);
            dpos = std::max(dpos, (r.pos - e.pos).norm() / size);
            dder = std::max(dder, std::max((r.dxi - e.dxi).norm(), (r.deta - e.deta).norm()) / size);
            if (!(r.status & GP_ST_FOLD) && angle(r.dxi, r.deta) > 1e-3 && angle(r.dxi, r.deta) < M_PI - 1e-3)
              dnor = std::max(dnor, angle(r.normal, e.normal));
          }
          const std::string what = std::string(rel) + " " + toString(p) + " " + toString(mode) + " " + toString(t);
          EXPECT_EQ(compared + flagged, out.size()) << what;
          EXPECT_LT(flagged, compared / 20) << what;
          if (p == Precision::Double) {
            EXPECT_LT(dpos, 1e-12) << what;
            EXPECT_LT(dder, 1e-10) << what;
            EXPECT_LT(dnor, 1e-8) << what;
          } else {
            EXPECT_LT(dpos, 2e-5) << what;
            EXPECT_LT(dder, 1e-4) << what;
          }
        }
      }
}

TEST(SimdEvaluation, RejectsWhatItCannotRun) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  EvalOptions o;
  o.backend = Backend::OpenCL;
  EXPECT_THROW(PatchEvaluator(c, o), std::invalid_argument);
  const PatchCache sk = test::skeletonFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  EXPECT_THROW(PatchEvaluator{sk}, std::invalid_argument);
  BuildOptions b;
  b.backend = Backend::OpenCL;
  PatchCache s = c;
  EXPECT_THROW(constructPatches(s, b), std::invalid_argument);
  PatchCache k = sk;
  EXPECT_THROW(constructPatches(k, BuildOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace sf
