// SPDX-License-Identifier: Apache-2.0
// Mesh readers: expected-failure table over tests/data/malformed, and unit tests of what
// the OBJ, OFF and PLY (ASCII, binary LE/BE) readers accept: line ends (LF, CRLF, CR),
// encodings, OBJ line continuation and OFF headers whose counts disagree with the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <smoothforce/mesh/mesh_io.h>
#include "file_bytes.h"
#include "mesh_file_support.h"

namespace fs = std::filesystem;

namespace {

const std::string kMalformed = std::string(SF_TEST_DATA) + "/malformed/";

using sf::test::errorOf;
using sf::test::writeTemp;

struct Malformed {
  const char* file;
  int line;  ///< expected line in `path:line: ...`
  const char* reason;
};

const Malformed kCases[] = {
    {"obj_bad_float.obj", 3, "bad number 'abc'"},
    {"obj_nan.obj", 2, "non-finite"},
    {"obj_inf.obj", 3, "non-finite"},
    {"obj_overflow_float.obj", 2, "bad number '1e999'"},
    {"obj_missing_coordinate.obj", 3, "missing z"},
    {"obj_too_many_vertex_values.obj", 1, "too many values"},
    {"obj_index_out_of_range.obj", 6, "vertex index 5 out of range"},
    {"obj_forward_index_out_of_range.obj", 3, "vertex index 4 out of range"},
    {"obj_zero_index.obj", 4, "start at 1"},
    {"obj_relative_out_of_range.obj", 5, "relative vertex index -4"},
    {"obj_huge_index.obj", 4, "bad integer"},
    {"obj_two_corner_face.obj", 6, "face with 2 corners"},
    {"obj_one_corner_face.obj", 4, "face with 1 corner"},
    {"obj_garbage_in_face.obj", 4, "bad integer 'x'"},
    {"obj_bad_corner_syntax.obj", 5, "bad face corner"},
    {"obj_empty_texture_index.obj", 4, "empty texture index"},
    {"obj_mixed_normals.obj", 7, "the face on line 6 has them"},
    {"obj_mixed_normals_in_face.obj", 5, "some corners"},
    {"obj_normal_index_out_of_range.obj", 5, "normal index 2 out of range"},
    {"obj_bad_normal.obj", 4, "unexpected 'x'"},
    {"obj_crlf_bad_float.obj", 3, "bad number '0x'"},
    {"obj_no_faces.obj", 4, "no faces"},
    {"obj_empty.obj", 1, "empty"},
    {"off_bad_header.off", 1, "not an OFF file"},
    {"off_binary.off", 1, "binary OFF"},
    {"off_missing_counts.off", 2, "missing vertex and face counts"},
    {"off_bad_counts.off", 2, "bad integer 'one'"},
    {"off_negative_count.off", 2, "vertex count -3 out of range"},
    {"off_huge_count.off", 2, "more than the remaining"},
    {"off_truncated.off", 7, "file ends after 1 of 2 faces"},
    {"off_truncated_vertices.off", 5, "file ends after 3 of 5 vertices"},
    {"off_bad_vertex.off", 4, "bad number 'zz'"},
    {"off_nan.off", 5, "non-finite"},
    {"off_index_out_of_range.off", 6, "vertex index 3 out of range"},
    {"off_negative_index.off", 6, "vertex index -1 out of range"},
    {"off_two_corner_face.off", 7, "face with 2 corners"},
    {"off_missing_index.off", 7, "only 3 vertex indices"},
    {"off_garbage_after_face.off", 6, "bad number 'red'"},
    {"off_extra_data.off", 7, "unexpected data after the last face"},
    {"off_noff_missing_normal.off", 5, "missing normal x"},
    {"off_empty.off", 1, "empty"},
    {"ply_bad_magic.ply", 1, "not a PLY file"},
    {"ply_bad_header.ply", 9, "unknown header line 'bogus'"},
    {"ply_bad_version.ply", 2, "unsupported PLY version"},
    {"ply_no_end_header.ply", 4, "no end_header"},
    {"ply_unknown_type.ply", 4, "unknown property type 'float128'"},
    {"ply_huge_count.ply", 3, "more than the rest of the file"},
    {"ply_missing_z.ply", 3, "lacks x, y or z"},
    {"ply_no_face_list.ply", 7, "lacks a 'vertex_indices'"},
    {"ply_bad_float.ply", 11, "bad number '0.5.5'"},
    {"ply_nan.ply", 12, "non-finite y"},
    {"ply_index_out_of_range.ply", 14, "vertex index 3 out of range"},
    {"ply_two_corner_face.ply", 14, "2 corners"},
    {"ply_uchar_out_of_range.ply", 13, "'300' out of range"},
    {"ply_extra_value.ply", 11, "unexpected '7'"},
    {"ply_truncated_ascii.ply", 13, "file ends before face 1"},
    {"ply_extra_data.ply", 14, "unexpected data after the last element"},
};

}  // namespace

