// SPDX-License-Identifier: Apache-2.0
// Cross-check of the OpenCL refinement (kernels/refine.cl, host/opencl_refine.h) against the
// CPU PatchRefiner (Newton and the paper's descent) on real meshes, double and float: starts
// from the paper's global query, Eq. 15 crossings, a boundary edge; and a sweep with --backend
// tbb vs opencl.
// Skipped with the reason when no OpenCL device exists.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/opencl/opencl_context.h>
#include <smoothforce/opencl/opencl_refine.h>
#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_opencl.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include <smoothforce/sweep/sweep_run.h>
#include "patch_test_support.h"

namespace sf {
namespace {

// Tolerances relative to the bounding-box diagonal. Double: the kernel runs PatchRefiner's
// operations on the same constants (the host's domain table and sin(angle tolerance)), so the
// two give the same bits; kTolD only sorts pairs into "the same point" and "another stationary
// point" for the counts below, which assert exact agreement. Float: the kernel computes in
// float, PatchRefiner in double around float evaluations; both stop at the angle tolerance
// within float noise.
constexpr double kTolD = 1e-9, kTolF = 1e-4;

class OpenCLRefine : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!openclAvailable(&why)) GTEST_SKIP() << "no OpenCL device: " << why;
  }
  /// float / and sqrt correctly rounded on the device: its float evaluations are the host's bits
  static bool exactFloat() {
    static const bool exact = OpenCLContext().hasCorrectlyRoundedDivSqrt();
    return exact;
  }
};

