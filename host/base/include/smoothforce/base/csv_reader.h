// Strict reader for small numeric CSV inputs (query points, HIP sequences, trajectories).
#pragma once

#include <string>
#include <vector>

namespace sf {

/// Rows of finite numbers under a fixed header, read strictly.
/// values: rows() by columns.size(), row-major; line[r]: the file line of row r.
struct NumericCsv {
  std::vector<std::string> columns;
  std::vector<double> values;
  std::vector<int> line;
  size_t rows() const { return line.size(); }
  double at(size_t r, size_t c) const { return values[r * columns.size() + c]; }
};

/// Reads `path`. The first non-blank, non-`#` line must be the header `columns` joined by
/// commas (blanks ignored); with headerRequired = false a row of numbers may come first.
/// Blank lines and lines starting with `#` are skipped. Throws InputError `path:line: what`
/// for a missing or wrong header, a wrong column count, a field that is not a finite number,
/// and `path: no rows` for a file without data.
NumericCsv readNumericCsv(const std::string& path, const std::vector<std::string>& columns, bool headerRequired = true);

/// Throws InputError `path:line: what`, for callers that check values themselves.
[[noreturn]] void throwCsvError(const std::string& path, int line, const std::string& what);

}  // namespace sf
