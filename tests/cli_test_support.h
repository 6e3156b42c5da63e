// SPDX-License-Identifier: Apache-2.0
// Runs the `smoothforce` binary under test (SF_CLI_PATH) for end-to-end tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace sf::test {

struct CliResult {
  int status = -1;  ///< exit status; -1 when killed by a signal
  std::string out;  ///< stdout and stderr together
};

/// Runs `smoothforce ARGS` through the shell and captures its output.
inline CliResult smoothforce(const std::string& args) {
  const std::string cmd = std::string(SF_CLI_PATH) + " " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace sf::test
