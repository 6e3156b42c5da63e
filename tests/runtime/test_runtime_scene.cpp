// SPDX-License-Identifier: Apache-2.0
// Scene files: parsing, poses, force transforms and sums, errors naming file and JSON path.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <smoothforce/force/force_presets.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/scene.h>

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using namespace sf::rt;

const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv -0.5 0.5 0.5\nv 0.5 0.5 0.5\n"
    "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

/// What the fake factory was asked for.
struct Made {
  sf::ForceMethod method;
  double stiffness;
  int faces;
  double angleTolerance = 0;
  int maxIterations = 0;
  sf::FinalStep finalStep = sf::FinalStep::Evaluated;
};

class RuntimeScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("sf_rt_scene_" + std::to_string(::getpid()));
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "cube.obj") << kCubeObj;
  }
  void TearDown() override { fs::remove_all(dir); }

  /// Each object's renderer: the half-space z <= 0.5 of its own frame (the cube's top plane).
  RendererFactory factory() {
    return [this](std::shared_ptr<const sf::PatchCache> c, sf::ForceMethod m, const sf::ForceOptions& o) {
      made.push_back({m, o.stiffness, c->numFaces(), o.angleTolerance, o.maxIterations, o.finalStep});
      return std::make_unique<PlaneRenderer>(Vector3d::UnitZ(), 0.5, o.stiffness);
    };
  }
  Scene load(const std::string& json, const std::string& name = "sub/scene.json") {
    const std::string p = (dir / name).string();
    std::ofstream(p) << json;
    return loadScene(p, defaults, factory());
  }
  std::string error(const std::string& json) {
    try {
      load(json);
    } catch (const sf::InputError& e) {
      return e.what();
    }
    return "no error";
  }

  fs::path dir;
  SceneDefaults defaults;
  std::vector<Made> made;
};

TEST_F(RuntimeScene, ParsesObjectsWithDefaults) {
  defaults.method = sf::ForceMethod::Shading;
  defaults.force.stiffness = 321;
  const Scene s = load(R"({"comment": "two cubes",
    "objects": [
      {"mesh": "../cube.obj"},
      {"name": "b", "mesh": "../cube.obj", "stiffness": 800, "method": "direct",
       "pose": {"translation": [1, 2, 3], "scale": 0.5}}
    ]})");
  ASSERT_EQ(s.objects().size(), 2u);
  EXPECT_EQ(s.objects()[0].name, "cube");
  EXPECT_TRUE(s.objects()[0].fromMesh);
  EXPECT_EQ(s.objects()[1].name, "b");
  ASSERT_EQ(made.size(), 2u);
  EXPECT_EQ(made[0].method, sf::ForceMethod::Shading);
  EXPECT_EQ(made[0].stiffness, 321);
  EXPECT_EQ(made[1].method, sf::ForceMethod::Direct);
  EXPECT_EQ(made[1].stiffness, 800);
  EXPECT_EQ(made[1].faces, 6);
  EXPECT_EQ(s.totalFaces(), 6);  // both name one file: one cache
  EXPECT_TRUE(s.worldVertex(1, 7).isApprox(Vector3d(1.25, 2.25, 3.25)));
}

TEST_F(RuntimeScene, PresetSetsRefinementAndMeshPrecisionButNotStiffness) {
  defaults.force.stiffness = 321;
  const sf::ForcePreset& fast = sf::findForcePreset("fast");
  const Scene s = load(R"({"objects": [
      {"mesh": "../cube.obj", "preset": "fast", "stiffness": 700},
      {"mesh": "../cube.obj", "preset": "fast"},
      {"mesh": "../cube.obj"}]})");
  ASSERT_EQ(made.size(), 3u);
  EXPECT_EQ(made[0].stiffness, 700);
  EXPECT_EQ(made[1].stiffness, 321);
  EXPECT_EQ(made[0].angleTolerance, fast.angleTolerance);
  EXPECT_EQ(made[0].maxIterations, fast.maxIterations);
  EXPECT_EQ(s.objects()[0].cache->options.precision, fast.precision);
  EXPECT_EQ(made[2].angleTolerance, sf::ForceOptions{}.angleTolerance);
  EXPECT_EQ(s.objects()[2].cache->options.precision, defaults.patchOptions.precision);
  const std::string e = error(R"({"objects": [{"mesh": "../cube.obj", "preset": "turbo"}]})");
  EXPECT_NE(e.find("scene.json: /objects/0/preset: preset: expected fast|balanced|accurate, got 'turbo'"),
            std::string::npos)
      << e;
}

