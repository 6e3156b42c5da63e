// SPDX-License-Identifier: Apache-2.0
// Strict PLY reader: ascii, binary_little_endian and binary_big_endian 1.0. Reads x y z
// (and nx ny nz) of `vertex`, the `vertex_indices`/`vertex_index` list of `face`, and crease
// edges: `vertex1`, `vertex2` and `crease` (or `sharpness`) of `edge`. Every other property
// and element is read past (and checked in ASCII).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "mesh_io_detail.h"

namespace sf::detail {
namespace {

enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

/// PLY type names, two spellings each, in Scalar order; and their sizes in bytes.
constexpr std::string_view kScalarNames[8][2] = {{"char", "int8"},     {"uchar", "uint8"},   {"short", "int16"},
                                                 {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                                                 {"float", "float32"}, {"double", "float64"}};
constexpr size_t kScalarSize[8] = {1, 1, 2, 2, 4, 4, 4, 8};

bool scalarFromName(std::string_view s, Scalar& t) {
  for (int i = 0; i < 8; ++i) {
    if (s != kScalarNames[i][0] && s != kScalarNames[i][1]) continue;
    t = static_cast<Scalar>(i);
    return true;
  }
  return false;
}
size_t scalarSize(Scalar t) { return kScalarSize[static_cast<int>(t)]; }
bool isInteger(Scalar t) { return t != Scalar::F32 && t != Scalar::F64; }

struct Prop {
  std::string name;
  bool list = false;
  Scalar type = Scalar::F32, countType = Scalar::U8;
};
struct Element {
  std::string name;
  int64_t count = 0;
  std::vector<Prop> props;
  size_t line = 0;
};

/// The data section, read one scalar at a time, in ASCII (one element per line) or binary.
class Source {
 public:
  Source(const std::string& path, std::string_view data, size_t start, size_t headerLines, int format)
      : path_(path), data_(data), lines_(data, start), pos_(start), format_(format), headerLines_(headerLines) {}

  void beginRow(const Element& e, int64_t i) {
    elem_ = &e;
    index_ = i;
    if (format_ != 0) return;
    std::string_view line;
    do {
      if (!lines_.next(line)) fail("file ends before " + e.name + " " + std::to_string(i));
      tokens_ = Tokens(line);
    } while (tokens_.done());
  }
  void endRow() {
    std::string_view tok;
    if (format_ == 0 && tokens_.next(tok))
      fail("unexpected " + quoted(tok) + " at the end of " + elem_->name + " " + std::to_string(index_));
  }
  double scalar(Scalar t, const std::string& what) {
    return format_ == 0 ? asciiScalar(t, what) : binaryScalar(t, what);
  }
  /// Checks that `n` more values of type t can still be there (binary only).
  void checkAvailable(int64_t n, Scalar t, const std::string& what) {
    if (format_ != 0 && static_cast<uint64_t>(n) > (data_.size() - pos_) / scalarSize(t))
      fail(what + " " + std::to_string(n) + " is more than the rest of the file holds");
  }
  void finish() {
    std::string_view line;
    if (format_ == 0) {
      while (lines_.next(line)) {
        if (!Tokens(line).done()) fail("unexpected data after the last element");
      }
    } else if (pos_ != data_.size()) {
      valuePos_ = pos_;
      fail(std::to_string(data_.size() - pos_) + " bytes of unexpected data after the last element");
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    const std::string where = elem_ ? " (" + elem_->name + " " + std::to_string(index_) + ")" : "";
    if (format_ == 0) failAt(path_, headerLines_ + lines_.lineNo(), what);
    throw InputError(path_ + ": byte " + std::to_string(valuePos_) + ": " + what + where);
  }

 private:
  double asciiScalar(Scalar t, const std::string& what) {
    std::string_view tok;
    if (!tokens_.next(tok)) fail("missing " + what + " in " + elem_->name + " " + std::to_string(index_));
    double v;
    if (isInteger(t)) {
      int64_t i;
      if (!parseInt(tok, i)) fail("bad integer " + quoted(tok) + " for " + what);
      static const int64_t lo[] = {-128, 0, -32768, 0, INT32_MIN, 0};
      static const int64_t hi[] = {127, 255, 32767, 65535, INT32_MAX, UINT32_MAX};
      const int k = static_cast<int>(t);
      if (i < lo[k] || i > hi[k]) fail(quoted(tok) + " out of range for the type of " + what);
      v = static_cast<double>(i);
    } else if (!parseDouble(tok, v)) {
      fail("bad number " + quoted(tok) + " for " + what);
    }
    return v;
  }
  double binaryScalar(Scalar t, const std::string& what) {
    const size_t n = scalarSize(t);
    valuePos_ = pos_;
    if (data_.size() - pos_ < n) fail("file ends inside " + what);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    const bool big = format_ == 2;
    if (big != (std::endian::native == std::endian::big)) {
      for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    }
    pos_ += n;
    if (t == Scalar::I8) return load<int8_t>(b);
    if (t == Scalar::U8) return load<uint8_t>(b);
    if (t == Scalar::I16) return load<int16_t>(b);
    if (t == Scalar::U16) return load<uint16_t>(b);
    if (t == Scalar::I32) return load<int32_t>(b);
    if (t == Scalar::U32) return load<uint32_t>(b);
    return t == Scalar::F32 ? load<float>(b) : load<double>(b);
  }
  template <class T>
  static double load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  const std::string& path_;
  std::string_view data_;
  LineReader lines_;  // ASCII
  Tokens tokens_{""};
  size_t pos_;           // binary
  size_t valuePos_ = 0;  // where the last binary value started
  int format_;           // 0 ascii, 1 little endian, 2 big endian
  size_t headerLines_;
  const Element* elem_ = nullptr;
  int64_t index_ = 0;
};

struct Header {
  int format = -1;
  std::vector<Element> elements;
  size_t dataStart = 0, lines = 0;
};

Header parseHeader(const std::string& path, std::string_view data) {
  Header h;
  LineReader lines(data);
  std::string_view line, tok;
  const bool any = lines.next(line);
  Tokens first(line);
  if (!any || !first.next(tok) || tok != "ply" || !first.done())
    failAt(path, 1, "not a PLY file (first line must be 'ply')");
  const bool crHeader = data[lines.pos() - 1] == '\r';  // CR-only line ends
  for (;;) {
    if (!lines.next(line)) failAt(path, lines.lineNo(), "header has no end_header line");
    const LineCtx c{path, lines.lineNo()};
    Tokens t(line);
    std::string_view kw;
    if (!t.next(kw)) continue;
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") break;
    if (kw == "format") {
      const std::string_view f = c.need(t, "format");
      static const char* formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
      for (int i = 0; i < 3; ++i) {
        if (f == formats[i]) h.format = i;
      }
      if (h.format < 0) c.fail("unknown PLY format " + quoted(f));
      const std::string_view version = c.need(t, "format version");
      if (version != "1.0") c.fail("unsupported PLY version " + quoted(version));
    } else if (kw == "element") {
      Element e;
      e.name = std::string(c.need(t, "element name"));
      e.count = c.count(c.need(t, "element count"), "element count");
      e.line = c.line;
      for (const Element& o : h.elements) {
        if (o.name == e.name) c.fail("element " + quoted(e.name) + " declared twice");
      }
      h.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (h.elements.empty()) c.fail("property before any element");
      Prop p;
      std::string_view type = c.need(t, "property type");
      if (type == "list") {
        p.list = true;
        const std::string_view ct = c.need(t, "list count type");
        if (!scalarFromName(ct, p.countType) || !isInteger(p.countType)) c.fail("bad list count type " + quoted(ct));
        type = c.need(t, "list value type");
      }
      if (!scalarFromName(type, p.type)) c.fail("unknown property type " + quoted(type));
      p.name = std::string(c.need(t, "property name"));
      if (t.next(tok)) c.fail("unexpected " + quoted(tok) + " after the property name");
      for (const Prop& o : h.elements.back().props) {
        if (o.name == p.name) c.fail("property " + quoted(p.name) + " declared twice");
      }
      h.elements.back().props.push_back(std::move(p));
    } else {
      c.fail("unknown header line " + quoted(kw));
    }
    if (kw != "property" && kw != "element" && t.next(tok)) c.fail("unexpected " + quoted(tok) + " in header line");
  }
  if (h.format < 0) failAt(path, lines.lineNo(), "header has no format line");
  h.dataStart = lines.pos();
  // With CR-only line ends, binary data starts right after "end_header\r", also where its
  // first byte is 10 (which the line reader takes for the LF of a CRLF).
  if (crHeader && h.format != 0 && data.substr(0, h.dataStart).ends_with("\r\n")) --h.dataStart;
  h.lines = lines.lineNo();
  return h;
}

std::string formatNumber(double v) {
  if (std::abs(v) < 9e15 && v == static_cast<double>(static_cast<int64_t>(v)))
    return std::to_string(static_cast<int64_t>(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

int findProp(const Element& e, std::string_view name) {
  for (size_t i = 0; i < e.props.size(); ++i) {
    if (e.props[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

PolygonMesh readPly(const std::string& path, std::string_view data) {
  const Header h = parseHeader(path, data);
  int vi = -1, fi = -1;   // the vertex and face elements
  uint64_t minBytes = 0;  // what the declared counts need at least
  for (size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    if (e.props.empty()) failAt(path, e.line, "element " + quoted(e.name) + " has no properties");
    // Binary: the fixed part of a row. ASCII: one character and a line break (looser than a
    // valid row needs, so that short bad rows get their own message).
    uint64_t row = h.format == 0 ? 2 : 0;
    for (const Prop& p : e.props) row += h.format == 0 ? 0 : scalarSize(p.list ? p.countType : p.type);
    const uint64_t rest = data.size() - h.dataStart + (h.format == 0 ? 1 : 0);
    if (static_cast<uint64_t>(e.count) > (rest - std::min(rest, minBytes)) / row) {
      failAt(path, e.line,
             "element " + quoted(e.name) + " count " + std::to_string(e.count) +
                 " is more than the rest of the file can hold");
    }
    minBytes += row * static_cast<uint64_t>(e.count);
    if (e.name == "vertex") vi = static_cast<int>(ei);
    if (e.name == "face") fi = static_cast<int>(ei);
  }
  if (vi < 0) failAt(path, h.lines, "no 'vertex' element");
  if (fi < 0 || h.elements[fi].count == 0) failAt(path, h.lines, "no faces");

  // What each property is for: -1 nothing, 0-2 x y z, 3-5 nx ny nz, 6 face vertex indices,
  // 7-9 crease edge vertex1, vertex2 and sharpness.
  std::vector<std::vector<int>> role(h.elements.size());
  for (size_t ei = 0; ei < h.elements.size(); ++ei) role[ei].assign(h.elements[ei].props.size(), -1);
  const Element &ve = h.elements[vi], &fe = h.elements[fi];
  static const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  int found[2] = {0, 0};  // positions, normals
  for (int a = 0; a < 6; ++a) {
    const int pi = findProp(ve, names[a]);
    if (pi < 0) continue;
    if (ve.props[pi].list) failAt(path, ve.line, std::string("vertex property ") + names[a] + " is a list");
    role[vi][pi] = a;
    ++found[a / 3];
  }
  if (found[0] != 3) failAt(path, ve.line, "vertex element lacks x, y or z");
  if (found[1] != 0 && found[1] != 3) failAt(path, ve.line, "vertex element has some but not all of nx, ny, nz");
  int pi = findProp(fe, "vertex_indices");
  if (pi < 0) pi = findProp(fe, "vertex_index");
  if (pi < 0 || !fe.props[pi].list)
    failAt(path, fe.line, "face element lacks a 'vertex_indices' or 'vertex_index' list");
  role[fi][pi] = 6;
  // An `edge` element with a `crease` or `sharpness` value: 7 vertex1, 8 vertex2, 9 the value.
  // Without such a value the element is read past, whatever else it holds.
  int ei = -1;
  bool edgeCreases = false;
  for (size_t k = 0; k < h.elements.size(); ++k) {
    if (h.elements[k].name == "edge") ei = static_cast<int>(k);
  }
  if (ei >= 0) {
    const Element& ee = h.elements[ei];
    const int ci = findProp(ee, "crease"), si = findProp(ee, "sharpness");
    if (ci >= 0 && si >= 0) failAt(path, ee.line, "edge element has both a 'crease' and a 'sharpness' property");
    const int ki = ci >= 0 ? ci : si;
    if (ki >= 0) {
      const std::string value = quoted(ee.props[ki].name);
      if (ee.props[ki].list) failAt(path, ee.line, "edge property " + value + " is a list");
      const int ends[2] = {findProp(ee, "vertex1"), findProp(ee, "vertex2")};
      if (ends[0] < 0 || ends[1] < 0)
        failAt(path, ee.line, "edge element has a " + value + " property but lacks 'vertex1' or 'vertex2'");
      for (int k = 0; k < 2; ++k) {
        const Prop& p = ee.props[ends[k]];
        if (p.list || !isInteger(p.type))
          failAt(path, ee.line, "edge property " + quoted(p.name) + " is not an integer scalar");
        role[ei][ends[k]] = 7 + k;
      }
      role[ei][ki] = 9;
      edgeCreases = true;
    }
  }

  PolygonMesh m;
  const int64_t nv = ve.count;
  m.positions.resize(static_cast<size_t>(nv));
  if (found[1]) m.fileNormals.resize(static_cast<size_t>(nv));
  m.faceOffsets.reserve(static_cast<size_t>(fe.count) + 1);
  Source src(path, data, h.dataStart, h.lines, h.format);
  std::vector<int32_t> verts;
  CreaseTag edge;  // the crease edge being read
  for (size_t ek = 0; ek < h.elements.size(); ++ek) {
    const Element& e = h.elements[ek];
    const bool creases = edgeCreases && static_cast<int>(ek) == ei;
    if (creases) m.creaseTags.reserve(static_cast<size_t>(e.count));  // the count fits the file (checked above)
    edge.line = e.line;
    for (int64_t i = 0; i < e.count; ++i) {
      src.beginRow(e, i);
      for (size_t p = 0; p < e.props.size(); ++p) {
        const Prop& prop = e.props[p];
        const int r = role[ek][p];
        if (!prop.list) {
          const double v = src.scalar(prop.type, prop.name);
          if (r == 7 || r == 8) {
            if (!(v >= 0 && v < static_cast<double>(nv))) {
              src.fail("edge " + std::to_string(i) + ": " + prop.name + " " + formatNumber(v) +
                       " out of range (file has " + std::to_string(nv) + " vertices)");
            }
            (r == 7 ? edge.v0 : edge.v1) = static_cast<int32_t>(v);
            continue;
          }
          if (r == 9) {
            if (!std::isfinite(v)) src.fail("non-finite " + prop.name + " in edge " + std::to_string(i));
            if (v < 0) src.fail("negative " + prop.name + " " + formatNumber(v) + " in edge " + std::to_string(i));
            edge.sharpness = v;
            continue;
          }
          if (r >= 0 && !std::isfinite(v)) src.fail("non-finite " + prop.name + " in vertex " + std::to_string(i));
          if (r >= 0 && r < 3 && !(std::fabs(v) <= kMaxCoordinate))
            src.fail(prop.name + " in vertex " + std::to_string(i) + " is beyond the coordinate range +-1e15");
          if (r >= 0) (r < 3 ? m.positions[i][r] : m.fileNormals[i][r - 3]) = v;
          continue;
        }
        const double count = src.scalar(prop.countType, prop.name + " count");
        if (count < 0) src.fail("negative list count for " + prop.name);
        const auto n = static_cast<int64_t>(count);
        src.checkAvailable(n, prop.type, prop.name + " count");
        if (r == 6 && n < 3)
          src.fail("face " + std::to_string(i) + " has " + std::to_string(n) + " corners (at least 3 needed)");
        verts.clear();
        for (int64_t k = 0; k < n; ++k) {
          const double v = src.scalar(prop.type, prop.name);
          if (r != 6) continue;
          if (!(v >= 0 && v < static_cast<double>(nv)) || v != std::floor(v)) {
            src.fail("face " + std::to_string(i) + ": vertex index " + formatNumber(v) + " out of range (file has " +
                     std::to_string(nv) + " vertices)");
          }
          verts.push_back(static_cast<int32_t>(v));
        }
        if (r != 6) continue;
        if (m.faceVertices.size() + verts.size() > static_cast<size_t>(kMaxCount)) src.fail("too many face corners");
        m.addFace(verts);
      }
      src.endRow();
      if (!creases) continue;
      if (edge.v0 == edge.v1)
        src.fail("edge " + std::to_string(i) + " joins vertex " + std::to_string(edge.v0) + " to itself");
      m.creaseTags.push_back(edge);
    }
  }
  src.finish();
  return m;
}

}  // namespace sf::detail
