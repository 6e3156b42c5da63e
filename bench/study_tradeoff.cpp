// SPDX-License-Identifier: Apache-2.0
// Speed against accuracy of patch evaluation and of the full SCP query (global query +
// refinement). A plain main (not Google Benchmark) so that every query is timed
// on its own and percentiles come out directly. The query's configurations stop the refinement
// by the angle tolerance alone (position tolerance 1, the diagonal: not binding).
//
//   build/bench/study_tradeoff [--out DIR] [--samples N] [--reps R] [--seed S]
// (SF_STUDY_VERBOSE=1 prints every query whose SCP error exceeds 1e-6 of the diagonal, and every missed contact.)
//
// Meshes: spot control cage and quad-sphere (../shared/meshes), a generated torus (exact
// normals). HIPs: area-uniform patch samples pushed inside by 0.25%, 1% and 2% of the bounding
// diagonal. Per configuration every HIP runs one warm-up pass and R timed passes (each query
// timed alone with steady_clock; per query the fastest of the R passes counts, which removes
// most interference from other processes). Errors against a reference: the double cache, Newton,
// angleTolerance 1e-12, 500 iterations, the nearest of three starts: the polygon, the level-8
// tessellation and the nearest vertex of a level-16 tessellation (dense sampling; brute force
// over every vertex through a k-d tree); the reference is checked against that dense vertex's
// distance on the first 40 HIPs of each mesh. Query errors: SCP distance to the reference over
// the diagonal and the angle between the force directions; a query whose SCP error exceeds
// 1e-3 of the diagonal found another local minimum (a failure of the global query) and is
// counted in `far` instead; `missed`: no contact where the reference has one. Writes DIR/tradeoff.csv (one row per mesh
// and configuration, plus pooled rows with mesh "all" that carry the Pareto flag) and DIR/reference_check.csv.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_seeds.h>
#include <smoothforce/sweep/generators.h>
#include <smoothforce/sweep/sweep_sampling.h>