/// HIPs within `depth` of random patch points (both sides), with the paper's start: the
/// nearest polygon point mapped into its face's domain by mean value coordinates.
std::vector<RefineQuery> globalQueries(const PatchCache& c, int count, double depth, unsigned seed) {
  const PolygonScene scene(c);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pf(0, c.numFaces() - 1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> lambda(GP_MAX_N);
  std::vector<RefineQuery> q;
  while (static_cast<int>(q.size()) < count) {
    const int f = pf(rng);
    const double x = u(rng), y = u(rng);
    if (!insideDomain(c.faceSize(f), x, y)) continue;
    const PatchPoint p = evaluatePatch(c, f, x, y);
    RefineQuery r;
    r.hip = p.pos + depth * u(rng) * p.normal;
    const NearestPolygonPoint np = scene.nearest(r.hip);
    const Eigen::Vector2d X = polygonToDomain(scene.facets(), c, np.face, np.point, lambda.data());
    r.face = np.face;
    r.xi = X.x();
    r.eta = X.y();
    q.push_back(r);
  }
  return q;
}

struct Agreement {
  double maxScp = 0;  // m, over the HIPs that reach the same minimum
  int otherFace = 0, transitions = 0, statusDiff = 0, compared = 0;
  double maxNormalAngle = 0;     // rad, between the two sides' normals on the same face
  double maxOwnNormalAngle = 0;  // rad, device normal vs the patch normal at the device's own (face, X)
  int otherMinimum = 0;          // both converged, to different stationary points (another basin)
  int modelPoints = 0, modelDiff = 0;  // device results on a model point; the bit differing from the CPU's
};

/// Runs the queries on the device and on PatchRefiner. Each pair reaches the same point within
/// tol x diagonal (the same face unless the point lies on a shared edge: a tie), or both
/// converged to stationary points of the distance (residual |r x n| within `stationary` x
/// diagonal) in different basins: counted in otherMinimum (float arithmetic can take another
/// path from a start near a basin boundary; the caller bounds the count).
Agreement compareWithCpu(const PatchCache& c, const std::vector<RefineQuery>& q, double tol, double stationary,
                         const ForceOptions& o = {}) {
  OpenCLRefiner dev(c);
  std::vector<RefineResult> g(q.size());
  dev.refine(q.data(), q.size(), o, g.data());
  PatchRefiner cpu(c);
  const double diag = boundingDiagonal(c);
  Agreement a;
  auto residual = [&](const RefineResult& r, const Eigen::Vector3d& hip) {
    return (hip - r.scp).cross(r.normal).norm() / diag;
  };
  for (size_t i = 0; i < q.size(); ++i) {
    const RefineResult r = cpu.refine(q[i].hip, q[i].face, q[i].xi, q[i].eta, o);
    const double d = (r.scp - g[i].scp).norm();
    a.transitions += g[i].transitions > 0;
    const uint32_t mask = SF_TRACK_CONVERGED | SF_TRACK_BOUNDARY | SF_TRACK_DEGENERATE;
    // stationary, or held on an edge (boundary, fold) and stationary along it
    auto isStationary = [&](const RefineResult& x) {
      return (x.status & SF_TRACK_CONVERGED) && (x.edge >= 0 || residual(x, q[i].hip) <= stationary);
    };
    if (d > tol * diag) {
      const bool bothStationary = isStationary(r) && isStationary(g[i]);
      EXPECT_TRUE(bothStationary) << "HIP " << i << ": SCPs " << d / diag << " x diagonal apart, status " << std::hex
                                  << r.status << " / " << g[i].status << std::dec << std::setprecision(17)
                                  << "; start face " << q[i].face << " X " << q[i].xi << " " << q[i].eta << " HIP "
                                  << q[i].hip.transpose() << "; device it " << g[i].iterations;
      ++a.otherMinimum;
      continue;
    }
    a.maxScp = std::max(a.maxScp, d);
    EXPECT_NEAR(r.distance, g[i].distance, tol * diag) << i;
    ++a.compared;
    if (r.face == g[i].face) {  // across a fold edge the two faces' normals differ
      a.maxNormalAngle =
          std::max(a.maxNormalAngle, std::atan2(g[i].normal.cross(r.normal).norm(), g[i].normal.dot(r.normal)));
    }
    const Eigen::Vector3d own = evaluatePatch(c, g[i].face, g[i].xi, g[i].eta).normal;
    a.maxOwnNormalAngle =
        std::max(a.maxOwnNormalAngle, std::atan2(g[i].normal.cross(own).norm(), g[i].normal.dot(own)));
    if (r.face != g[i].face) ++a.otherFace;
    a.statusDiff += (r.status & mask) != (g[i].status & mask);
    a.modelPoints += (g[i].status & SF_ST_MODEL_POINT) != 0;
    a.modelDiff += ((r.status ^ g[i].status) & SF_ST_MODEL_POINT) != 0;
  }
  return a;
}

TEST_F(OpenCLRefine, AgreesWithPatchRefinerDoubleAndFloat) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    for (Precision p : {Precision::Double, Precision::Float}) {
      const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, p);
      const double diag = boundingDiagonal(c);
      const std::vector<RefineQuery> q = globalQueries(c, 400, 0.05 * diag, 11);
      const bool dbl = p == Precision::Double;
      const Agreement a = compareWithCpu(c, q, dbl ? kTolD : kTolF, dbl ? 1e-9 : 1e-5);
      std::printf(
          "  %s %s: max |SCP_cl - SCP_cpu| = %.3g x diagonal; other face (a tie on an edge) %d; other "
          "stationary point %d; %d HIPs cross patch edges; converged/boundary status differs on %d; normals %.3g rad "
          "apart "
          "(same face), device normal vs its own point's %.3g rad; %d compared\n",
          rel, dbl ? "double" : "float", a.maxScp / diag, a.otherFace, a.otherMinimum, a.transitions, a.statusDiff,
          a.maxNormalAngle, a.maxOwnNormalAngle, a.compared);
      EXPECT_GT(a.transitions, 0) << rel;  // some refinements cross patch edges (Eq. 15)
      EXPECT_EQ(a.compared + a.otherMinimum, static_cast<int>(q.size())) << rel;
      EXPECT_EQ(a.statusDiff, 0) << rel;  // converged/boundary/degenerate bits, in both precisions
      // the device's normal is the patch normal at its own point, the host's evaluation there bit
      // for bit (float where / and sqrt round as the host's; else evaluation rounding, measured
      // <= 8.4e-6 rad); in float, on the same face the two sides' normals differ by the
      // surface's turn between SCPs up to tol x diagonal apart (measured <= 0.002 rad; bound
      // 0.01 rad = 0.57 degrees)
      EXPECT_LE(a.maxOwnNormalAngle, dbl || exactFloat() ? 0.0 : 1e-4) << rel;
      if (dbl) {  // the same arithmetic: the same path to the same bits
        EXPECT_EQ(a.maxScp, 0.0) << rel;
        EXPECT_EQ(a.maxNormalAngle, 0.0) << rel;
        EXPECT_EQ(a.otherFace, 0) << rel;
        EXPECT_EQ(a.otherMinimum, 0) << rel;
      } else {
        EXPECT_LE(a.maxNormalAngle, 1e-2) << rel;  // starts up to 5% of the diagonal away, near folded patches: few take another basin
        EXPECT_LE(a.otherMinimum, static_cast<int>(q.size()) / 50) << rel;
      }
    }
  }
}

