// SPDX-License-Identifier: Apache-2.0
// Helpers for the hostile-input tests (tests/test_hostile_*.cpp).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <exception>
#include <filesystem>
#include <string>

#include <smoothforce/mesh/mesh.h>

namespace sf::hostile {

/// A temporary folder for this process, removed with everything in it.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() / (tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

/// Runs `read`, which must throw sf::InputError whose message starts with `path` followed by
/// ':' (and contains `fragment`). Any other exception, or none, is a test failure.
/// Returns the message.
template <class F>
std::string expectRejected(const std::string& path, F&& read, const std::string& fragment = "") {
  try {
    read();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << "message does not start with the path: " << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": threw " << typeid(e).name() << " instead of sf::InputError: " << e.what();
    return "";
  } catch (...) {
    ADD_FAILURE() << path << ": threw a non-std exception";
    return "";
  }
  ADD_FAILURE() << path << " was accepted";
  return "";
}

}  // namespace sf::hostile
