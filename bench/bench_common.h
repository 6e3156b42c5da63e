// SPDX-License-Identifier: Apache-2.0
// Inputs shared by the benchmark programs.
#pragma once

#include <cstdio>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_eval.h>

namespace sf::bench {

/// Runs a measuring program's body: an error (a mesh that cannot be read, ...) is one line
/// "NAME: message" on stderr and exit status 1, not an abort.
template <class Body>
int guardedMain(const char* name, Body&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 1;
  }
}

/// `count` separate n-gons (no shared vertices): regular polygons of radius 1 with their
/// vertices lifted by up to 0.1 and normals tilted by up to ~15 degrees (seeded).
inline PatchCache ngonSoup(int n, int count, Precision precision) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  PolygonMesh m;
  std::vector<Eigen::Vector3d> normals;
  for (int f = 0; f < count; ++f) {
    std::vector<int32_t> face;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n;
      face.push_back(m.numVertices());
      m.positions.emplace_back(std::cos(a), std::sin(a), 0.1 * u(rng));
      normals.push_back(Eigen::Vector3d(0.25 * u(rng), 0.25 * u(rng), 1).normalized());
    }
    m.addFace(face);
  }
  PatchOptions o;
  o.precision = precision;
  return preparePatchCache(m, normals, o, 0);
}

/// A built cache of a real mesh.
inline PatchCache meshCache(const std::string& path, Precision precision) {
  PatchOptions o;
  o.precision = precision;
  return buildPatchCache(loadMesh(path, o), o, Backend::Tbb);
}

/// N random (face, xi, eta) queries, uniform over faces and over each domain (seeded).
struct Queries {
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
};
inline Queries randomQueries(const PatchCache& c, size_t count) {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> pf(0, c.numFaces() - 1);
  std::uniform_real_distribution<double> u(-1, 1);
  Queries q;
  while (q.face.size() < count) {
    const int f = pf(rng);
    const double x = u(rng), y = u(rng);
    if (!insideDomain(c.faceSize(f), x, y)) continue;
    q.face.push_back(f);
    q.xi.push_back(x);
    q.eta.push_back(y);
  }
  return q;
}

}  // namespace sf::bench
