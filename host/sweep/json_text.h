// SPDX-License-Identifier: Apache-2.0
// Private to the sweep module: JSON text that cannot throw on the bytes of a file name.
#pragma once

#include <string>

namespace sf {

/// j as JSON text (indent < 0: one line); bytes that are not UTF-8 (a path in another
/// encoding) become U+FFFD instead of nlohmann's type_error 316.
template <class J>
std::string jsonText(const J& j, int indent = -1) {
  return j.dump(indent, ' ', false, J::error_handler_t::replace);
}

}  // namespace sf
