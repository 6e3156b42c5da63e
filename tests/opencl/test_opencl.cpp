// SPDX-License-Identifier: Apache-2.0
// Cross-check tests of the OpenCL backend against the CPU backends (construction vs
// constructPatches(Backend::Tbb), evaluation vs evaluatePatches(Backend::Tbb)), float and
// double, on real meshes and random irregular polytopes; plus the kernels' OpenCL C 1.2
// syntax under clang. Skipped with the reason when no OpenCL device exists.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_context.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_eval.h>
#include "gp_config.h"  // GP_* status bits and record layout
#include "patch_test_support.h"
#include "test_hostile_support.h"

namespace {

using namespace sf;

// Float tolerance on a device whose float / and sqrt are not correctly rounded (see the comment
// at the top of host/opencl_backend.h), relative to the mesh's bounding-box diagonal; normals
// absolute. Elsewhere the device computes the CPU's bits.
constexpr double kEvalTolF = 2e-5;

/// A random irregular polytope: a jittered prism (m quads) or antiprism (2m triangles)
/// between two m-gons with random radii and angles; m in 5..9.
PolygonMesh randomPolytope(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const int m = 5 + static_cast<int>(rng() % 5);
  const bool anti = seed % 2;
  PolygonMesh pm;
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < m; ++k) {
      const double a = 2 * M_PI * (k + 0.25 * u(rng) + (anti && ring ? 0.5 : 0.0)) / m;
      const double r = 1 + 0.3 * u(rng);
      pm.positions.emplace_back(r * std::cos(a), r * std::sin(a), (ring ? 1.0 : -1.0) + 0.2 * u(rng));
    }
  std::vector<int32_t> bottom, top;
  for (int k = 0; k < m; ++k) {
    bottom.push_back(m - 1 - k);  // CCW seen from below
    top.push_back(m + k);
  }
  pm.addFace(bottom);
  pm.addFace(top);
  for (int k = 0; k < m; ++k) {
    const int k1 = (k + 1) % m;
    if (anti) {
      pm.addFace({k, k1, m + k});
      pm.addFace({k1, m + k1, m + k});
    } else {
      pm.addFace({k, k1, m + k1, m + k});
    }
  }
  return pm;
}

struct NamedMesh {
  std::string name;
  PolygonMesh mesh;
};

const std::vector<NamedMesh>& testMeshes() {
  static const std::vector<NamedMesh> meshes = [] {
    std::vector<NamedMesh> v;
    for (unsigned s : {1u, 2u, 7u}) v.push_back({"polytope" + std::to_string(s), randomPolytope(s)});
    for (const char* rel :
         {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/hexaSphere.off", "geomview/dodecahedron.off"}) {
      const std::string path = std::string(SF_SHARED_MESHES) + "/" + rel;
      if (std::filesystem::exists(path)) v.push_back({rel, readMesh(path)});
    }
    return v;
  }();
  return meshes;
}

PatchCache prepared(const PolygonMesh& m, Precision p) {
  PatchOptions o;
  o.precision = p;
  return preparePatchCache(m, cornerNormals(m, NormalMode::Auto), o, 0);
}

/// `perFace` points uniform in each face's n-gon domain: a random fan triangle
/// (origin, C_k, C_k+1), then uniform barycentrics.
struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
};
Queries randomQueries(const PatchCache& c, int perFace, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Queries q;
  for (int f = 0; f < c.numFaces(); ++f)
    for (int i = 0; i < perFace; ++i) {
      const int n = c.faceSize(f), k = static_cast<int>(rng() % n);
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Eigen::Vector2d p = a * domainCorner(n, k) + b * domainCorner(n, (k + 1) % n);
      q.face.push_back(f);
      q.xi.push_back(p.x());
      q.eta.push_back(p.y());
    }
  return q;
}

