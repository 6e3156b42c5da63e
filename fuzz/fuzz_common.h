// SPDX-License-Identifier: Apache-2.0
// Shared parts of the libFuzzer harnesses. The readers take a path, so each
// input is written to one temporary file per process (on /dev/shm when it exists) with the
// extension that selects the reader. A crash is: any sanitizer report, any exception other
// than sf::InputError (printed, then abort()), and a returned object that breaks the
// reader's documented guarantees. The harness allocates only in proportion to the input's
// actual size (<= -max_len), never to sizes the input claims.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <smoothforce/mesh/mesh.h>

namespace sf::fuzz {

/// Path of this process's temporary input file with extension `ext` (".obj", ...).
inline const std::string& tempPath(const char* ext) {
  static const std::string path = [&] {
    const char* dir =
        access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
    std::string p = std::string(dir) + "/sf_fuzz_" + std::to_string(::getpid()) + ext;
    std::atexit([] { std::remove(tempPath("").c_str()); });
    return p;
  }();
  return path;
}

/// Writes the bytes to the temporary file; returns its path.
inline const std::string& writeInput(const uint8_t* data, size_t size, const char* ext) {
  const std::string& path = tempPath(ext);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd < 0) std::perror(path.c_str()), std::abort();
  for (size_t done = 0; done < size;) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n <= 0) std::perror(path.c_str()), std::abort();
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  return path;
}

[[noreturn]] inline void crash(const std::string& why) {
  std::fprintf(stderr, "\n*** sf fuzz: %s\n", why.c_str());
  std::abort();
}

/// Runs `read`; sf::InputError is the expected rejection (returns false), success returns
/// true, anything else is a crash.
template <class F>
bool accepted(const std::string& path, F&& read) {
  try {
    read();
    return true;
  } catch (const InputError& e) {
    if (std::string(e.what()).rfind(path, 0) != 0) crash("InputError does not name the file: " + std::string(e.what()));
    return false;
  } catch (const std::exception& e) {
    crash(std::string("exception other than sf::InputError: ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    crash("non-std exception");
  }
}

}  // namespace sf::fuzz
