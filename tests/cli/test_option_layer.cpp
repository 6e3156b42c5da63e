// SPDX-License-Identifier: Apache-2.0
// The patch and force options have one reader each (patch_option_text.h, force_option_text.h):
// every bad value of every option gets the same message from the parser, the command line (exit
// 2, a usage error) and scene files, naming the option as each spells it; test_capi.cpp and
// python/tests check the C API and Python against the same tables, and every good value reads
// back as it was written.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include <smoothforce/force/force_option_text.h>
#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/runtime/loop_option_text.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/sweep/sweep_option_text.h>

#include "cli_test_support.h"
#include "test_hostile_support.h"

namespace sf {
namespace {

/// A bad value of each option (crease_angle: as the command line and scene files give it).
struct BadValue {
  const char* key;
  const char* value;
};
constexpr BadValue kBad[] = {{"precision", "half"},     {"normals", "fancy"},     {"cross_tangent", "sideways"},
                             {"orient", "inward"},      {"cage", "loop"},         {"creases", "tags,foo"},
                             {"crease_angle", "200"},   {"fold_repair", "sometimes"}};

const PatchOptionSpec& spec(const std::string& key) {
  for (const PatchOptionSpec& s : kPatchOptionSpecs)
    if (key == s.key) return s;
  throw std::logic_error("no spec " + key);
}

std::string core(const BadValue& b) {
  return std::string("expected ") + spec(b.key).values + ", got '" + b.value + "'";
}

TEST(OptionLayer, EveryOptionHasABadValueHere) {
  ASSERT_EQ(std::size(kBad), std::size(kPatchOptionSpecs));
  for (size_t i = 0; i < std::size(kBad); ++i) EXPECT_STREQ(kBad[i].key, kPatchOptionSpecs[i].key);
}

TEST(OptionLayer, TheParserNamesTheKeyOrTheFlag) {
  for (const BadValue& b : kBad) {
    for (OptionSpelling sp : {OptionSpelling::Key, OptionSpelling::Flag}) {
      PatchOptions o;
      try {
        setPatchOption(o, b.key, b.value, sp);
        ADD_FAILURE() << b.key << " accepted " << b.value;
      } catch (const InputError& e) {
        const std::string name = sp == OptionSpelling::Key ? spec(b.key).key : spec(b.key).flag;
        EXPECT_EQ(std::string(e.what()), name + ": " + core(b));
      }
    }
  }
  PatchOptions o;
  EXPECT_THROW(setPatchOption(o, "colour", "red"), InputError);
}

TEST(OptionLayer, EveryGoodValueReadsBackAsWritten) {
  const std::vector<PatchOptionText> texts = {
      PatchOptionText{},
      PatchOptionText{"float", "file", "paper", "keep", "none", "none", 30},
      PatchOptionText{"double", "angle", "blend", "outward", "catmull-clark", "tags,normals", 0},
      PatchOptionText{"double", "area", "corrected", "keep", "none", "groups", 179.5},
  };
  for (const PatchOptionText& t : texts) {
    const PatchOptionText back = patchOptionText(parsePatchOptions(t));
    EXPECT_EQ(back.precision, t.precision);
    EXPECT_EQ(back.normals, t.normals);
    EXPECT_EQ(back.crossTangent, t.crossTangent);
    EXPECT_EQ(back.orient, t.orient);
    EXPECT_EQ(back.cage, t.cage);
    EXPECT_EQ(back.creases, t.creases);
    EXPECT_EQ(back.creaseAngle, t.creaseAngle);
  }
}

TEST(OptionLayer, TheCommandLineAndSceneFilesGiveTheSameMessage) {
  hostile::TempDir dir("sf_option_layer");
  const std::string mesh = std::string(SF_DATA_DIR) + "/chamfer-cube.off";
  for (const BadValue& b : kBad) {
    SCOPED_TRACE(b.key);
    const test::CliResult r =
        test::smoothforce("cache build " + mesh + " " + spec(b.key).flag + " " + b.value + " -o " +
                          (dir.path / "x.sfcache").string());
    EXPECT_EQ(r.status, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find(std::string(spec(b.key).flag) + ": " + core(b)), std::string::npos) << r.out;
    const bool number = std::string(b.key) == "crease_angle";
    const std::string scene = (dir.path / "scene.json").string();
    std::ofstream(scene) << R"({"objects": [{"mesh": ")" << mesh << R"(", ")" << b.key
                         << "\": " << (number ? std::string(b.value) : "\"" + std::string(b.value) + "\"") << "}]}";
    try {
      rt::loadScene(scene, rt::SceneDefaults{}, rt::sharedRendererFactory());
      ADD_FAILURE() << "the scene file was read";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                scene + ": /objects/0/" + b.key + ": " + b.key + ": " + core(b));
    }
  }
}

