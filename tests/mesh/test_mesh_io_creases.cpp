// SPDX-License-Identifier: Apache-2.0
// Crease marks in mesh files: OBJ smoothing groups (`s N`, `s off`), OpenSubdiv's OBJ tags
// (`t crease`, `t corner` with 0-based vertex ids; other tags checked and ignored) and PLY
// `edge` elements with a crease value, in ASCII and binary; and the errors each reader gives,
// named by file and line (or byte, in binary PLY).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <smoothforce/mesh/mesh_io.h>

#include "mesh_file_support.h"

namespace fs = std::filesystem;

namespace {

using sf::test::errorOf;
using sf::test::writeTemp;

sf::PolygonMesh readText(const std::string& name, const std::string& text) {
  return sf::readMesh(writeTemp(name, text));
}

/// Expects reading `text` as file `name` to fail with "path:line: " followed by a message
/// that contains `what`.
void expectError(const std::string& name, const std::string& text, size_t line, const std::string& what) {
  SCOPED_TRACE(name + ":\n" + text);
  const std::string path = writeTemp(name, text);
  const std::string msg = errorOf(path);
  const std::string prefix = path + ":" + std::to_string(line) + ": ";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix " << prefix << "\n got: " << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
}

/// A unit cube: 8 vertices (vertex i at the bits of i: x = bit 0, y = bit 1, z = bit 2) and 6
/// quads, outward, 1-based as OBJ writes them.
const char* const kCubeVertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n";
const int kCubeFaces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};

std::string cubeFace(int f) {
  std::string s = "f";
  for (int v : kCubeFaces[f]) {
    s += ' ';  // appended piecewise: GCC 12 warns (-Wrestrict) about " " + std::to_string(...)
    s += std::to_string(v);
  }
  return s + "\n";
}

std::string cubeFaces() {
  std::string s;
  for (int f = 0; f < 6; ++f) s += cubeFace(f);
  return s;
}

/// The cube's 12 edges as 0-based vertex pairs, in the order the faces first give them.
std::vector<std::pair<int, int>> cubeEdges() {
  std::vector<std::pair<int, int>> edges;
  std::set<std::pair<int, int>> seen;
  for (const auto& f : kCubeFaces) {
    for (int k = 0; k < 4; ++k) {
      const int a = f[k] - 1, b = f[(k + 1) % 4] - 1;
      if (seen.insert({std::min(a, b), std::max(a, b)}).second) edges.emplace_back(a, b);
    }
  }
  return edges;
}

void expectCrease(const sf::CreaseTag& t, int v0, int v1, double sharpness, size_t line) {
  EXPECT_EQ(t.v0, v0);
  EXPECT_EQ(t.v1, v1);
  EXPECT_EQ(t.sharpness, sharpness);
  EXPECT_EQ(t.line, line);
}

