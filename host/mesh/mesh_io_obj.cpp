// SPDX-License-Identifier: Apache-2.0
// Strict Wavefront OBJ reader: v, vn, f (v, v/vt, v//vn, v/vt/vn; 1-based or negative
// indices), s (smoothing groups: `s N`, `s off`) and OpenSubdiv's tags `t name i/f/s args`
// (`crease` and `corner` are kept, with 0-based vertex ids; the others are checked and
// ignored). Other statements (vt, o, g, usemtl, mtllib, l, p, unknown) are ignored. A line
// that ends in a backslash continues on the next line.
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_io_detail.h"

namespace sf::detail {
namespace {

/// One kind of OBJ element (v, vt, vn): how many so far, and the largest positive index
/// seen with the line it was first seen on (positive indices may point forward; they are
/// checked against the final count at the end).
struct IndexSpace {
  const char* name;
  int64_t count = 0;
  int64_t maxPositive = 0;
  size_t maxLine = 0;

  /// Resolves a 1-based or negative (relative) index to 0-based.
  int32_t resolve(const LineCtx& c, std::string_view tok) {
    const int64_t i = c.integer(tok, name);
    if (i == 0) c.fail(std::string(name) + " 0 (OBJ indices start at 1)");
    if (i < 0) {
      if (i < -count) {  // not -i > count: -INT64_MIN overflows
        c.fail("relative " + std::string(name) + " " + std::to_string(i) + " but only " + std::to_string(count) +
               " defined so far");
      }
      return static_cast<int32_t>(count + i);
    }
    if (i > kMaxCount) c.fail(std::string(name) + " " + std::to_string(i) + " out of range");
    if (i > maxPositive) {
      maxPositive = i;
      maxLine = c.line;
    }
    return static_cast<int32_t>(i - 1);
  }
  void checkFinal(const std::string& path) const {
    if (maxPositive > count) {
      failAt(path, maxLine,
             std::string(name) + " " + std::to_string(maxPositive) + " out of range (file has " +
                 std::to_string(count) + ")");
    }
  }
};

/// Tokens of one statement: a line whose last character before any comment (blanks aside) is
/// a backslash continues on the next line. `c.line` follows the line of the last token
/// returned, so that messages name the physical line.
class StatementTokens {
 public:
  StatementTokens(std::string_view line, LineReader& lines, LineCtx& c) : lines_(lines), c_(c) { start(line); }
  bool next(std::string_view& tok) { return t_.next(tok) || (continues_ && nextLine(tok)); }
  /// Reads past the rest of the statement.
  void skipRest() {
    std::string_view tok;
    while (next(tok)) continue;
  }

 private:
  bool nextLine(std::string_view& tok) {
    std::string_view line;
    do {
      if (!continues_ || !lines_.next(line)) return false;
      c_.line = lines_.lineNo();
      start(line);
    } while (!t_.next(tok));
    return true;
  }
  void start(std::string_view line) {
    line = stripComment(line);
    while (!line.empty() && isSpace(line.back())) line.remove_suffix(1);
    continues_ = !line.empty() && line.back() == '\\';
    if (continues_) line.remove_suffix(1);
    t_ = Tokens(line);
  }