/// Largest difference of two point sets: positions and derivatives over `scale`; normals
/// absolute (`normal`) and over their condition number |G_xi| |G_eta| / |G_xi x G_eta|
/// (`normalRel`: the unit normal of a nearly singular parametrisation amplifies rounding);
/// counts status mismatches.
struct Diff {
  double vec = 0, normal = 0, normalRel = 0;
  int statusMismatch = 0;
};
Diff compare(const std::vector<PatchPoint>& a, const std::vector<PatchPoint>& b, double scale) {
  Diff d;
  for (size_t i = 0; i < a.size(); ++i) {
    d.vec = std::max({d.vec, (a[i].pos - b[i].pos).lpNorm<Eigen::Infinity>() / scale,
                      (a[i].dxi - b[i].dxi).lpNorm<Eigen::Infinity>() / scale,
                      (a[i].deta - b[i].deta).lpNorm<Eigen::Infinity>() / scale});
    const double dn = (a[i].normal - b[i].normal).lpNorm<Eigen::Infinity>();
    const double cross = a[i].dxi.cross(a[i].deta).norm(), lens = a[i].dxi.norm() * a[i].deta.norm();
    d.normal = std::max(d.normal, dn);
    d.normalRel = std::max(d.normalRel, dn / std::max(1.0, cross > 0 ? lens / cross : 1e300));
    d.statusMismatch += a[i].status != b[i].status;
  }
  return d;
}

template <class Real>
double maxRecordDiff(const std::vector<Real>& a, const std::vector<Real>& b, size_t* unequal) {
  double m = 0;
  *unequal = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = std::abs(double(a[i]) - double(b[i]));
    if (!(d == 0)) ++*unequal;  // NaN counts as unequal
    m = std::max(m, std::isnan(d) ? INFINITY : d);
  }
  return m;
}

/// One constructor and one evaluator for the suite: PoCL compiles each program in seconds.
class OpenCLBackend : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!openclAvailable(&reason_)) return;
    constructor_ = std::make_unique<OpenCLConstructor>();
    exactFloat_ = OpenCLContext().hasCorrectlyRoundedDivSqrt();
  }
  static void TearDownTestSuite() {
    evaluator_.reset();
    constructor_.reset();
  }
  void SetUp() override {
    if (!constructor_) GTEST_SKIP() << "no OpenCL device: " << reason_;
  }
  static OpenCLEvaluator& evaluator(const PatchCache& c) {
    if (!evaluator_)
      evaluator_ = std::make_unique<OpenCLEvaluator>(c);
    else
      evaluator_->setCache(c);
    return *evaluator_;
  }
  static PatchCache cpuCache(const PolygonMesh& m, Precision p) {
    PatchCache c = prepared(m, p);
    constructPatches(c, Backend::Tbb);
    return c;
  }

  static inline std::string reason_;
  static inline bool exactFloat_ = false;  // float / and sqrt correctly rounded on the device
  static inline std::unique_ptr<OpenCLConstructor> constructor_;
  static inline std::unique_ptr<OpenCLEvaluator> evaluator_;
};

TEST_F(OpenCLBackend, ConstructionMatchesTbb) {
  for (Precision p : {Precision::Double, Precision::Float})
    for (const auto& [name, mesh] : testMeshes()) {
      SCOPED_TRACE(name + ", " + toString(p));
      const PatchCache cpu = cpuCache(mesh, p);
      PatchCache gpu = prepared(mesh, p);
      constructor_->construct(gpu);
      size_t unequal = 0;
      const double d = p == Precision::Double ? maxRecordDiff(cpu.edgeDataD, gpu.edgeDataD, &unequal)
                                              : maxRecordDiff(cpu.edgeDataF, gpu.edgeDataF, &unequal);
      double bulge = 0;
      for (int f = 0; f < cpu.numFaces(); ++f)
        bulge = std::max(bulge, double(std::abs(cpu.faceBulge[f] - gpu.faceBulge[f])));
      std::printf("[ OpenCL   ] construct %-36s %-6s max|rec diff| %.3g (%zu unequal), max|bulge diff| %.3g\n",
                  name.c_str(), toString(p), d, unequal, bulge);
      EXPECT_EQ(cpu.faceStatus, gpu.faceStatus);
      // records use + - * / sqrt only, contraction is off, and the quality samples read the
      // host's domain table: equal wherever / and sqrt are correctly rounded (always in double;
      // in float when the device offers it)
      if (p == Precision::Double || exactFloat_) {
        EXPECT_EQ(unequal, 0u);
        EXPECT_EQ(bulge, 0.0);
      } else {
        EXPECT_LE(d, 1e-5 * boundingDiagonal(cpu));
        EXPECT_LE(bulge, 1e-5);
      }
    }
}