// FinalStep::Model: the kernel takes the same steps as PatchRefiner, model points included (the
// same source, kernels/gp_refine.h), so the double results agree as with evaluated final steps;
// the device normal lies within the model's error of the patch normal at its own point.
TEST_F(OpenCLRefine, ModelFinalStepAgreesWithPatchRefiner) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off"}) {
    const PatchCache c = test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, Precision::Double);
    const double diag = boundingDiagonal(c);
    const std::vector<RefineQuery> q = globalQueries(c, 400, 0.05 * diag, 11);
    ForceOptions o;
    o.finalStep = FinalStep::Model;
    const Agreement a = compareWithCpu(c, q, kTolD, 2e-10, o);
    std::printf("  %s: %d of %d device results on a model point (the bit differs on %d); max |SCP_cl - SCP_cpu| = "
                "%.3g x diagonal; device normal vs its own point's %.3g rad\n",
                rel, a.modelPoints, a.compared, a.modelDiff, a.maxScp / diag, a.maxOwnNormalAngle);
    EXPECT_EQ(a.compared, static_cast<int>(q.size())) << rel;
    EXPECT_EQ(a.statusDiff, 0) << rel;
    EXPECT_EQ(a.modelDiff, 0) << rel;
    EXPECT_GE(a.modelPoints, a.compared / 4) << rel << ": the option takes effect";
    EXPECT_EQ(a.maxScp, 0.0) << rel;  // the same steps to the same bits
    EXPECT_LE(a.maxOwnNormalAngle, 1e-7) << rel;
    // float: the kernel computes in float (finite-difference step 1e-3), PatchRefiner in double
    // around the float records, so they may take other paths; the bounds of the evaluated test.
    // Measured: the kernel takes no model point in float (the position tolerance lies below
    // float rounding, where the model's error estimate refuses it)
    const PatchCache cf = test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, Precision::Float);
    const Agreement f = compareWithCpu(cf, q, kTolF, 1e-5, o);
    std::printf("  %s float: %d of %d device results on a model point; max |SCP_cl - SCP_cpu| = %.3g x diagonal; "
                "device normal vs its own point's %.3g rad; other stationary point %d\n",
                rel, f.modelPoints, f.compared, f.maxScp / diag, f.maxOwnNormalAngle, f.otherMinimum);
    EXPECT_EQ(f.compared + f.otherMinimum, static_cast<int>(q.size())) << rel;
    EXPECT_LE(f.otherMinimum, static_cast<int>(q.size()) / 50) << rel;
    EXPECT_EQ(f.statusDiff, 0) << rel;
    EXPECT_LE(f.maxOwnNormalAngle, exactFloat() ? 0.0 : 1e-4) << rel;  // no model point: an evaluation
  }
}