void expectCorner(const sf::CornerTag& t, int v, double sharpness, size_t line) {
  EXPECT_EQ(t.v, v);
  EXPECT_EQ(t.sharpness, sharpness);
  EXPECT_EQ(t.line, line);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// OBJ smoothing groups

TEST(ObjSmoothingGroups, NoStatementLeavesThemEmpty) {
  const sf::PolygonMesh m = readText("no_s.obj", kCubeVertices + cubeFaces());
  EXPECT_EQ(m.numFaces(), 6);
  EXPECT_TRUE(m.faceSmoothingGroups.empty());
  EXPECT_TRUE(m.creaseTags.empty());
  EXPECT_TRUE(m.cornerTags.empty());
}

TEST(ObjSmoothingGroups, OneGroupPerFace) {
  // Face 0 before the first `s` (group 0), then groups 1, 1, off, 0 and a large one; a `s` that
  // continues on the next line, and a comment after the group.
  const std::string text = std::string(kCubeVertices) + cubeFace(0) + "s 1\n" + cubeFace(1) + cubeFace(2) + "s off\n" +
                           cubeFace(3) + "s 0 # no group\n" + cubeFace(4) + "s \\\n 9000000000\n" + cubeFace(5);
  const sf::PolygonMesh m = readText("groups.obj", text);
  EXPECT_EQ(m.faceSmoothingGroups, (std::vector<int64_t>{0, 1, 1, 0, 0, 9000000000}));
}

TEST(ObjSmoothingGroups, AnSAfterTheLastFaceStillGivesEveryFaceAGroup) {
  const sf::PolygonMesh m = readText("late_s.obj", kCubeVertices + cubeFaces() + "s 4\n");
  EXPECT_EQ(m.faceSmoothingGroups, std::vector<int64_t>(6, 0));
  const sf::PolygonMesh first = readText("first_s.obj", std::string("s 2\n") + kCubeVertices + cubeFaces());
  EXPECT_EQ(first.faceSmoothingGroups, std::vector<int64_t>(6, 2));
}

TEST(ObjSmoothingGroups, BadGroupsNameTheLine) {
  const std::string head = std::string(kCubeVertices) + cubeFaces();  // 14 lines
  expectError("s_negative.obj", head + "s -1\n", 15, "bad smoothing group '-1' (expected a number >= 0 or 'off')");
  expectError("s_garbage.obj", head + "s x\n", 15, "bad smoothing group 'x'");
  expectError("s_fraction.obj", head + "s 1.5\n", 15, "bad smoothing group '1.5'");
  expectError("s_on.obj", head + "s on\n", 15, "bad smoothing group 'on'");
  expectError("s_huge.obj", head + "s 99999999999999999999\n", 15, "bad smoothing group");
  expectError("s_missing.obj", head + "s\n", 15, "missing smoothing group");
  expectError("s_missing_comment.obj", head + "s # off\n", 15, "missing smoothing group");
  expectError("s_extra.obj", head + "s 1 2\n", 15, "unexpected '2' after the smoothing group");
  expectError("s_off_extra.obj", head + "s off 1\n", 15, "unexpected '1' after the smoothing group");
  expectError("s_continued.obj", head + "s 1 \\\n x\n", 16, "unexpected 'x' after the smoothing group");
}

// ---------------------------------------------------------------------------------------------
// OBJ tags

TEST(ObjTags, CreaseAndCornerTagsUseZeroBasedIds) {
  // Tags before the vertices they name, between and after; sharpness 0 is kept.
  const std::string text = std::string("t crease 2/1/0 0 1 2.5\n") +  // line 1
                           kCubeVertices +                            // lines 2-9
                           "t corner 1/1/0 7 10\n" +                  // line 10
                           cubeFaces() +                              // lines 11-16
                           "t crease 2/1/0 +7 6 0\n" +                // line 17
                           "t corner 1/1/0 0 0.0\n";                  // line 18
  const sf::PolygonMesh m = readText("tags.obj", text);
  ASSERT_EQ(m.creaseTags.size(), 2u);
  expectCrease(m.creaseTags[0], 0, 1, 2.5, 1);
  expectCrease(m.creaseTags[1], 7, 6, 0, 17);
  ASSERT_EQ(m.cornerTags.size(), 2u);
  expectCorner(m.cornerTags[0], 7, 10, 10);
  expectCorner(m.cornerTags[1], 0, 0, 18);
  EXPECT_TRUE(m.faceSmoothingGroups.empty());
}

// OpenSubdiv (regression/common/far_utils.h, assignComponentTags) reads the ids of a crease
// tag as pairs, one edge per pair: 4 ids are the edges a-b and c-d, not a chain a-b-c-d.
TEST(ObjTags, ACreaseTagWithMoreIdsIsOneEdgePerPair) {
  const std::string text = std::string(kCubeVertices) + cubeFaces() +
                           "t crease 4/1/0 0 1 1 3 3\n"          // line 15: 0-1, 1-3
                           "t crease 6/1/0 4 5 7 6 2 0 1.25\n";  // line 16: 4-5, 7-6, 2-0
  const sf::PolygonMesh m = readText("pairs.obj", text);
  ASSERT_EQ(m.creaseTags.size(), 5u);
  expectCrease(m.creaseTags[0], 0, 1, 3, 15);
  expectCrease(m.creaseTags[1], 1, 3, 3, 15);
  expectCrease(m.creaseTags[2], 4, 5, 1.25, 16);
  expectCrease(m.creaseTags[3], 7, 6, 1.25, 16);
  expectCrease(m.creaseTags[4], 2, 0, 1.25, 16);
  // 0 1 2 3 is the edges 0-1 and 2-3; a chain would have given 1-2 as well.
  const sf::PolygonMesh q =
      readText("pairs_not_chain.obj", std::string(kCubeVertices) + cubeFaces() + "t crease 4/1/0 0 1 2 3 10\n");
  ASSERT_EQ(q.creaseTags.size(), 2u);
  expectCrease(q.creaseTags[0], 0, 1, 10, 15);
  expectCrease(q.creaseTags[1], 2, 3, 10, 15);
}

// OpenSubdiv gives every vertex of a corner tag the one sharpness, or vertex j value j.
TEST(ObjTags, CornerTagsWithSeveralVertices) {
  const std::string text = std::string(kCubeVertices) + cubeFaces() +
                           "t corner 3/1/0 0 1 2 4\n"         // line 15: one sharpness for all
                           "t corner 3/3/0 5 6 7 1 2.5 0\n";  // line 16: one per vertex
  const sf::PolygonMesh m = readText("corners.obj", text);
  ASSERT_EQ(m.cornerTags.size(), 6u);
  expectCorner(m.cornerTags[0], 0, 4, 15);
  expectCorner(m.cornerTags[1], 1, 4, 15);
  expectCorner(m.cornerTags[2], 2, 4, 15);
  expectCorner(m.cornerTags[3], 5, 1, 16);
  expectCorner(m.cornerTags[4], 6, 2.5, 16);
  expectCorner(m.cornerTags[5], 7, 0, 16);
  EXPECT_TRUE(m.creaseTags.empty());
}

TEST(ObjTags, ATagMayContinueOnTheNextLines) {
  const std::string text = std::string(kCubeVertices) + cubeFaces() +
                           "t crease \\\n 4/1/0 0 1 \\\n 2 3 \\\n 5\n"  // lines 15-18
                           "t corner 1/1/0 6 1 # a comment\n";          // line 19
  const sf::PolygonMesh m = readText("continued_tag.obj", text);
  ASSERT_EQ(m.creaseTags.size(), 2u);
  expectCrease(m.creaseTags[0], 0, 1, 5, 15);  // the line the statement starts on
  expectCrease(m.creaseTags[1], 2, 3, 5, 15);
  ASSERT_EQ(m.cornerTags.size(), 1u);
  expectCorner(m.cornerTags[0], 6, 1, 19);
}

TEST(ObjTags, OtherTagsAreCheckedAndIgnored) {
  const std::string text = std::string(kCubeVertices) + cubeFaces() +
                           "t hole 1/0/0 3\n"
                           "t hole 2/0/0 0 1\n"
                           "t interpolateboundary 1/0/0 2\n"
                           "t facevaryinginterpolateboundary 1/0/0 1\n"
                           "t facevaryingpropagatecorners 1/0/0 0\n"
                           "t creasemethod 0/0/1 chaikin\n"
                           "t smoothtriangles 0/0/1 smooth\n"
                           "t some_other_tag 2/2/2 -1 99 0.5 -1e3 a b\n"
                           "t empty 0/0/0\n"
                           "t Crease 2/1/0 0 1 1\n";  // names are case-sensitive, as in OpenSubdiv
  const sf::PolygonMesh m = readText("ignored_tags.obj", text);
  EXPECT_EQ(m.numFaces(), 6);
  EXPECT_TRUE(m.creaseTags.empty());
  EXPECT_TRUE(m.cornerTags.empty());
}

TEST(ObjTags, CubeWithEveryEdgeTaggedGivesTwelveTags) {
  const auto edges = cubeEdges();
  ASSERT_EQ(edges.size(), 12u);
  std::string text = std::string(kCubeVertices) + "s 1\n" + cubeFaces();  // lines 1-15
  for (size_t i = 0; i < edges.size(); ++i) {
    text += "t crease 2/1/0 " + std::to_string(edges[i].first) + " " + std::to_string(edges[i].second) + " " +
            std::to_string(i % 3 == 0 ? 10 : i) + "\n";
  }
  const sf::PolygonMesh m = readText("cube_creases.obj", text);
  EXPECT_EQ(m.numVertices(), 8);
  EXPECT_EQ(m.faceSmoothingGroups, std::vector<int64_t>(6, 1));
  ASSERT_EQ(m.creaseTags.size(), 12u);
  std::set<std::pair<int, int>> distinct;
  for (size_t i = 0; i < edges.size(); ++i) {
    SCOPED_TRACE("tag " + std::to_string(i));
    expectCrease(m.creaseTags[i], edges[i].first, edges[i].second, i % 3 == 0 ? 10.0 : static_cast<double>(i), 16 + i);
    // Each tag is an edge of a face (0-based ids: the face's 1-based ones less 1).
    bool onFace = false;
    for (int f = 0; f < m.numFaces(); ++f) {
      for (int k = 0; k < m.faceSize(f); ++k) {
        const int a = m.faceVertex(f, k), b = m.faceVertex(f, k + 1);
        onFace |= (a == m.creaseTags[i].v0 && b == m.creaseTags[i].v1) ||
                  (b == m.creaseTags[i].v0 && a == m.creaseTags[i].v1);
      }
    }
    EXPECT_TRUE(onFace);
    distinct.insert(
        {std::min(m.creaseTags[i].v0, m.creaseTags[i].v1), std::max(m.creaseTags[i].v0, m.creaseTags[i].v1)});
  }
  EXPECT_EQ(distinct.size(), 12u);
}

TEST(ObjTags, MalformedTagsNameTheLine) {
  const std::string head = std::string(kCubeVertices) + cubeFaces();  // 14 lines; tags go on line 15
  const struct {
    const char* name;
    const char* tag;
    const char* what;
  } cases[] = {
      // The tag statement itself.
      {"t_no_name", "t\n", "missing tag name"},
      {"t_no_counts", "t crease\n", "missing tag argument counts"},
      {"t_two_counts", "t crease 2/1 0 1 1\n", "bad argument counts '2/1' for tag 'crease'"},
      {"t_four_counts", "t crease 2/1/0/0 0 1 1\n", "bad argument counts '2/1/0/0'"},
      {"t_empty_count", "t crease 2//0 0 1 1\n", "bad argument counts '2//0'"},
      {"t_word_count", "t crease a/1/0 0 1 1\n", "bad argument counts 'a/1/0'"},
      {"t_negative_count", "t corner 1/-1/0 0\n", "bad argument counts '1/-1/0'"},
      {"t_huge_count", "t hole 3000000000/0/0 0\n", "bad argument counts '3000000000/0/0'"},
      // Counts that disagree with the arguments, for kept and ignored tags alike.
      {"t_missing_int", "t crease 2/1/0 0\n", "declares 2/1/0 arguments but has only 1 of its 2 integer arguments"},
      {"t_missing_float", "t crease 2/1/0 0 1\n", "declares 2/1/0 arguments but has only 0 of its 1 float argument"},
      {"t_extra_arg", "t crease 2/1/0 0 1 1 7\n", "unexpected '7' after the 2/1/0 arguments of tag 'crease'"},
      {"t_corner_extra", "t corner 1/1/0 0 1 2\n", "unexpected '2' after the 1/1/0 arguments of tag 'corner'"},
      {"t_hole_missing", "t hole 1/0/0\n", "tag 'hole' declares 1/0/0 arguments but has only 0 of its 1 integer"},
      {"t_hole_extra", "t hole 1/0/0 3 4\n", "unexpected '4' after the 1/0/0 arguments of tag 'hole'"},
      {"t_boundary_extra", "t interpolateboundary 0/0/0 1\n", "unexpected '1' after the 0/0/0 arguments"},
      {"t_method_missing", "t creasemethod 0/0/1\n", "has only 0 of its 1 string argument"},
      {"t_unknown_short", "t mytag 1/1/1 0 0.5\n",
       "tag 'mytag' declares 1/1/1 arguments but has only 0 of its 1 string"},
      {"t_boundary_word", "t interpolateboundary 1/0/0 edge\n", "bad integer 'edge' for tag integer argument"},
      {"t_unknown_float", "t mytag 0/1/0 abc\n", "bad number 'abc' for tag float argument"},
      // Crease and corner tags: ids.
      {"t_crease_word_id", "t crease 2/1/0 0 x 1\n", "bad integer 'x' for crease vertex id"},
      {"t_crease_float_id", "t crease 2/1/0 0 1.0 1\n", "bad integer '1.0' for crease vertex id"},
      {"t_crease_negative_id", "t crease 2/1/0 -1 0 1\n",
       "crease vertex id -1 out of range (tag vertex ids are 0-based)"},
      {"t_corner_negative_id", "t corner 1/1/0 -8 1\n", "corner vertex id -8 out of range"},
      {"t_crease_huge_id", "t crease 2/1/0 0 2147483648 1\n", "crease vertex id 2147483648 out of range"},
      {"t_crease_same", "t crease 2/1/0 3 3 1\n", "crease tag edge 3-3 joins a vertex to itself"},
      {"t_crease_same_second", "t crease 4/1/0 0 1 2 2 1\n", "crease tag edge 2-2 joins a vertex to itself"},
      // Crease and corner tags: counts.
      {"t_crease_odd", "t crease 3/1/0 0 1 2 1\n", "crease tag with 3 vertex ids (counts 3/1/0): it takes pairs"},
      {"t_crease_no_ids", "t crease 0/1/0 1\n", "crease tag with 0 vertex ids"},
      {"t_crease_no_sharpness", "t crease 2/0/0 0 1\n", "tag 'crease' without a sharpness (counts 2/0/0)"},
      {"t_crease_two_sharpness", "t crease 4/2/0 0 1 2 3 1 2\n", "crease tag with 2 sharpness values (counts 4/2/0)"},
      {"t_crease_string", "t crease 2/1/1 0 1 1 x\n", "tag 'crease' takes no string arguments"},
      {"t_corner_no_ids", "t corner 0/1/0 1\n", "corner tag without vertex ids"},
      {"t_corner_no_sharpness", "t corner 1/0/0 1\n", "tag 'corner' without a sharpness"},
      {"t_corner_some_sharpness", "t corner 3/2/0 0 1 2 1 1\n", "corner tag with 3 vertex ids and 2 sharpness values"},
      // Sharpness values.
      {"t_crease_negative", "t crease 2/1/0 0 1 -1\n", "negative crease sharpness '-1'"},
      {"t_crease_negative_small", "t crease 2/1/0 0 1 -1e-300\n", "negative crease sharpness"},
      {"t_crease_inf", "t crease 2/1/0 0 1 inf\n", "non-finite value 'inf' for crease sharpness"},
      {"t_crease_nan", "t crease 2/1/0 0 1 nan\n", "non-finite value 'nan' for crease sharpness"},
      {"t_crease_word", "t crease 2/1/0 0 1 sharp\n", "bad number 'sharp' for crease sharpness"},
      {"t_corner_negative", "t corner 2/2/0 0 1 1 -0.5\n", "negative corner sharpness '-0.5'"},
      {"t_corner_inf", "t corner 1/1/0 0 -inf\n", "non-finite value '-inf' for corner sharpness"},
  };
  for (const auto& c : cases) expectError(std::string(c.name) + ".obj", head + c.tag, 15, c.what);
  // A continued tag: the error names the line of the value.
  expectError("t_continued_bad.obj", head + "t crease 2/1/0 \\\n 0 1 \\\n -2\n", 17, "negative crease sharpness '-2'");
  expectError("t_continued_missing.obj", head + "t corner 2/1/0 \\\n 0\n", 16, "has only 1 of its 2 integer");
}

TEST(ObjTags, VertexIdsAreCheckedAgainstTheFinalVertexCount) {
  // Tags before the vertices are fine as long as the file has them in the end.
  const std::string ok = "t crease 2/1/0 6 7 1\nt corner 1/1/0 7 1\n" + std::string(kCubeVertices) + cubeFaces();
  EXPECT_EQ(readText("forward_tags.obj", ok).creaseTags.size(), 1u);
  // The cube has 8 vertices: id 8 is out of range (1-based thinking); named at its tag's line.
  expectError("crease_id_8.obj", "t crease 2/1/0 7 8 1\n" + std::string(kCubeVertices) + cubeFaces(), 1,
              "tag vertex id 8 out of range (file has 8 vertices; tag vertex ids are 0-based)");
  expectError("corner_id_8.obj", std::string(kCubeVertices) + cubeFaces() + "t corner 1/1/0 8 1\n", 15,
              "tag vertex id 8 out of range (file has 8 vertices");
  // The largest id is named, on the line it is on (here a continuation line).
  expectError("largest_id.obj",
              std::string(kCubeVertices) + cubeFaces() + "t crease 2/1/0 0 9 1\nt corner 2/1/0 8 \\\n 12 1\n", 17,
              "tag vertex id 12 out of range");
  // Ids of ignored tags (hole: face ids) are not vertex ids.
  EXPECT_TRUE(
      readText("hole_id.obj", std::string(kCubeVertices) + cubeFaces() + "t hole 1/0/0 100\n").creaseTags.empty());
}

// ---------------------------------------------------------------------------------------------
// PLY edge elements

namespace {

const double kTet[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};

/// Appends v's bytes to s, big- or little-endian.
template <class T>
void put(std::string& s, T v, bool big) {
  char b[sizeof v];
  std::memcpy(b, &v, sizeof v);
  if (big) std::reverse(b, b + sizeof v);
  s.append(b, sizeof v);
}

/// A tetrahedron as PLY (format 0 ascii, 1 binary little-endian, 2 big-endian) with an `edge`
/// element of `edgeCount` rows between `vertex` and `face` (or first, with `edgeFirst`), whose
/// properties are `edgeProps` ("property ..." lines) and whose rows are `edgeBody` (text or
/// bytes). `edgeLine` receives the header line of the edge element.
std::string tetPly(int format, int edgeCount, const std::string& edgeProps, const std::string& edgeBody,
                   size_t* edgeLine = nullptr, bool edgeFirst = false) {
  static const char* formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  const bool big = format == 2;
  const std::string edgeHeader = "element edge " + std::to_string(edgeCount) + "\n" + edgeProps;
  const std::string vertexHeader = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string faceHeader = "element face 4\nproperty list uchar int vertex_indices\n";
  std::string head = std::string("ply\nformat ") + formats[format] + " 1.0\ncomment crease edges\n";
  if (edgeLine) *edgeLine = std::count(head.begin(), head.end(), '\n') + 1 + (edgeFirst ? 0 : 4);
  head += edgeFirst ? edgeHeader + vertexHeader : vertexHeader + edgeHeader;
  head += faceHeader + "end_header\n";
  std::string vertices, faces;
  for (const auto& p : kTet) {
    if (format == 0) {
      vertices += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    } else {
      for (double c : p) put(vertices, static_cast<float>(c), big);
    }
  }
  for (const auto& f : kTetFaces) {
    if (format == 0) {
      faces += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    } else {
      put(faces, uint8_t{3}, big);
      for (int v : f) put(faces, int32_t{v}, big);
    }
  }
  return head + (edgeFirst ? edgeBody + vertices : vertices + edgeBody) + faces;
}

/// The edge rows (vertex1 int, vertex2 int, red uchar, crease float) of three tetrahedron edges, in binary.
std::string tetEdgeBytes(bool big, float lastCrease = 0.f) {
  std::string s;
  const int32_t ends[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  const float crease[3] = {10.f, 2.5f, lastCrease};
  for (int i = 0; i < 3; ++i) {
    put(s, ends[i][0], big), put(s, ends[i][1], big), put(s, uint8_t{255}, big), put(s, crease[i], big);
  }
  return s;
}

const char* const kEdgeProps =
    "property int vertex1\nproperty int32 vertex2\nproperty uchar red\nproperty float crease\n";

void expectTetCreases(const sf::PolygonMesh& m, size_t line, double lastCrease = 0) {
  EXPECT_EQ(m.numVertices(), 4);
  EXPECT_EQ(m.numFaces(), 4);
  ASSERT_EQ(m.creaseTags.size(), 3u);
  expectCrease(m.creaseTags[0], 0, 1, 10, line);
  expectCrease(m.creaseTags[1], 1, 2, 2.5, line);
  expectCrease(m.creaseTags[2], 2, 0, lastCrease, line);
  EXPECT_TRUE(m.cornerTags.empty());
  EXPECT_TRUE(m.faceSmoothingGroups.empty());
}

}  // namespace

TEST(PlyCreases, AsciiEdgeElement) {
  size_t line = 0;
  const std::string text = tetPly(0, 3, kEdgeProps, "0 1 255 10\n1 2 255 2.5\n2 0 255 0\n", &line);
  ASSERT_EQ(line, 8u);
  expectTetCreases(readText("edges.ply", text), line);
  // `sharpness` of another type, the edge element first, other property order.
  const std::string first = tetPly(
      0, 3,
      "property uchar sharpness\nproperty uint vertex2\nproperty list uchar float extra\nproperty ushort vertex1\n",
      "10 1 0 0\n3 2 2 0.5 0.5 1\n0 0 0 2\n", &line, true);
  ASSERT_EQ(line, 4u);
  const sf::PolygonMesh m = readText("edges_first.ply", first);
  ASSERT_EQ(m.creaseTags.size(), 3u);
  expectCrease(m.creaseTags[0], 0, 1, 10, 4);
  expectCrease(m.creaseTags[1], 1, 2, 3, 4);
  expectCrease(m.creaseTags[2], 2, 0, 0, 4);
}

TEST(PlyCreases, BinaryLittleAndBigEndianEdgeElement) {
  size_t line = 0;
  const std::string le = tetPly(1, 3, kEdgeProps, tetEdgeBytes(false, 0.75f), &line);
  ASSERT_EQ(line, 8u);
  expectTetCreases(readText("edges_le.ply", le), line, 0.75);
  const std::string be = tetPly(2, 3, kEdgeProps, tetEdgeBytes(true, 0.75f));
  expectTetCreases(readText("edges_be.ply", be), line, 0.75);
  // Doubles, and ids of a small unsigned type.
  std::string bytes;
  put(bytes, uint8_t{3}, false), put(bytes, uint8_t{1}, false), put(bytes, 7.25, false);
  const sf::PolygonMesh m =
      readText("edges_double.ply",
               tetPly(1, 1, "property uint8 vertex1\nproperty uchar vertex2\nproperty double crease\n", bytes));
  ASSERT_EQ(m.creaseTags.size(), 1u);
  expectCrease(m.creaseTags[0], 3, 1, 7.25, line);
}

TEST(PlyCreases, EdgeElementsWithoutACreaseValueAreReadPast) {
  const sf::PolygonMesh a =
      readText("plain_edges.ply",
               tetPly(0, 2, "property int vertex1\nproperty int vertex2\nproperty uchar red\n", "0 1 255\n1 2 0\n"));
  EXPECT_EQ(a.numFaces(), 4);
  EXPECT_TRUE(a.creaseTags.empty());
  // Without a crease value, vertex1 and vertex2 are not checked.
  std::string bytes;
  put(bytes, 7.5f, false), put(bytes, -3.f, false);
  const sf::PolygonMesh b =
      readText("plain_edges_le.ply", tetPly(1, 1, "property float vertex1\nproperty float vertex2\n", bytes));
  EXPECT_TRUE(b.creaseTags.empty());
  // The same properties in an element of another name are no crease edges.
  std::string other = tetPly(0, 1, kEdgeProps, "0 0 0 -1\n");
  other.replace(other.find("element edge "), 13, "element edges ");
  const sf::PolygonMesh c = readText("crease_elsewhere.ply", other);
  EXPECT_EQ(c.numFaces(), 4);
  EXPECT_TRUE(c.creaseTags.empty());
}

TEST(PlyCreases, BadEdgeElementsNameTheFileAndLine) {
  size_t line = 0;
  // Header: roles that cannot be read as crease edges (named at the element's header line).
  std::string text =
      tetPly(0, 1, "property float vertex1\nproperty int vertex2\nproperty float crease\n", "0 1 1\n", &line);
  expectError("float_id.ply", text, line, "edge property 'vertex1' is not an integer scalar");
  text = tetPly(0, 1, "property int vertex1\nproperty list uchar int vertex2\nproperty float crease\n", "0 1 1 1\n",
                &line);
  expectError("list_id.ply", text, line, "edge property 'vertex2' is not an integer scalar");
  text = tetPly(0, 1, "property int vertex1\nproperty float crease\n", "0 1\n", &line);
  expectError("no_vertex2.ply", text, line, "edge element has a 'crease' property but lacks 'vertex1' or 'vertex2'");
  text = tetPly(0, 1, "property int vertex1\nproperty int vertex2\nproperty float crease\nproperty float sharpness\n",
                "0 1 1 1\n", &line);
  expectError("both.ply", text, line, "edge element has both a 'crease' and a 'sharpness' property");
  text = tetPly(0, 1, "property int vertex1\nproperty int vertex2\nproperty list uchar float sharpness\n", "0 1 1 1\n",
                &line);
  expectError("list_sharpness.ply", text, line, "edge property 'sharpness' is a list");

  // Rows, in ASCII: named by the line of the row. The header has 15 lines (ply, format,
  // comment, 4 of vertex, 5 of edge, 2 of face, end_header); the edge rows follow 4 vertex rows.
  const auto rowError = [&](const std::string& name, const std::string& rows, int row, const std::string& what) {
    expectError(name, tetPly(0, 3, kEdgeProps, rows), 15 + 4 + row + 1, what);
  };
  rowError("id_range.ply", "0 1 0 1\n1 4 0 1\n2 0 0 1\n", 1, "edge 1: vertex2 4 out of range (file has 4 vertices)");
  rowError("id_negative.ply", "0 1 0 1\n1 2 0 1\n-1 0 0 1\n", 2, "edge 2: vertex1 -1 out of range");
  rowError("id_same.ply", "0 1 0 1\n2 2 0 1\n2 0 0 1\n", 1, "edge 1 joins vertex 2 to itself");
  rowError("negative.ply", "0 1 0 -0.5\n1 2 0 1\n2 0 0 1\n", 0, "negative crease -0.5 in edge 0");
  rowError("nan.ply", "0 1 0 1\n1 2 0 nan\n2 0 0 1\n", 1, "non-finite crease in edge 1");
  rowError("inf.ply", "0 1 0 1\n1 2 0 1\n2 0 0 inf\n", 2, "non-finite crease in edge 2");
  rowError("bad.ply", "0 1 0 1\n1 2 0 x\n2 0 0 1\n", 1, "bad number 'x' for crease");
  rowError("short.ply", "0 1 0 1\n1 2 0\n2 0 0 1\n", 1, "missing crease in edge 1");

  // Binary: the byte of the value.
  for (const bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    // Where the first edge row starts: after the header and 4 vertex rows, before 4 faces of
    // 13 bytes each.
    const size_t edges = tetPly(big ? 2 : 1, 3, kEdgeProps, "").size() - 4 * 13;
    const auto binError = [&](const std::string& name, const std::string& edgeBytes, size_t byte,
                              const std::string& what) {
      const std::string path = writeTemp(name, tetPly(big ? 2 : 1, 3, kEdgeProps, edgeBytes));
      const std::string msg = errorOf(path);
      EXPECT_EQ(msg.rfind(path + ": byte " + std::to_string(byte) + ": " + what, 0), 0u) << msg;
    };
    std::string bad = tetEdgeBytes(big);
    bad[13 + (big ? 7 : 4)] = 9;  // edge 1, vertex2 = 9
    binError("bin_range.ply", bad, edges + 13 + 4, "edge 1: vertex2 9 out of range (file has 4 vertices)");
    bad = tetEdgeBytes(big);
    bad[26 + (big ? 7 : 4)] = 2;  // edge 2: 2-2
    binError("bin_same.ply", bad, edges + 26 + 9, "edge 2 joins vertex 2 to itself");
    binError("bin_negative.ply", tetEdgeBytes(big, -1.f), edges + 26 + 9, "negative crease -1 in edge 2");
    binError("bin_nan.ply", tetEdgeBytes(big, std::numeric_limits<float>::quiet_NaN()), edges + 26 + 9,
             "non-finite crease in edge 2");
    binError("bin_inf.ply", tetEdgeBytes(big, std::numeric_limits<float>::infinity()), edges + 26 + 9,
             "non-finite crease in edge 2");
    bad = tetEdgeBytes(big);
    std::string negId;
    put(negId, int32_t{-1}, big);
    bad.replace(0, 4, negId);
    binError("bin_negative_id.ply", bad, edges, "edge 0: vertex1 -1 out of range");
  }
}
