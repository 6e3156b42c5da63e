// SPDX-License-Identifier: Apache-2.0
// Simulated devices: replay interpolation and CSV errors; scripted paths' speed and depth.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/scripted.h>

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using namespace sf::rt;

/// A scene of one polygon mesh (base polygons only; no patches are built).
Scene meshScene(const std::vector<Vector3d>& pts, const std::vector<std::vector<int32_t>>& faces) {
  sf::PolygonMesh m;
  m.positions = pts;
  for (const auto& f : faces) m.addFace(f);
  std::vector<Vector3d> normals(m.numCorners(), Vector3d::UnitZ());
  auto cache = std::make_shared<const sf::PatchCache>(sf::preparePatchCache(m, normals, sf::PatchOptions{}, 0));
  auto factory = [](std::shared_ptr<const sf::PatchCache>, sf::ForceMethod, const sf::ForceOptions&) {
    return std::make_unique<PlaneRenderer>(Vector3d::UnitZ(), 0.0, 100.0);
  };
  return singleObjectScene(cache, "test.obj", sf::ForceMethod::Patch, sf::ForceOptions{}, factory);
}

/// The cube [-0.5, 0.5]^3, faces outward.
Scene cubeScene() {
  std::vector<Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  return meshScene(p, {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}});
}

class RuntimeReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_rt_dev_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string file(const std::string& content) {
    const std::string p = (dir / ("t" + std::to_string(n++) + ".csv")).string();
    std::ofstream(p) << content;
    return p;
  }
  std::string error(const std::string& content) {
    const std::string p = file(content);
    try {
      readTrajectoryCsv(p);
    } catch (const sf::InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir;
  int n = 0;
};

TEST_F(RuntimeReplay, InterpolatesLinearlyAndHoldsEnds) {
  ReplayDevice d(readTrajectoryCsv(file("t,x,y,z\n0,0,0,0\n1,1,0,0\n# comment\n\n3,1,2,-4\n")));
  EXPECT_TRUE(d.read(0.5).position.isApprox(Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(d.read(2.0).position.isApprox(Vector3d(1, 1, -2)));
  EXPECT_EQ(d.read(1.0).position, Vector3d(1, 0, 0));
  EXPECT_EQ(d.read(-1.0).position, Vector3d(0, 0, 0));
  EXPECT_EQ(d.read(10.0).position, Vector3d(1, 2, -4));
  EXPECT_EQ(d.read(std::nan("")).position, Vector3d(0, 0, 0));
}

TEST_F(RuntimeReplay, HeaderIsOptional) {
  const Trajectory t = readTrajectoryCsv(file("0.5, 1, 2, 3\n1.5,4,5,6\n"));
  ASSERT_EQ(t.t.size(), 2u);
  EXPECT_EQ(t.t[0], 0.5);
  EXPECT_EQ(t.p[1], Vector3d(4, 5, 6));
}

TEST_F(RuntimeReplay, ErrorsNameFileAndLine) {
  std::string e = error("t,x,y,z\n0,0,0,0\n1,abc,0,0\n");
  EXPECT_NE(e.find(".csv:3: x is not a finite number: 'abc'"), std::string::npos) << e;
  e = error("0,0,0,0\n1,0,0\n");
  EXPECT_NE(e.find(".csv:2: expected 4 columns t,x,y,z, got 3"), std::string::npos) << e;
  e = error("0,0,0,0\n1,0,0,0\n1,0,0,1\n");
  EXPECT_NE(e.find(".csv:3: time 1 s is not greater"), std::string::npos) << e;
  e = error("0,0,0,nan\n");
  EXPECT_NE(e.find(".csv:1: z is not a finite number"), std::string::npos) << e;
  e = error("t,x,y,z\n");
  EXPECT_NE(e.find(".csv: no rows"), std::string::npos) << e;
  e = error("");
  EXPECT_NE(e.find(".csv: no rows"), std::string::npos) << e;
  try {
    readTrajectoryCsv((dir / "missing.csv").string());
    FAIL();
  } catch (const sf::InputError& x) {
    EXPECT_NE(std::string(x.what()).find("missing.csv: cannot open"), std::string::npos);
  }
}

/// Positions along the path at times t and t + dt: |p1 - p0| / dt.
double speedAt(HapticDevice& d, double t, double dt = 1e-4) {
  return (d.read(t + dt).position - d.read(t).position).norm() / dt;
}

// A replay's times are seconds from the loop's start: a file whose first time is not before
// the run's end (absolute times, 1.7e9 s since 1970) held its first position for the whole
// run, silently. makeDevice refuses it, naming the file, the first time and the duration.
TEST_F(RuntimeReplay, AFirstSampleAfterTheRunsEndIsRefused) {
  const Scene s = cubeScene();
  ScriptOptions o;
  o.duration = 2;
  int refused = 0;
  for (const char* t0 : {"1700000000.000000", "2", "2.5"}) {
    const std::string p = file(std::string("t,x,y,z\n") + t0 + ",0,0,1\n1e10,0,0,2\n");
    try {
      makeDevice("replay:" + p, s, o);
      ADD_FAILURE() << t0;
    } catch (const sf::InputError& e) {
      const std::string w = e.what();
      EXPECT_EQ(w.rfind(p + ": the first sample is at t = " + (t0[1] == '7' ? "1700000000" : t0) + " s", 0), 0u) << w;
      EXPECT_NE(w.find(", not before the run's end (2 s)"), std::string::npos) << w;
      ++refused;
    }
  }
  EXPECT_EQ(refused, 3);
  // a first time before the end plays; without a duration nothing is checked
  EXPECT_NE(makeDevice("replay:" + file("t,x,y,z\n1.9,0,0,1\n3,0,0,2\n"), s, o), nullptr);
  o.duration = 0;
  EXPECT_NE(makeDevice("replay:" + file("t,x,y,z\n1e9,0,0,1\n"), s, o), nullptr);
}

// An absurd --speed overflowed the arc length (speed * t = inf, fmod gave NaN), NaN passed
// PathDevice::at's tests and it read one past the end of its arrays: makeDevice refuses
// speeds beyond 10 m/s, and a PathDevice made with one (the class takes any finite speed)
// still stays on its path, on both kinds of path.
TEST(RuntimeScripted, AbsurdSpeedsAreRefusedAndThePathNeverLeft) {
  const Scene s = cubeScene();
  int refused = 0, onPath = 0;
  for (const std::string spec : {"scripted:slide", "scripted:circle"}) {
    for (const double v : {1e308, 1e200, 1e3, 10.000001, 0.0, -1.0, double(NAN), double(INFINITY)}) {
      ScriptOptions o;
      o.speed = v;
      try {
        makeDevice(spec, s, o);
        ADD_FAILURE() << spec << " " << v;
      } catch (const sf::InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--speed: expected a speed in (0, 10] m/s, got ", 0), 0u) << e.what();
        ++refused;
      }
    }
    ScriptOptions o;
    o.speed = 10;
    const auto fast = makeDevice(spec, s, o);
    ASSERT_NE(fast, nullptr);
    const ScriptedPath path = spec == "scripted:circle" ? circlePath(s, 0.01) : slidePath(s, 0.01);
    Eigen::AlignedBox3d box;
    for (const Vector3d& q : path.points) box.extend(q);
    for (const double v : {1e308, 1e200, 1.7e308}) {
      PathDevice d(path, v);
      for (const double t : {1e-3, 0.5, 1.0, 2.0, 3.0, 1e300}) {
        const Vector3d p = d.read(t).position;
        ASSERT_TRUE(p.allFinite()) << spec << " speed " << v << " t " << t;
        ASSERT_TRUE(box.contains(p)) << spec << " speed " << v << " t " << t;
      }
      ++onPath;
    }
  }
  EXPECT_EQ(refused, 16);
  EXPECT_EQ(onPath, 6);
}

TEST(RuntimeScripted, SlideOnCubeTopAtDepthAndSpeed) {
  const Scene s = cubeScene();
  EXPECT_NEAR(effectiveDepth(s, 0), 0.01 * std::sqrt(3.0), 1e-12);
  const ScriptedPath p = slidePath(s, 0.01);
  ASSERT_GE(p.points.size(), 4u);
  EXPECT_FALSE(p.closed);
  EXPECT_NEAR(p.points.front().z(), 0.51, 1e-12);  // enters from above
  EXPECT_NEAR(p.points.back().z(), 0.51, 1e-12);
  for (size_t i = 1; i + 1 < p.points.size(); ++i) {
    EXPECT_NEAR(p.points[i].z(), 0.49, 1e-12);
    EXPECT_NEAR(p.points[i].y(), 0.0, 1e-12);
    EXPECT_GE(p.points[i].x(), -0.4 - 1e-12);
    EXPECT_LE(p.points[i].x(), 0.4 + 1e-12);
  }
  EXPECT_NEAR(p.points[1].x(), -p.points[p.points.size() - 2].x(), 1e-12);  // symmetric, ~80% of the top
  EXPECT_GT(p.points.back().x() - p.points.front().x(), 0.79);

  PathDevice d(p, 0.1);
  const double total = 0.02 + (p.points.back().x() - p.points.front().x()) + 0.02;
  for (double t : {0.05, 1.0, 3.3, 7.7}) EXPECT_NEAR(speedAt(d, t), 0.1, 1e-9) << t;
  EXPECT_NEAR(d.read(0.2 + 0.5).position.z(), 0.49, 1e-12);  // sliding
  // Back and forth: at the far end after total / speed, back at the start after twice that.
  EXPECT_TRUE(d.read(total / 0.1).position.isApprox(p.points.back(), 1e-9));
  EXPECT_TRUE(d.read(2 * total / 0.1).position.isApprox(p.points.front(), 1e-9));
  EXPECT_TRUE(d.read(-1).position.isApprox(p.points.front()));
}

TEST(RuntimeScripted, SlideFollowsASlope) {
  // One quad z = 0.2 x over [-1, 1]^2.
  const Scene s = meshScene({{-1, -1, -0.2}, {1, -1, 0.2}, {1, 1, 0.2}, {-1, 1, -0.2}}, {{0, 1, 2, 3}});
  const ScriptedPath p = slidePath(s, 0.05);
  for (size_t i = 1; i + 1 < p.points.size(); ++i) EXPECT_NEAR(p.points[i].z(), 0.2 * p.points[i].x() - 0.05, 1e-12);
  PathDevice d(p, 0.3);
  EXPECT_NEAR(speedAt(d, 2.0), 0.3, 1e-9);
}

TEST(RuntimeScripted, SlideFindsTheRunNearestTheCentre) {
  // Squares at z = 0, x in [-3, -1.5], and z = 1, x in [1, 2]: the bounding-box centre x = -0.5
  // lies in the gap, 1 from the left square and 1.5 from the right one.
  const Scene s =
      meshScene({{-3, 0, 0}, {-1.5, 0, 0}, {-1.5, 1, 0}, {-3, 1, 0}, {1, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}},
                {{0, 1, 2, 3}, {4, 5, 6, 7}});
  const ScriptedPath p = slidePath(s, 0.01);
  for (size_t i = 1; i + 1 < p.points.size(); ++i) {
    EXPECT_GT(p.points[i].x(), -3.0);
    EXPECT_LT(p.points[i].x(), -1.5);
    EXPECT_NEAR(p.points[i].z(), -0.01, 1e-12);
  }
  EXPECT_THROW(circlePath(s, 0.01), sf::InputError);  // the circle crosses the gap
}

TEST(RuntimeScripted, CircleOnCubeTop) {
  const Scene s = cubeScene();
  const ScriptedPath p = circlePath(s, 0.02);
  EXPECT_TRUE(p.closed);
  EXPECT_EQ(p.loopStart, 1u);
  EXPECT_NEAR(p.points[0].z(), 0.52, 1e-12);
  for (size_t i = 1; i < p.points.size(); ++i) {
    EXPECT_NEAR(p.points[i].z(), 0.48, 1e-12);
    EXPECT_NEAR(p.points[i].head<2>().norm(), 0.25, 1e-12);
  }
  PathDevice d(p, 0.2);
  for (double t : {0.5, 2.0, 100.3}) {
    EXPECT_NEAR(speedAt(d, t), 0.2, 2e-5) << t;  // along the chords of a 256-gon
    EXPECT_NEAR(d.read(t).position.z(), 0.48, 1e-12);
    EXPECT_NEAR(d.read(t).position.head<2>().norm(), 0.25, 0.25 * (1 - std::cos(M_PI / 256)) + 1e-12);
  }
}

TEST(RuntimeScripted, NoSurfaceIsAnError) {
  // A vertical wall is seen edge-on from above.
  const Scene s = meshScene({{0, -1, 0}, {0, 1, 0}, {0, 1, 1}, {0, -1, 1}}, {{0, 1, 2, 3}});
  try {
    slidePath(s, 0.01);
    FAIL();
  } catch (const sf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scripted:slide: no surface"), std::string::npos) << e.what();
  }
}

TEST(RuntimeScripted, MakeDeviceSpecs) {
  const Scene s = cubeScene();
  ScriptOptions o;
  o.speed = 0.1;
  auto n = makeDevice("null", s, o);
  EXPECT_NEAR(n->read(0).position.z(), 0.5 + 0.1 * std::sqrt(3.0), 1e-12);
  n->writeForce(Vector3d(1, 2, 3));  // discarded
  auto sl = makeDevice("scripted", s, o);
  EXPECT_NEAR(sl->read(1.0).position.z(), 0.5 - 0.01 * std::sqrt(3.0), 1e-12);  // default depth
  auto c = makeDevice("scripted:circle", s, o);
  EXPECT_NE(c->describe().find("scripted:circle"), std::string::npos);
  EXPECT_NE(makeDevice("scripted:slide", s, o)->describe().find("scripted:slide"), std::string::npos);
  try {
    makeDevice("haptx", s, o);
    FAIL();
  } catch (const sf::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--device: expected", 0), 0u) << e.what();
  }
  EXPECT_THROW(makeDevice("replay:", s, o), sf::InputError);
  EXPECT_THROW(makeDevice("replay:/nonexistent/x.csv", s, o), sf::InputError);
  o.speed = 0;
  EXPECT_THROW(makeDevice("scripted", s, o), sf::InputError);
}

}  // namespace