TEST(MeshReaderMalformed, EachFileThrowsWithFileAndLine) {
  for (const Malformed& c : kCases) {
    const std::string path = kMalformed + c.file;
    ASSERT_TRUE(fs::exists(path)) << path;
    const std::string msg = errorOf(path);
    const std::string prefix = path + ":" + std::to_string(c.line) + ": ";
    EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix " << prefix << "\n got: " << msg;
    EXPECT_NE(msg.find(c.reason), std::string::npos) << "expected '" << c.reason << "' in: " << msg;
  }
}

TEST(MeshReaderMalformed, TableCoversEveryFileInTheFolder) {
  std::set<std::string> listed;
  for (const Malformed& c : kCases) listed.insert(c.file);
  EXPECT_EQ(listed.size(), std::size(kCases)) << "duplicate table entry";
  EXPECT_GE(listed.size(), 20u);
  for (const auto& e : fs::directory_iterator(kMalformed))
    EXPECT_TRUE(listed.count(e.path().filename().string())) << e.path() << " has no table entry";
}

TEST(MeshReaderDispatch, ExtensionAndFileErrors) {
  EXPECT_NE(errorOf("/nonexistent/mesh.stl").find("/nonexistent/mesh.stl: unknown mesh file extension '.stl'"),
            std::string::npos);
  EXPECT_NE(errorOf("/nonexistent/mesh").find("unknown mesh file extension"), std::string::npos);
  EXPECT_NE(errorOf("/nonexistent/mesh.obj").find("/nonexistent/mesh.obj: cannot open"), std::string::npos);
  const std::string upper = writeTemp("TRI.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const sf::PolygonMesh m = sf::readMesh(upper);
  EXPECT_EQ(m.numFaces(), 1);
  EXPECT_EQ(m.sourcePath, upper);
  const std::string dir = writeTemp("x", "");
  fs::create_directories(dir + ".dir.obj");
  EXPECT_NE(errorOf(dir + ".dir.obj").find("is a directory"), std::string::npos);
}

TEST(ObjReader, AcceptsCommonSyntax) {
  const std::string body =
      "# comment\nmtllib missing.mtl\no thing\n"
      "v 0 0 0 1.0\nv 1 0 0 0.5 0.5 0.5\nv\t+1 1 0\t \nv 0 1 0   \n"
      "vt 0 0\nvt 1 0\nvn 0 0 1\ng grp\nusemtl m\ns 1\n\n"
      "f 1/1 2/2 3/1   # a comment after a face\n"
      "f -4 -2 -1\nl 1 2\np 1\ncurv2 1 2\nvp 0.5\n";
  for (const bool crlf : {false, true}) {
    std::string text = body;
    if (crlf) {
      text.clear();
      for (char c : body) text += c == '\n' ? std::string("\r\n") : std::string(1, c);
    }
    const sf::PolygonMesh m = sf::readMesh(writeTemp(crlf ? "crlf.obj" : "lf.obj", text));
    ASSERT_EQ(m.numVertices(), 4);
    EXPECT_EQ(m.positions[2], Eigen::Vector3d(1, 1, 0));
    EXPECT_EQ(m.faceOffsets, (std::vector<int32_t>{0, 3, 6}));
    EXPECT_EQ(m.faceVertices, (std::vector<int32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_TRUE(m.fileNormals.empty());  // one vn for four vertices, unreferenced
    EXPECT_TRUE(m.fileCornerNormals.empty());
  }
}

TEST(ObjReader, NormalsPerCornerAndPerVertex) {
  const sf::PolygonMesh c = sf::readMesh(writeTemp("corner.obj",
                                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\nvn 0 0 2\n"
                                                   "f 1//1 2//2 3//1\nf 2/1/2 4/1/1 3/1/-1\n"));
  ASSERT_EQ(c.fileCornerNormals.size(), 6u);
  EXPECT_EQ(c.fileCornerNormals[1], Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(c.fileCornerNormals[3], Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(c.fileCornerNormals[5], Eigen::Vector3d(0, 0, 2));
  EXPECT_TRUE(c.fileNormals.empty());
  const sf::PolygonMesh v =
      sf::readMesh(writeTemp("vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 1 1\nf 1 2 3\n"));
  ASSERT_EQ(v.fileNormals.size(), 3u);
  EXPECT_EQ(v.fileNormals[2], Eigen::Vector3d(0, 1, 1));
  EXPECT_TRUE(v.fileCornerNormals.empty());
}

TEST(ObjReader, ForwardReferencesAndLargeNgons) {
  std::string text = "f 1 2 3 4 5 6 7 8 9 10 11 12\n";
  for (int i = 0; i < 12; ++i) text += "v " + std::to_string(i) + " " + std::to_string(i * i) + " 0\n";
  const sf::PolygonMesh m = sf::readMesh(writeTemp("ngon.obj", text));
  EXPECT_EQ(m.numFaces(), 1);
  EXPECT_EQ(m.faceSize(0), 12);
  EXPECT_EQ(m.positions[11], Eigen::Vector3d(11, 121, 0));
}

TEST(OffReader, HeaderVariantsCommentsAndColours) {
  const sf::PolygonMesh a =
      sf::readMesh(writeTemp("inline.off",
                             "# leading comment\nOFF 4 2 99\n\t0 0 0\n1 0 0 # x axis\n\n1 1 0  \n0 1 0\n"
                             "3 0 1 2 255 0 0\n3\t0 2 3 0.1 0.2 0.3 1\n# trailing comment\n"));
  EXPECT_EQ(a.numVertices(), 4);
  EXPECT_EQ(a.faceVertices, (std::vector<int32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_TRUE(a.fileNormals.empty());

  const sf::PolygonMesh n =
      sf::readMesh(writeTemp("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0.5 0.5\n3 0 1 2\n"));
  ASSERT_EQ(n.fileNormals.size(), 3u);
  EXPECT_EQ(n.fileNormals[2], Eigen::Vector3d(0, 0.5, 0.5));

  const sf::PolygonMesh c =
      sf::readMesh(writeTemp("c.off", "COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n"));
  EXPECT_TRUE(c.fileNormals.empty());
  EXPECT_EQ(c.positions[1], Eigen::Vector3d(1, 0, 0));

  const sf::PolygonMesh cn = sf::readMesh(
      writeTemp("cn.off", "CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1\n1 0 0 0 0 1 0 1 0 1\n0 1 0 0 0 1 0 0 1 1\n4 0 1 2 0\n"));
  EXPECT_EQ(cn.fileNormals.size(), 3u);
  EXPECT_EQ(cn.faceSize(0), 4);
}

namespace {

/// A square pyramid written as PLY: an extra element first, mixed scalar types, normals,
/// a list property inside the vertex element, and extra face properties.
std::string pyramidHeader(const char* format) {
  return std::string("ply\nformat ") + format +
         " 1.0\ncomment written by test_mesh_io\nelement material 1\nproperty uchar id\n"
         "property list uchar float values\nelement vertex 5\nproperty double x\nproperty float y\n"
         "property int16 z\nproperty float nx\nproperty float ny\nproperty float nz\n"
         "property uchar red\nproperty list int uchar extra\nelement face 5\nproperty uchar flags\n"
         "property list uint8 uint32 vertex_indices\nproperty float quality\nend_header\n";
}
const double kPyramid[5][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 2}};
const std::vector<std::vector<uint32_t>> kPyramidFaces = {{3, 2, 1, 0}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};

/// Binary body of the pyramid; `offsets` (if given) receives where each face's indices start.
std::string pyramidBinary(bool big, std::vector<size_t>* offsets = nullptr) {
  std::string s;
  const auto put = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (big) std::reverse(b, b + sizeof v);
    s.append(b, sizeof v);
  };
  put(uint8_t{7}), put(uint8_t{2}), put(0.5f), put(0.25f);
  for (const auto& p : kPyramid) {
    put(p[0]), put(static_cast<float>(p[1])), put(static_cast<int16_t>(p[2]));
    put(0.f), put(0.f), put(1.f), put(uint8_t{200}), put(int32_t{3});
    put(uint8_t{1}), put(uint8_t{2}), put(uint8_t{3});
  }
  for (const auto& f : kPyramidFaces) {
    put(uint8_t{0}), put(static_cast<uint8_t>(f.size()));
    if (offsets) offsets->push_back(s.size());
    for (uint32_t v : f) put(v);
    put(1.5f);
  }
  return s;
}

void expectPyramid(const sf::PolygonMesh& m) {
  ASSERT_EQ(m.numVertices(), 5);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(m.positions[i], Eigen::Vector3d(kPyramid[i][0], kPyramid[i][1], kPyramid[i][2]));
  ASSERT_EQ(m.numFaces(), 5);
  for (int f = 0; f < 5; ++f) {
    ASSERT_EQ(m.faceSize(f), static_cast<int>(kPyramidFaces[f].size()));
    for (int k = 0; k < m.faceSize(f); ++k) EXPECT_EQ(m.faceVertex(f, k), static_cast<int>(kPyramidFaces[f][k]));
  }
  ASSERT_EQ(m.fileNormals.size(), 5u);
  EXPECT_EQ(m.fileNormals[4], Eigen::Vector3d(0, 0, 1));
}

}  // namespace

TEST(PlyReader, AsciiAnyElementOrder) {
  std::string text = pyramidHeader("ascii") + "7 2 0.5 0.25\n";
  for (const auto& p : kPyramid)
    text +=
        std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(int(p[2])) + " 0 0 1 200 3 1 2 3 \r\n";
  for (const auto& f : kPyramidFaces) {
    text += "0 ";
    text += std::to_string(f.size());
    for (uint32_t v : f) (text += ' ') += std::to_string(v);
    text += " 1.5\n";
  }
  expectPyramid(sf::readMesh(writeTemp("pyramid_ascii.ply", text)));

  // Faces before vertices, `vertex_index`, no normals.
  const sf::PolygonMesh m =
      sf::readMesh(writeTemp("faces_first.ply",
                             "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_index\n"
                             "element vertex 3\nproperty float z\nproperty float y\nproperty float x\n"
                             "end_header\n3 2 1 0\n0 0 1\n0 1 0\n1 0 0\n"));
  EXPECT_EQ(m.faceVertices, (std::vector<int32_t>{2, 1, 0}));
  EXPECT_EQ(m.positions[0], Eigen::Vector3d(1, 0, 0));
  EXPECT_TRUE(m.fileNormals.empty());
}

TEST(PlyReader, BinaryLittleAndBigEndian) {
  expectPyramid(sf::readMesh(writeTemp("le.ply", pyramidHeader("binary_little_endian") + pyramidBinary(false))));
  expectPyramid(sf::readMesh(writeTemp("be.ply", pyramidHeader("binary_big_endian") + pyramidBinary(true))));
  // A header with CRLF line ends: the data starts right after "end_header\r\n".
  std::string crlf;
  for (char c : pyramidHeader("binary_little_endian")) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  expectPyramid(sf::readMesh(writeTemp("le_crlf.ply", crlf + pyramidBinary(false))));
}

TEST(PlyReader, BinaryErrorsNameTheByte) {
  const std::string header = pyramidHeader("binary_little_endian");
  std::vector<size_t> at;
  const std::string body = pyramidBinary(false, &at);

  // Every truncation fails cleanly; inside the face data it names the byte.
  for (size_t cut = 0; cut < body.size(); ++cut) {
    const std::string path = writeTemp("ply_truncated_binary.ply", header + body.substr(0, cut));
    const std::string msg = errorOf(path);
    EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << msg;
    if (cut > at[1]) {
      EXPECT_NE(msg.find(": byte "), std::string::npos) << msg;
    }
  }
  std::string bad = body;
  bad[at[2] + 4] = 9;  // face 2, corner 1 -> vertex 9
  std::string path = writeTemp("ply_binary_index.ply", header + bad);
  EXPECT_NE(errorOf(path).find(path + ": byte " + std::to_string(header.size() + at[2] + 4) +
                               ": face 2: vertex index 9 out of range"),
            std::string::npos);
  bad = body;
  bad[at[0] - 1] = static_cast<char>(255);  // face 0 claims 255 corners: more than the rest holds
  path = writeTemp("ply_binary_list_count.ply", header + bad);
  EXPECT_NE(errorOf(path).find(path + ": byte " + std::to_string(header.size() + at[0] - 1) +
                               ": vertex_indices count 255 is more than the rest of the file holds"),
            std::string::npos);
  path = writeTemp("ply_binary_trailing.ply", header + body + "\n");
  EXPECT_NE(errorOf(path).find("1 bytes of unexpected data after the last element"), std::string::npos);
  bad = body;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bad[10 + 8], &nan, 4);  // y of vertex 0, after the 10-byte material row and x
  path = writeTemp("ply_binary_nan.ply", header + bad);
  EXPECT_NE(errorOf(path).find("non-finite y in vertex 0"), std::string::npos);
  const std::string hugeList = std::string(
                                   "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                                   "property float y\nproperty float z\nelement face 1\n"
                                   "property list uint int vertex_indices\nend_header\n") +
                               std::string("\xff\xff\xff\x7f", 4) + std::string(12, '\0');
  path = writeTemp("ply_binary_huge_list.ply", hugeList);
  EXPECT_NE(errorOf(path).find("more than the rest of the file holds"), std::string::npos);
}

namespace {

const std::string kSpot = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";


/// `text` with every "\n" replaced by `eol`.
std::string withLineEnds(const std::string& text, const std::string& eol) {
  std::string s;
  for (char c : text) c == '\n' ? s += eol : s += c;
  return s;
}

void expectSameMesh(const sf::PolygonMesh& a, const sf::PolygonMesh& b) {
  ASSERT_EQ(a.numVertices(), b.numVertices());
  EXPECT_TRUE(a.positions == b.positions);
  EXPECT_EQ(a.faceOffsets, b.faceOffsets);
  EXPECT_EQ(a.faceVertices, b.faceVertices);
}

std::string coordinates(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", p.x(), p.y(), p.z());
  return buf;
}

/// `m` as OFF whose header declares `nv` vertices and `nf` faces: the counts on line 2,
/// vertex i on line 3 + i, face f on line 3 + #V + f.
std::string offText(const sf::PolygonMesh& m, int nv, int nf) {
  std::string s = "OFF\n" + std::to_string(nv) + " " + std::to_string(nf) + " 0\n";
  for (const auto& p : m.positions) s += coordinates(p) + "\n";
  for (int f = 0; f < m.numFaces(); ++f) {
    s += std::to_string(m.faceSize(f));
    for (int k = 0; k < m.faceSize(f); ++k) (s += ' ') += std::to_string(m.faceVertex(f, k));
    s += "\n";
  }
  return s;
}

/// `m` as ASCII PLY.
std::string plyText(const sf::PolygonMesh& m) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.numVertices()) +
                  "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                  std::to_string(m.numFaces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string off = offText(m, 0, 0);
  return s + off.substr(off.find('\n', 4) + 1);  // the OFF body is the same
}

}  // namespace

TEST(OffReader, HeaderCountsThatDisagreeWithTheFileAreRefusedNamingTheLine) {
  const sf::PolygonMesh spot = sf::readMesh(kSpot);
  const int nv = spot.numVertices(), nf = spot.numFaces();
  ASSERT_GT(nv, nf);               // the swapped header below declares fewer vertices
  ASSERT_LE(spot.faceSize(0), 5);  // "4 i j k l": no OFF vertex line has 5 values
  expectSameMesh(sf::readMesh(writeTemp("spot.off", offText(spot, nv, nf))), spot);
  const int firstFace = 3 + nv;  // the line of face 0
  const auto expectError = [](const std::string& path, int line, const std::string& what) {
    const std::string msg = errorOf(path);
    EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line) + ": " + what, 0), 0u) << msg;
  };
  const std::string face0 = "('" + std::to_string(spot.faceSize(0));
  for (int k = 1; k <= 6; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const std::string more = "the header declares " + std::to_string(nv + k) + " vertices, but this line (vertex " +
                             std::to_string(nv + 1) + ") is a face " + face0;
    // More vertices than there are, with the right face count, or as many faces fewer (the
    // counts add up to the lines): the first face line is where a vertex was expected.
    expectError(writeTemp("more_vertices.off", offText(spot, nv + k, nf)), firstFace, more);
    expectError(writeTemp("more_vertices_fewer_faces.off", offText(spot, nv + k, nf - k)), firstFace, more);
    // Fewer vertices: a vertex line is where face 1 was expected.
    for (const int faces : {nf, nf + k}) {
      expectError(writeTemp("fewer_vertices.off", offText(spot, nv - k, faces)), firstFace - k,
                  "the header declares " + std::to_string(nv - k) + " vertices, but this line (face 1 of " +
                      std::to_string(faces) + ") is a vertex ('");
    }
    // More faces than there are: the file ends; fewer: the first line after the last face.
    expectError(writeTemp("more_faces.off", offText(spot, nv, nf + k)), firstFace + nf - 1,
                "file ends after " + std::to_string(nf) + " of " + std::to_string(nf + k) + " faces");
    expectError(writeTemp("fewer_faces.off", offText(spot, nv, nf - k)), firstFace + nf - k,
                "unexpected data after the last face");
  }
  // The counts swapped.
  expectError(writeTemp("swapped.off", offText(spot, nf, nv)), 3 + nf,
              "the header declares " + std::to_string(nf) + " vertices, but this line (face 1 of " +
                  std::to_string(nv) + ") is a vertex");
  // A tetrahedron that declares 5 vertices: its first face is no vertex with a colour.
  const std::string path =
      writeTemp("tet.off", "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
  expectError(path, 7, "the header declares 5 vertices, but this line (vertex 5) is a face ('3 0 2 1')");
}