namespace {

using namespace sf;
using Clock = std::chrono::steady_clock;

struct Study {
  std::string out = "out/tradeoff";
  int samples = 100, reps = 3;
  uint64_t seed = 7;
};

struct MeshCase {
  std::string name;
  double diagonal = 0;
  std::map<std::string, std::shared_ptr<const PatchCache>> caches;  ///< "double", "float", "double-blend", ...
  std::vector<Eigen::Vector3d> hips;
  std::vector<ForceSample> ref;  ///< per HIP; contact false: no reference (dropped)
};

PatchOptions patchOptions(Precision p, CrossTangentMode ct) {
  PatchOptions o;
  o.precision = p;
  o.crossTangent = ct;
  return o;
}

/// The caches of one mesh in both precisions and both cross-tangent variants.
void buildCaches(MeshCase& m, const std::function<PatchCache(const PatchOptions&)>& build) {
  for (Precision p : {Precision::Double, Precision::Float})
    for (CrossTangentMode ct : {CrossTangentMode::Corrected, CrossTangentMode::Blend}) {
      const std::string key = std::string(toString(p)) + (ct == CrossTangentMode::Blend ? "-blend" : "");
      m.caches[key] = std::make_shared<const PatchCache>(build(patchOptions(p, ct)));
    }
}

MeshCase fileCase(const std::string& name, const std::string& path) {
  MeshCase m;
  m.name = name;
  buildCaches(m, [&](const PatchOptions& o) { return buildPatchCache(loadMesh(path, o), o, Backend::Tbb); });
  return m;
}

MeshCase torusCase() {
  MeshCase m;
  m.name = "torus (generated)";
  const PolygonMesh mesh = torusMesh(1.0, 0.4, 16, 8).toPolygonMesh();
  buildCaches(m, [&](const PatchOptions& o) {
    PatchCache c = preparePatchCache(mesh, cornerNormals(mesh, NormalMode::Auto), o, 0);
    constructPatches(c, Backend::Tbb);
    return c;
  });
  return m;
}

struct Stats {
  double median = 0, p99 = 0, max = 0;
};
Stats stats(std::vector<double> v) {
  Stats s;
  if (v.empty()) return {NAN, NAN, NAN};
  std::sort(v.begin(), v.end());
  auto q = [&](double f) { return v[std::min(v.size() - 1, static_cast<size_t>(f * (v.size() - 1) + 0.5))]; };
  return {q(0.5), q(0.99), v.back()};
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

/// One configuration's samples (per query), pooled over meshes for the "all" rows.
struct Samples {
  std::vector<double> us, err, ang, iters;  ///< err, ang: queries on the reference's minimum only
  int missed = 0, far = 0, n = 0;
  double farMax = 0;  ///< largest SCP error / diagonal of the `far` queries
  void append(const Samples& o) {
    us.insert(us.end(), o.us.begin(), o.us.end());
    err.insert(err.end(), o.err.begin(), o.err.end());
    ang.insert(ang.end(), o.ang.begin(), o.ang.end());
    iters.insert(iters.end(), o.iters.begin(), o.iters.end());
    missed += o.missed;
    far += o.far;
    farMax = std::max(farMax, o.farMax);
    n += o.n;
  }
};

/// SCP errors above this fraction of the diagonal are counted as `far` (the query converged to
/// another local minimum of the distance than the reference) instead of entering the error stats.
constexpr double kFar = 1e-3;

struct Config {
  std::string part, precision, crossTangent = "corrected", refine = "-", guess = "-";
  double tol = 0;
  int maxIter = 0;
  std::string key() const {
    char b[160];
    std::snprintf(b, sizeof b, "%s|%s|%s|%s|%g|%d|%s", part.c_str(), precision.c_str(), crossTangent.c_str(),
                  refine.c_str(), tol, maxIter, guess.c_str());
    return b;
  }
};

struct Row {
  Config c;
  std::string mesh;
  Samples s;
  bool pareto = false;
};

/// Reference SCP per HIP (see the file comment); writes the dense-sampling check of the first 40.
void computeReference(MeshCase& m, const std::shared_ptr<const PolygonScene>& scene, std::FILE* check) {
  const auto cache = m.caches.at("double");
  ForceOptions o;
  o.angleTolerance = 1e-12;
  o.maxIterations = 500;
  auto byPolygon = makeForceRenderer(cache, scene, ForceMethod::Patch, o);
  o.initialGuess = InitialGuess::Surface;
  o.tessellationLevel = 8;
  auto bySeeds = makeForceRenderer(cache, scene, ForceMethod::Patch, o);
  const PatchSeeds dense(*cache, 16);
  PatchRefiner refiner(*cache);
  int denseWins = 0;
  double worst = -1e300, best = 1e300;
  for (size_t i = 0; i < m.hips.size(); ++i) {
    byPolygon->reset();
    bySeeds->reset();
    const ForceSample a = byPolygon->step(m.hips[i]), b = bySeeds->step(m.hips[i]);
    const double da = a.contact ? (a.scp - m.hips[i]).norm() : 1e300;
    const double db = b.contact ? (b.scp - m.hips[i]).norm() : 1e300;
    m.ref.push_back(da <= db ? a : b);
    // a third start, the nearest vertex of the dense tessellation (global by construction)
    const PatchSeed s = dense.nearest(m.hips[i]);
    const RefineResult rr = refiner.refine(m.hips[i], s.face, s.X.x(), s.X.y(), o);
    if ((m.hips[i] - rr.scp).dot(rr.normal) < 0 && rr.distance < std::min(da, db) - 1e-9 * m.diagonal) {
      ForceSample& f = m.ref.back();
      f.contact = true;
      f.scp = rr.scp;
      f.normal = rr.normal;
      f.face = rr.face;
      ++denseWins;
    }
    if (i < 40 && m.ref.back().contact) {
      const double dd = (s.point - m.hips[i]).norm(), dr = (m.ref.back().scp - m.hips[i]).norm();
      const double rel = (dd - dr) / m.diagonal;
      worst = std::max(worst, rel);
      best = std::min(best, rel);
      std::fprintf(check, "%s,%zu,%.17g,%.17g,%.6g\n", m.name.c_str(), i, dr, dd, rel);
    }
  }
  std::printf(
      "  reference vs dense level-16 sampling: (dense - reference) distance / diagonal in [%.3g, %.3g]; the "
      "dense start won %d of %zu HIPs\n",
      best, worst, denseWins, m.hips.size());
}

Samples runQueries(const MeshCase& m, const std::shared_ptr<const PatchCache>& cache,
                   const std::shared_ptr<const PolygonScene>& scene, const ForceOptions& o, int reps) {
  auto r = makeForceRenderer(cache, scene, ForceMethod::Patch, o);
  Samples s;
  std::vector<double> best(m.hips.size(), 1e300);
  std::vector<ForceSample> res(m.hips.size());
  for (int rep = 0; rep <= reps; ++rep)  // pass 0: warm-up
    for (size_t i = 0; i < m.hips.size(); ++i) {
      r->reset();
      const auto t0 = Clock::now();
      res[i] = r->step(m.hips[i]);
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
      if (rep > 0) best[i] = std::min(best[i], us);
    }
  for (size_t i = 0; i < m.hips.size(); ++i) {
    if (!m.ref[i].contact) continue;
    ++s.n;
    s.us.push_back(best[i]);
    if (!res[i].contact) {
      ++s.missed;
      if (std::getenv("SF_STUDY_VERBOSE"))
        std::printf("  missed: %s HIP %zu tol %g it %d guess %d: status %x; reference face %d (construction bits %x), "
                    "distance %.3g of the diagonal\n",
                    m.name.c_str(), i, o.angleTolerance, o.maxIterations, int(o.initialGuess), res[i].status,
                    m.ref[i].face, m.ref[i].face >= 0 ? cache->faceStatus[m.ref[i].face] : 0u,
                    (m.ref[i].scp - m.hips[i]).norm() / m.diagonal);
      continue;
    }
    const double e = (res[i].scp - m.ref[i].scp).norm() / m.diagonal;
    if (e > kFar || (e > 1e-6 && std::getenv("SF_STUDY_VERBOSE"))) {
      if (std::getenv("SF_STUDY_VERBOSE"))
        std::printf("  far: %s HIP %zu tol %g it %d guess %d: error %.3g, status %x, %d iterations, face %d (ref %d)\n",
                    m.name.c_str(), i, o.angleTolerance, o.maxIterations, int(o.initialGuess), e, res[i].status,
                    res[i].iterations, res[i].face, m.ref[i].face);
    }
    if (e > kFar) {  // another local minimum of the distance: a failure of the global query
      ++s.far;
      s.farMax = std::max(s.farMax, e);
      continue;
    }
    s.err.push_back(e);
    s.ang.push_back(angleDeg(res[i].scp - m.hips[i], m.ref[i].scp - m.hips[i]));
    s.iters.push_back(res[i].iterations);
  }
  return s;
}

Samples runEval(const MeshCase& m, const PatchCache& c, const PatchCache& ref, const std::vector<SurfaceSample>& q,
                int reps) {
  Samples s;
  std::vector<double> best(q.size(), 1e300);
  std::vector<PatchPoint> res(q.size());
  for (int rep = 0; rep <= reps; ++rep)
    for (size_t i = 0; i < q.size(); ++i) {
      const auto t0 = Clock::now();
      res[i] = evaluatePatch(c, q[i].face, q[i].xi, q[i].eta);
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
      if (rep > 0) best[i] = std::min(best[i], us);
    }
  for (size_t i = 0; i < q.size(); ++i) {
    const PatchPoint r = evaluatePatch(ref, q[i].face, q[i].xi, q[i].eta);
    ++s.n;
    s.us.push_back(best[i]);
    s.err.push_back((res[i].pos - r.pos).norm() / m.diagonal);
    s.ang.push_back(angleDeg(res[i].normal, r.normal));
  }
  return s;
}

/// Pareto front of the pooled rows of each part over four objectives, all minimised: median
/// time, median and max error (of the queries on the reference's minimum), failures (missed + far).
/// A row is on the front when no other row of its part is at least as good in all three and
/// better in one.
void markPareto(std::vector<Row>& rows) {
  auto objectives = [](const Row& r) {
    const Stats e = stats(r.s.err);
    return std::array<double, 4>{stats(r.s.us).median, e.median, e.max, double(r.s.missed + r.s.far)};
  };
  for (Row& a : rows) {
    if (a.mesh != "all") continue;
    const auto oa = objectives(a);
    a.pareto = true;
    for (const Row& b : rows) {
      if (&a == &b || b.mesh != "all" || b.c.part != a.c.part) continue;
      const auto ob = objectives(b);
      bool noWorse = true, better = false;
      for (int k = 0; k < 4; ++k) {
        noWorse = noWorse && ob[k] <= oa[k];
        better = better || ob[k] < oa[k];
      }
      if (noWorse && better) {
        a.pareto = false;
        break;
      }
    }
  }
}

void writeCsv(const std::vector<Row>& rows, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write");
  std::fprintf(
      f,
      "part,mesh,precision,cross_tangent,refine,angle_tol,max_iter,initial_guess,queries,missed,far,far_err_max,"
      "time_median_us,time_p99_us,err_median,err_max,angle_median_deg,angle_max_deg,iter_mean,pareto\n");
  for (const Row& r : rows) {
    const Stats t = stats(r.s.us), e = stats(r.s.err), a = stats(r.s.ang);
    double it = 0;
    for (double v : r.s.iters) it += v;
    it = r.s.iters.empty() ? 0 : it / r.s.iters.size();
    std::fprintf(f, "%s,%s,%s,%s,%s,%g,%d,%s,%d,%d,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.3g,%d\n", r.c.part.c_str(),
                 r.mesh.c_str(), r.c.precision.c_str(), r.c.crossTangent.c_str(), r.c.refine.c_str(), r.c.tol,
                 r.c.maxIter, r.c.guess.c_str(), r.s.n, r.s.missed, r.s.far, r.s.farMax, t.median, t.p99, e.median,
                 e.max, a.median, a.max, it, r.pareto ? 1 : 0);
  }
  std::fclose(f);
}

int run(const Study& st) {
  const auto t0 = Clock::now();
  std::filesystem::create_directories(st.out);
  const std::string shared = SF_SHARED_MESHES;
  std::vector<MeshCase> meshes;
  meshes.push_back(fileCase("spot", shared + "/keenan_crane/spot_control_mesh.obj"));
  meshes.push_back(fileCase("quad-sphere", shared + "/polygon_laplacian/quad-sphere.off"));
  meshes.push_back(torusCase());
  std::FILE* check = std::fopen((st.out + "/reference_check.csv").c_str(), "w");
  std::fprintf(check, "mesh,hip,reference_distance,dense_distance,difference_over_diagonal\n");
  std::vector<Row> rows;
  std::map<std::string, Samples> pooled;
  std::map<std::string, Config> configs;
  auto add = [&](const Config& c, const std::string& mesh, Samples s) {
    pooled[c.key()].append(s);
    configs[c.key()] = c;
    rows.push_back({c, mesh, std::move(s)});
  };
  for (MeshCase& m : meshes) {
    const auto& cd = m.caches.at("double");
    m.diagonal = boundingDiagonal(*cd);
    std::printf("%s: %d faces, diagonal %.4g m\n", m.name.c_str(), cd->numFaces(), m.diagonal);
    const PatchSurfaceSampler sampler(*cd, 8);
    const std::vector<SurfaceSample> surf = sampler.sample(3 * st.samples, st.seed);
    const double depths[3] = {0.0025, 0.01, 0.02};
    for (size_t i = 0; i < surf.size(); ++i)
      m.hips.push_back(surf[i].point - depths[i % 3] * m.diagonal * surf[i].normal);
    // patch evaluation: 4 caches against the double corrected one, at the sampled domain points
    for (const auto& [key, cache] : m.caches) {
      Config c;
      c.part = "eval";
      c.precision = toString(cache->options.precision);
      c.crossTangent = toString(cache->options.crossTangent);
      add(c, m.name, runEval(m, *cache, *cd, surf, st.reps));
    }
    // full SCP queries
    std::map<std::string, std::shared_ptr<const PolygonScene>> scenes;
    for (const char* key : {"double", "float"}) scenes[key] = std::make_shared<const PolygonScene>(*m.caches.at(key));
    computeReference(m, scenes.at("double"), check);
    for (const char* prec : {"double", "float"})
      for (RefineMethod rm : {RefineMethod::Newton, RefineMethod::PaperDescent})
        for (double tol : {1e-2, 1e-3, 1e-4, 1e-6})
          for (int it : {3, 10, 50})
            for (InitialGuess g : {InitialGuess::Polygon, InitialGuess::Surface}) {
              ForceOptions o;
              o.refine = rm;
              o.angleTolerance = tol;
              // the angle tolerance alone stops the refinement: the position tolerance (1e-10 of
              // the diagonal by default, the smaller of the two decides) would stop every row at
              // the same residual; the presets carry this choice (force_presets.h)
              o.positionTolerance = 1;
              o.maxIterations = it;
              o.initialGuess = g;
              o.tessellationLevel = 0;
              Config c;
              c.part = "query";
              c.precision = prec;
              c.refine = toString(rm);
              c.tol = tol;
              c.maxIter = it;
              c.guess = g == InitialGuess::Polygon ? "polygon" : "tessellation2";
              add(c, m.name, runQueries(m, m.caches.at(prec), scenes.at(prec), o, st.reps));
            }
    std::printf("  done after %.1f s\n", std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::fclose(check);
  for (auto& [key, s] : pooled) rows.push_back({configs[key], "all", std::move(s)});
  markPareto(rows);
  writeCsv(rows, st.out + "/tradeoff.csv");
  std::printf("wrote %s/tradeoff.csv (%zu rows) in %.1f s\n", st.out.c_str(), rows.size(),
              std::chrono::duration<double>(Clock::now() - t0).count());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Study st;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--out")
      st.out = v;
    else if (k == "--samples")
      st.samples = std::stoi(v);
    else if (k == "--reps")
      st.reps = std::stoi(v);
    else if (k == "--seed")
      st.seed = std::stoull(v);
    else {
      std::fprintf(stderr, "usage: study_tradeoff [--out DIR] [--samples N] [--reps R] [--seed S]\n");
      return 2;
    }
  }
  try {
    return run(st);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "study_tradeoff: %s\n", e.what());
    return 1;
  }
}
