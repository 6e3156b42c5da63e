// SPDX-License-Identifier: Apache-2.0
// Strict ASCII OFF reader: [ST][C][N]OFF header (counts on the same line or the next),
// one vertex per line, one face per line (`n i0 .. i(n-1)` then optional colour values),
// `#` comments, blank lines. The edge count is ignored. A header whose counts disagree with
// the file is refused at the first line of the other kind (readOff).
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_io_detail.h"

namespace sf::detail {
namespace {

struct OffHeader {
  bool normals = false;  // N: nx ny nz after x y z
  bool colours = false;  // C: r g b [a] (not used)
  bool texture = false;  // ST: s t (not used)
};

/// Next line that is not blank or only a comment, as tokens; false at end of file.
bool nextContent(LineReader& lines, std::string_view& content) {
  std::string_view line;
  while (lines.next(line)) {
    content = stripComment(line);
    Tokens t(content);
    if (!t.done()) return true;
  }
  return false;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

/// Whether a line reads as a face: an integer n >= 3, n integers >= 0, then numbers (colour).
/// Returns the largest of the n indices, or -1 when the line is no face.
int64_t faceLineMaxIndex(std::string_view content) {
  Tokens t(content);
  std::string_view tok;
  int64_t n = 0, v = 0, top = 0;
  if (!t.next(tok) || !parseInt(tok, n) || n < 3) return -1;
  for (int64_t k = 0; k < n; ++k) {
    if (!t.next(tok) || !parseInt(tok, v) || v < 0) return -1;
    top = std::max(top, v);
  }
  double x;
  while (t.next(tok)) {
    if (!parseDouble(tok, x)) return -1;
  }
  return top;
}

bool isFaceLine(std::string_view content) { return faceLineMaxIndex(content) >= 0; }

/// A vertex line that reads as a face (faceLineMaxIndex), at the end of the vertex section.
struct FaceLikeVertex {
  size_t line;
  int64_t maxIndex;
  std::string_view content;
};

/// The header declares nv vertices and nf faces; `tail` are the last vertex lines, all reading
/// as faces, and `m` holds the faces read after them. With nv + k and nf - k declared, the first
/// k face lines are read as vertices (a pentagon "5 0 1 2 3 4" is x y z and a colour, so is a
/// triangle with a colour), the faces after them read as faces, and the mesh is silently wrong;
/// but those k "vertices" are the last ones, they read as faces of the vertices before them
/// (indices below nv - k), and no face refers to them (faces index the nv - k real vertices).
/// Fails at the first of the longest such tail.
void refuseFaceLinesReadAsVertices(const LineCtx& c, int64_t nv, int64_t nf, const std::vector<FaceLikeVertex>& tail,
                                   const PolygonMesh& m) {
  if (tail.empty()) return;
  const int64_t first = nv - static_cast<int64_t>(tail.size());  // the vertex of tail[0]
  std::vector<uint8_t> used(tail.size(), 0);
  for (const int32_t v : m.faceVertices)
    if (v >= first) used[static_cast<size_t>(v - first)] = 1;
  size_t k = tail.size();  // tail[k..] is the longest tail unreferenced, indexing below vertex first + k
  int64_t top = -1;
  for (size_t j = tail.size(); j-- > 0;) {
    top = std::max(top, tail[j].maxIndex);
    if (used[j] || top >= first + static_cast<int64_t>(j)) break;
    k = j;
  }
  const int64_t r = static_cast<int64_t>(tail.size() - k);
  if (r == 0) return;
  LineCtx at{c.path, tail[k].line};
  const std::string lines =
      r == 1 ? "this line (vertex " + std::to_string(nv) + ", the last) reads as a face of the vertices before it ("
             : "this line (vertex " + std::to_string(nv - r + 1) + ") and the " + std::to_string(r - 1) +
                   " vertex lines after it read as faces of the vertices before them (";
  at.fail("the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces, but " + lines +
          quoted(trim(tail[k].content)) + ") and no face refers to " + (r == 1 ? "it" : "them") + ": the lines fit " +
          std::to_string(nv - r) + " vertices and " + std::to_string(nf + r) + " faces");
}

/// The number of values on a line if all are numbers, else -1; `real` is set when one is
/// not an integer.
int countNumbers(std::string_view content, bool& real) {
  Tokens t(content);
  std::string_view tok;
  int n = 0;
  real = false;
  for (; t.next(tok); ++n) {
    int64_t i;
    double x;
    if (!parseDouble(tok, x)) return -1;
    if (!parseInt(tok, i)) real = true;
  }
  return n;
}

/// Content lines from one element on, counted when first asked (only a line that looks out of
/// place asks, so a valid file is read once).
class LinesLeft {
 public:
  /// The lines from `element` (the one whose line `lines` returned last) to the end.
  int64_t from(const LineReader& lines, int64_t element) {
    if (at_ < 0) {
      LineReader rest = lines;
      std::string_view content;
      at_ = element;
      for (count_ = 1; nextContent(rest, content);) ++count_;
    }
    return count_ - (element - at_);
  }

 private:
  int64_t at_ = -1, count_ = 0;
};

OffHeader parseKeyword(const LineCtx& c, std::string_view kw) {
  OffHeader h;
  std::string_view k = kw;
  if (k.substr(0, 2) == "ST") h.texture = true, k.remove_prefix(2);
  if (k.substr(0, 1) == "C") h.colours = true, k.remove_prefix(1);
  if (k.substr(0, 1) == "N") h.normals = true, k.remove_prefix(1);
  if (k.substr(0, 1) == "4" || k.substr(0, 1) == "n")
    c.fail("unsupported OFF variant " + quoted(kw) + " (only 3D OFF is read)");
  if (k != "OFF") c.fail("not an OFF file: header is " + quoted(kw) + ", expected OFF");
  return h;
}

}  // namespace

PolygonMesh readOff(const std::string& path, std::string_view data) {
  LineReader lines(data);
  std::string_view content;
  if (!nextContent(lines, content)) failAt(path, lines.lineNo(), "file is empty");
  LineCtx c{path, lines.lineNo()};
  Tokens header(content);
  const OffHeader h = parseKeyword(c, c.need(header, "OFF keyword"));

  // Counts: on the header line or on the next content line.
  std::string_view tok;
  Tokens counts = header;
  if (counts.done()) {
    if (!nextContent(lines, content)) failAt(path, lines.lineNo(), "missing vertex and face counts");
    c.line = lines.lineNo();
    counts = Tokens(content);
  }
  tok = c.need(counts, "vertex count");
  if (tok == "BINARY") c.fail("binary OFF is not supported");
  const int64_t nv = c.count(tok, "vertex count");
  const int64_t nf = c.count(c.need(counts, "face count"), "face count");
  if (counts.next(tok)) c.integer(tok, "edge count");  // value ignored
  if (counts.next(tok)) c.fail("unexpected " + quoted(tok) + " after the counts");
  if (nf == 0) c.fail("no faces (face count is 0)");
  // Every vertex and face needs a line of at least one character and a line break (a
  // looser bound than a valid line needs, so that short bad lines get their own message).
  const uint64_t need = 2 * static_cast<uint64_t>(nv) + 2 * static_cast<uint64_t>(nf);
  if (need > lines.remaining() + 1) {
    c.fail("counts say " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
           " faces, more than the remaining " + std::to_string(lines.remaining()) + " bytes can hold");
  }

  PolygonMesh m;
  m.positions.reserve(static_cast<size_t>(nv));
  if (h.normals) m.fileNormals.reserve(static_cast<size_t>(nv));
  static const char* axes[3] = {"x coordinate", "y coordinate", "z coordinate"};
  static const char* naxes[3] = {"normal x", "normal y", "normal z"};
  // A header whose counts disagree with the file would have face lines read as vertices
  // (with colours) or vertex lines as faces. A line that looks like the other kind is
  // refused where the lines left cannot hold the declared elements, or where its number of
  // values fits no vertex line (x y z, the normal, colour 3 or 4, texture 2). Face lines
  // that do fit one, with as many faces fewer declared, are refused after the faces
  // (refuseFaceLinesReadAsVertices: the last vertex lines read as faces no face refers to).
  const int vertexValues = 3 + (h.normals ? 3 : 0) + (h.texture ? 2 : 0);
  bool real = false;  // set by fitsVertex: the line has a value that is not an integer
  const auto fitsVertex = [&](std::string_view line) {
    const int colour = countNumbers(line, real) - vertexValues;
    return colour == 0 || colour == 3 || colour == 4;
  };
  LinesLeft left;
  std::vector<FaceLikeVertex> faceLike;  // the last vertex lines, while they read as faces
  for (int64_t i = 0; i < nv; ++i) {
    if (!nextContent(lines, content)) {
      failAt(path, lines.lineNo(), "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    }
    c.line = lines.lineNo();
    const int64_t maxIndex = faceLineMaxIndex(content);
    if (maxIndex < 0)
      faceLike.clear();
    else
      faceLike.push_back({c.line, maxIndex, content});
    if (maxIndex >= 0 && (!fitsVertex(content) || left.from(lines, i) < nv - i + nf)) {
      c.fail("the header declares " + std::to_string(nv) + " vertices, but this line (vertex " + std::to_string(i + 1) +
             ") is a face (" + quoted(trim(content)) + ")");
    }
    Tokens t(content);
    Eigen::Vector3d p, n;
    for (int a = 0; a < 3; ++a) p[a] = c.coordinate(c.need(t, axes[a]), axes[a]);
    if (h.normals) {
      for (int a = 0; a < 3; ++a) n[a] = c.finite(c.need(t, naxes[a]), naxes[a]);
      m.fileNormals.push_back(n);
    }
    while (t.next(tok)) c.number(tok, "extra vertex value (colour or texture)");
    m.positions.push_back(p);
  }

  m.faceOffsets.reserve(static_cast<size_t>(nf) + 1);
  std::vector<int32_t> verts;
  for (int64_t f = 0; f < nf; ++f) {
    if (!nextContent(lines, content)) {
      failAt(path, lines.lineNo(), "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    }
    c.line = lines.lineNo();
    // Vertex lines read as faces start at the first face line.
    if (f == 0 && !isFaceLine(content) && fitsVertex(content) && (real || left.from(lines, nv) > nf)) {
      c.fail("the header declares " + std::to_string(nv) + " vertices, but this line (face 1 of " + std::to_string(nf) +
             ") is a vertex (" + quoted(trim(content)) + ")");
    }
    Tokens t(content);
    const int64_t n = c.integer(c.need(t, "face corner count"), "face corner count");
    if (n < 3) c.fail("face with " + std::to_string(n) + " corners (at least 3 needed)");
    verts.clear();
    for (int64_t k = 0; k < n; ++k) {
      if (!t.next(tok)) {
        c.fail("face has " + std::to_string(n) + " corners but only " + std::to_string(k) + " vertex indices");
      }
      const int64_t v = c.integer(tok, "vertex index");
      if (v < 0 || v >= nv) {
        c.fail("vertex index " + std::to_string(v) + " out of range (file has " + std::to_string(nv) + " vertices)");
      }
      verts.push_back(static_cast<int32_t>(v));
    }
    while (t.next(tok)) c.number(tok, "face colour value");
    if (m.faceVertices.size() + verts.size() > static_cast<size_t>(kMaxCount)) c.fail("too many face corners");
    m.addFace(verts);
  }
  if (nextContent(lines, content)) {
    failAt(path, lines.lineNo(),
           "unexpected data after the last face (the header says " + std::to_string(nv) + " vertices and " +
               std::to_string(nf) + " faces)");
  }
  refuseFaceLinesReadAsVertices(c, nv, nf, faceLike, m);
  return m;
}

}  // namespace sf::detail
