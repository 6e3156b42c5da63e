// SPDX-License-Identifier: Apache-2.0
// RefineOptions::finalStep = FinalStep::Model (kernels/gp_refine.h, gp_rf_model_point): the
// converging step's point from the refinement's quadratic model instead of a patch evaluation.
// Over every closed shape (query_test_support.h), constant-depth slides generated on the surface
// (walkSurface) at three depths, each HIP rendered by two patch renderers side by side, one with
// evaluated final steps (the default) and one with model final steps. Checked on every step:
// the same contact decisions; and on every model point, against an evaluation of the patch at
// the point's own (face, xi, eta) (independent of the model): the SCP on the patch, its normal
// the patch's, the SCP stationary, and the SCP and force of the evaluated renderer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>
#include <smoothforce/base/csv_reader.h>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "cli_test_support.h"
#include "patch_test_support.h"
#include "query_test_support.h"

namespace sf {
namespace {

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

struct ModelStats {
  long expected = 0;  // HIPs given: 3 depths x each slide's points
  long steps = 0, contacts = 0, modelPoints = 0, contactDiffers = 0, capHits = 0;
  double offPatch = 0;      // |SCP - G(face, xi, eta)| / diagonal
  double normalOff = 0;     // rad, model normal against the patch normal at its point
  double residual = 0;      // |(HIP - SCP) x n_patch| / diagonal, n_patch evaluated at the point
  double scpApart = 0;      // |SCP_model - SCP_evaluated| / diagonal
  double normalApart = 0;   // rad, between the two renderers' normals
};

/// The cache as the CPU refinement evaluates it: float records widened to double, evaluated in
/// double (patch_refine.cpp); a double cache as it is.
PatchCache widened(const PatchCache& c) {
  PatchCache w = c;
  if (c.options.precision == Precision::Float) {
    w.edgeDataD.assign(c.edgeDataF.begin(), c.edgeDataF.end());
    w.edgeDataF.clear();
    w.options.precision = Precision::Double;
  }
  return w;
}

ModelStats slideBoth(const std::string& shape, std::shared_ptr<const PatchCache> cache) {
  const PatchCache exact = widened(*cache);  // the patch the model stands in for
  const double diag = boundingDiagonal(*cache);
  PatchRefiner walker(*cache);
  const PatchSurfaceSampler sampler(*cache, cache->numFaces() > 4000 ? 2 : 6);
  const std::vector<SurfaceSample> starts = sampler.sample(12, 11);
  auto surface = std::make_shared<const PatchSurface>(*cache);
  auto scene = std::make_shared<const PolygonScene>(*cache);
  ForceOptions evaluated, model;
  model.finalStep = FinalStep::Model;
  auto E = makeForceRenderer(cache, scene, ForceMethod::Patch, evaluated, surface);
  auto M = makeForceRenderer(cache, scene, ForceMethod::Patch, model, surface);
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss;
  ModelStats st;
  const double step = 0.001 * diag;
  for (const SurfaceSample& s0 : starts) {
    const Eigen::Vector3d dir(gauss(rng), gauss(rng), gauss(rng));
    const test::SurfacePath path = test::walkSurface(*cache, walker, s0.face, {s0.xi, s0.eta}, dir, step, 150);
    st.expected += 3 * static_cast<long>(path.point.size());
    for (double depth : {0.001 * diag, 0.0025 * diag, 0.01 * diag}) {
      E->reset();
      M->reset();
      const Eigen::Vector3d entry = path.point[0] + 1e-3 * depth * path.normal[0];
      E->step(entry);
      M->step(entry);
      for (size_t i = 0; i < path.point.size(); ++i) {
        const Eigen::Vector3d hip = path.point[i] - depth * path.normal[i];
        const ForceSample e = E->step(hip), m = M->step(hip);
        ++st.steps;
        st.contactDiffers += e.contact != m.contact;
        st.capHits += (m.status & SF_TRACK_MAX_ITER) != 0;
        if (!(m.contact && e.contact)) continue;
        ++st.contacts;
        st.scpApart = std::max(st.scpApart, (m.scp - e.scp).norm() / diag);
        st.normalApart = std::max(st.normalApart, angle(m.normal, e.normal));
        if (!(m.status & SF_ST_MODEL_POINT)) continue;
        ++st.modelPoints;
        const PatchPoint p = evaluatePatch(exact, m.face, m.xi, m.eta);
        st.offPatch = std::max(st.offPatch, (m.scp - p.pos).norm() / diag);
        st.normalOff = std::max(st.normalOff, angle(m.normal, p.normal));
        if (!(m.status & SF_TRACK_FOLD_EDGE))
          st.residual = std::max(st.residual, (hip - m.scp).cross(p.normal).norm() / diag);
      }
    }
  }
  std::printf(
      "  %s: %ld steps, %ld in contact on both, %ld model points; contact differs %ld, cap hits %ld; model SCP off "
      "its patch point %.3g x diagonal, normal off %.3g rad, residual %.3g x diagonal; against evaluated final "
      "steps: SCPs %.3g x diagonal, normals %.3g rad apart\n",
      shape.c_str(), st.steps, st.contacts, st.modelPoints, st.contactDiffers, st.capHits, st.offPatch, st.normalOff,
      st.residual, st.scpApart, st.normalApart);
  return st;
}

/// The bounds every mesh and precision meets (measured below), `where` naming the case.
void expectWithinBounds(const ModelStats& st, const std::string& where) {
  EXPECT_EQ(st.steps, st.expected) << where;
  EXPECT_GE(st.steps, 12 * 3 * 100) << where << ": slides of at least 100 points on average";
  EXPECT_EQ(st.contactDiffers, 0) << where;
  EXPECT_EQ(st.capHits, 0) << where;
  EXPECT_GE(st.contacts, st.steps * 9 / 10) << where;
  EXPECT_GE(st.modelPoints, st.contacts / 3) << where << ": the option takes effect";
  EXPECT_LE(st.offPatch, 1e-13) << where;
  EXPECT_LE(st.normalOff, 1e-7) << where;
  EXPECT_LE(st.residual, 2 * ForceOptions{}.positionTolerance) << where;
  EXPECT_LE(st.scpApart, 3 * ForceOptions{}.positionTolerance) << where;
  EXPECT_LE(st.normalApart, 1e-7) << where;
}

class FinalStepModel : public ::testing::TestWithParam<std::string> {};

// Measured (2026-11-23, 22 shapes): model points on 47% (the knot's slides) to 99% of the steps
// in contact; SCPs at most 2.0e-14 x diagonal off their patch point, normals 2.5e-8 rad off the
// patch's; the residual against the patch's normal at most 1.12e-10 x diagonal (the default
// position tolerance is 1e-10 and the model's estimated error may add half of it); SCPs at
// most 1.11e-10 x diagonal and normals 2.5e-8 rad from those of evaluated final steps.
TEST_P(FinalStepModel, StaysOnThePatchWithinItsBounds) {
  expectWithinBounds(slideBoth(GetParam(), test::closedShapeCache(GetParam())), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Shapes, FinalStepModel, ::testing::ValuesIn(test::closedShapes()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return test::shapeTestName(i.param); });

// The same on float caches (the CPU refinement evaluates the float records widened to double: the
// model is checked against that patch), of a quad cage, a quad sphere and a triangle mesh, with
// the same bounds.
TEST(FinalStepModelFloat, StaysOnThePatchWithinItsBounds) {
  for (const char* rel : {"keenan_crane/spot_control_mesh.obj", "polygon_laplacian/quad-sphere.off", "odedstein/bunny.obj"}) {
    const auto cache = std::make_shared<const PatchCache>(
        test::cacheFromFile(test::sharedMesh(rel), CrossTangentMode::Corrected, Precision::Float));
    const std::string name = std::string(rel) + " (float)";
    expectWithinBounds(slideBoth(name, cache), name);
  }
}

// `--final-step` on the command line: trace marks model points in its status column (and never
// with the default), an unknown value and `model` with the paper's descent are usage errors
// naming the option, and a sweep records the choice in sweep.json.
TEST(FinalStepModelCli, TraceMarksModelPointsAndSweepRecordsTheChoice) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sf_final_step_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string mesh = std::string(SF_SHARED_MESHES) + "/polygon_laplacian/quad-sphere.off";
  const auto cache = test::closedShapeCache("polygon_laplacian/quad-sphere.off");
  const double diag = boundingDiagonal(*cache);
  PatchRefiner walker(*cache);
  const test::SurfacePath path = test::walkSurface(*cache, walker, 0, {0.1, 0.2}, {1, 0.3, 0.2}, 0.001 * diag, 200);
  ASSERT_EQ(path.point.size(), 200u);
  const std::string hips = (dir / "hips.csv").string(), out = (dir / "out.csv").string();
  {
    std::ofstream f(hips);
    f.precision(17);
    f << "x,y,z\n";
    for (size_t i = 0; i < path.point.size(); ++i) {
      const Eigen::Vector3d h = path.point[i] - 0.0025 * diag * path.normal[i];
      f << h.x() << "," << h.y() << "," << h.z() << "\n";
    }
  }
  for (const char* choice : {"evaluated", "model"}) {
    const auto r = test::smoothforce("trace --mesh " + mesh + " --hips " + hips + " --final-step " + choice + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.out;
    const NumericCsv t = readNumericCsv(out, {"x", "y", "z", "contact", "face", "xi", "eta", "scp_x", "scp_y", "scp_z",
                                              "fx", "fy", "fz", "iterations", "status"});
    ASSERT_EQ(t.rows(), path.point.size());
    size_t contacts = 0, model = 0;
    for (size_t i = 0; i < t.rows(); ++i) {
      contacts += t.at(i, 3) == 1;
      model += (static_cast<uint32_t>(t.at(i, 14)) & SF_ST_MODEL_POINT) != 0;
    }
    EXPECT_EQ(contacts, t.rows()) << choice;
    if (std::string(choice) == "model")
      EXPECT_GE(model, contacts / 2);
    else
      EXPECT_EQ(model, 0u);
  }
  const auto bad = test::smoothforce("trace --mesh " + mesh + " --hips " + hips + " --final-step turbo -o " + out);
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_NE(bad.out.find("--final-step"), std::string::npos) << bad.out;
  const auto paper =
      test::smoothforce("trace --mesh " + mesh + " --hips " + hips + " --refine paper --final-step model -o " + out);
  EXPECT_EQ(paper.status, 2) << paper.out;
  EXPECT_NE(paper.out.find("needs --refine newton"), std::string::npos) << paper.out;
  const auto s = test::smoothforce("sweep --mesh " + mesh + " --depth 1% --samples 8 --methods patch --no-plots " +
                                   "--final-step model -o " + (dir / "sw").string());
  ASSERT_EQ(s.status, 0) << s.out;
  std::ifstream j((dir / "sw" / "sweep.json").string());
  const nlohmann::json sweep = nlohmann::json::parse(j);
  EXPECT_EQ(sweep.at("config").at("final_step"), "model") << sweep.dump();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sf
