// SPDX-License-Identifier: Apache-2.0
// The one strict reader for numeric CSV inputs (query points, HIP sequences, trajectories,
// replay files): every command reads its CSV through it, so they all accept the same files.
#pragma once

#include <string>
#include <vector>

namespace sf {

/// Rows of finite numbers of the wanted columns, read strictly.
/// values: rows() by columns.size(), row-major, in the order of `columns` (not the file's);
/// line[r]: the file line of row r (1-based).
struct NumericCsv {
  std::vector<std::string> columns;
  std::vector<double> values;
  std::vector<int> line;
  size_t rows() const { return line.size(); }
  double at(size_t r, size_t c) const { return values[r * columns.size() + c]; }
};

/// Reads `path` ("-": standard input, named `<stdin>` in errors). The header names the
/// columns: `columns` must each be among its fields once, in any order, matched without regard
/// to case, blanks or one pair of quotes around a name ("X", " x", "\"x\""); its other columns
/// are read past (a time stamp, forces). The header is the first non-blank, non-comment line, or
/// a `#` line before any data that names every column (NumPy's `savetxt(..., delimiter=",",
/// header="x,y,z")` writes `# x,y,z`); with headerRequired = false a row of numbers may come
/// first, and the columns are then `columns`, in that order. The delimiter is the first line's:
/// of comma, semicolon and tab the one it holds most often (ties in that order), else runs of
/// blanks; every row has as many fields as that line. Blank lines and other lines starting with `#` are skipped; a
/// UTF-8 byte-order mark and LF, CRLF and CR-only line ends are accepted. Fields: decimal or exponent numbers, one
/// optional sign (`+` or `-`), blanks around them. Throws InputError `path:line: what` for a missing or wrong header
/// (naming the column it lacks), a wrong field count or a wanted field that is not a finite number, `path: cannot
/// open`, `path: is UTF-16 encoded ...` for UTF-16 or UTF-32 text, and `path: no rows` for a file without data.
NumericCsv readNumericCsv(const std::string& path, const std::vector<std::string>& columns, bool headerRequired = true);

/// The name readNumericCsv uses for `path` in messages ("<stdin>" for "-").
std::string csvDisplayName(const std::string& path);

/// Throws InputError `path:line: what` for the first row whose columns [first, first + 3) are
/// not a position within kMaxCoordinate (coordinate_range.h), naming the column and value.
void requirePositions(const NumericCsv& t, const std::string& path, size_t first = 0);

/// Throws InputError `path:line: what`, for callers that check values themselves.
[[noreturn]] void throwCsvError(const std::string& path, int line, const std::string& what);

}  // namespace sf