namespace {

/// `m` as OFF with header keyword `keyword` and counts nv nf: each vertex line x y z then
/// `vertexExtra` values 0.25 (normal, texture or colour), each face line n i0 .. i(n-1) padded
/// with colour values 1 to `faceValues` values. Vertex i on line 3 + i, face f on 3 + #V + f.
std::string offTextPadded(const sf::PolygonMesh& m, int nv, int nf, const std::string& keyword, int vertexExtra,
                          int faceValues) {
  std::string s = keyword + "\n" + std::to_string(nv) + " " + std::to_string(nf) + " 0\n";
  for (const auto& p : m.positions) {
    s += coordinates(p);
    for (int k = 0; k < vertexExtra; ++k) s += " 0.25";
    s += "\n";
  }
  for (int f = 0; f < m.numFaces(); ++f) {
    s += std::to_string(m.faceSize(f));
    for (int k = 0; k < m.faceSize(f); ++k) (s += ' ') += std::to_string(m.faceVertex(f, k));
    for (int k = 1 + m.faceSize(f); k < faceValues; ++k) s += " 1";
    s += "\n";
  }
  return s;
}

/// A pentagonal prism: 10 vertices, 2 pentagons ("5 0 1 2 3 4": x y z and an RGB colour to
/// a vertex line) and 5 quads.
sf::PolygonMesh pentagonalPrism() {
  sf::PolygonMesh m;
  for (int z = 0; z < 2; ++z)
    for (int i = 0; i < 5; ++i)
      m.positions.emplace_back(std::cos(1.2566370614359172 * i), std::sin(1.2566370614359172 * i), z);
  m.addFace({4, 3, 2, 1, 0});
  m.addFace({5, 6, 7, 8, 9});
  for (int i = 0; i < 5; ++i) m.addFace({i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i});
  return m;
}

}  // namespace

