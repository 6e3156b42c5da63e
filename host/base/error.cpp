// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/base/error.h>

namespace sf::detail {

void throwCheckFailed(const char* file, int line, const std::string& what) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": " + what);
}

}  // namespace sf::detail