// RefineMethod::PaperDescent: the kernel runs gp_refine_descent, which PatchRefiner runs on the
// CPU. Double: the same arithmetic on the same constants (the host's domain table), so the same
// path to the same bits, though the descent creeps along shallow valleys and many starts stop at
// maxIterations, where one ulp parted the paths by a few halvings while the device computed its
// own cos and sin (then: 3 of 400 SCPs up to 1.2e-6 x diagonal apart). Float: the
// kernel computes in float (finite-difference step 1e-3), PatchRefiner in double around the
// float evaluations: paths part more (measured: 398 of 400 within 1e-4 x diagonal).
TEST_F(OpenCLRefine, PaperDescentAgreesWithPatchRefiner) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const double diag = boundingDiagonal(c);
  const std::vector<RefineQuery> q = globalQueries(c, 400, 0.05 * diag, 11);
  ForceOptions o;
  o.refine = RefineMethod::PaperDescent;
  for (Precision p : {Precision::Double, Precision::Float}) {
    const PatchCache cp =
        test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"), CrossTangentMode::Corrected, p);
    OpenCLRefiner dev(cp);
    std::vector<RefineResult> g(q.size());
    dev.refine(q.data(), q.size(), o, g.data());
    PatchRefiner cpu(cp);
    int same = 0, statusDiff = 0, transitions = 0;
    double maxScp = 0, maxDistance = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      const RefineResult r = cpu.refine(q[i].hip, q[i].face, q[i].xi, q[i].eta, o);
      const double d = (r.scp - g[i].scp).norm() / diag;
      maxScp = std::max(maxScp, d);
      maxDistance = std::max(maxDistance, std::abs(r.distance - g[i].distance) / diag);
      same += d <= (p == Precision::Double ? kTolD : kTolF);
      statusDiff += (r.status & SF_TRACK_MASK) != (g[i].status & SF_TRACK_MASK);
      transitions += g[i].transitions > 0;
    }
    std::printf(
        "  paper's descent, %s: %d of %zu within tolerance, max |SCP_cl - SCP_cpu| = %.3g x diagonal, "
        "distances %.3g x diagonal apart; tracking bits differ on %d; %d cross patch edges\n",
        p == Precision::Double ? "double" : "float", same, q.size(), maxScp, maxDistance, statusDiff, transitions);
    EXPECT_GT(transitions, 0);
    if (p == Precision::Double) {  // the same operations on the same constants: the same bits
      EXPECT_EQ(same, static_cast<int>(q.size()));
      EXPECT_EQ(maxScp, 0.0);
      EXPECT_EQ(statusDiff, 0);
    } else {
      EXPECT_GE(same, static_cast<int>(q.size()) * 9 / 10);
    }
  }
}

TEST_F(OpenCLRefine, CrossesPatchBoundariesByEq15) {
  // as Refine.CrossesPatchBoundariesByEq15 (test_force_refine.cpp): two faces away from face 0
  const PatchCache c = test::cacheFromFile(test::sharedMesh("polygon_laplacian/quad-sphere.off"));
  const int f2 = test::faceTwoAcross(c);
  ASSERT_GE(f2, 0);
  const PatchPoint target = evaluatePatch(c, f2, 0.1, -0.05);
  RefineQuery q;
  q.hip = target.pos - 0.02 * target.normal;
  q.face = 0;
  ForceOptions o;
  o.maxIterations = 200;
  RefineResult r;
  refineNearestPointsOpenCL(c, &q, 1, o, &r);
  EXPECT_EQ(r.face, f2);
  EXPECT_GE(r.transitions, 2);
  EXPECT_TRUE(r.status & SF_TRACK_CONVERGED);
  EXPECT_NEAR((r.scp - target.pos).norm(), 0, 1e-6);
  const RefineResult cpu = refineNearestPoint(c, q.hip, 0, 0, 0, o);
  EXPECT_EQ(r.transitions, cpu.transitions);
  EXPECT_EQ(r.iterations, cpu.iterations);
}

TEST_F(OpenCLRefine, StaysOnBoundaryEdgeOfOpenMesh) {
  // one flat quad (open mesh): HIPs beyond edge 0 and one inside
  const PatchCache c = test::flatQuadCache();
  ASSERT_EQ(c.slotTwin[0], kBoundarySlot);
  std::vector<RefineQuery> q(3);
  q[0].hip = {0.4, -0.5, -0.1};
  q[1].hip = {0.7, -0.2, 0.3};
  q[2].hip = {0.5, 0.5, -0.2};  // inside: no boundary
  for (auto& x : q) x.face = 0;
  std::vector<RefineResult> r(q.size());
  refineNearestPointsOpenCL(c, q.data(), q.size(), {}, r.data());
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(r[i].status & SF_TRACK_BOUNDARY) << i;
    EXPECT_TRUE(r[i].status & SF_TRACK_CONVERGED) << i;
    EXPECT_EQ(r[i].edge, 0) << i;
    EXPECT_NEAR(r[i].scp.y(), 0, 1e-12) << i;
    EXPECT_NEAR(r[i].scp.x(), q[i].hip.x(), 2e-5) << i;
    EXPECT_NEAR(r[i].scp.z(), 0, 1e-12) << i;
  }
  EXPECT_FALSE(r[2].status & SF_TRACK_BOUNDARY);
  EXPECT_EQ(r[2].edge, -1);
  EXPECT_NEAR((r[2].scp - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 0, 1e-9);
  EXPECT_EQ(compareWithCpu(c, q, kTolD, 1e-9).otherMinimum, 0);
  // restarting on the edge (in contact) keeps it held there, as PatchRefiner's reuse does
  RefineQuery again = q[0];
  again.face = r[0].face;
  again.xi = r[0].xi;
  again.eta = r[0].eta;
  again.edge = r[0].edge;
  RefineResult r2;
  refineNearestPointsOpenCL(c, &again, 1, {}, &r2);
  EXPECT_EQ(r2.iterations, 0);
  EXPECT_TRUE(r2.status & SF_TRACK_BOUNDARY);
}