TEST_F(RuntimeScene, FinalStepPerObjectOverTheDefault) {
  defaults.force.finalStep = sf::FinalStep::Model;  // loop --final-step model
  const Scene s = load(R"({"objects": [
      {"mesh": "../cube.obj", "final_step": "evaluated", "preset": "fast"},
      {"mesh": "../cube.obj"}]})");
  ASSERT_EQ(made.size(), 2u);
  EXPECT_EQ(made[0].finalStep, sf::FinalStep::Evaluated);
  EXPECT_EQ(made[1].finalStep, sf::FinalStep::Model);
  const std::string e = error(R"({"objects": [{"mesh": "../cube.obj", "final_step": "turbo"}]})");
  EXPECT_NE(e.find("scene.json: /objects/0/final_step: final_step: expected evaluated|model, got 'turbo'"),
            std::string::npos)
      << e;
  EXPECT_NE(error(R"({"objects": [{"mesh": "../cube.obj", "final_step": 1}]})").find("/objects/0/final_step"),
            std::string::npos);
}

TEST_F(RuntimeScene, LoadsCacheFiles) {
  sf::PatchOptions o;
  const auto cache = sf::buildPatchCache(sf::loadMesh((dir / "cube.obj").string(), o), o, sf::Backend::Serial);
  sf::writePatchCache(cache, (dir / "cube.sfpc").string());
  const Scene s = load(R"({"objects": [{"cache": "cube.sfpc"}]})", "scene.json");
  ASSERT_EQ(s.objects().size(), 1u);
  EXPECT_FALSE(s.objects()[0].fromMesh);
  EXPECT_EQ(s.objects()[0].cache->numFaces(), 6);
  EXPECT_NE(error(R"({"objects": [{"cache": "../cube.obj"}]})").find("/objects/0/cache: "), std::string::npos);
}

TEST_F(RuntimeScene, TransformsHipAndForce) {
  // Rotation of +90 degrees about x maps the object's +z to world -y; scale 2.
  for (const char* rot : {R"({"axis": [2, 0, 0], "angle": 1.5707963267948966})",
                          R"({"quaternion": [0.7071067811865476, 0.7071067811865476, 0, 0]})"}) {
    made.clear();
    Scene s = load(std::string(R"({"objects": [{"mesh": "../cube.obj", "stiffness": 100,
        "pose": {"translation": [1, 2, 3], "scale": 2, "rotation": )") +
                   rot + "}}]}");
    // Object-frame HIP (0, 0, 0.4): 0.1 object units = 0.2 m below the top plane.
    const Vector3d hip = Vector3d(1, 2, 3) + 2 * Vector3d(0, -0.4, 0);
    const sf::ForceSample f = s.step(hip);
    EXPECT_TRUE(f.contact);
    EXPECT_TRUE(f.force.isApprox(Vector3d(0, -100 * 0.2, 0), 1e-12)) << f.force.transpose();
    EXPECT_TRUE(f.normal.isApprox(Vector3d(0, -1, 0), 1e-12));
    EXPECT_TRUE(f.scp.isApprox(Vector3d(1, 2 - 1.0, 3), 1e-12)) << f.scp.transpose();
    EXPECT_FALSE(s.step(Vector3d(1, 0.5, 3)).contact);
  }
}

TEST_F(RuntimeScene, SumsForcesOfObjects) {
  Scene s = load(R"({"objects": [
      {"mesh": "../cube.obj", "stiffness": 100},
      {"mesh": "../cube.obj", "stiffness": 50, "pose": {"rotation": {"axis": [0, 1, 0], "angle": 3.141592653589793}}}
    ]})");
  // z = 0.45: 0.05 below the first cube's top (force +z), and 0.95 "below" the flipped
  // cube's top plane z = -0.5 in world (force -z).
  const sf::ForceSample f = s.step(Vector3d(0, 0, 0.45));
  EXPECT_NEAR(f.force.z(), 100 * 0.05 - 50 * 0.95, 1e-9);
  EXPECT_TRUE(f.contact);
  s.reset();
  EXPECT_EQ(s.patchesBuilt(), 0);
}

