#include <smoothforce/base/csv_reader.h>

#include <charconv>
#include <cmath>
#include <fstream>

#include <smoothforce/base/error.h>

namespace sf {

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cols;
  size_t start = 0;
  for (size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') {
      cols.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    }
  return cols;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& c : v) s += (s.empty() ? "" : ",") + c;
  return s;
}

}  // namespace

void throwCsvError(const std::string& path, int line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

NumericCsv readNumericCsv(const std::string& path, const std::vector<std::string>& columns, bool headerRequired) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  NumericCsv t;
  t.columns = columns;
  const std::string header = join(columns);
  std::string line;
  int lineNo = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string tl = trim(line);
    if (tl.empty() || tl[0] == '#') continue;
    std::vector<std::string> cols = split(tl);
    if (first) {
      first = false;
      std::string h;
      for (char ch : tl)
        if (ch != ' ' && ch != '\t') h += ch;
      if (h == header) continue;
      if (headerRequired) throwCsvError(path, lineNo, "expected header '" + header + "', got '" + tl + "'");
    }
    if (cols.size() != columns.size())
      throwCsvError(
          path, lineNo,
          "expected " + std::to_string(columns.size()) + " columns " + header + ", got " + std::to_string(cols.size()));
    for (size_t k = 0; k < cols.size(); ++k) {
      double v = 0;
      const std::string& f = cols[k];
      const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
      if (f.empty() || r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(v))
        throwCsvError(path, lineNo, columns[k] + " is not a finite number: '" + f + "'");
      t.values.push_back(v);
    }
    t.line.push_back(lineNo);
  }
  if (first && headerRequired) throw InputError(path + ": empty file (expected header " + header + ")");
  if (t.rows() == 0) throw InputError(path + ": no rows (expected " + header + ")");
  return t;
}

}  // namespace sf