TEST_F(OpenCLBackend, EvaluationMatchesCpu) {
  for (Precision p : {Precision::Double, Precision::Float})
    for (const auto& [name, mesh] : testMeshes()) {
      SCOPED_TRACE(name + ", " + toString(p));
      const PatchCache c = cpuCache(mesh, p);
      const Queries q = randomQueries(c, 64, 5);
      std::vector<PatchPoint> cpu(q.face.size()), gpu(q.face.size());
      evaluatePatches(c, q.face.data(), q.xi.data(), q.eta.data(), cpu.size(), cpu.data(), Backend::Tbb);
      evaluator(c).evaluate(q.face.data(), q.xi.data(), q.eta.data(), gpu.size(), gpu.data());
      const Diff d = compare(cpu, gpu, boundingDiagonal(c));
      std::printf("[ OpenCL   ] evaluate  %-36s %-6s max|diff|/diag %.3g, max|normal diff| %.3g (%.3g / cond)\n",
                  name.c_str(), toString(p), d.vec, d.normal, d.normalRel);
      EXPECT_EQ(d.statusMismatch, 0);
      if (p == Precision::Double || exactFloat_) {  // the same operations on the same constants
        EXPECT_EQ(d.vec, 0.0);
        EXPECT_EQ(d.normal, 0.0);
        continue;
      }
      EXPECT_LE(d.vec, kEvalTolF);
      // float normals: OpenCL may differ from the CPU by what float rounding costs the CPU
      // itself against double (folded or near-singular points amplify it), plus a floor.
      // Per point that is noise; over the mesh it is a bound.
      const PatchCache cd = cpuCache(mesh, Precision::Double);
      std::vector<PatchPoint> ref(q.face.size());
      evaluatePatches(cd, q.face.data(), q.xi.data(), q.eta.data(), ref.size(), ref.data(), Backend::Tbb);
      double own = 0;
      for (size_t i = 0; i < ref.size(); ++i)
        own = std::max(own, (cpu[i].normal - ref[i].normal).lpNorm<Eigen::Infinity>());
      std::printf("[ OpenCL   ]           CPU float normals vs double: max %.3g\n", own);
      EXPECT_LE(d.normal, 2 * own + kEvalTolF) << "OpenCL float normals further from the CPU's than its own error";
    }
}

TEST_F(OpenCLBackend, EvaluatorReusesBuffersAcrossBatches) {
  const PatchCache c = cpuCache(randomPolytope(11), Precision::Double);
  const Queries q = randomQueries(c, 200, 9);  // >= 2000 points
  OpenCLEvaluator& ev = evaluator(c);
  const size_t allocs0 = ev.allocations();
  std::vector<PatchPoint> cpu(q.face.size()), gpu(q.face.size());
  evaluatePatches(c, q.face.data(), q.xi.data(), q.eta.data(), cpu.size(), cpu.data(), Backend::Tbb);
  const size_t sizes[] = {1000, 1000, 500, 1000, q.face.size(), 7};
  const size_t expectCap[] = {1000, 1000, 1000, 1000, q.face.size(), q.face.size()};
  for (int b = 0; b < 6; ++b) {
    const size_t n = sizes[b], off = (b * 37) % 100;  // shifted windows: new data each batch
    std::fill(gpu.begin(), gpu.end(), PatchPoint{});
    ev.evaluate(&q.face[off], &q.xi[off], &q.eta[off], std::min(n, q.face.size() - off), gpu.data());
    std::vector<PatchPoint> want(cpu.begin() + off, cpu.begin() + off + std::min(n, q.face.size() - off));
    gpu.resize(want.size());
    const Diff d = compare(want, gpu, boundingDiagonal(c));
    EXPECT_EQ(d.vec, 0.0) << "batch " << b;
    EXPECT_EQ(d.statusMismatch, 0) << "batch " << b;
    gpu.resize(q.face.size());
    EXPECT_GE(ev.capacity(), std::min(expectCap[b], q.face.size() - off)) << "batch " << b;
  }
  EXPECT_EQ(ev.allocations() - allocs0, 2u);  // 1000 once, then the one larger batch
  EXPECT_GT(ev.lastKernelSeconds(), 0.0);
  EXPECT_GT(ev.lastTransferSeconds(), 0.0);

  // the float overload on a double cache equals the double call with the same values
  std::vector<float> xf(q.xi.begin(), q.xi.begin() + 100), yf(q.eta.begin(), q.eta.begin() + 100);
  std::vector<double> xd(xf.begin(), xf.end()), yd(yf.begin(), yf.end());
  std::vector<PatchPoint> a(100), b(100);
  ev.evaluate(q.face.data(), xf.data(), yf.data(), 100, a.data());
  ev.evaluate(q.face.data(), xd.data(), yd.data(), 100, b.data());
  EXPECT_EQ(compare(a, b, 1.0).vec, 0.0);
}