TEST_F(OpenCLRefine, RefusesUnusableStartsWithEitherMethod) {
  const PatchCache c = test::cacheFromShape(ref::refUnitSphereCube());
  std::vector<RefineQuery> q(3);
  q[0].hip = {NAN, 0, 0};
  q[0].face = 0;
  q[1].face = 99;
  q[2].hip = {0, 0, 0.2};
  q[2].face = 0;
  q[2].xi = q[2].eta = 5;  // clamped into the domain
  std::vector<RefineResult> r(3);
  OpenCLRefiner dev(c);
  dev.refine(q.data(), q.size(), {}, r.data());
  EXPECT_TRUE(r[0].status & SF_TRACK_DEGENERATE);
  EXPECT_TRUE(r[1].status & SF_TRACK_DEGENERATE);
  EXPECT_FALSE(r[2].status & SF_TRACK_DEGENERATE);
  EXPECT_TRUE(std::isfinite(r[2].distance));
  ForceOptions paper;  // the paper's descent runs on the device too, with the same verdicts
  paper.refine = RefineMethod::PaperDescent;
  std::vector<RefineResult> d(3);
  dev.refine(q.data(), q.size(), paper, d.data());
  EXPECT_TRUE(d[0].status & SF_TRACK_DEGENERATE);
  EXPECT_TRUE(d[1].status & SF_TRACK_DEGENERATE);
  EXPECT_FALSE(d[2].status & SF_TRACK_DEGENERATE);
  EXPECT_TRUE(std::isfinite(d[2].distance));
  dev.refine(q.data(), 0, {}, r.data());  // an empty batch is fine
}

TEST_F(OpenCLRefine, SharedCodeMatchesOnHostAndDevice) {
  // gp_refine.h compiled as C++ (sf::gpd) against the kernel: the same code on the same
  // constants, so the same bits
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const std::vector<RefineQuery> q = globalQueries(c, 100, 0.05 * boundingDiagonal(c), 3);
  std::vector<RefineResult> g(q.size());
  refineNearestPointsOpenCL(c, q.data(), q.size(), {}, g.data());
  gpd::gp_refine_mesh mesh{};
  mesh.faceOffsets = c.faceOffsets.data();
  mesh.edgeData = c.edgeDataD.data();
  mesh.faceStatus = c.faceStatus.data();
  mesh.slotTwin = c.slotTwin.data();
  mesh.numFaces = c.numFaces();
  mesh.numSlots = c.numSlots();
  mesh.mode = static_cast<int>(c.options.crossTangent);
  mesh.scale = boundingDiagonal(c);
  auto work = std::make_unique<gpd::gp_refine_work>();
  const double diag = boundingDiagonal(c);
  gpd::gp_refine_options opt;
  opt.maxIterations = ForceOptions{}.maxIterations;
  opt.angleTol = ForceOptions{}.angleTolerance;
  opt.positionTol = ForceOptions{}.positionTolerance * diag;
  opt.modelFinal = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    work->loaded = -1;
    const gpd::gp_refine_result h =
        gpd::gp_refine_newton(&mesh, work.get(), gpd::gp_v3(q[i].hip.x(), q[i].hip.y(), q[i].hip.z()), q[i].face,
                              q[i].xi, q[i].eta, -1, &opt);
    EXPECT_EQ(Eigen::Vector3d(h.scp.x, h.scp.y, h.scp.z), g[i].scp) << i;
    EXPECT_EQ(h.face, g[i].face) << i;
    EXPECT_EQ(h.status, g[i].status) << i;
    EXPECT_EQ(h.iterations, g[i].iterations) << i;
    EXPECT_EQ(h.transitions, g[i].transitions) << i;
  }
}

