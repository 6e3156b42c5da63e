// SPDX-License-Identifier: Apache-2.0
// Moving objects: Scene::setPose between steps without rebuilding anything. A moving object
// gives the force of a still one with the HIP moved the other way, a slow motion in contact
// gives a continuous force, a fast one does not pop through, and poses published from another
// thread are never torn.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/runtime/scripted.h>
#include <smoothforce/runtime/servo_step.h>
#include "patch_test_support.h"

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using namespace sf::rt;

sf::ForceOptions tightOptions() {
  sf::ForceOptions o;
  o.stiffness = 500;
  o.angleTolerance = 1e-10;
  return o;
}

Scene oneObject(std::shared_ptr<const sf::PatchCache> cache, sf::ForceMethod m, const Pose& pose = {}) {
  SceneObject obj;
  obj.name = "object";
  obj.method = m;
  obj.force = tightOptions();
  obj.cache = cache;
  obj.pose = pose;
  obj.renderer = sf::makeForceRenderer(cache, m, obj.force);
  Scene s;
  s.add(std::move(obj));
  return s;
}

Pose poseAt(int k) {  // rises 5 um and turns 1e-4 rad about a tilted axis per step
  Pose p;
  p.translation = Vector3d(0, 0, 5e-6 * k);
  p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(1e-4 * k, Vector3d(0.2, 0.1, 1).normalized()));
  return p;
}

// A still object with the HIP moved by the inverse motion is the independent computation.
TEST(RuntimeMoving, SlowMotionInContactIsContinuousAndMatchesAStillObject) {
  auto cache = std::make_shared<const sf::PatchCache>(
      sf::test::cacheFromFile(sf::test::sharedMesh("keenan_crane/spot_control_mesh.obj")));
  for (sf::ForceMethod m : {sf::ForceMethod::Patch, sf::ForceMethod::Direct, sf::ForceMethod::Shading}) {
    Scene moving = oneObject(cache, m);
    Scene still = oneObject(cache, m);
    const SurfaceProbe probe(moving);
    const Eigen::AlignedBox3d box = sceneBounds(moving);
    const double x = box.center().x(), y = box.center().y();
    const auto top = probe.topHeight(x, y);
    ASSERT_TRUE(top.has_value());
    const Vector3d hip(x, y, *top - 0.004);  // 4 mm deep, held still
    const int n = 1000;
    Vector3d prevForce = Vector3d::Zero(), prevLocal = Vector3d::Zero();
    double worst = 0;
    int contacts = 0;
    for (int k = 0; k < n; ++k) {
      const Pose p = poseAt(k);
      ASSERT_TRUE(moving.setPose(0, p));
      const sf::ForceSample a = moving.step(hip);
      const Eigen::Matrix3d r = p.rotation.toRotationMatrix();
      const Vector3d local = r.transpose() * (hip - p.translation);
      const sf::ForceSample b = still.step(local);
      ASSERT_EQ(a.contact, b.contact) << k;
      contacts += a.contact;
      ASSERT_LT((a.force - r * b.force).norm(), 1e-8) << sf::toString(m) << " step " << k;
      ASSERT_LT((a.scp - (p.translation + r * b.scp)).norm(), 1e-10) << k;
      if (k > 0 && m == sf::ForceMethod::Patch) {  // the polygon methods jump at edges even when still
        // Lipschitz bound of a continuous force: k times the HIP's motion in the object frame,
        // with room for the SCP's motion on a curved surface (factor 3).
        const double bound = 3 * 500 * (local - prevLocal).norm() + 1e-9;
        const double jump = (a.force - prevForce).norm();
        worst = std::max(worst, jump / bound);
        ASSERT_LE(jump, bound) << sf::toString(m) << " step " << k;
      }
      prevForce = a.force;
      prevLocal = local;
    }
    EXPECT_EQ(contacts, n) << sf::toString(m);  // 4 mm deep, rising 5 mm: contact throughout
    EXPECT_EQ(moving.motion().updates, n);
    EXPECT_EQ(moving.motion().jumps, 0);
    EXPECT_GT(moving.objects()[0].pose.translation.z(), 4.99e-3);  // the current pose is visible
    EXPECT_EQ(moving.patchesBuilt(), cache->numFaces()) << "a prebuilt cache: nothing is rebuilt";
    if (m == sf::ForceMethod::Patch) std::printf("patch: largest force change / its bound %.3f\n", worst);
  }
}

