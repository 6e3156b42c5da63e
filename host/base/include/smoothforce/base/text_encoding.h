// SPDX-License-Identifier: Apache-2.0
// Text files this project reads (meshes, CSVs) must be ASCII or UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace sf {

/// Why `text` (a file's first bytes suffice) is not ASCII or UTF-8, "" when it may be: UTF-32
/// or UTF-16 by its byte-order mark, or UTF-16 without one by a NUL in every other byte of its
/// first 64 (ASCII in UTF-16). E.g. "is UTF-16 encoded (byte-order mark FF FE)"; a reader
/// prefixes the file name and asks for UTF-8 or ASCII. A UTF-8 byte-order mark is not a problem.
std::string textEncodingProblem(std::string_view text);

}  // namespace sf
