// SPDX-License-Identifier: Apache-2.0
// Shared by the mesh reader tests (test_mesh_io.cpp, test_mesh_io_creases.cpp): files written
// from text, and the error a reader gives for one.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <smoothforce/mesh/mesh_io.h>

#include "test_hostile_support.h"

namespace sf::test {

/// Writes `bytes` to file `name` in this process's temporary folder (removed at exit); returns
/// its path.
inline std::string writeTemp(const std::string& name, const std::string& bytes) {
  static const hostile::TempDir dir("sf_test_mesh_files");
  const std::string path = (dir.path / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// The InputError message readMesh(path) throws, or "" (a test failure) when it does not.
inline std::string errorOf(const std::string& path) {
  try {
    readMesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without error";
  return "";
}

}  // namespace sf::test