TEST_F(OpenCLBackend, BadQueriesGiveStatusLikeCpu) {
  for (Precision p : {Precision::Double, Precision::Float}) {
    const PatchCache c = cpuCache(randomPolytope(3), p);
    const std::vector<int32_t> faces = {-1, c.numFaces(), 0, 0, 1};
    const std::vector<double> xi = {0, 0, 5, 0.99, 0.1}, eta = {0, 0, 5, 0.5, 0.2};
    std::vector<PatchPoint> cpu(faces.size()), gpu(faces.size());
    evaluatePatches(c, faces.data(), xi.data(), eta.data(), faces.size(), cpu.data(), Backend::Tbb);
    evaluator(c).evaluate(faces.data(), xi.data(), eta.data(), faces.size(), gpu.data());
    for (size_t i = 0; i < faces.size(); ++i) {
      EXPECT_EQ(cpu[i].status, gpu[i].status) << "query " << i;
      if (i < 4) {
        EXPECT_TRUE(gpu[i].status & GP_ST_OUTSIDE) << "query " << i;
        EXPECT_EQ(gpu[i].pos, Eigen::Vector3d::Zero()) << "query " << i;
      }
    }
  }
}

TEST_F(OpenCLBackend, OneShotWrappersMatch) {
  const PolygonMesh m = randomPolytope(4);
  const PatchCache cpu = cpuCache(m, Precision::Double);
  PatchCache gpu = prepared(m, Precision::Double);
  constructPatchesOpenCL(gpu);
  EXPECT_EQ(cpu.faceStatus, gpu.faceStatus);
  size_t unequal = 0;
  EXPECT_EQ(maxRecordDiff(cpu.edgeDataD, gpu.edgeDataD, &unequal), 0.0);
  const Queries q = randomQueries(cpu, 16, 2);
  std::vector<PatchPoint> a(q.face.size()), b(q.face.size());
  evaluatePatches(cpu, q.face.data(), q.xi.data(), q.eta.data(), a.size(), a.data(), Backend::Serial);
  evaluatePatchesOpenCL(gpu, q.face.data(), q.xi.data(), q.eta.data(), b.size(), b.data());
  EXPECT_EQ(compare(a, b, boundingDiagonal(cpu)).vec, 0.0);
  // an empty batch is fine
  evaluatePatchesOpenCL(gpu, nullptr, static_cast<const double*>(nullptr), nullptr, 0, nullptr);
}

