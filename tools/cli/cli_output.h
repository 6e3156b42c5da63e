// SPDX-License-Identifier: Apache-2.0
// Where a command's results go: files written atomically, `-` for standard output, the
// report on stdout unless stdout carries the data; JSON reports.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace sf::cli {

/// A text output file: standard output for "-", else PATH written as PATH.tmp.PID and
/// renamed over PATH by commit() (atomic: readers see the old file or the whole new one; an
/// output not committed is removed). Throws InputError `PATH: cannot open for writing`.
class TextOutput {
 public:
  explicit TextOutput(std::string path);
  ~TextOutput();
  TextOutput(const TextOutput&) = delete;
  TextOutput& operator=(const TextOutput&) = delete;
  std::FILE* file() const { return file_; }
  bool toStdout() const { return path_ == "-"; }
  /// The name for messages: the path, or "<stdout>".
  std::string name() const { return toStdout() ? "<stdout>" : path_; }
  /// Flushes, checks for write errors and renames into place. Throws InputError `PATH: write failed`.
  void commit();

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
};

/// The stream for a command's report (text or JSON): stdout, or stderr when stdout carries
/// the command's data (`-o -`).
inline std::FILE* reportStream(bool dataOnStdout) { return dataOnStdout ? stderr : stdout; }

/// Writes j (2-space indent) and a newline to f and flushes.
void printJson(std::FILE* f, const nlohmann::ordered_json& j);

}  // namespace sf::cli
