// SPDX-License-Identifier: Apache-2.0
// Shared helpers for the mesh readers: whole-file input, line and token scanning, strict
// number parsing, and errors that name `path:line`. Internal to host/mesh_io*.cpp.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <system_error>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/mesh/mesh.h>

namespace sf::detail {

/// Readers, one per format. `data` is the whole file; `path` is only used in messages.
PolygonMesh readObj(const std::string& path, std::string_view data);
PolygonMesh readOff(const std::string& path, std::string_view data);
PolygonMesh readPly(const std::string& path, std::string_view data);

/// Largest element count a reader accepts (indices are int32).
constexpr int64_t kMaxCount = INT32_MAX;

/// A token as it should appear in a message: quoted, at most 40 characters, bytes that are
/// not printable ASCII written as \xNN.
inline std::string quoted(std::string_view tok) {
  static const char* hex = "0123456789abcdef";
  std::string s = "'";
  for (size_t i = 0; i < tok.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(tok[i]);
    if (c >= 0x20 && c < 0x7f) {
      s += static_cast<char>(c);
    } else {
      s += "\\x";
      s += hex[c >> 4];
      s += hex[c & 15];
    }
  }
  if (tok.size() > 40) s += "...";
  return s + "'";
}

[[noreturn]] inline void failAt(const std::string& path, size_t line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

/// Splits text into lines. Accepts LF, CRLF and CR (old Mac OS) line ends, also mixed; the
/// returned line has none of them.
class LineReader {
 public:
  explicit LineReader(std::string_view text, size_t pos = 0) : text_(text), pos_(pos), lf_(findLf(pos)) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    if (lf_ < pos_) lf_ = findLf(pos_);
    line = text_.substr(pos_, lf_ - pos_);
    const size_t cr = line.find('\r');
    if (cr != std::string_view::npos && cr + 1 < line.size()) {  // a lone CR ends the line
      line = line.substr(0, cr);
      pos_ += cr + 1;
    } else {
      if (cr != std::string_view::npos) line.remove_suffix(1);  // CRLF, or a CR that ends the file
      pos_ = lf_ < text_.size() ? lf_ + 1 : lf_;
    }
    ++lineNo_;
    return true;
  }
  size_t lineNo() const { return lineNo_; }  ///< 1-based number of the line last returned
  size_t pos() const { return pos_; }        ///< byte offset where the next line starts
  size_t remaining() const { return text_.size() - pos_; }

 private:
  size_t findLf(size_t from) const { return std::min(text_.find('\n', from), text_.size()); }

  std::string_view text_;
  size_t pos_ = 0;
  size_t lf_ = 0;  ///< the next LF at or after pos_ (or the end), kept across CR-only lines
  size_t lineNo_ = 0;
};

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// The part of a line before a `#` comment.
inline std::string_view stripComment(std::string_view line) {
  const size_t h = line.find('#');
  return h == std::string_view::npos ? line : line.substr(0, h);
}

/// Whitespace-separated tokens of one line.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : rest_(line) {}
  bool next(std::string_view& tok) {
    skip();
    if (rest_.empty()) return false;
    size_t n = 0;
    while (n < rest_.size() && !isSpace(rest_[n])) ++n;
    tok = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return true;
  }
  bool done() {
    skip();
    return rest_.empty();
  }

 private:
  void skip() {
    while (!rest_.empty() && isSpace(rest_.front())) rest_.remove_prefix(1);
  }
  std::string_view rest_;
};

/// Parses the whole token as a decimal number (an optional leading '+' is allowed).
/// Accepts nan/inf spellings (callers reject non-finite values where it matters); values
/// too small for a double round towards zero; too large ones fail.
inline bool parseDouble(std::string_view tok, double& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  if (tok.empty() || tok.front() == '+') return false;
  const char* end = tok.data() + tok.size();
  const auto r = std::from_chars(tok.data(), end, out);
  if (r.ptr != end) return false;
  if (r.ec == std::errc::result_out_of_range) {  // overflow, or underflow (which is fine)
    const std::string s(tok);
    const double v = std::strtod(s.c_str(), nullptr);
    if (std::isinf(v)) return false;
    out = v;
    return true;
  }
  return r.ec == std::errc();
}

/// Parses the whole token as a decimal integer (an optional leading '+' is allowed).
inline bool parseInt(std::string_view tok, int64_t& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  if (tok.empty() || tok.front() == '+') return false;
  const char* end = tok.data() + tok.size();
  const auto r = std::from_chars(tok.data(), end, out);
  return r.ec == std::errc() && r.ptr == end;
}

/// Error context for one line of a text file, with checked parsers that throw
/// `path:line: ...` on failure.
struct LineCtx {
  const std::string& path;
  size_t line = 0;

  [[noreturn]] void fail(const std::string& what) const { failAt(path, line, what); }
  double number(std::string_view tok, const char* what) const {
    double v;
    if (!parseDouble(tok, v)) fail("bad number " + quoted(tok) + " for " + what);
    return v;
  }
  double finite(std::string_view tok, const char* what) const {
    const double v = number(tok, what);
    if (!std::isfinite(v)) fail("non-finite value " + quoted(tok) + " for " + what);
    return v;
  }
  /// A vertex coordinate: finite and within kMaxCoordinate (coordinate_range.h).
  double coordinate(std::string_view tok, const char* what) const {
    const double v = finite(tok, what);
    if (!(std::fabs(v) <= kMaxCoordinate)) fail(std::string(what) + " " + quoted(tok) + " is beyond the coordinate range +-1e15");
    return v;
  }
  int64_t integer(std::string_view tok, const char* what) const {
    int64_t v;
    if (!parseInt(tok, v)) fail("bad integer " + quoted(tok) + " for " + what);
    return v;
  }
  /// A count in a header: 0 <= count <= kMaxCount.
  int64_t count(std::string_view tok, const char* what) const {
    const int64_t v = integer(tok, what);
    if (v < 0 || v > kMaxCount) fail(std::string(what) + " " + std::to_string(v) + " out of range");
    return v;
  }
  template <class TokenSource>
  std::string_view need(TokenSource& t, const char* what) const {
    std::string_view tok;
    if (!t.next(tok)) fail(std::string("missing ") + what);
    return tok;
  }
};

}  // namespace sf::detail