TEST_F(RuntimeScene, ErrorsNameFileAndJsonPath) {
  auto has = [&](const std::string& json, const std::string& want) {
    const std::string e = error(json);
    EXPECT_NE(e.find("scene.json: " + want), std::string::npos) << "got: " << e;
  };
  has(R"({"objects": [)", "invalid JSON: ");
  has(R"([1, 2])", "/: expected an object");
  has(R"({})", "/objects: missing");
  has(R"({"objects": []})", "/objects: expected a non-empty array");
  has(R"({"objects": [{"mesh": "../cube.obj"}], "extra": 1})", "/extra: unknown key");
  has(R"({"objects": [{"pose": {}}]})", "/objects/0: missing \"mesh\" or \"cache\"");
  has(R"({"objects": [{"mesh": "a.obj", "cache": "b.sfpc"}]})", "/objects/0: give either");
  has(R"({"objects": [{"mesh": 3}]})", "/objects/0/mesh: expected a non-empty string");
  has(R"({"objects": [{"mesh": "../cube.obj", "stifness": 3}]})", "/objects/0/stifness: unknown key");
  has(R"({"objects": [{"mesh": "../cube.obj", "stiffness": 0}]})",
      "/objects/0/stiffness: stiffness: expected a stiffness in (0, 1e12] N/m, got '0'");
  has(R"({"objects": [{"mesh": "../cube.obj", "stiffness": "hard"}]})", "/objects/0/stiffness: stiffness: expected");
  has(R"({"objects": [{"mesh": "../cube.obj"}, {"mesh": "../cube.obj", "method": "magic"}]})",
      "/objects/1/method: method: expected patch|direct|shading, got 'magic'");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"scale": -1}}]})",
      "/objects/0/pose/scale: expected a scale in [1e-09, 1e+09], got -1");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"translation": [1, 2]}}]})",
      "/objects/0/pose/translation: expected an array of 3 numbers");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"translation": [1, "x", 2]}}]})",
      "/objects/0/pose/translation/1: expected a finite number");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"rotation": {"axis": [0, 0, 0], "angle": 1}}}]})",
      "/objects/0/pose/rotation/axis: the axis is zero");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"rotation": {"axis": [0, 0, 1]}}}]})",
      "/objects/0/pose/rotation: axis-angle needs both");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"rotation": {"quaternion": [0, 0, 0, 0]}}}]})",
      "/objects/0/pose/rotation/quaternion: the quaternion is zero");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"rotation": {"quaternion": [1, 0, 0]}}}]})",
      "/objects/0/pose/rotation/quaternion: expected [w, x, y, z]");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"shear": 1}}]})", "/objects/0/pose/shear: unknown key");
  has(R"({"objects": [{"mesh": "../cube.obj", "stiffness": 1e400}]})", "invalid JSON: ");  // beyond a double
  has(R"({"objects": [{"mesh": "../cube.obj\u0000x"}]})", "/objects/0/mesh: expected a string without NUL");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"translation": [1e300, 0, 0]}}]})",
      "/objects/0/pose/translation: beyond the coordinate range");
  has(R"({"objects": [{"mesh": "../cube.obj", "pose": {"rotation": {"quaternion": [1e300, 1e300, 0, 0]}}}]})",
      "/objects/0/pose/rotation/quaternion: the quaternion's norm is beyond 1e150");
  // Errors inside the mesh name the mesh file too.
  const std::string e = error(R"({"objects": [{"mesh": "missing.obj"}]})");
  EXPECT_NE(e.find("scene.json: /objects/0/mesh: "), std::string::npos) << e;
  EXPECT_NE(e.find("missing.obj"), std::string::npos) << e;
  // A scene file that is not there.
  EXPECT_THROW(loadScene((dir / "nope.json").string(), defaults, factory()), sf::InputError);
}

