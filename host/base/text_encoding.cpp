// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/base/text_encoding.h>

#include <algorithm>

namespace sf {

std::string textEncodingProblem(std::string_view text) {
  using namespace std::string_view_literals;
  if (text.starts_with("\xff\xfe\0\0"sv)) return "is UTF-32 encoded (byte-order mark FF FE 00 00)";
  if (text.starts_with("\0\0\xfe\xff"sv)) return "is UTF-32 encoded (byte-order mark 00 00 FE FF)";
  if (text.starts_with("\xff\xfe"sv)) return "is UTF-16 encoded (byte-order mark FF FE)";
  if (text.starts_with("\xfe\xff"sv)) return "is UTF-16 encoded (byte-order mark FE FF)";
  const size_t n = std::min<size_t>(text.size(), 64) / 2;  // byte pairs looked at
  size_t nul[2] = {0, 0};                                  // pairs with a NUL first, second
  for (size_t i = 0; i < n; ++i) {
    const bool a = text[2 * i] == '\0', b = text[2 * i + 1] == '\0';
    if (a != b) ++nul[b];
  }
  if (n >= 2 && (nul[0] == n || nul[1] == n)) return "looks UTF-16 encoded (NUL bytes between the characters)";
  return "";
}

}  // namespace sf