  LineReader& lines_;
  LineCtx& c_;
  Tokens t_{""};
  bool continues_ = false;
};

struct ObjState {
  IndexSpace v{"vertex index"}, vt{"texture index"}, vn{"normal index"};
  std::vector<Eigen::Vector3d> normals;
  std::vector<int32_t> cornerVn;  ///< per corner, while faces carry normal indices
  int faceNormals = -1;           ///< -1 unknown, 0 faces have no vn, 1 faces have vn
  size_t firstFaceLine = 0;
  bool smoothing = false;      ///< the file has an `s` statement (so faces get a group each)
  int64_t smoothingGroup = 0;  ///< group of the faces that follow
  /// The largest vertex id of a crease or corner tag and the line it is on: tags may come
  /// before the `v` lines they refer to, so ids are checked against the final count.
  int64_t maxTagVertex = -1;
  size_t maxTagVertexLine = 0;
};

void readVertex(const LineCtx& c, StatementTokens& t, PolygonMesh& m) {
  Eigen::Vector3d p;
  static const char* axes[3] = {"x coordinate", "y coordinate", "z coordinate"};
  for (int a = 0; a < 3; ++a) p[a] = c.coordinate(c.need(t, axes[a]), axes[a]);
  std::string_view tok;
  int extra = 0;
  while (t.next(tok)) {  // w, or r g b [a]
    c.number(tok, "optional vertex value (w or colour)");
    if (++extra > 4) c.fail("too many values on vertex line (expected x y z [w | r g b [a]])");
  }
  if (m.positions.size() >= static_cast<size_t>(kMaxCount)) c.fail("too many vertices");
  m.positions.push_back(p);
}

void readNormal(const LineCtx& c, StatementTokens& t, ObjState& s) {
  Eigen::Vector3d n;
  static const char* axes[3] = {"normal x", "normal y", "normal z"};
  for (int a = 0; a < 3; ++a) n[a] = c.finite(c.need(t, axes[a]), axes[a]);
  std::string_view tok;
  if (t.next(tok)) c.fail("unexpected " + quoted(tok) + " after normal x y z");
  s.normals.push_back(n);
}

void readFace(const LineCtx& c, StatementTokens& t, ObjState& s, PolygonMesh& m, std::vector<int32_t>& verts,
              std::vector<int32_t>& vns) {
  verts.clear();
  vns.clear();
  int withVn = 0;
  std::string_view tok;
  while (t.next(tok)) {
    const size_t s1 = tok.find('/');
    const size_t s2 = s1 == std::string_view::npos ? s1 : tok.find('/', s1 + 1);
    if (s2 != std::string_view::npos && tok.find('/', s2 + 1) != std::string_view::npos)
      c.fail("bad face corner " + quoted(tok) + " (expected v, v/vt, v//vn or v/vt/vn)");
    const std::string_view vPart = tok.substr(0, s1);
    if (vPart.empty()) c.fail("face corner " + quoted(tok) + " has no vertex index");
    verts.push_back(s.v.resolve(c, vPart));
    if (s1 == std::string_view::npos) continue;
    const std::string_view vtPart = s2 == std::string_view::npos ? tok.substr(s1 + 1) : tok.substr(s1 + 1, s2 - s1 - 1);
    if (!vtPart.empty()) s.vt.resolve(c, vtPart);
    if (s2 == std::string_view::npos) {
      if (vtPart.empty()) c.fail("face corner " + quoted(tok) + " has an empty texture index");
      continue;
    }
    const std::string_view vnPart = tok.substr(s2 + 1);
    if (vnPart.empty()) c.fail("face corner " + quoted(tok) + " has an empty normal index");
    vns.push_back(s.vn.resolve(c, vnPart));
    ++withVn;
  }
  const int n = static_cast<int>(verts.size());
  if (n < 3) c.fail("face with " + std::to_string(n) + " corner" + (n == 1 ? "" : "s") + " (at least 3 needed)");
  if (withVn != 0 && withVn != n) c.fail("some corners of this face have normal indices and some do not");
  const int has = withVn ? 1 : 0;
  if (s.faceNormals < 0) {
    s.faceNormals = has;
    s.firstFaceLine = c.line;
  } else if (s.faceNormals != has) {
    c.fail(std::string("face ") + (has ? "has" : "lacks") + " normal indices but the face on line " +
           std::to_string(s.firstFaceLine) + (has ? " lacks them" : " has them"));
  }
  if (m.faceVertices.size() + verts.size() > static_cast<size_t>(kMaxCount)) c.fail("too many face corners");
  m.addFace(verts);
  s.cornerVn.insert(s.cornerVn.end(), vns.begin(), vns.end());
}

/// `s N` or `s off`: the smoothing group (N >= 0; off is 0) of the faces that follow. The first
/// one gives the faces before it group 0.
void readSmoothingGroup(const LineCtx& c, StatementTokens& t, ObjState& s, PolygonMesh& m) {
  const std::string_view tok = c.need(t, "smoothing group (a number >= 0 or 'off')");
  int64_t group = 0;
  if (tok != "off" && (!parseInt(tok, group) || group < 0))
    c.fail("bad smoothing group " + quoted(tok) + " (expected a number >= 0 or 'off')");
  std::string_view extra;
  if (t.next(extra)) c.fail("unexpected " + quoted(extra) + " after the smoothing group");
  if (!s.smoothing) m.faceSmoothingGroups.assign(static_cast<size_t>(m.numFaces()), 0);
  s.smoothing = true;
  s.smoothingGroup = group;
}

/// A tag's argument counts `nint/nfloat/nstring`, each a number >= 0.
void tagCounts(const LineCtx& c, std::string_view tok, const std::string& tag, int64_t counts[3]) {
  constexpr size_t npos = std::string_view::npos;
  const size_t a = tok.find('/');
  const size_t b = a == npos ? npos : tok.find('/', a + 1);
  bool ok = b != npos && tok.find('/', b + 1) == npos && parseInt(tok.substr(0, a), counts[0]) &&
            parseInt(tok.substr(a + 1, b - a - 1), counts[1]) && parseInt(tok.substr(b + 1), counts[2]);
  for (int k = 0; ok && k < 3; ++k) ok = counts[k] >= 0 && counts[k] <= kMaxCount;
  if (!ok) {
    c.fail("bad argument counts " + quoted(tok) + " for tag " + tag +
           " (expected three numbers >= 0, ints/floats/strings, as in 2/1/0)");
  }
}

/// Notes a tag vertex id, for the range check at the end of the file.
void noteTagVertex(const LineCtx& c, ObjState& s, int64_t v) {
  if (v > s.maxTagVertex) {
    s.maxTagVertex = v;
    s.maxTagVertexLine = c.line;
  }
}

/// `t name nint/nfloat/nstring ints.. floats.. strings..`: OpenSubdiv's tag statement (its
/// regression/common/shape_utils.cpp reads it; far_utils.h applies it). The counts must match
/// the arguments that follow, for every tag. Kept, with 0-based vertex ids:
///   crease: pairs of vertex ids `a b c d ..`, each pair one edge (a-b, c-d: no chain), and one
///           sharpness for all of them;
///   corner: vertex ids, and one sharpness for all of them or one per vertex.
/// Sharpness is finite and >= 0. OpenSubdiv reads a crease tag with more than one sharpness by
/// the position of each edge's first id (edge a-b takes value 0, c-d value 2), which is no value
/// per edge; such tags are refused, as are crease tags without a sharpness or with an odd id
/// count. Other tags (hole, interpolateboundary, creasemethod, unknown ones) are ignored.
void readTag(const LineCtx& c, StatementTokens& t, ObjState& s, PolygonMesh& m) {
  const size_t line = c.line;
  const std::string_view name = c.need(t, "tag name");
  const std::string tag = quoted(name);
  int64_t n[3];
  tagCounts(c, c.need(t, "tag argument counts (ints/floats/strings, as in 2/1/0)"), tag, n);
  const bool crease = name == "crease", corner = name == "corner";
  const std::string counts = std::to_string(n[0]) + "/" + std::to_string(n[1]) + "/" + std::to_string(n[2]);
  if (crease || corner) {
    if (n[2] != 0) c.fail("tag " + tag + " takes no string arguments (counts " + counts + ")");
    if (crease && (n[0] == 0 || n[0] % 2 != 0))
      c.fail("crease tag with " + std::to_string(n[0]) + " vertex ids (counts " + counts +
             "): it takes pairs of vertex ids, one pair per edge");
    if (corner && n[0] == 0) c.fail("corner tag without vertex ids (counts " + counts + ")");
    if (n[1] == 0) c.fail("tag " + tag + " without a sharpness (counts " + counts + ")");
    if (crease && n[1] != 1)
      c.fail("crease tag with " + std::to_string(n[1]) + " sharpness values (counts " + counts +
             "): give one, for all its edges, or write one tag per edge");
    if (corner && n[1] != 1 && n[1] != n[0])
      c.fail("corner tag with " + std::to_string(n[0]) + " vertex ids and " + std::to_string(n[1]) +
             " sharpness values (counts " + counts + "): give one for all of them or one per vertex");
  }
  const auto arg = [&](const char* kind, int64_t i, int64_t of) {
    std::string_view tok;
    if (!t.next(tok)) {
      c.fail("tag " + tag + " declares " + counts + " arguments but has only " + std::to_string(i) + " of its " +
             std::to_string(of) + " " + kind + " argument" + (of == 1 ? "" : "s"));
    }
    return tok;
  };
  const char* idWhat = crease ? "crease vertex id" : corner ? "corner vertex id" : "tag integer argument";
  std::vector<int64_t> ids;
  for (int64_t i = 0; i < n[0]; ++i) {
    const int64_t v = c.integer(arg("integer", i, n[0]), idWhat);
    if (crease || corner) {
      if (v < 0 || v > kMaxCount)
        c.fail(std::string(idWhat) + " " + std::to_string(v) + " out of range (tag vertex ids are 0-based)");
      noteTagVertex(c, s, v);
      if (crease && i % 2 == 1 && v == ids.back())
        c.fail("crease tag edge " + std::to_string(v) + "-" + std::to_string(v) + " joins a vertex to itself");
      ids.push_back(v);
    }
  }
  const char* sharpWhat = crease ? "crease sharpness" : "corner sharpness";
  std::vector<double> sharpness;
  for (int64_t i = 0; i < n[1]; ++i) {
    const std::string_view tok = arg("float", i, n[1]);
    if (!crease && !corner) {
      c.number(tok, "tag float argument");
      continue;
    }
    const double v = c.finite(tok, sharpWhat);
    if (v < 0) c.fail("negative " + std::string(sharpWhat) + " " + quoted(tok));
    sharpness.push_back(v);
  }
  for (int64_t i = 0; i < n[2]; ++i) arg("string", i, n[2]);
  std::string_view extra;
  if (t.next(extra)) c.fail("unexpected " + quoted(extra) + " after the " + counts + " arguments of tag " + tag);
  if (crease) {
    for (size_t i = 0; i + 1 < ids.size(); i += 2)
      m.creaseTags.push_back({static_cast<int32_t>(ids[i]), static_cast<int32_t>(ids[i + 1]), sharpness[0], line});
  } else if (corner) {
    for (size_t i = 0; i < ids.size(); ++i)
      m.cornerTags.push_back({static_cast<int32_t>(ids[i]), sharpness[sharpness.size() == 1 ? 0 : i], line});
  }
}

}  // namespace

PolygonMesh readObj(const std::string& path, std::string_view data) {
  PolygonMesh m;
  ObjState s;
  std::vector<int32_t> verts, vns;
  LineReader lines(data);
  std::string_view line;
  while (lines.next(line)) {
    LineCtx c{path, lines.lineNo()};
    StatementTokens t(line, lines, c);
    std::string_view kw;
    if (!t.next(kw)) continue;
    if (kw == "v") {
      readVertex(c, t, m);
      s.v.count = m.numVertices();
    } else if (kw == "vn") {
      readNormal(c, t, s);
      s.vn.count = static_cast<int64_t>(s.normals.size());
    } else if (kw == "vt") {
      ++s.vt.count;  // contents are not used
    } else if (kw == "f" || kw == "fo") {
      readFace(c, t, s, m, verts, vns);
      if (s.smoothing) m.faceSmoothingGroups.push_back(s.smoothingGroup);
    } else if (kw == "s") {
      readSmoothingGroup(c, t, s, m);
    } else if (kw == "t") {
      readTag(c, t, s, m);
    }
    // Everything else (o, g, usemtl, mtllib, l, p, vp, unknown extensions) is ignored, with
    // the lines it continues on.
    t.skipRest();
  }
  if (m.numFaces() == 0) failAt(path, lines.lineNo(), "no faces in file");
  s.v.checkFinal(path);
  s.vt.checkFinal(path);
  s.vn.checkFinal(path);
  if (s.maxTagVertex >= m.numVertices()) {
    failAt(path, s.maxTagVertexLine,
           "tag vertex id " + std::to_string(s.maxTagVertex) + " out of range (file has " +
               std::to_string(m.numVertices()) + " vertices; tag vertex ids are 0-based)");
  }
  if (s.faceNormals == 1) {
    m.fileCornerNormals.reserve(s.cornerVn.size());
    for (int32_t i : s.cornerVn) m.fileCornerNormals.push_back(s.normals[i]);
  } else if (!s.normals.empty() && s.normals.size() == m.positions.size()) {
    m.fileNormals = std::move(s.normals);
  }
  return m;
}

}  // namespace sf::detail
