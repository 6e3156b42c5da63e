// SPDX-License-Identifier: Apache-2.0
// A program outside the SmoothForce tree, built against the installed package (CMake
// find_package or pkg-config): builds the patch cache of a mesh file, checks that a patch
// corner interpolates its vertex (Eq. 1-5), then runs force steps that press a HIP into the
// surface along the normal of a patch point p: the patch method must report contact with
// F = stiffness * depth * n (the SCP is p itself), and no force once the HIP is back outside.
// Prints what it measured and "consumer: OK", or "consumer: FAILED: ..." with exit status 1.
#include <smoothforce/smoothforce.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer MESH_FILE\n");
    return 2;
  }
  int failures = 0;
  auto check = [&](bool ok, const char* what) {
    if (!ok) {
      std::printf("consumer: FAILED: %s\n", what);
      ++failures;
    }
  };
  try {
    std::printf("SmoothForce %s (OpenCL backend: %s)\n", SF_VERSION_STRING, SF_HAS_OPENCL ? "yes" : "no");
    const sf::PatchOptions po;
    const sf::LoadedMesh lm = sf::loadMesh(argv[1], po);
    auto cache = std::make_shared<const sf::PatchCache>(sf::buildPatchCache(lm, po, sf::Backend::Tbb));
    std::printf("mesh: %d faces, %d vertices\n", cache->numFaces(), cache->numVertices());

    // Corner k of the domain maps to vertex k of the face, on every face.
    double cornerErr = 0;
    for (int f = 0; f < cache->numFaces(); ++f)
      for (int k = 0; k < cache->faceSize(f); ++k) {
        const Eigen::Vector2d c = sf::domainCorner(cache->faceSize(f), k);
        const sf::PatchPoint p = sf::evaluatePatch(*cache, f, c.x(), c.y());
        cornerErr = std::max(cornerErr, (p.pos - lm.mesh.positions[lm.mesh.faceVertex(f, k)]).norm());
      }
    std::printf("corners: max |G(C_k) - V_k| = %.3g m\n", cornerErr);
    check(cornerErr < 1e-12, "a patch corner is not its vertex");

    // The centre of the first face built without any status bit.
    int face = 0;
    while (face < cache->numFaces() && cache->faceStatus[face] != 0) ++face;
    const sf::PatchPoint p = sf::evaluatePatch(*cache, face, 0.0, 0.0);
    std::printf("centre of face %d: (%.6f, %.6f, %.6f), normal (%.6f, %.6f, %.6f)\n", face, p.pos.x(), p.pos.y(),
                p.pos.z(), p.normal.x(), p.normal.y(), p.normal.z());

    const sf::ForceOptions fo;
    auto renderer = sf::makeForceRenderer(cache, sf::ForceMethod::Patch, fo);
    const double depths[] = {-1e-3, 5e-4, 1e-3, 1.5e-3, 2e-3, -1e-3};  // m, > 0 inside
    int contacts = 0;
    for (double d : depths) {
      const sf::ForceSample s = renderer->step(p.pos - d * p.normal);
      const Eigen::Vector3d expected = d > 0 ? Eigen::Vector3d(fo.stiffness * d * p.normal) : Eigen::Vector3d::Zero();
      const double err = (s.force - expected).norm();
      contacts += s.contact;
      std::printf("depth %+.4f m: contact %d, |F| = %.6f N, |F - k d n| = %.3g N\n", d, int(s.contact), s.force.norm(),
                  err);
      check(s.contact == (d > 0), "contact state");
      check(err <= 1e-3 * fo.stiffness * std::abs(d), "force is not stiffness * depth along the normal");
    }
    std::printf("force steps: %d in contact of %zu\n", contacts, std::size(depths));
  } catch (const sf::InputError& e) {
    std::printf("consumer: FAILED: %s\n", e.what());
    return 1;
  }
  if (failures) return 1;
  std::printf("consumer: OK\n");
  return 0;
}
