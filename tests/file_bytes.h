// SPDX-License-Identifier: Apache-2.0
// The bytes of a file, for the tests that compare written files byte for byte.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sf::test {

/// The whole content of the file at p, as bytes ("" where it cannot be opened).
inline std::string fileBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace sf::test
