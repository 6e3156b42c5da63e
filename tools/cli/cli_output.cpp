// SPDX-License-Identifier: Apache-2.0
#include "cli_output.h"

#include <smoothforce/base/staged_output.h>

#include <unistd.h>

#include <smoothforce/base/error.h>  // InputError

namespace sf::cli {

TextOutput::TextOutput(std::string path) : path_(std::move(path)) {
  if (toStdout()) {
    file_ = stdout;
    return;
  }
  tmp_ = stagingPath(path_);
  file_ = std::fopen(tmp_.c_str(), "w");
  if (!file_) throw InputError(path_ + ": cannot open for writing");
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

TextOutput::~TextOutput() {
  if (!file_ || toStdout()) return;
  std::fclose(file_);
  discardStaging(tmp_, path_);
}

void TextOutput::commit() {
  if (toStdout()) {
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) throw InputError("<stdout>: write failed");
    return;
  }
  const bool bad = std::ferror(file_) != 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (bad || !closed || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    discardStaging(tmp_, path_);
    throw InputError(path_ + ": write failed");
  }
}

void printJson(std::FILE* f, const nlohmann::ordered_json& j) {
  const std::string s = j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  std::fputs(s.c_str(), f);
  std::fflush(f);
}

}  // namespace sf::cli
