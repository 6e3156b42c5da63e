// SPDX-License-Identifier: Apache-2.0
// `smoothforce generate torus-knot|sphere|torus -o OUT.obj`
#include "cmd_generate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>

#include <smoothforce/sweep/generators.h>
#include <smoothforce/sweep/sweep_sampling.h>
#include "cli_exit.h"
#include "cli_output.h"

namespace sf::cli {

namespace {

/// Runs a generator; its parameter errors are option errors (exit 2).
template <class F>
GeneratedMesh generated(F&& make) {
  GeneratedMesh m;
  checkOptions([&] { m = make(); });
  return m;
}

void report(const GeneratedMesh& m, const std::string& what, const std::string& out, const std::string& analytic,
            std::FILE* to = stdout) {
  Eigen::Vector3d lo = m.positions[0], hi = lo;
  for (const auto& p : m.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::fprintf(to, "generate: %s: %zu quads, %zu vertices, box %.6g x %.6g x %.6g -> %s\n", what.c_str(),
               m.quads.size(), m.positions.size(), hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), out.c_str());
  std::fprintf(to, "  exact vertex normals: build patches with --normals file; reference surface: --analytic %s\n",
               analytic.c_str());
}

/// The shortest %g form that reads back as x.
std::string g17(double x) {
  char b[40];
  for (int p = 6; p <= 17; ++p) {
    std::snprintf(b, sizeof b, "%.*g", p, x);
    if (std::strtod(b, nullptr) == x) break;
  }
  return b;
}

double largestExtent(const GeneratedMesh& m) {
  Eigen::Vector3d lo = m.positions[0], hi = lo;
  for (const auto& p : m.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).maxCoeff();
}

}  // namespace

void addGenerateCommand(CLI::App& app) {
  auto* gen = app.add_subcommand("generate", "Write test objects with exact vertex normals (OBJ, v//vn faces)");
  gen->require_subcommand(1);

  auto* knot = gen->add_subcommand("torus-knot", "A (p,q) torus knot tube of quads (segments x sides)");
  auto k = std::make_shared<TorusKnotParams>();
  auto out = std::make_shared<std::string>();
  auto traj = std::make_shared<std::string>();
  auto turns = std::make_shared<double>(7);
  auto trajPoints = std::make_shared<int>(20000);
  knot->add_option("--p", k->p, "windings around the z axis")->capture_default_str();
  knot->add_option("--q", k->q, "windings around the torus tube")->capture_default_str();
  knot->add_option("--segments", k->segments, "quads along the knot")
      ->check(CLI::Range(3, 1000000))
      ->capture_default_str();
  knot->add_option("--sides", k->sides, "quads around the tube")->check(CLI::Range(3, 100000))->capture_default_str();
  knot->add_option("--R", k->R, "torus major radius")->capture_default_str();
  knot->add_option("--r", k->r, "torus minor radius (knot amplitude)")->capture_default_str();
  knot->add_option("--tube", k->tube, "tube radius")->capture_default_str();
  knot->add_option("--scale", k->scale, "multiplies every length (e.g. 0.1/3.1 for a 10 cm knot)")
      ->capture_default_str();
  auto size = std::make_shared<std::optional<double>>();
  knot->add_option("--size", *size, "sets --scale so that the largest bounding-box side is this long (e.g. 0.1)");
  knot->add_option("--trajectory-out", *traj,
                   "also write a helix on the tube as x,y,z CSV (for sweep --trajectory); - writes stdout");
  knot->add_option("--turns", *turns, "helix turns around the tube over one lap")->capture_default_str();
  knot->add_option("--trajectory-points", *trajPoints, "helix points")
      ->check(CLI::Range(2, 10000000))
      ->capture_default_str();
  knot->add_option("-o,--output", *out, "OUT.obj")->required();
  knot->callback([=] {
    // the options CLI11 cannot range-check: finite, positive, and a helix that stays finite
    if (size->has_value() && !(**size > 0 && std::isfinite(**size)))
      throw UsageError("--size: expected a finite length > 0, got " + g17(**size));
    if (!(std::isfinite(*turns) && std::fabs(*turns) <= 1e6))
      throw UsageError("--turns: expected a finite number of turns within +-1e6, got " + g17(*turns));
    if (*size && **size > 0) {
      k->scale = 1;
      k->scale = **size / largestExtent(generated([&] { return torusKnot(*k); }));
    }
    // the helix's file opened first: a path that cannot be written fails before the OBJ is written
    std::unique_ptr<TextOutput> helix = traj->empty() ? nullptr : std::make_unique<TextOutput>(*traj);
    const GeneratedMesh m = generated([&] { return torusKnot(*k); });
    const std::string spec = "torus-knot:" + std::to_string(k->p) + "," + std::to_string(k->q) + "," + g17(k->R) + "," +
                             g17(k->r) + "," + g17(k->tube) + "," + g17(k->scale);
    writeGeneratedObj(m, *out,
                      "SmoothForce generate " + spec + " segments " + std::to_string(k->segments) + " sides " +
                          std::to_string(k->sides));
    std::FILE* to = *traj == "-" ? stderr : stdout;  // stdout carries the helix with --trajectory-out -
    report(m, "torus-knot", *out, spec, to);
    if (helix) {
      std::fprintf(helix->file(), "x,y,z\n");
      for (const auto& p : torusKnotHelix(*k, *turns, *trajPoints))
        std::fprintf(helix->file(), "%.17g,%.17g,%.17g\n", p.x(), p.y(), p.z());
      helix->commit();
      std::fprintf(to, "  helix trajectory (%g turns, %d points) -> %s\n", *turns, *trajPoints, helix->name().c_str());
    }
  });

  auto* sph = gen->add_subcommand("sphere", "A quad-sphere (cube faces split segments x segments), radial normals");
  auto radius = std::make_shared<double>(1);
  auto segs = std::make_shared<int>(4);
  auto outS = std::make_shared<std::string>();
  sph->add_option("--radius", *radius, "sphere radius")->capture_default_str();
  sph->add_option("--segments", *segs, "quads per cube-face edge")->check(CLI::Range(1, 4096))->capture_default_str();
  sph->add_option("-o,--output", *outS, "OUT.obj")->required();
  sph->callback([=] {
    const GeneratedMesh m = generated([&] { return quadSphere(*radius, *segs); });
    writeGeneratedObj(m, *outS, "SmoothForce generate sphere radius " + g17(*radius));
    report(m, "sphere", *outS, "sphere:" + g17(*radius));
  });

  auto* tor = gen->add_subcommand("torus", "A torus about the z axis, exact normals");
  auto R = std::make_shared<double>(1), r = std::make_shared<double>(0.4);
  auto tsegs = std::make_shared<int>(24), tsides = std::make_shared<int>(12);
  auto outT = std::make_shared<std::string>();
  tor->add_option("--R", *R, "major radius")->capture_default_str();
  tor->add_option("--r", *r, "minor radius")->capture_default_str();
  tor->add_option("--segments", *tsegs, "quads around the axis")->check(CLI::Range(3, 1000000))->capture_default_str();
  tor->add_option("--sides", *tsides, "quads around the tube")->check(CLI::Range(3, 100000))->capture_default_str();
  tor->add_option("-o,--output", *outT, "OUT.obj")->required();
  tor->callback([=] {
    const GeneratedMesh m = generated([&] { return torusMesh(*R, *r, *tsegs, *tsides); });
    writeGeneratedObj(m, *outT, "SmoothForce generate torus R " + g17(*R) + " r " + g17(*r));
    report(m, "torus", *outT, "torus:" + g17(*R) + "," + g17(*r));
  });
}

}  // namespace sf::cli