// Flat triangles marked GP_ST_AFFINE, with straight and curved edges (a plate with a round hole,
// its rim a crease curve): the device marks the same faces, builds the same records and evaluates
// the same bits as the CPU (double), or within the float tolerance.
TEST_F(OpenCLBackend, FlatTrianglesWithCurvedEdgesMatchCpu) {
  hostile::TempDir dir("sf_opencl_plate");
  const std::filesystem::path path = dir.path / "plate24.obj";
  std::ofstream(path) << test::holedPlateObj(24, 0.5, 0.4);
  for (Precision p : {Precision::Double, Precision::Float}) {
    SCOPED_TRACE(toString(p));
    PatchOptions o;
    o.creases.angleDeg = 30;
    o.precision = p;
    const LoadedMesh lm = loadMesh(path.string(), o);
    const PatchCache cpu = buildPatchCache(lm, o, Backend::Tbb);
    PatchCache gpu = preparePatchCache(lm.mesh, lm.cornerNormals, o, lm.fileHash);
    constructor_->construct(gpu);
    EXPECT_EQ(cpu.faceStatus, gpu.faceStatus);
    int marked = 0, curved = 0;
    for (int f = 0; f < cpu.numFaces(); ++f) {
      if (!(cpu.faceStatus[f] & GP_ST_AFFINE)) continue;
      ++marked;
      double recs[3 * GP_E_NFIELDS];
      if (p == Precision::Double) {
        gatherRecords(cpu, f, recs);
      } else {
        float fr[3 * GP_E_NFIELDS];
        gatherRecords(cpu, f, fr);
        std::copy(fr, fr + 3 * GP_E_NFIELDS, recs);
      }
      curved += test::hasCurvedEdge(3, recs, 1e-3);
    }
    EXPECT_EQ(marked, 2 * (24 + 4) + 8);  // top, bottom and the outer sides
    EXPECT_EQ(curved, 2 * 24);            // the rim's triangles
    size_t unequal = 0;
    const double d = p == Precision::Double ? maxRecordDiff(cpu.edgeDataD, gpu.edgeDataD, &unequal)
                                            : maxRecordDiff(cpu.edgeDataF, gpu.edgeDataF, &unequal);
    const Queries q = randomQueries(cpu, 64, 11);
    std::vector<PatchPoint> a(q.face.size()), b(q.face.size());
    evaluatePatches(cpu, q.face.data(), q.xi.data(), q.eta.data(), a.size(), a.data(), Backend::Tbb);
    evaluator(cpu).evaluate(q.face.data(), q.xi.data(), q.eta.data(), b.size(), b.data());
    const Diff e = compare(a, b, boundingDiagonal(cpu));
    std::printf("[ OpenCL   ] holed plate %-6s %d affine faces (%d curved): max|rec diff| %.3g, max|diff|/diag %.3g\n",
                toString(p), marked, curved, d, e.vec);
    EXPECT_EQ(e.statusMismatch, 0);
    if (p == Precision::Double || exactFloat_) {
      EXPECT_EQ(unequal, 0u);
      EXPECT_EQ(e.vec, 0.0);
      EXPECT_EQ(e.normal, 0.0);
    } else {
      EXPECT_LE(d, 1e-5 * boundingDiagonal(cpu));
      EXPECT_LE(e.vec, kEvalTolF);
    }
  }
}

TEST_F(OpenCLBackend, RejectsUnpreparedCache) {
  PatchCache c = prepared(randomPolytope(5), Precision::Double);
  c.edgeDataD.clear();
  EXPECT_THROW(constructor_->construct(c), std::invalid_argument);
  EXPECT_THROW(OpenCLEvaluator{c}, std::invalid_argument);
}

// Each kernel file, as the standalone OpenCL C 1.2 it claims to be, in float and double.
TEST(OpenCLKernelSyntax, ClangAcceptsKernelsFloatAndDouble) {
  if (std::system("command -v clang > /dev/null 2>&1") != 0) GTEST_SKIP() << "clang not found on PATH";
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(SF_KERNEL_DIR)) {
    if (e.path().extension() != ".cl") continue;
    ++files;
    for (const char* defs : {"-DGP_REAL=float -DGP_IS_DOUBLE=0", "-DGP_REAL=double -DGP_IS_DOUBLE=1"}) {
      const std::string cmd = std::string("clang -x cl -cl-std=CL1.2 -fsyntax-only -Xclang -finclude-default-header ") +
                              "-Werror -I'" SF_KERNEL_DIR "' " + defs + " '" + e.path().string() + "' 2>&1";
      std::string out;
      if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[512];
        while (fgets(buf, sizeof buf, p)) out += buf;
        EXPECT_EQ(pclose(p), 0) << cmd << "\n" << out;
      } else {
        ADD_FAILURE() << "cannot run " << cmd;
      }
    }
  }
  EXPECT_GE(files, 3);  // construct.cl, evaluate.cl, refine.cl
}

}  // namespace
