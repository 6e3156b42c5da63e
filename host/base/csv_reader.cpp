#include <smoothforce/base/csv_reader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string_view>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/error.h>
#include <smoothforce/base/text_encoding.h>

namespace sf {

namespace {

std::string_view trim(std::string_view s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

/// The line without blanks: "x, y ,z" -> "x,y,z".
std::string squeeze(std::string_view s) {
  std::string h;
  for (char ch : s)
    if (ch != ' ' && ch != '\t' && ch != '\r') h += ch;
  return h;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& c : v) s += (s.empty() ? "" : ",") + c;
  return s;
}

std::string readAll(const std::string& path) {
  if (path == "-") {
    std::string text{std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>()};
    if (std::cin.bad()) throw InputError("<stdin>: read failed");
    return text;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, not a CSV file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(path + ": read failed");
  return text;
}

/// The shortest decimal form that reads back as x ("1.0000001e+15", not %.6g's "1e+15").
std::string shortest(double x) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, x);
  return std::string(b, r.ptr);
}

bool parseField(std::string_view f, double& v) {
  f = trim(f);
  if (!f.empty() && f[0] == '+') {
    f.remove_prefix(1);
    if (!f.empty() && (f[0] == '-' || f[0] == '+')) return false;  // "+-1": one sign only
  }
  if (f.empty()) return false;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec == std::errc::result_out_of_range && r.ptr == f.data() + f.size()) {  // overflow, or underflow
    const std::string s(f);
    v = std::strtod(s.c_str(), nullptr);  // a value too small for a double is its rounding to 0
    return std::isfinite(v);
  }
  return r.ec == std::errc() && r.ptr == f.data() + f.size() && std::isfinite(v);
}

}  // namespace

std::string csvDisplayName(const std::string& path) { return path == "-" ? "<stdin>" : path; }

void throwCsvError(const std::string& path, int line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

void requirePositions(const NumericCsv& t, const std::string& path, size_t first) {
  for (size_t r = 0; r < t.rows(); ++r)
    for (size_t c = first; c < first + 3 && c < t.columns.size(); ++c)
      if (!(std::fabs(t.at(r, c)) <= kMaxCoordinate)) {
        throwCsvError(csvDisplayName(path), t.line[r],
                      t.columns[c] + " = " + shortest(t.at(r, c)) + " m is beyond the coordinate range +-1e15 m");
      }
}

NumericCsv readNumericCsv(const std::string& path, const std::vector<std::string>& columns, bool headerRequired) {
  const std::string name = csvDisplayName(path);
  const std::string text = readAll(path);
  NumericCsv t;
  t.columns = columns;
  const std::string header = join(columns);
  const size_t n = columns.size();
  if (const std::string why = textEncodingProblem(text); !why.empty())
    throw InputError(name + ": " + why + "; save it as UTF-8 or ASCII");
  std::string_view rest(text);
  if (rest.substr(0, 3) == "\xEF\xBB\xBF") rest.remove_prefix(3);  // UTF-8 byte-order mark
  int lineNo = 0;
  bool headerSeen = false, first = true;
  while (!rest.empty()) {
    // a line ends in LF, CRLF or a lone CR (old Mac OS; some spreadsheets still write it)
    const size_t nl = rest.find_first_of("\r\n");
    const std::string_view raw = rest.substr(0, nl);
    const bool crlf = nl != std::string_view::npos && rest[nl] == '\r' && nl + 1 < rest.size() && rest[nl + 1] == '\n';
    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + (crlf ? 2 : 1));
    ++lineNo;
    const std::string_view line = trim(raw);
    if (line.empty()) continue;
    if (line[0] == '#') {  // a comment, or the header after '#' (NumPy savetxt) before any data
      if (first && !headerSeen && squeeze(line.substr(1)) == header) headerSeen = true;
      continue;
    }
    if (first) {
      first = false;
      if (!headerSeen) {
        if (squeeze(line) == header) {
          headerSeen = true;
          continue;
        }
        if (headerRequired)
          throwCsvError(name, lineNo, "expected header '" + header + "', got '" + std::string(line) + "'");
      }
    }
    const size_t k = 1 + static_cast<size_t>(std::count(line.begin(), line.end(), ','));
    if (k != n)
      throwCsvError(name, lineNo,
                    "expected " + std::to_string(n) + " columns " + header + ", got " + std::to_string(k));
    size_t start = 0;
    for (size_t c = 0; c < n; ++c) {
      const size_t end = c + 1 < n ? line.find(',', start) : line.size();
      double v = 0;
      const std::string_view f = line.substr(start, end - start);
      if (!parseField(f, v))
        throwCsvError(name, lineNo, columns[c] + " is not a finite number: '" + std::string(trim(f)) + "'");
      t.values.push_back(v);
      start = end + 1;
    }
    t.line.push_back(lineNo);
  }
  if (first && !headerSeen && headerRequired) throw InputError(name + ": empty file (expected header " + header + ")");
  if (t.rows() == 0) throw InputError(name + ": no rows (expected " + header + ")");
  return t;
}

}  // namespace sf