/// A 1 x 1 m slab 5 cm thick, top face at z = 0, each big face a 4 x 4 grid of quads so that
/// the vertices inside them have vertical normals (flat patches in the middle).
std::string writeSlab(const fs::path& dir) {
  const std::string path = (dir / "slab.obj").string();
  std::ofstream out(path);
  auto id = [](int layer, int i, int j) { return 1 + layer * 25 + i * 5 + j; };  // OBJ ids, 5 x 5 per layer
  for (int layer = 0; layer < 2; ++layer)
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        out << "v " << -0.5 + 0.25 * i << " " << -0.5 + 0.25 * j << " " << (layer ? 0 : -0.05) << "\n";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      out << "f " << id(1, i, j) << " " << id(1, i + 1, j) << " " << id(1, i + 1, j + 1) << " " << id(1, i, j + 1)
          << "\n";
      out << "f " << id(0, i, j) << " " << id(0, i, j + 1) << " " << id(0, i + 1, j + 1) << " " << id(0, i + 1, j)
          << "\n";
    }
  for (int k = 0; k < 4; ++k) {  // the four sides, outward
    out << "f " << id(0, k, 0) << " " << id(0, k + 1, 0) << " " << id(1, k + 1, 0) << " " << id(1, k, 0) << "\n";
    out << "f " << id(0, k + 1, 4) << " " << id(0, k, 4) << " " << id(1, k, 4) << " " << id(1, k + 1, 4) << "\n";
    out << "f " << id(0, 0, k + 1) << " " << id(0, 0, k) << " " << id(1, 0, k) << " " << id(1, 0, k + 1) << "\n";
    out << "f " << id(0, 4, k) << " " << id(0, 4, k + 1) << " " << id(1, 4, k + 1) << " " << id(1, 4, k) << "\n";
  }
  return path;
}