// The hole left by the test above: with k vertices more and k faces fewer declared, the first
// k face lines were read as vertices when they have as many values as a vertex line with a
// colour (a pentagon "5 0 1 2 3 4" in OFF, a quad with one colour value, a triangle with RGB;
// quads in STOFF; RGB triangles in COFF with RGBA vertices), and the mesh read was silently
// wrong (k vertices made of face lines, k faces lost). Each file below reads as the mesh with
// the right header, and is refused at the first face line for k = 1..6.
TEST(OffReader, FaceLinesReadAsVerticesWithAColourAreRefusedNamingTheLine) {
  struct Variant {
    const char* keyword;
    int vertexExtra, faceValues;
  };
  const Variant variants[] = {{"OFF", 0, 6}, {"OFF", 0, 7}, {"COFF", 4, 7}, {"NOFF", 3, 6}, {"STOFF", 2, 5}};
  const sf::PolygonMesh spot = sf::readMesh(kSpot), prism = pentagonalPrism();
  int refused = 0, read = 0;
  for (const sf::PolygonMesh* mesh : {&spot, &prism}) {
    const int nv = mesh->numVertices(), nf = mesh->numFaces();
    for (const Variant& v : variants) {
      if (mesh == &prism && v.faceValues < 6) continue;  // no room for "5 i j k l m" in 5 values
      SCOPED_TRACE(std::string(v.keyword) + " " + std::to_string(v.faceValues) + " values per face line, " +
                   std::to_string(nv) + " vertices");
      const std::string good =
          writeTemp("good.off", offTextPadded(*mesh, nv, nf, v.keyword, v.vertexExtra, v.faceValues));
      expectSameMesh(sf::readMesh(good), *mesh);
      ++read;
      const int firstFace = 3 + nv;  // the line of face 0
      for (int k = 1; k <= 6; ++k) {
        SCOPED_TRACE("k = " + std::to_string(k));
        const std::string path =
            writeTemp("lie.off", offTextPadded(*mesh, nv + k, nf - k, v.keyword, v.vertexExtra, v.faceValues));
        const std::string lines = k == 1 ? "this line (vertex " + std::to_string(nv + 1) +
                                               ", the last) reads as a face of the vertices before it"
                                         : "this line (vertex " + std::to_string(nv + 1) + ") and the " +
                                               std::to_string(k - 1) +
                                               " vertex lines after it read as faces of the vertices before them";
        const std::string msg = errorOf(path);
        EXPECT_EQ(msg.rfind(path + ":" + std::to_string(firstFace) + ": the header declares " + std::to_string(nv + k) +
                                " vertices and " + std::to_string(nf - k) + " faces, but " + lines + " ('" +
                                std::to_string(mesh->faceSize(0)) + " ",
                            0),
                  0u)
            << msg;
        EXPECT_NE(msg.find("the lines fit " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces"),
                  std::string::npos)
            << msg;
        ++refused;
      }
    }
  }
  EXPECT_EQ(read, 5 + 4);
  EXPECT_EQ(refused, 6 * (5 + 4));

  // Vertex lines that read as faces are still vertices where a face refers to them, or where
  // they index vertices at or after their own (no face of the vertices before): integer
  // coordinates with an RGBA colour.
  const std::string ints = "COFF\n5 2 0\n3 0 1 2 1 1 1\n4 0 0 1 1 1 1\n3 1 0 0 1 1 1\n3 2 2 2 1 1 1\n3 4 9 4 1 1 1\n";
  const sf::PolygonMesh m = sf::readMesh(writeTemp("ints.off", ints + "3 0 1 2\n3 0 2 3\n"));
  EXPECT_EQ(m.numVertices(), 5);
  EXPECT_EQ(m.numFaces(), 2);
  EXPECT_EQ(m.positions[4], Eigen::Vector3d(3, 4, 9));
  // The same with the last vertex "3 2 1 0 ...": a face of the four before it that no face
  // refers to, refused (the file may be valid; the reader cannot tell it from a header lie).
  const std::string amb = "COFF\n5 2 0\n3 0 1 2 1 1 1\n4 0 0 1 1 1 1\n3 1 0 0 1 1 1\n3 2 2 2 1 1 1\n3 2 1 0 1 1 1\n";
  const std::string path = writeTemp("amb.off", amb + "3 0 1 2\n3 0 2 3\n");
  EXPECT_EQ(errorOf(path).rfind(path + ":7: the header declares 5 vertices and 2 faces, but this line (vertex 5, the "
                                       "last) reads as a face of the vertices before it ('3 2 1 0 1 1 1')",
                                0),
            0u)
      << errorOf(path);
}

TEST(MeshReaderLineEnds, CrOnlyReadsLikeLf) {
  const sf::PolygonMesh spot = sf::readMesh(kSpot);
  const std::string obj = sf::test::fileBytes(kSpot), off = offText(spot, spot.numVertices(), spot.numFaces()),
                    ply = plyText(spot);
  for (const char* eol : {"\r", "\r\n"}) {
    SCOPED_TRACE(eol[1] ? "CRLF" : "CR");
    expectSameMesh(sf::readMesh(writeTemp("spot_eol.obj", withLineEnds(obj, eol))), spot);
    expectSameMesh(sf::readMesh(writeTemp("spot_eol.off", withLineEnds(off, eol))), spot);
    expectSameMesh(sf::readMesh(writeTemp("spot_eol.ply", withLineEnds(ply, eol))), spot);
  }
  // Errors count CR-only lines: a bad value on line 100 is named there.
  std::string bad = obj;
  size_t at = 0;
  for (int line = 1; line < 100; ++line) at = bad.find('\n', at) + 1;
  bad.insert(at, "v 0 0 zz\n");
  const std::string path = writeTemp("spot_cr_bad.obj", withLineEnds(bad, "\r"));
  EXPECT_EQ(errorOf(path).rfind(path + ":100: bad number 'zz'", 0), 0u) << errorOf(path);
  // A binary PLY header with CR-only line ends: its data starts right after "end_header\r",
  // even where the first data byte is 10 (LF).
  const std::string header =
      "ply\rformat binary_little_endian 1.0\relement vertex 3\rproperty uchar x\rproperty uchar y\r"
      "property uchar z\relement face 1\rproperty list uchar uchar vertex_indices\rend_header\r";
  const sf::PolygonMesh tri =
      sf::readMesh(writeTemp("cr_header.ply", header + std::string("\x0a\0\0\0\x0a\0\0\0\x0a\x03\0\x01\x02", 13)));
  ASSERT_EQ(tri.numVertices(), 3);
  EXPECT_EQ(tri.positions[0], Eigen::Vector3d(10, 0, 0));
  EXPECT_EQ(tri.faceVertices, (std::vector<int32_t>{0, 1, 2}));
}

TEST(MeshReaderDispatch, Utf16AndUtf32AreRefusedNamingTheFile) {
  const sf::PolygonMesh spot = sf::readMesh(kSpot);
  const std::string texts[3] = {sf::test::fileBytes(kSpot), offText(spot, spot.numVertices(), spot.numFaces()), plyText(spot)};
  const char* exts[3] = {".obj", ".off", ".ply"};
  int refused = 0;
  for (int i = 0; i < 3; ++i) {
    for (const bool big : {false, true}) {
      for (const bool bom : {true, false}) {
        std::string bytes = bom ? (big ? "\xfe\xff" : "\xff\xfe") : "";
        for (char c : texts[i]) big ? (bytes += '\0', bytes += c) : (bytes += c, bytes += '\0');
        const std::string path = writeTemp(std::string("spot_utf16") + exts[i], bytes);
        const std::string msg = errorOf(path);
        const std::string what =
            bom ? ": is UTF-16 encoded (byte-order mark " + std::string(big ? "FE FF" : "FF FE") + ")"
                : ": looks UTF-16 encoded (NUL bytes between the characters)";
        EXPECT_EQ(msg.rfind(path + what, 0), 0u) << msg;
        EXPECT_NE(msg.find("save it as UTF-8 or ASCII"), std::string::npos) << msg;
        ++refused;
      }
    }
  }
  EXPECT_EQ(refused, 12);
  std::string utf32 = "\xff\xfe";
  utf32 += std::string(2, '\0');
  for (char c : texts[0]) (utf32 += c) += std::string(3, '\0');
  const std::string path = writeTemp("spot_utf32.obj", utf32);
  EXPECT_EQ(errorOf(path).rfind(path + ": is UTF-32 encoded (byte-order mark FF FE 00 00)", 0), 0u) << errorOf(path);
  // A UTF-8 byte-order mark is read past.
  expectSameMesh(sf::readMesh(writeTemp("spot_utf8_bom.obj", "\xef\xbb\xbf" + texts[0])), spot);
}

TEST(ObjReader, BackslashContinuesAStatementOnTheNextLine) {
  const sf::PolygonMesh spot = sf::readMesh(kSpot);
  const std::string obj = sf::test::fileBytes(kSpot);
  // Every v and f statement split after its first value, three ways: "v x \", "v x\" and a
  // backslash followed by blanks.
  for (const char* split : {" \\\n  ", "\\\n", " \\ \t\n\t"}) {
    std::string text;
    std::istringstream in(obj);
    int joined = 0;
    for (std::string line; std::getline(in, line);) {
      const size_t second = line.find(' ', 2);
      if ((line.rfind("v ", 0) == 0 || line.rfind("f ", 0) == 0) && second != std::string::npos) {
        line.replace(second, 1, split);
        ++joined;
      }
      text += line + "\n";
    }
    EXPECT_EQ(joined, spot.numVertices() + spot.numFaces());
    expectSameMesh(sf::readMesh(writeTemp("spot_continued.obj", text)), spot);
  }
  // Errors name the physical line of the value.
  const std::string tri = "v 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\n";
  std::string path = writeTemp("continued_index.obj", tri + "f 1 2 \\\n 3 \\\n 9\n");
  EXPECT_EQ(errorOf(path).rfind(path + ":7: vertex index 9 out of range", 0), 0u) << errorOf(path);
  path = writeTemp("continued_bad.obj", tri + "f 1 \\\n 2 3\nf 1 \\\n 2 x\n");
  EXPECT_EQ(errorOf(path).rfind(path + ":8: bad integer 'x'", 0), 0u) << errorOf(path);
  // A comment does not continue, and a backslash inside a line is no continuation.
  EXPECT_EQ(sf::readMesh(writeTemp("comment.obj", "# note \\\n" + tri + "f 1 2 3\n")).numFaces(), 1);
  path = writeTemp("inner_backslash.obj", tri + "f 1 \\ 2 3\n");
  EXPECT_EQ(errorOf(path).rfind(path + ":5: bad integer '\\'", 0), 0u) << errorOf(path);
}