// Scales beyond [1e-9, 1e9] (objects and the device transform) and stiffnesses beyond 1e12
// N/m are refused at their JSON path: 1e300 overflowed the HIP ("non-finite HIP position",
// blamed on the device), a device scale of 1e300 gave a replay no contact, silently, and a
// stiffness of 1e13 was blamed on /objects/0/cache.
TEST_F(RuntimeScene, ScalesAndStiffnessesOutOfRangeNameTheirPath) {
  int refused = 0, accepted = 0;
  for (const char* scale : {"1e300", "1e-300", "1e10", "1e-10", "1.0000001e9", "-1", "0"}) {
    for (const bool device : {false, true}) {
      const std::string pose = std::string(R"({"scale": )") + scale + "}";
      const std::string json =
          device ? R"({"device": {"transform": )" + pose + R"(}, "objects": [{"mesh": "../cube.obj"}]})"
                 : R"({"objects": [{"mesh": "../cube.obj", "pose": )" + pose + "}]}";
      const std::string want = std::string(device ? "/device/transform/scale" : "/objects/0/pose/scale") +
                               ": expected a scale in [1e-09, 1e+09], got ";
      const std::string e = error(json);
      EXPECT_NE(e.find("scene.json: " + want), std::string::npos) << json << "\ngot: " << e;
      refused += e.find(want) != std::string::npos;
    }
  }
  for (const char* scale : {"1e9", "1e-9", "0.001", "1"}) {
    for (const bool device : {false, true}) {
      const std::string pose = std::string(R"({"scale": )") + scale + "}";
      const Scene sc =
          load(device ? R"({"device": {"transform": )" + pose + R"(}, "objects": [{"mesh": "../cube.obj"}]})"
                      : R"({"objects": [{"mesh": "../cube.obj", "pose": )" + pose + "}]}");
      EXPECT_EQ(device ? sc.deviceTransform().scale() : sc.objects()[0].pose.scale, std::stod(scale));
      ++accepted;
    }
  }
  EXPECT_EQ(refused, 14);
  EXPECT_EQ(accepted, 8);
  int stiff = 0;
  for (const char* k : {"1e13", "1.0000001e12", "1e300", "-5"}) {
    const std::string e = error(std::string(R"({"objects": [{"mesh": "../cube.obj", "stiffness": )") + k + "}]}");
    EXPECT_NE(e.find("scene.json: /objects/0/stiffness: stiffness: expected a stiffness in (0, 1e12] N/m, got "),
              std::string::npos)
        << k << "\ngot: " << e;
    stiff += e.find("/objects/0/stiffness:") != std::string::npos;
  }
  EXPECT_EQ(stiff, 4);
  EXPECT_EQ(load(R"({"objects": [{"mesh": "../cube.obj", "stiffness": 1e12}]})").objects()[0].force.stiffness, 1e12);
}

// A given name names one object (both JSON paths named) and has no control characters (the
// report prints it); default names (the file's stem) may repeat.
TEST_F(RuntimeScene, ObjectNamesAreUniqueAndPrintable) {
  struct Bad {
    std::string json, want;
  };
  int checked = 0;
  for (const Bad& b :
       {Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "a"}, {"mesh": "../cube.obj", "name": "a"}]})",
            "/objects/1/name: \"a\" is also the name of /objects/0"},
        Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "a"}, {"mesh": "../cube.obj"},
                            {"mesh": "../cube.obj", "name": "a"}]})",
            "/objects/2/name: \"a\" is also the name of /objects/0"},
        Bad{R"({"objects": [{"mesh": "../cube.obj"}, {"mesh": "../cube.obj", "name": "cube"}]})",
            "/objects/1/name: \"cube\" is also the name of /objects/0"},
        Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "cube"}, {"mesh": "../cube.obj"}]})",
            "/objects/1/name: \"cube\" is also the name of /objects/0 (this object's default name"},
        Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "a\nb\u0007"}]})",
            "/objects/0/name: expected a name without control characters, got U+000A"},
        Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "tab\there"}]})",
            "/objects/0/name: expected a name without control characters, got U+0009"},
        Bad{R"({"objects": [{"mesh": "../cube.obj", "name": "del\u007f"}]})",
            "/objects/0/name: expected a name without control characters, got U+007F"}}) {
    const std::string e = error(b.json);
    EXPECT_NE(e.find("scene.json: " + b.want), std::string::npos) << b.json << "\ngot: " << e;
    checked += e.find(b.want) != std::string::npos;
  }
  EXPECT_EQ(checked, 7);
  const Scene sc = load(R"({"objects": [{"mesh": "../cube.obj"}, {"mesh": "../cube.obj"}, {"mesh": "../cube.obj",
                            "name": "caf\u00e9"}]})");
  ASSERT_EQ(sc.objects().size(), 3u);
  EXPECT_EQ(sc.objects()[0].name, "cube");
  EXPECT_EQ(sc.objects()[1].name, "cube");
  EXPECT_EQ(sc.objects()[2].name, "caf\xc3\xa9");
}

TEST(RuntimeSceneMethods, Names) {
  EXPECT_EQ(sf::parseForceMethod("patch"), sf::ForceMethod::Patch);
  EXPECT_EQ(sf::parseForceMethod("direct"), sf::ForceMethod::Direct);
  EXPECT_EQ(sf::parseForceMethod("shading"), sf::ForceMethod::Shading);
  EXPECT_THROW(sf::parseForceMethod("Patch"), sf::InputError);
  EXPECT_STREQ(sf::toString(sf::ForceMethod::Direct), "direct");
}

}  // namespace