// The slab jumps up 4 cm in one step while the HIP touches its top 5 mm deep: the HIP is then
// 5 mm above the bottom face. A stateless nearest-surface force would push it out through the
// bottom; the tracked contact keeps pushing it up, the jump is counted and the safety layer
// clamps and rate-limits the force.
TEST(RuntimeMoving, FastMotionDoesNotPopThroughSilently) {
  const fs::path dir = fs::temp_directory_path() / ("sf_rt_moving_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto cache = std::make_shared<const sf::PatchCache>(sf::test::cacheFromFile(writeSlab(dir)));
  fs::remove_all(dir);
  for (sf::ForceMethod m : {sf::ForceMethod::Patch, sf::ForceMethod::Direct, sf::ForceMethod::Shading}) {
    Pose start;
    start.translation.z() = -0.02;  // the slab's top 2 cm below the HIP
    Scene scene = oneObject(cache, m, start);
    SafetyOptions so;
    so.rampTime = 0;
    SafetyFilter safety(so);
    ServoStep step(scene, safety);
    const Vector3d hip(0.02, -0.03, 0.0);  // at the top face; the slab comes up from below
    int64_t k = 0;
    auto at = [&](double lift) {
      Pose p;
      p.translation = Vector3d(0, 0, lift);
      EXPECT_TRUE(scene.setPose(0, p));
      StepTime t;
      t.wake = double(k++) * 1e-3;
      DeviceState d;
      d.position = hip;
      return step.step(t, d);
    };
    // Rises 10 um per step until the renderer pushes with 2.5 N (5 mm deep).
    StepOutput out;
    double lift = -0.02;
    for (int i = 0; i < 6000 && !(out.sample.force.norm() >= 2.5); ++i) out = at(lift += 1e-5);
    ASSERT_TRUE(out.sample.contact) << sf::toString(m);
    const Vector3d before = out.worldForce;
    EXPECT_GT(before.z(), 2.4) << sf::toString(m);
    EXPECT_LT(lift, 0.02) << sf::toString(m);
    EXPECT_EQ(scene.motion().jumps, 0);
    EXPECT_EQ(safety.counters().clamps, 0);
    const int64_t rateLimitsBefore = safety.counters().rateLimits;
    lift += 0.04;
    out = at(lift);  // 4 cm in one step: the HIP is past the slab's mid-plane
    EXPECT_EQ(scene.motion().jumps, 1) << sf::toString(m);
    EXPECT_NEAR(scene.motion().largestStep, 0.04, 1e-12);
    ASSERT_TRUE(out.sample.contact) << sf::toString(m) << ": contact lost";
    EXPECT_GT(out.sample.force.z(), 500 * 0.03) << sf::toString(m) << ": the renderer should push up, 4 cm deeper";
    EXPECT_GT(out.sample.normal.z(), 0.9) << sf::toString(m) << ": the SCP should stay on the top face";
    EXPECT_TRUE(out.flags & kSafetyClamped);
    EXPECT_TRUE(out.flags & kSafetyRateLimited);
    EXPECT_NEAR((out.worldForce - before).norm(), 0.5, 1e-9);  // one maxForceStep
    for (int i = 0; i < 20; ++i) out = at(lift);
    EXPECT_NEAR(out.worldForce.norm(), 3.3, 1e-9) << sf::toString(m);  // held at the clamp
    EXPECT_GT(out.worldForce.z(), 3.29);
    EXPECT_GT(safety.counters().clamps, 0);
    EXPECT_GT(safety.counters().rateLimits, rateLimitsBefore);
    EXPECT_EQ(safety.counters().fault, Fault::None);
  }
}

TEST(RuntimeMoving, BadPosesAreRefused) {
  Scene s;
  SceneObject o;
  o.name = "plane";
  o.renderer = std::make_unique<PlaneRenderer>(Vector3d::UnitZ(), 0.0, 500.0);
  s.add(std::move(o));
  Pose p;
  EXPECT_TRUE(s.setPose(0, p));
  EXPECT_FALSE(s.setPose(1, p));  // no such object
  Pose bad = p;
  bad.scale = 0;
  EXPECT_FALSE(s.setPose(0, bad));
  bad = p;
  bad.translation.x() = NAN;
  EXPECT_FALSE(s.setPose(0, bad));
  bad = p;
  bad.rotation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_FALSE(s.setPose(0, bad));
  s.step(Vector3d(0, 0, 1));
  EXPECT_EQ(s.motion().updates, 1);  // only the good one
  EXPECT_THROW(s.setMaxPoseStep(0), sf::InputError);
  EXPECT_THROW(s.setMaxPoseStep(NAN), sf::InputError);
}

// A writer thread publishes poses i = 1, 2, ... (translation (i, 2i, 0) um, rotation 1e-4 i rad
// about z, scale 1 + 1e-9 i) while the servo thread steps: every pose the scene applies is one
// of them, whole (no field from another i), i never goes back, and the force is the plane's
// for that pose.
TEST(RuntimeMoving, PosesFromAnotherThreadAreNeverTorn) {
  Scene s;
  SceneObject o;
  o.name = "plane";
  o.renderer = std::make_unique<PlaneRenderer>(Vector3d::UnitZ(), 0.0, 500.0);  // z <= 0 in its frame
  s.add(std::move(o));
  auto poseOf = [](int64_t i) {
    Pose p;
    p.translation = Vector3d(1e-6 * double(i), 2e-6 * double(i), 0);
    p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(1e-4 * double(i), Vector3d::UnitZ()));
    p.scale = 1 + 1e-9 * double(i);
    return p;
  };
  std::atomic<bool> readerDone{false};
  std::atomic<int64_t> published{0};
  std::thread writer([&] {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    for (int64_t i = 1; !readerDone.load(std::memory_order_relaxed) && std::chrono::steady_clock::now() < until; ++i) {
      if (s.setPose(0, poseOf(i))) published.store(i, std::memory_order_relaxed);
      // About 2 us apart (a physics thread publishes at 0.1-10 kHz; back-to-back writes
      // would leave the reader only the rare gaps between them: it then keeps the old pose).
      const auto next = std::chrono::steady_clock::now() + std::chrono::microseconds(2);
      while (std::chrono::steady_clock::now() < next) {
      }
    }
  });
  const Vector3d hip(0.3, -0.2, -0.1);  // 0.1 m below the plane, which only turns about z and moves sideways
  int64_t last = 0, distinct = 0, steps = 0, contacts = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while ((steps < 100000 || distinct < 100) && std::chrono::steady_clock::now() < until) {
    const sf::ForceSample f = s.step(hip);
    ++steps;
    const Pose& p = s.objects()[0].pose;
    const int64_t i = std::llround(p.translation.x() * 1e6);
    ASSERT_GE(i, last);
    if (i != last) ++distinct;
    last = i;
    if (i == 0) continue;
    const Pose want = poseOf(i);
    ASSERT_EQ(p.translation, want.translation) << i;
    ASSERT_EQ(p.scale, want.scale) << i;
    ASSERT_LT((p.rotation.coeffs() - want.rotation.coeffs()).norm(), 1e-15) << i;
    // The plane z <= 0 of the object frame in the world: F = s R (k (0 - z_local) e_z).
    const Eigen::Matrix3d r = want.rotation.toRotationMatrix();
    const double zl = (r.transpose() * (hip - want.translation) / want.scale).z();
    const Vector3d expect = want.scale * (r * Vector3d(0, 0, -500 * zl));
    ASSERT_LT((f.force - expect).norm(), 1e-9) << i;
    contacts += f.contact;
  }
  readerDone.store(true);
  writer.join();
  s.step(hip);
  const int64_t final = std::llround(s.objects()[0].pose.translation.x() * 1e6);
  EXPECT_EQ(final, published.load());  // the last one wins
  EXPECT_GT(distinct, 10) << steps << " steps";
  std::printf("%lld steps saw %lld distinct poses of %lld published\n", (long long)steps, (long long)distinct,
              (long long) final);
  EXPECT_GT(contacts, 0);
  EXPECT_EQ(s.motion().updates, distinct + (final != last));
}

}  // namespace