// Seeds (RefineQuery::maxIterations 0: the start evaluated and tested, not refined) on the
// device as on the host (PatchRefiner with maxIterations 0): the same point and the same
// RefineResult::startMinimum for every query, at converged starts (each query's own nearest
// point) and at unconverged ones (its first start), with both verdicts present.
TEST_F(OpenCLRefine, SeedsMatchOnHostAndDevice) {
  const PatchCache c = test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj"));
  const double diag = boundingDiagonal(c);
  std::vector<RefineQuery> q = globalQueries(c, 100, 0.05 * diag, 3);
  std::vector<RefineResult> full(q.size());
  refineNearestPointsOpenCL(c, q.data(), q.size(), {}, full.data());
  std::vector<RefineQuery> seeds;
  for (size_t i = 0; i < q.size(); ++i) {
    RefineQuery s = q[i];
    s.maxIterations = 0;
    seeds.push_back(s);  // the first start: mostly not converged
    if (full[i].status & SF_TRACK_DEGENERATE) continue;
    s.face = full[i].face;
    s.xi = full[i].xi;
    s.eta = full[i].eta;
    s.edge = full[i].edge;
    seeds.push_back(s);  // the nearest point found: converged
  }
  std::vector<RefineResult> device(seeds.size());
  refineNearestPointsOpenCL(c, seeds.data(), seeds.size(), {}, device.data());
  PatchRefiner host(c);
  RefineOptions o = ForceOptions{};
  o.maxIterations = 0;
  size_t same = 0, minima = 0;
  for (size_t i = 0; i < seeds.size(); ++i) {
    const RefineResult h = host.refine(seeds[i].hip, seeds[i].face, seeds[i].xi, seeds[i].eta, o, seeds[i].edge);
    EXPECT_EQ(device[i].iterations, 0) << i;
    EXPECT_EQ(h.scp, device[i].scp) << i;
    same += h.startMinimum == device[i].startMinimum;
    minima += h.startMinimum;
  }
  EXPECT_EQ(same, seeds.size());
  EXPECT_GT(minima, 0u);
  EXPECT_LT(minima, seeds.size());
  std::printf("  %zu seeds: the same startMinimum on host and device %zu, minima %zu\n", seeds.size(), same, minima);
}

/// Every number in a and b (same structure) equal within rel x max(|a|, |b|, 1e-3).
void expectJsonNear(const nlohmann::json& a, const nlohmann::json& b, double rel, const std::string& path,
                    int* compared) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    // iteration counts: a refinement that ends right at the tolerance may take one more step on
    // one side (the two agree to ~1e-14 of the diagonal): 1% on their mean
    const double r = path.find("iterations") != std::string::npos ? std::max(rel, 1e-2) : rel;
    EXPECT_NEAR(x, y, r * std::max({std::abs(x), std::abs(y), 1e-3})) << path;
    ++*compared;
  } else if (a.is_object() && b.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (it.key() == "backend") continue;
      ASSERT_TRUE(b.contains(it.key())) << path << "/" << it.key();
      expectJsonNear(it.value(), b.at(it.key()), rel, path + "/" + it.key(), compared);
    }
  } else if (a.is_array() && b.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    for (size_t i = 0; i < a.size(); ++i)
      expectJsonNear(a[i], b[i], rel, path + "[" + std::to_string(i) + "]", compared);
  }
}

/// HIPs at `depths` (a depth list) below n patch points of `cache` sampled with `seed`.
HipSet depthHipsOf(const PatchCache& cache, size_t n, uint64_t seed, const char* depths) {
  const PatchSurfaceSampler sampler(cache);
  return makeDepthHips(sampler.sample(n, seed), parseDepthList(depths), boundingDiagonal(cache), sampler.area());
}

