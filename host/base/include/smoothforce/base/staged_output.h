// SPDX-License-Identifier: Apache-2.0
// Outputs are written beside their path and renamed into place, so that a failed write (a full
// disk) leaves no partial file; but an existing path that is not a regular file (/dev/null, a
// FIFO, a terminal) is written in place: renaming over it would replace the device with a file
// (as root, `cache build -o /dev/null` did).
#pragma once

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

namespace sf {

/// Where to write `path`'s content: `path` itself when it exists and is not a regular file,
/// else path + ".tmp." + pid (then renamed over path; renaming a path onto itself does nothing).
inline std::string stagingPath(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) return path;
  return path + ".tmp." + std::to_string(::getpid());
}

/// Removes the staging file of a failed write (never `path` itself, a device written in place).
inline void discardStaging(const std::string& staging, const std::string& path) {
  if (staging != path) std::remove(staging.c_str());
}

}  // namespace sf