/// A bad value of each force option, as text (the command line, scene-file strings) and, for
/// the numeric ones, as the number a typed front end passes; `shown` is how messages show it.
struct BadForceValue {
  const char* key;
  const char* value;
  const char* shown;
};
constexpr BadForceValue kBadForce[] = {
    {"method", "magic", "magic"},          {"preset", "turbo", "turbo"},
    {"stiffness", "1e13", "1e+13"},        {"refine", "gauss", "gauss"},
    {"angle_tolerance", "-1", "-1"},       {"position_tolerance", "0", "0"},
    {"max_iterations", "0", "0"},          {"initial_guess", "random", "random"},
    {"guess_level", "65", "65"},           {"final_step", "turbo", "turbo"},
    {"patch_capacity", "2.5", "2.5"},      {"surface_index", "octree", "octree"},
};

const OptionSpec& forceSpec(const std::string& key) {
  for (const OptionSpec& s : kForceOptionSpecs)
    if (key == s.key) return s;
  throw std::logic_error("no spec " + key);
}

std::string forceCore(const BadForceValue& b) {
  return std::string("expected ") + forceSpec(b.key).values + ", got '" + b.shown + "'";
}

TEST(ForceOptionLayer, EveryOptionHasABadValueHere) {
  ASSERT_EQ(std::size(kBadForce), std::size(kForceOptionSpecs));
  for (size_t i = 0; i < std::size(kBadForce); ++i) EXPECT_STREQ(kBadForce[i].key, kForceOptionSpecs[i].key);
}

TEST(ForceOptionLayer, TextAndNumbersGetOneMessageNamingTheKeyOrTheFlag) {
  int numeric = 0;
  for (const BadForceValue& b : kBadForce) {
    for (OptionSpelling sp : {OptionSpelling::Key, OptionSpelling::Flag}) {
      const std::string want = std::string(optionName(forceSpec(b.key), sp)) + ": " + forceCore(b);
      ForceSettings f;
      try {
        setForceOption(f, b.key, b.value, sp);
        ADD_FAILURE() << b.key << " accepted " << b.value;
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), want);
      }
      if (forceSpec(b.key).type == OptionType::Text) continue;
      numeric += sp == OptionSpelling::Key;
      try {
        setForceOption(f, b.key, std::strtod(b.value, nullptr), sp);
        ADD_FAILURE() << b.key << " accepted " << b.value << " as a number";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), want);
      }
    }
  }
  EXPECT_EQ(numeric, 6);
  ForceSettings f;
  EXPECT_THROW(setForceOption(f, "colour", "red"), InputError);
  EXPECT_THROW(setForceOption(f, "method", 1.0), InputError);  // a text option takes no number
}