/// How many of the records a[i], b[i] (i < a.size()) differ in any byte.
size_t differingRecords(const std::vector<HipResult>& a, const std::vector<HipResult>& b) {
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], sizeof(HipResult)) != 0;
  return differ;
}

// The OpenCL prober resets each HIP's contact state per chunk and keeps per-HIP arrays sized to the
// chunk: every HIP's record is the same bits whatever the chunk (1 HIP, odd sizes, all at once)
// and whatever range of the HIP list a run covers.
TEST_F(OpenCLRefine, SweepProbesAreTheSameBitsForEveryChunk) {
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  const HipSet set = depthHipsOf(*cache, 700, 3, "0.5%,2%");
  OpenCLPatchProber prober(cache, ForceOptions{});
  std::vector<HipResult> all(set.size());
  ASSERT_EQ(prober.run(set, 0, set.size(), nullptr, all.data(), {}), set.size());
  size_t contact = 0;
  for (const HipResult& r : all) {
    ASSERT_EQ(r.done, 1);
    contact += r.contact;
  }
  EXPECT_GT(contact, set.size() / 2);
  for (size_t chunk : {size_t(1), size_t(2), size_t(3), size_t(97), size_t(1000)}) {
    std::vector<HipResult> part(set.size());
    const size_t mid = 333;  // two ranges: the second starts inside the first's last chunk
    ASSERT_EQ(prober.run(set, 0, mid, nullptr, part.data(), {}, chunk), mid);
    ASSERT_EQ(prober.run(set, mid, set.size(), nullptr, part.data() + mid, {}, chunk), set.size() - mid);
    EXPECT_EQ(differingRecords(part, all), 0u) << "chunk " << chunk;
  }
}

// Given the caller's polygon scene and patch surface (as `smoothforce sweep` shares its CPU
// renderers'), the prober's records are those of a prober that builds its own, for every HIP;
// a scene or surface of another cache is refused.
TEST_F(OpenCLRefine, SweepProberWithTheCallersSceneAndSurfaceGivesTheSameBits) {
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  const HipSet set = depthHipsOf(*cache, 600, 7, "0.3%,1%,3%");
  std::vector<HipResult> own(set.size()), given(set.size());
  ASSERT_EQ(OpenCLPatchProber(cache, ForceOptions{}).run(set, 0, set.size(), nullptr, own.data(), {}), set.size());
  auto scene = std::make_shared<const PolygonScene>(*cache, kPlanarTolerance);
  auto surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(ForceOptions{}));
  OpenCLPatchProber shared(cache, scene, surface, ForceOptions{});
  ASSERT_EQ(shared.run(set, 0, set.size(), nullptr, given.data(), {}), set.size());
  size_t contact = 0;
  for (const HipResult& r : own) contact += r.contact;
  EXPECT_EQ(differingRecords(own, given), 0u) << "of " << set.size() << " HIPs";
  EXPECT_GT(contact, set.size() / 2);
  auto other = std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  EXPECT_THROW(OpenCLPatchProber(other, scene, nullptr, ForceOptions{}), InputError);
  EXPECT_THROW(OpenCLPatchProber(other, nullptr, surface, ForceOptions{}), InputError);
}

// The OpenCL prober (refinements and candidate searches on the device, the rest on the CPU)
// gives the CPU path's records byte for byte on every kind of shared mesh in double: a cage, a
// non-convex part cut by the fold repair, an open sheet, a part with creases, a quad sphere.
TEST_F(OpenCLRefine, SweepProbesAreTheCpuPathsBytesOnEveryKindOfMesh) {
  size_t meshes = 0, hips = 0, contacts = 0;
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/tetris.obj",
                          "polygon_laplacian/L-plane.obj", "pmp/chamfer-cube.off", "polygon_laplacian/quad-sphere.off"}) {
    auto cache = std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh(rel)));
    const HipSet set = depthHipsOf(*cache, 400, 11, "0.2%,1%,3%");
    auto scene = std::make_shared<const PolygonScene>(*cache, kPlanarTolerance);
    auto surface = std::make_shared<const PatchSurface>(*cache, patchSurfaceOptions(ForceOptions{}));
    std::vector<HipResult> cpu(set.size()), device(set.size());
    ASSERT_EQ(runProbes(set, 0, set.size(),
                        [&] { return makeForceRenderer(cache, scene, ForceMethod::Patch, ForceOptions{}, surface); },
                        nullptr, cpu.data(), {}),
              set.size());
    ASSERT_EQ(OpenCLPatchProber(cache, scene, surface, ForceOptions{}).run(set, 0, set.size(), nullptr, device.data(), {}),
              set.size());
    for (const HipResult& r : cpu) contacts += r.contact;
    EXPECT_EQ(differingRecords(cpu, device), 0u) << rel << ": of " << set.size() << " HIPs";
    hips += set.size();
    ++meshes;
  }
  EXPECT_EQ(meshes, 5u);
  EXPECT_EQ(hips, 5u * 1200u);
  EXPECT_GT(contacts, hips / 2);
}

