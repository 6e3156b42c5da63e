// SPDX-License-Identifier: Apache-2.0
// The patch options have one reader (patch_option_text.h): every bad value of every option gets
// the same message from the parser, the command line (exit 2, a usage error) and scene files,
// naming the option as each spells it; test_capi.cpp and python/tests check the C API and
// Python against the same table, and every good value reads back as it was written.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/runtime/scene.h>

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
                             {"crease_angle", "200"}};

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

}  // namespace
}  // namespace sf