TEST(ForceOptionLayer, EveryGoodValueReadsBackAsWritten) {
  const std::vector<std::vector<std::pair<const char*, const char*>>> sets = {
      {{"method", "direct"}, {"stiffness", "800"}, {"refine", "paper"}, {"angle_tolerance", "1e-07"},
       {"position_tolerance", "3e-09"}, {"max_iterations", "7"}, {"initial_guess", "polygon"}, {"guess_level", "5"},
       {"final_step", "evaluated"}, {"patch_capacity", "-1"}, {"surface_index", "bounds"}},
      {{"method", "shading"}, {"preset", "fast"}, {"stiffness", "0.1"}, {"final_step", "model"},
       {"patch_capacity", "64"}, {"angle_tolerance", "0.25"}, {"surface_index", "tessellation"}},
  };
  int checked = 0;
  for (const auto& set : sets) {
    ForceSettings f;
    for (const auto& [key, value] : set) setForceOption(f, key, value);
    checkForceOptions(f.options);
    ForceSettings back;
    for (const OptionSpec& s : kForceOptionSpecs) {
      const std::string text = forceOptionValue(f, s.key);
      if (!text.empty()) setForceOption(back, s.key, text);
    }
    for (const OptionSpec& s : kForceOptionSpecs) {
      EXPECT_EQ(forceOptionValue(back, s.key), forceOptionValue(f, s.key)) << s.key;
      ++checked;
    }
    for (const auto& [key, value] : set) EXPECT_EQ(forceOptionValue(f, key), value) << key;
  }
  EXPECT_EQ(checked, 2 * 12);
  // the pair the values must agree on, by key and by flag
  ForceSettings f;
  setForceOption(f, "refine", "paper");
  setForceOption(f, "final_step", "model");
  EXPECT_THROW(checkForceOptions(f.options), InputError);
  try {
    checkForceOptions(f.options, OptionSpelling::Flag);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--final-step: 'model'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs --refine newton"), std::string::npos) << e.what();
  }
}

TEST(ForceOptionLayer, TheCommandLineAndSceneFilesGiveTheSameMessage) {
  hostile::TempDir dir("sf_force_option_layer");
  const std::string mesh = std::string(SF_DATA_DIR) + "/chamfer-cube.off";
  const std::string hips = (dir.path / "hips.csv").string();
  std::ofstream(hips) << "x,y,z\n0,0,0\n";
  int checked = 0;
  for (const BadForceValue& b : kBadForce) {
    SCOPED_TRACE(b.key);
    const OptionSpec& s = forceSpec(b.key);
    const test::CliResult r = test::smoothforce("trace --mesh " + mesh + " --hips " + hips + " " + s.flag + " " +
                                                b.value + " -o " + (dir.path / "t.csv").string());
    EXPECT_EQ(r.status, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find(std::string(s.flag) + ": " + forceCore(b)), std::string::npos) << r.out;
    const std::string scene = (dir.path / "scene.json").string();
    const std::string value = s.type == OptionType::Text ? "\"" + std::string(b.value) + "\"" : b.value;
    std::ofstream(scene) << R"({"objects": [{"mesh": ")" << mesh << R"(", ")" << b.key << "\": " << value << "}]}";
    try {
      rt::loadScene(scene, rt::SceneDefaults{}, rt::sharedRendererFactory());
      ADD_FAILURE() << "the scene file was read";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), scene + ": /objects/0/" + b.key + ": " + b.key + ": " + forceCore(b));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 12);
}

/// A bad value of each loop option, as the command line gives it (and as a number).
constexpr BadValue kBadLoop[] = {{"rate", "0"},           {"duration", "-1"},   {"max_force", "0"},
                                 {"max_force_step", "0"}, {"ramp_time", "-1"}, {"max_missed", "0"}};

const OptionSpec& loopSpec(const std::string& key) {
  for (const OptionSpec& s : rt::kLoopOptionSpecs)
    if (key == s.key) return s;
  throw std::logic_error("no spec " + key);
}

