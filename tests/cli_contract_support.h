// SPDX-License-Identifier: Apache-2.0
// Runs the `smoothforce` binary under test (SF_CLI_PATH) with stdout and stderr captured
// apart, optional standard input, and optional signals, for the CLI contract tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "file_bytes.h"

namespace sf::test {

struct CliStreams {
  int status = -1;  ///< exit status; -1 when killed by a signal
  std::string out, err;
};

inline std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs `smoothforce ARGS` (ARGS as shell words) with `input` on stdin; scratch files go to
/// `dir`. With signal > 0 (SIGINT, SIGTERM), coreutils' timeout sends it `afterSeconds` after
/// the start (--preserve-status: the command's own exit status comes back).
inline CliStreams runStreams(const std::filesystem::path& dir, const std::string& args, const std::string& input = "",
                             int signal = 0, double afterSeconds = 0) {
  static int serial = 0;
  const std::string base = (dir / ("run" + std::to_string(++serial))).string();
  std::ofstream(base + ".in", std::ios::binary) << input;
  std::string cmd = std::string(SF_CLI_PATH) + " " + args + " < " + shellQuote(base + ".in") + " > " +
                    shellQuote(base + ".out") + " 2> " + shellQuote(base + ".err");
  if (signal > 0)
    cmd = "timeout --preserve-status -s " + std::to_string(signal) + " " + std::to_string(afterSeconds) + " " + cmd;
  const int st = std::system(cmd.c_str());
  CliStreams r;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = fileBytes(base + ".out");
  r.err = fileBytes(base + ".err");
  return r;
}

}  // namespace sf::test
