// SPDX-License-Identifier: Apache-2.0
// SmoothForce from C++: a patch cache from a mesh (file and in-memory arrays), a force trace,
// a foreign-loop servo step. CMake: find_package(SmoothForce) and link SmoothForce::core and
// SmoothForce::runtime. Run: ./example_cpp MESH.obj   (exit status 1 on any failure)
#include <cstdio>
#include <memory>
#include <vector>

#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/runtime/servo_step.h>
#include <smoothforce/smoothforce.h>

int main(int argc, char** argv) try {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s MESH\n", argv[0]);
    return 2;
  }
  // 1. A cache from a mesh file, and the same mesh handed over as arrays.
  sf::PatchOptions opt;
  const sf::LoadedMesh file = sf::loadMesh(argv[1], opt);
  std::vector<double> positions;
  for (const auto& p : file.mesh.positions) positions.insert(positions.end(), {p.x(), p.y(), p.z()});
  sf::MeshArrays arrays;
  arrays.positions = positions.data();
  arrays.numVertices = file.mesh.positions.size();
  arrays.faceOffsets = file.mesh.faceOffsets.data();
  arrays.numFaces = static_cast<size_t>(file.mesh.numFaces());
  arrays.faceVertices = file.mesh.faceVertices.data();
  auto cache = std::make_shared<const sf::PatchCache>(sf::buildPatchCache(file, opt, sf::Backend::Tbb));
  const sf::PatchCache fromArrays = sf::buildPatchCache(sf::loadMeshArrays(arrays, opt), opt, sf::Backend::Tbb);
  const bool same = fromArrays.edgeDataD == cache->edgeDataD;
  std::printf("cache: %d faces, %d vertices; from arrays: %s patches\n", cache->numFaces(), cache->numVertices(),
              same ? "the same" : "DIFFERENT");

  // 2. A force trace along face 0's patch, 5 mm inside.
  const int n = 101;
  std::vector<int32_t> faces(n, 0);
  std::vector<double> xi(n), eta(n, 0.0);
  for (int i = 0; i < n; ++i) xi[i] = -0.5 + i / double(n - 1);
  std::vector<sf::PatchPoint> pts(n);
  sf::evaluatePatches(*cache, faces.data(), xi.data(), eta.data(), n, pts.data(), sf::Backend::Tbb);
  std::vector<Eigen::Vector3d> hips;
  for (const auto& p : pts) hips.push_back(p.pos - 0.005 * p.normal);
  sf::ForceOptions force;  // stiffness 500 N/m
  auto renderer = sf::makeForceRenderer(cache, sf::ForceMethod::Patch, force);
  int contacts = 0;
  double maxJump = 0;
  Eigen::Vector3d last(0, 0, 0);
  for (int i = 0; i < n; ++i) {
    const sf::ForceSample s = renderer->step(hips[i]);
    contacts += s.contact;
    if (i > 0) maxJump = std::max(maxJump, (s.force - last).norm());
    last = s.force;
  }
  std::printf("trace: %d of %d steps in contact, largest step-to-step change %.4f N\n", contacts, n, maxJump);

  // 3. The servo step from the caller's own loop: scene + safety + ServoStep.
  sf::rt::Scene scene =
      sf::rt::singleObjectScene(cache, argv[1], sf::ForceMethod::Patch, force,
                                [](std::shared_ptr<const sf::PatchCache> c, sf::ForceMethod m,
                                   const sf::ForceOptions& f) { return sf::makeForceRenderer(std::move(c), m, f); });
  sf::rt::SafetyFilter safety;
  sf::rt::ServoStep step(scene, safety);
  double maxForce = 0;
  int inContact = 0;
  const int steps = 2000;
  for (int k = 0; k < steps; ++k) {
    sf::rt::StepTime t;
    t.wake = k * 1e-3;  // s, the caller's clock
    sf::rt::DeviceState device;
    device.position = hips[k % n];
    const sf::rt::StepOutput out = step.step(t, device);
    maxForce = std::max(maxForce, out.force.norm());
    inContact += out.sample.contact;
  }
  std::printf("servo: %d steps, %d in contact, largest commanded force %.4f N (limit 3.3)\n", steps, inContact,
              maxForce);
  const bool ok = same && contacts == n && inContact == steps && maxForce <= 3.3 + 1e-9;
  std::printf("example_cpp: %s\n", ok ? "OK" : "FAILED");
  return ok ? 0 : 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "example_cpp: %s\n", e.what());
  return 1;
}
