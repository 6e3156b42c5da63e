// SPDX-License-Identifier: Apache-2.0
// Speed/accuracy presets (force_presets.h), `--preset` on the CLI, and the tessellation initial
// guess (ForceOptions::initialGuess). Properties only: no timings are asserted.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include <smoothforce/base/csv_reader.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "cli_test_support.h"
#include "query_test_support.h"

namespace sf {
namespace {

namespace fs = std::filesystem;

const std::string kSpot = std::string(SF_SHARED_MESHES) + "/keenan_crane/spot_control_mesh.obj";
const std::string kSphere = std::string(SF_SHARED_MESHES) + "/polygon_laplacian/quad-sphere.off";

std::shared_ptr<const PatchCache> doubleCache(const std::string& path) {
  const PatchOptions o;
  return std::make_shared<const PatchCache>(buildPatchCache(loadMesh(path, o), o, Backend::Tbb));
}

/// HIPs pressed `depth` (fraction of the diagonal) under area-uniform patch samples.
/// With `exits`: also the points 2% of the diagonal outside the same surface samples.
std::vector<Eigen::Vector3d> insideHips(const PatchCache& c, size_t n, double depth, uint64_t seed,
                                        std::vector<Eigen::Vector3d>* exits = nullptr) {
  const double diag = boundingDiagonal(c);
  std::vector<Eigen::Vector3d> hips;
  for (const SurfaceSample& s : PatchSurfaceSampler(c, 8).sample(n, seed)) {
    hips.push_back(s.point - depth * diag * s.normal);
    if (exits) exits->push_back(s.point + 0.02 * diag * s.normal);
  }
  return hips;
}

/// A fresh global query (reset, then one step) per HIP.
std::vector<ForceSample> query(const std::shared_ptr<const PatchCache>& c, const ForceOptions& o,
                               const std::vector<Eigen::Vector3d>& hips) {
  auto r = makeForceRenderer(c, ForceMethod::Patch, o);
  std::vector<ForceSample> out;
  for (const auto& h : hips) {
    r->reset();
    out.push_back(r->step(h));
  }
  return out;
}

ForceOptions tight() {
  ForceOptions o;
  o.angleTolerance = 1e-12;
  o.maxIterations = 500;
  return o;
}

TEST(ForcePresets, NamesParseAndUnknownNamesAreInputErrors) {
  ASSERT_EQ(forcePresets().size(), 3u);
  EXPECT_EQ(forcePresets()[0].name, "fast");
  EXPECT_EQ(forcePresets()[1].name, "balanced");
  EXPECT_EQ(forcePresets()[2].name, "accurate");
  for (const ForcePreset& p : forcePresets()) EXPECT_EQ(&findForcePreset(p.name), &p);
  try {
    findForcePreset("turbo");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--preset: expected fast|balanced|accurate, got 'turbo'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(findForcePreset(""), InputError);
  EXPECT_THROW(findForcePreset("Fast"), InputError);
}

TEST(ForcePresets, ApplySetsRefinementOnlyAndTightensFromFastToAccurate) {
  for (const ForcePreset& p : forcePresets()) {
    ForceOptions o;
    o.stiffness = 123;
    applyForcePreset(p, o);
    EXPECT_EQ(o.stiffness, 123);
    EXPECT_EQ(o.refine, p.refine);
    EXPECT_EQ(o.angleTolerance, p.angleTolerance);
    EXPECT_EQ(o.positionTolerance, p.positionTolerance);
    EXPECT_EQ(o.maxIterations, p.maxIterations);
    EXPECT_EQ(o.initialGuess, p.initialGuess);
    EXPECT_EQ(o.tessellationLevel, p.tessellationLevel);
    EXPECT_NO_THROW(validateForceOptions(o));
  }
  const auto& v = forcePresets();
  for (size_t i = 1; i < v.size(); ++i) {
    EXPECT_LT(v[i].angleTolerance, v[i - 1].angleTolerance);
    EXPECT_LE(v[i].positionTolerance, v[i - 1].positionTolerance);
  }
  // accurate is never looser than no preset: both of its tolerances at most the defaults
  const ForceOptions defaults;
  EXPECT_LE(findForcePreset("accurate").angleTolerance, defaults.angleTolerance);
  EXPECT_LE(findForcePreset("accurate").positionTolerance, defaults.positionTolerance);
  EXPECT_EQ(findForcePreset("accurate").precision, Precision::Double);
}

TEST(ForcePresets, FasterPresetsTakeFewerRefinementStepsOnEverySlide) {
  // The refinement stops at the smaller of the angle and the position tolerance, so a preset that
  // loosened only the angle's changed nothing (every preset took the default's steps). Over slides
  // pressed 0.5% and 1% into the spot cage and the quad-sphere, from one surface sample to the next
  // (40 of them, 30 steps apart): fast takes fewer iterations than balanced, balanced fewer than
  // accurate, and accurate as many as no preset (whose tolerances it keeps); each step's iterations
  // at most the preset's cap.
  int slides = 0;
  for (const std::string& mesh : {kSpot, kSphere}) {
    const auto cache = doubleCache(mesh);
    const double diag = boundingDiagonal(*cache);
    for (const double depth : {0.005, 0.01}) {
      const std::vector<SurfaceSample> at = PatchSurfaceSampler(*cache, 8).sample(40, 3);
      std::vector<Eigen::Vector3d> hips;
      for (size_t i = 0; i + 1 < at.size(); ++i)
        for (int j = 0; j < 30; ++j) {
          const double t = j / 30.0;
          hips.push_back((1 - t) * (at[i].point - depth * diag * at[i].normal) +
                         t * (at[i + 1].point - depth * diag * at[i + 1].normal));
        }
      std::vector<long> iterations;
      for (const char* name : {"fast", "balanced", "accurate", ""}) {
        ForceOptions o;
        if (*name) applyForcePreset(findForcePreset(name), o);
        auto r = makeForceRenderer(cache, ForceMethod::Patch, o);
        long sum = 0;
        for (const Eigen::Vector3d& h : hips) {
          const ForceSample s = r->step(h);
          EXPECT_LE(s.iterations, o.maxIterations);
          sum += s.iterations;
        }
        iterations.push_back(sum);
      }
      std::printf("%s at %.1f%%: iterations over %zu steps: fast %ld, balanced %ld, accurate %ld, no preset %ld\n",
                  mesh.c_str() + mesh.rfind('/') + 1, 100 * depth, hips.size(), iterations[0], iterations[1],
                  iterations[2], iterations[3]);
      EXPECT_LT(iterations[0], iterations[1]) << mesh << " " << depth;
      EXPECT_LT(iterations[1], iterations[2]) << mesh << " " << depth;
      EXPECT_EQ(iterations[2], iterations[3]) << mesh << " " << depth;
      ++slides;
    }
  }
  EXPECT_EQ(slides, 4);
}

TEST(InitialGuess, ParsesAndValidatesTheLevel) {
  EXPECT_EQ(parseInitialGuess("polygon"), InitialGuess::Polygon);
  EXPECT_EQ(parseInitialGuess("surface"), InitialGuess::Surface);
  EXPECT_EQ(parseInitialGuess("tessellation"), InitialGuess::Surface);  // the former name
  EXPECT_STREQ(toString(InitialGuess::Surface), "surface");
  EXPECT_STREQ(toString(InitialGuess::Polygon), "polygon");
  EXPECT_THROW(parseInitialGuess("vertex"), InputError);
  ForceOptions o;
  o.tessellationLevel = -1;
  EXPECT_THROW(validateForceOptions(o), InputError);
  o.tessellationLevel = 65;
  EXPECT_THROW(validateForceOptions(o), InputError);
  o.tessellationLevel = 0;
  EXPECT_NO_THROW(validateForceOptions(o));
}

// The surface query's SCP is never farther from the HIP than the paper's polygon start's, and it
// starts contact at least as often at HIPs inside the surface (the dense oracle's winding number:
// near the spot cage's folds a sample pushed inward can come out in front of another sheet), on a
// real quad cage and on the quad-sphere (every HIP).
TEST(InitialGuess, SurfaceQueryIsNeverFartherThanThePolygonStart) {
  for (const std::string& mesh : {kSpot, kSphere}) {
    const auto c = doubleCache(mesh);
    const double diag = boundingDiagonal(*c);
    std::vector<Eigen::Vector3d> hips = insideHips(*c, 120, 0.01, 11);
    const auto more = insideHips(*c, 60, 0.003, 12);
    hips.insert(hips.end(), more.begin(), more.end());
    ForceOptions o = tight();
    o.initialGuess = InitialGuess::Polygon;
    const auto byPolygon = query(c, o, hips);
    o.initialGuess = InitialGuess::Surface;
    const auto bySurface = query(c, o, hips);
    const test::DenseOracle oracle(*c);
    int both = 0, polygonContacts = 0, surfaceContacts = 0, outside = 0;
    for (size_t i = 0; i < hips.size(); ++i) {
      const ForceSample &a = byPolygon[i], &b = bySurface[i];
      EXPECT_TRUE(b.status & SF_TRACK_GLOBAL);
      const bool inside = oracle.winding(hips[i]) >= 1;
      outside += !inside;
      polygonContacts += inside && a.contact;
      surfaceContacts += inside && b.contact;
      if (!a.contact || !b.contact) continue;
      ++both;
      EXPECT_LE((b.scp - hips[i]).norm(), (a.scp - hips[i]).norm() + 1e-9 * diag) << mesh << " HIP " << i;
    }
    EXPECT_GE(surfaceContacts, polygonContacts) << mesh;
    EXPECT_LE(outside, static_cast<int>(hips.size()) / 50) << mesh;
    EXPECT_GE(both, static_cast<int>(hips.size()) * 9 / 10) << mesh;
  }
}

class ForcePresetCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_presets_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  /// Writes the HIPs, each followed by its exit point 2% of the diagonal outside the surface
  /// point it was pushed in from: contact ends there, so every HIP starts a fresh global query
  /// (HIP i on row 2 i, as in the study).
  std::string hipFile(const std::vector<Eigen::Vector3d>& hips, const std::vector<Eigen::Vector3d>& exits) {
    const std::string p = (dir / "hips.csv").string();
    std::ofstream f(p);
    f.precision(17);
    f << "x,y,z\n";
    for (size_t i = 0; i < hips.size(); ++i)
      f << hips[i].x() << "," << hips[i].y() << "," << hips[i].z() << "\n"
        << exits[i].x() << "," << exits[i].y() << "," << exits[i].z() << "\n";
    return p;
  }
  /// Runs trace and returns its rows (every other row: the HIPs).
  NumericCsv trace(const std::string& args) {
    const std::string out = (dir / "out.csv").string();
    const auto r = test::smoothforce("trace " + args + " -o " + out);
    EXPECT_EQ(r.status, 0) << r.out;
    return readNumericCsv(out, {"x", "y", "z", "contact", "face", "xi", "eta", "scp_x", "scp_y", "scp_z", "fx", "fy",
                                "fz", "iterations", "status"});
  }
  fs::path dir;
};

TEST_F(ForcePresetCli, UnknownPresetIsRejectedByEveryForceCommand) {
  const std::string hips = hipFile({{0, 0, 0}}, {{0, 0, 2}});
  const auto t = test::smoothforce("trace --mesh " + kSphere + " --hips " + hips + " -o " + (dir / "o.csv").string() +
                                   " --preset turbo");
  EXPECT_NE(t.status, 0);
  EXPECT_NE(t.out.find("--preset: expected fast|balanced|accurate, got 'turbo'"), std::string::npos) << t.out;
  const auto l = test::smoothforce("loop --mesh " + kSphere + " --device null --duration 0.01 --preset turbo");
  EXPECT_NE(l.status, 0);
  EXPECT_NE(l.out.find("got 'turbo'"), std::string::npos) << l.out;
  const auto s = test::smoothforce("sweep --mesh " + kSphere + " --depth 1% --samples 4 --no-plots --preset turbo -o " +
                                   (dir / "sw").string());
  EXPECT_NE(s.status, 0);
  EXPECT_NE(s.out.find("got 'turbo'"), std::string::npos) << s.out;
}

TEST_F(ForcePresetCli, ExplicitOptionsOverrideThePreset) {
  const auto c = doubleCache(kSpot);
  std::vector<Eigen::Vector3d> exits;
  const std::vector<Eigen::Vector3d> in = insideHips(*c, 30, 0.01, 5, &exits);
  const std::string hips = hipFile(in, exits);
  const NumericCsv accurate = trace("--mesh " + kSpot + " --hips " + hips + " --preset accurate");
  const NumericCsv capped = trace("--mesh " + kSpot + " --hips " + hips + " --preset accurate --max-iter 1");
  int maxAccurate = 0, maxCapped = 0;
  for (size_t r = 0; r < accurate.rows(); r += 2) maxAccurate = std::max(maxAccurate, int(accurate.at(r, 13)));
  for (size_t r = 0; r < capped.rows(); r += 2) maxCapped = std::max(maxCapped, int(capped.at(r, 13)));
  EXPECT_GT(maxAccurate, 1);
  EXPECT_EQ(maxCapped, 1);
}

// docs/results.md "Speed against accuracy", "Checked bounds": on spot, against a converged double
// reference from the global query on the built cache, with SCP errors over the bounding diagonal and
// force-direction errors in degrees: failures (no contact, or an SCP error above 1e-3: another
// local minimum) at most 3% of the HIPs; of the rest, fast: median SCP error <= 1e-5 and max
// <= 1e-3, max angle <= 2; accurate: median SCP error <= 1e-9, median angle <= 1e-6.
TEST_F(ForcePresetCli, FastAndAccurateMeetTheirDocumentedErrorBounds) {
  const auto c = doubleCache(kSpot);
  const double diag = boundingDiagonal(*c);
  std::vector<Eigen::Vector3d> exits;
  std::vector<Eigen::Vector3d> hips = insideHips(*c, 50, 0.0025, 21, &exits);
  const auto deeper = insideHips(*c, 50, 0.01, 22, &exits);
  hips.insert(hips.end(), deeper.begin(), deeper.end());
  // trace --mesh builds patches lazily; its global query is the surface query as on a built cache
  const auto ref = query(c, tight(), hips);
  const std::string file = hipFile(hips, exits);
  struct Bound {
    std::string preset;
    double medianScp, maxScp, medianAngle, maxAngle;
  };
  for (const Bound& b : {Bound{"fast", 1e-5, 1e-3, 1.0, 2.0}, Bound{"accurate", 1e-9, 1e-3, 1e-6, 2.0}}) {
    const NumericCsv t = trace("--mesh " + kSpot + " --hips " + file + " --preset " + b.preset);
    ASSERT_EQ(t.rows(), 2 * hips.size());
    std::vector<double> scp, angle;
    int failures = 0, compared = 0;
    for (size_t i = 0; i < hips.size(); ++i) {
      const size_t r = 2 * i;
      if (!ref[i].contact) continue;  // pushed through a thin part: outside
      // the exit row before did not end contact (Algorithm 1 tracks locally): not a fresh query
      if (!(static_cast<uint32_t>(t.at(r, 14)) & SF_TRACK_GLOBAL)) continue;
      ++compared;
      const Eigen::Vector3d p(t.at(r, 7), t.at(r, 8), t.at(r, 9));
      const double e = (p - ref[i].scp).norm() / diag;
      if (t.at(r, 3) != 1 || e > 1e-3) {
        if (std::getenv("SF_VERBOSE"))
          std::printf("%s HIP %zu: contact %g, error %.3g, status %x, ref status %x\n", b.preset.c_str(), i, t.at(r, 3),
                      e, unsigned(t.at(r, 14)), ref[i].status);
        ++failures;
        continue;
      }
      const Eigen::Vector3d a = p - hips[i], w = ref[i].scp - hips[i];
      scp.push_back(e);
      angle.push_back(std::atan2(a.cross(w).norm(), a.dot(w)) * 180 / M_PI);
    }
    ASSERT_GE(compared, 85);
    EXPECT_LE(failures, compared * 3 / 100) << b.preset;
    std::sort(scp.begin(), scp.end());
    std::sort(angle.begin(), angle.end());
    EXPECT_LE(scp[scp.size() / 2], b.medianScp) << b.preset;
    EXPECT_LE(scp.back(), b.maxScp) << b.preset;
    EXPECT_LE(angle[angle.size() / 2], b.medianAngle) << b.preset;
    EXPECT_LE(angle.back(), b.maxAngle) << b.preset;
    if (std::getenv("SF_VERBOSE"))
      std::printf("%s: %d failures of %d; SCP error median %.3g max %.3g; angle median %.3g max %.3g deg\n",
                  b.preset.c_str(), failures, compared, scp[scp.size() / 2], scp.back(), angle[angle.size() / 2],
                  angle.back());
  }
}

}  // namespace
}  // namespace sf