TEST(LoopOptionLayer, EveryOptionGetsOneMessageFromTheParserAndTheCommandLine) {
  ASSERT_EQ(std::size(kBadLoop), std::size(rt::kLoopOptionSpecs));
  const std::string mesh = std::string(SF_DATA_DIR) + "/chamfer-cube.off";
  int checked = 0;
  for (size_t i = 0; i < std::size(kBadLoop); ++i) {
    const BadValue& b = kBadLoop[i];
    SCOPED_TRACE(b.key);
    EXPECT_STREQ(b.key, rt::kLoopOptionSpecs[i].key);
    const OptionSpec& s = loopSpec(b.key);
    const std::string core = std::string("expected ") + s.values + ", got '" + b.value + "'";
    for (OptionSpelling sp : {OptionSpelling::Key, OptionSpelling::Flag}) {
      const std::string want = std::string(optionName(s, sp)) + ": " + core;
      for (int asNumber = 0; asNumber < 2; ++asNumber) {
        try {
          if (asNumber)
            rt::checkLoopOption(b.key, std::strtod(b.value, nullptr), sp);
          else
            rt::checkLoopOption(b.key, std::string(b.value), sp);
          ADD_FAILURE() << "accepted " << b.value;
        } catch (const InputError& e) {
          EXPECT_EQ(std::string(e.what()), want);
          ++checked;
        }
      }
    }
    const test::CliResult r = test::smoothforce("loop --mesh " + mesh + " --device null --duration 0.01 " + s.flag +
                                                " " + b.value);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find(std::string(s.flag) + ": " + core), std::string::npos) << r.out;
  }
  EXPECT_EQ(checked, 6 * 4);
  EXPECT_THROW(rt::checkLoopOption("rate", std::string("fast")), InputError);
  EXPECT_THROW(rt::checkLoopOption("colour", 1.0), InputError);
  // the good values of the defaults pass
  rt::checkSafetyOptions(rt::SafetyOptions{});
}

/// A bad value of each sweep option, as the command line gives it.
constexpr BadValue kBadSweep[] = {{"samples", "0"},     {"seed", "-1"}, {"level", "65"},          {"approach", "nan"},
                                  {"sample_on", "mesh"}, {"knn", "0"},   {"threshold_deg", "200"}};

TEST(SweepOptionLayer, EveryOptionGetsOneMessageFromTheParserAndTheCommandLine) {
  ASSERT_EQ(std::size(kBadSweep), std::size(kSweepOptionSpecs));
  hostile::TempDir dir("sf_sweep_option_layer");
  const std::string mesh = std::string(SF_DATA_DIR) + "/chamfer-cube.off";
  int checked = 0;
  for (size_t i = 0; i < std::size(kBadSweep); ++i) {
    const BadValue& b = kBadSweep[i];
    SCOPED_TRACE(b.key);
    const OptionSpec& s = kSweepOptionSpecs[i];
    EXPECT_STREQ(b.key, s.key);
    const std::string core = std::string("expected ") + s.values + ", got '" + b.value + "'";
    for (OptionSpelling sp : {OptionSpelling::Key, OptionSpelling::Flag}) {
      SweepConfig c;
      try {
        setSweepOption(c, b.key, std::string(b.value), sp);
        ADD_FAILURE() << "accepted " << b.value;
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), std::string(optionName(s, sp)) + ": " + core);
        ++checked;
      }
      if (s.type == OptionType::Text || std::string(b.key) == "seed") continue;
      try {
        setSweepOption(c, b.key, std::strtod(b.value, nullptr), sp);
        ADD_FAILURE() << "accepted " << b.value << " as a number";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), std::string(optionName(s, sp)) + ": " + core);
        ++checked;
      }
    }
    const test::CliResult r = test::smoothforce("sweep --mesh " + mesh + " --depth 1% --no-plots " + s.flag + " " +
                                                b.value + " -o " + (dir.path / "s").string());
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find(std::string(s.flag) + ": " + core), std::string::npos) << r.out;
  }
  EXPECT_EQ(checked, 7 * 2 + 5 * 2);
  // a seed takes all 64 bits as text; checkSweepOptions passes good values, and a HIP file's
  // sweep (sample_on file) counts its own HIPs
  SweepConfig c;
  setSweepOption(c, "seed", std::string("18446744073709551615"));
  EXPECT_EQ(c.seed, 18446744073709551615ull);
  EXPECT_THROW(checkSweepOptions(c), InputError);  // samples 0
  c.samples = 1000;
  checkSweepOptions(c);
  c.samples = 0;
  c.sampleOn = "file";
  checkSweepOptions(c);
}

}  // namespace
}  // namespace sf