TEST_F(OpenCLRefine, SweepTbbAndOpenCLAgree) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sf_sweep_opencl_" + std::to_string(::getpid()));
  auto cache =
      std::make_shared<const PatchCache>(test::cacheFromFile(test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  SweepData d[2];
  for (int b = 0; b < 2; ++b) {
    SweepInputs in;
    in.cache = cache;
    in.config.source = "spot";
    in.config.methods = {"patch"};
    in.config.samples = 3000;
    in.config.seed = 5;
    in.config.backend = b ? "opencl" : "tbb";
    in.depths = parseDepthList("1%,3%");
    d[b] = runSweep(in, {});
    d[b].trajectories.clear();  // CPU renderers on both backends
  }
  const double diag = boundingDiagonal(*cache);
  size_t contactDiff = 0, faceDiff = 0, n = 0, equidistant = 0;
  double maxScp = 0;
  const auto& r0 = d[0].results[0];
  const auto& r1 = d[1].results[0];
  ASSERT_EQ(r0.size(), r1.size());
  for (size_t i = 0; i < r0.size(); ++i) {
    ASSERT_TRUE(r0[i].done && r1[i].done) << i << " " << int(r0[i].done) << int(r1[i].done) << " of " << r0.size();
    contactDiff += r0[i].contact != r1[i].contact;
    if (!(r0[i].contact && r1[i].contact)) continue;
    ++n;
    faceDiff += r0[i].face != r1[i].face;
    const double d = (Eigen::Vector3f(r0[i].scp) - Eigen::Vector3f(r1[i].scp)).norm() / diag;
    // two stationary points at the same distance from the HIP (a point of the medial axis): the
    // last bits of the arithmetic pick one; |F| = k |SCP - HIP| then agrees to float rounding
    const float f0 = Eigen::Vector3f(r0[i].force).norm(), f1 = Eigen::Vector3f(r1[i].force).norm();
    if (d >= 1e-6 && std::getenv("SF_VERBOSE"))
      std::printf("  HIP %zu: SCPs %.3g x diag apart, |F| %.9g / %.9g N, faces %d / %d, status %x / %x\n", i, d, f0, f1,
                  r0[i].face, r1[i].face, r0[i].status, r1[i].status);
    if (d >= 1e-6 && std::abs(f0 - f1) <= 1e-5f * std::max(f0, f1)) {
      ++equidistant;
      continue;
    }
    maxScp = std::max(maxScp, d);
  }
  std::printf(
      "  sweep tbb vs opencl: %zu HIPs, contact differs on %zu, face on %zu of %zu, max SCP diff %.3g x diag, "
      "equidistant points %zu\n",
      r0.size(), contactDiff, faceDiff, n, maxScp, equidistant);
  // the device refines with the host's operations on the host's constants: the same records
  EXPECT_EQ(contactDiff, 0u);
  EXPECT_EQ(equidistant, 0u);
  EXPECT_EQ(faceDiff, 0u);
  EXPECT_EQ(maxScp, 0.0);
  int compared = 0;
  for (int b = 0; b < 2; ++b) writeSweepSummary(d[b], (dir / ("sum" + std::to_string(b))).string());
  const auto j0 = nlohmann::json::parse(std::ifstream(dir / "sum0" / "summary.json"));
  const auto j1 = nlohmann::json::parse(std::ifstream(dir / "sum1" / "summary.json"));
  expectJsonNear(j0, j1, 1e-3, "", &compared);
  EXPECT_GT(compared, 10);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sf
