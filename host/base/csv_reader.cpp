// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/base/csv_reader.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string_view>
#include <vector>

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

namespace {

/// The delimiter of a file, from its first line of content: of comma, semicolon and tab, the
/// one it holds most often (a tie: in that order; "time, s;x;y;z" is split at semicolons), else
/// ' ' (runs of blanks).
char detectDelimiter(std::string_view line) {
  char best = ' ';
  std::ptrdiff_t most = 0;
  for (const char d : {',', ';', '\t'})
    if (const auto k = std::count(line.begin(), line.end(), d); k > most) {
      most = k;
      best = d;
    }
  return best;
}

/// The fields of a (trimmed) line split at d; with ' ', at runs of blanks.
std::vector<std::string_view> splitFields(std::string_view line, char d) {
  std::vector<std::string_view> f;
  if (d == ' ') {
    size_t a = line.find_first_not_of(" \t");
    while (a != std::string_view::npos) {
      const size_t b = line.find_first_of(" \t", a);
      f.push_back(line.substr(a, b == std::string_view::npos ? std::string_view::npos : b - a));
      a = b == std::string_view::npos ? b : line.find_first_not_of(" \t", b);
    }
    return f;
  }
  size_t a = 0;
  for (size_t b; (b = line.find(d, a)) != std::string_view::npos; a = b + 1) f.push_back(line.substr(a, b - a));
  f.push_back(line.substr(a));
  return f;
}

/// A header field as a column name: blanks and one pair of quotes around it dropped, lower case.
std::string columnName(std::string_view f) {
  f = trim(f);
  if (f.size() >= 2 && (f.front() == '"' || f.front() == '\'') && f.back() == f.front())
    f = trim(f.substr(1, f.size() - 2));
  std::string s(f);
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

/// Whether every field reads as a number (NaN and infinities included: a data row, whose
/// values the reader then checks).
bool allNumbers(const std::vector<std::string_view>& fields) {
  for (std::string_view f : fields) {
    f = trim(f);
    if (!f.empty() && f[0] == '+') f.remove_prefix(1);
    double v;
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
    if (f.empty() || r.ptr != f.data() + f.size()) return false;
  }
  return true;
}

/// Where each wanted column stands among the header's fields (-1: missing); "" or the problem.
std::string locateColumns(const std::vector<std::string_view>& fields, const std::vector<std::string>& wanted,
                          std::vector<int>& at) {
  at.assign(wanted.size(), -1);
  for (size_t c = 0; c < wanted.size(); ++c)
    for (size_t i = 0; i < fields.size(); ++i)
      if (columnName(fields[i]) == wanted[c]) {
        if (at[c] >= 0) return "the header names column '" + wanted[c] + "' twice";
        at[c] = static_cast<int>(i);
      }
  for (size_t c = 0; c < wanted.size(); ++c)
    if (at[c] < 0) return "the header has no column '" + wanted[c] + "'";
  return "";
}

}  // namespace

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
  char delim = ',';
  std::vector<int> at(n);  // the wanted columns' places among a row's fields
  for (size_t c = 0; c < n; ++c) at[c] = static_cast<int>(c);
  size_t width = n;            // fields per row
  std::string given = header;  // the header as the file gives it, for messages
  // the header whose fields are split at d: "" where it names every wanted column, else why not
  auto takeHeader = [&](const std::vector<std::string_view>& fields, char d) {
    std::vector<int> where;
    const std::string why = locateColumns(fields, columns, where);
    if (!why.empty()) return why;
    headerSeen = true;
    delim = d;
    at = where;
    width = fields.size();
    given.clear();
    for (const std::string_view f : fields) {
      if (!given.empty()) given += ',';
      given += trim(f);
    }
    return why;
  };
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
      if (first && !headerSeen) {
        const std::string_view h = trim(line.substr(1));
        const char d = detectDelimiter(h);
        takeHeader(splitFields(h, d), d);
      }
      continue;
    }
    if (first) {
      first = false;
      if (!headerSeen) {
        const char d = detectDelimiter(line);
        const std::vector<std::string_view> fields = splitFields(line, d);
        if (!allNumbers(fields)) {  // a header: the wanted columns by name, in any order, others ignored
          if (const std::string why = takeHeader(fields, d); !why.empty())
            throwCsvError(name, lineNo,
                          "expected header '" + header + "' (the columns in any order, others ignored), got '" +
                              std::string(line) + "': " + why);
          continue;
        }
        if (headerRequired)
          throwCsvError(name, lineNo, "expected header '" + header + "', got '" + std::string(line) + "'");
        delim = d;  // no header: the columns in order
      }
    }
    const std::vector<std::string_view> fields = splitFields(line, delim);
    if (fields.size() != width)
      throwCsvError(
          name, lineNo,
          "expected " + std::to_string(width) + " columns " + given + ", got " + std::to_string(fields.size()));
    for (size_t c = 0; c < n; ++c) {
      double v = 0;
      const std::string_view f = fields[static_cast<size_t>(at[c])];
      if (!parseField(f, v))
        throwCsvError(name, lineNo, columns[c] + " is not a finite number: '" + std::string(trim(f)) + "'");
      t.values.push_back(v);
    }
    t.line.push_back(lineNo);
  }
  if (first && !headerSeen && headerRequired) throw InputError(name + ": empty file (expected header " + header + ")");
  if (t.rows() == 0) throw InputError(name + ": no rows (expected " + header + ")");
  return t;
}

}  // namespace sf
